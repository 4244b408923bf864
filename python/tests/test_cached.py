"""Warm starts: ``dcol.Cache`` and the ``*_cached`` queries against the plain queries on the same
poses (the independent truth: a cold solve), on trajectories that move 1 mm and turn 1 degree
per step. Every cached answer equals the plain one (alpha within 1e-12 relative, points and
distances within 1e-12 of the pair's size l, derivatives within 1e-9 of their largest entry),
and between polytopes most answers are warm: the proximity's solver is ``"polish"`` where the
plain one's is the ray cast, the distance's path ``"gjk_polish"`` where the plain one's is
``"gjk"``. ``intersect_cached`` gives ``intersect``'s decision on every step (and alpha* < 1 of
the proximity wherever alpha* is more than 1e-9 from 1). Also: one cache carried across pairs, ``is_warm``, ``clear``, copies, and errors as
the plain queries raise them."""

import copy
import pickle
import zlib

import numpy as np
import pytest

import dcol

ALPHA = 1e-12  # relative
POINTS = 1e-11  # x* and the contact points, in units of l (see tests/warm_start.rs, POINTS)
DIST = 1e-12  # distance and witnesses, in units of l
DERIV = 1e-9  # relative to the largest entry
STEPS = 300


def hull_points(rng):
    d = rng.normal(size=(30, 3))
    d /= np.linalg.norm(d, axis=1)[:, None]
    r = rng.uniform(0.4, 0.6, size=(30, 1))
    return d * r * np.array([1.2, 1.0, 0.8])


RNG = np.random.default_rng(20261127)
BOX = dcol.Box(0.5, 0.35, 0.25)
HULL = dcol.ConvexHull(hull_points(RNG))
CAPSULE = dcol.Capsule(0.25, 0.8)
CYLINDER = dcol.Cylinder(0.3, 0.9)

# (name, shape1, shape2, both polytopes)
PAIRS = [
    ("box-hull", BOX, HULL, True),
    ("hull-box", HULL, BOX, True),
    ("box-box", BOX, BOX, True),
    ("capsule-cylinder", CAPSULE, CYLINDER, False),
]


def ell(a, b):
    return max(a.bounding_radius, b.bounding_radius)


def unit(rng, n):
    v = rng.normal(size=n)
    return v / np.linalg.norm(v)


def qmul(p, q):
    return np.array([
        p[0] * q[0] - p[1] * q[1] - p[2] * q[2] - p[3] * q[3],
        p[0] * q[1] + p[1] * q[0] + p[2] * q[3] - p[3] * q[2],
        p[0] * q[2] - p[1] * q[3] + p[2] * q[0] + p[3] * q[1],
        p[0] * q[3] + p[1] * q[2] - p[2] * q[1] + p[3] * q[0],
    ])


def trajectory(a, b, rng, steps, start):
    """Poses of the pair over `steps` steps: shape 2 starts where alpha* = `start` and moves
    1 mm per step (reversing every 150 steps), both turn 1 degree per step about their own
    axes; quaternions of lengths 0.7 to 1.3 (the same rotations, as a caller may pass them)."""
    h = np.radians(1.0) / 2

    def turn():
        return np.concatenate([[np.cos(h)], unit(rng, 3) * np.sin(h)])

    q1, q2, w1, w2 = unit(rng, 4), unit(rng, 4), turn(), turn()
    trial = unit(rng, 3) * (a.bounding_radius + b.bounding_radius)
    alpha = dcol.proximity(a, np.r_[0, 0, 0, q1], b, np.r_[trial, q2]).alpha
    r2 = trial * start / alpha
    v = unit(rng, 3) * 1e-3
    out = []
    for k in range(steps):
        s1, s2 = rng.uniform(0.7, 1.3, size=2)
        out.append((np.r_[0.0, 0.0, 0.0, q1 * s1], np.r_[r2, q2 * s2]))
        if k % 150 == 149:
            v = -v
        r2 = r2 + v
        q1, q2 = qmul(w1, q1), qmul(w2, q2)
    return out


def rel(x, y):
    """The largest difference of two arrays, relative to the largest entry of the second."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    return float(np.max(np.abs(x - y)) / max(np.max(np.abs(y)), 1e-300))


def proximity_difference(hot, cold, l):
    da = abs(hot.alpha - cold.alpha) / abs(cold.alpha)
    dp = max(np.linalg.norm(getattr(hot, k) - getattr(cold, k)) / l
             for k in ("point", "contact1", "contact2"))
    return da, dp


def distance_difference(hot, cold, l):
    dd = abs(hot.distance - cold.distance) / l
    dw = max(np.linalg.norm(hot.closest1 - cold.closest1),
             np.linalg.norm(hot.closest2 - cold.closest2)) / l
    return dd, dw


@pytest.mark.parametrize("name,a,b,polytopes", PAIRS, ids=[p[0] for p in PAIRS])
def test_cached_proximity_family_equals_plain(name, a, b, polytopes):
    """proximity, gradient, jacobian and derivatives: each with its own cache over three
    trajectories (starting overlapping, touching and separated)."""
    rng = np.random.default_rng(zlib.crc32(name.encode()))
    l = ell(a, b)
    steps = 0
    warm = {"proximity": 0, "gradient": 0, "jacobian": 0, "derivatives": 0}
    worst = {"alpha": 0.0, "points": 0.0, "derivatives": 0.0}
    for start in (0.7, 1.0, 1.4):
        caches = {k: dcol.Cache() for k in warm}
        for p1, p2 in trajectory(a, b, rng, STEPS, start):
            cold = dcol.proximity(a, p1, b, p2)
            hot = dcol.proximity_cached(a, p1, b, p2, caches["proximity"])
            da, dp = proximity_difference(hot, cold, l)
            assert da <= ALPHA and dp <= POINTS, (
                f"{name} step {steps}: alpha {da:.2e}, points {dp:.2e} "
                f"({hot.solver} vs {cold.solver})")
            assert hot.converged and hot.derivatives == cold.derivatives

            rc, gc = dcol.gradient(a, p1, b, p2)
            rw, gw = dcol.gradient_cached(a, p1, b, p2, caches["gradient"])
            assert gw.shape == (14,)
            dg = rel(gw, gc)
            assert proximity_difference(rw, rc, l)[0] <= ALPHA and dg <= DERIV, (
                f"{name} step {steps}: gradient {dg:.2e}")
            assert rw.derivatives == rc.derivatives

            jrc, jc = dcol.jacobian(a, p1, b, p2)
            jrw, jw = dcol.jacobian_cached(a, p1, b, p2, caches["jacobian"])
            assert jw.shape == (4, 14)
            dj = rel(jw, jc)
            assert proximity_difference(jrw, jrc, l)[0] <= ALPHA and dj <= DERIV, (
                f"{name} step {steps}: jacobian {dj:.2e}")

            dc = dcol.derivatives(a, p1, b, p2)
            dw = dcol.derivatives_cached(a, p1, b, p2, caches["derivatives"])
            assert isinstance(dw, dcol.Derivatives)
            dd = max(rel(getattr(dw, k), getattr(dc, k))
                     for k in ("gradient", "jacobian", "dcontact1", "dcontact2"))
            assert proximity_difference(dw.proximity, dc.proximity, l)[0] <= ALPHA, name
            assert dd <= DERIV, f"{name} step {steps}: derivatives {dd:.2e}"

            worst["alpha"] = max(worst["alpha"], da)
            worst["points"] = max(worst["points"], dp)
            worst["derivatives"] = max(worst["derivatives"], dg, dj, dd)
            steps += 1
            for k, (w, c) in {"proximity": (hot, cold), "gradient": (rw, rc),
                              "jacobian": (jrw, jrc),
                              "derivatives": (dw.proximity, dc.proximity)}.items():
                warm[k] += w.solver == "polish" and c.solver == "ray_cast"
    print(f"{name}: {steps} steps, worst {worst}, warm {warm}")
    if polytopes:
        for k, n in warm.items():
            assert n > steps / 2, f"{name}: only {n} of {steps} {k} answers warm"


@pytest.mark.parametrize("name,a,b,polytopes", PAIRS, ids=[p[0] for p in PAIRS])
def test_cached_distance_equals_plain(name, a, b, polytopes):
    """distance and distance_gradient, each with its own cache, over trajectories starting
    separated (alpha* 1.05 and 1.5); the warm share is counted over separated steps."""
    rng = np.random.default_rng(zlib.crc32(name.encode()) + 1)
    l = ell(a, b)
    steps = separated = 0
    warm = {"distance": 0, "distance_gradient": 0}
    for start in (1.05, 1.5):
        c1, c2 = dcol.Cache(), dcol.Cache()
        for p1, p2 in trajectory(a, b, rng, STEPS, start):
            cold = dcol.distance(a, p1, b, p2)
            hot = dcol.distance_cached(a, p1, b, p2, c1)
            dd, dw = distance_difference(hot, cold, l)
            assert dd <= DIST and dw <= DIST, (
                f"{name} step {steps}: distance {dd:.2e}, witnesses {dw:.2e} "
                f"({hot.path} vs {cold.path})")
            assert hot.converged
            if cold.distance > 1e-3 * l:
                assert np.linalg.norm(hot.normal - cold.normal) <= DERIV, name

            gcold, gc = dcol.distance_gradient(a, p1, b, p2)
            ghot, gw = dcol.distance_gradient_cached(a, p1, b, p2, c2)
            assert gw.shape == (14,)
            assert max(distance_difference(ghot, gcold, l)) <= DIST, name
            assert rel(gw, gc) <= DERIV, f"{name} step {steps}: gradient {rel(gw, gc):.2e}"
            steps += 1
            if cold.distance > 0:
                separated += 1
                warm["distance"] += hot.path == "gjk_polish" and cold.path == "gjk"
                warm["distance_gradient"] += ghot.path == "gjk_polish" and gcold.path == "gjk"
    print(f"{name}: {steps} steps, {separated} separated, warm {warm}")
    assert separated > steps / 2
    if polytopes:
        for k, n in warm.items():
            assert n > separated / 2, f"{name}: only {n} of {separated} {k} answers warm"


@pytest.mark.parametrize("name,a,b,polytopes", PAIRS, ids=[p[0] for p in PAIRS])
def test_cached_intersect_equals_plain(name, a, b, polytopes):
    """intersect_cached against intersect over trajectories starting overlapping, touching and
    separated: the same decision every step, both decisions occurring."""
    rng = np.random.default_rng(zlib.crc32(name.encode()) + 2)
    steps = overlapping = 0
    for start in (0.7, 1.0, 1.4):
        c = dcol.Cache()
        for p1, p2 in trajectory(a, b, rng, STEPS, start):
            hot = dcol.intersect_cached(a, p1, b, p2, c)
            cold = dcol.intersect(a, p1, b, p2)
            assert isinstance(hot, bool) and hot == cold, f"{name} step {steps}"
            alpha = dcol.proximity(a, p1, b, p2).alpha
            if abs(alpha - 1.0) > 1e-9:
                assert hot == (alpha < 1.0), f"{name} step {steps}: alpha {alpha}"
            overlapping += hot
            steps += 1
    assert 0 < overlapping < steps, f"{name}: {overlapping} of {steps} overlapping"


def test_one_cache_across_pairs_gives_plain_answers():
    """One cache passed to every query on every pair, the pair changing at random each step:
    every answer is still the plain one."""
    rng = np.random.default_rng(7)
    trajs = [(a, b, trajectory(a, b, rng, 200, 1.1)) for _, a, b, _ in PAIRS]
    shared = dcol.Cache()
    for step in range(600):
        a, b, traj = trajs[rng.integers(len(trajs))]
        p1, p2 = traj[step % len(traj)]
        l = ell(a, b)
        da, dp = proximity_difference(dcol.proximity_cached(a, p1, b, p2, shared),
                                      dcol.proximity(a, p1, b, p2), l)
        assert da <= ALPHA and dp <= POINTS, step
        dd, dw = distance_difference(dcol.distance_cached(a, p1, b, p2, shared),
                                     dcol.distance(a, p1, b, p2), l)
        assert dd <= DIST and dw <= DIST, step
        (_, gw), (_, gc) = (dcol.gradient_cached(a, p1, b, p2, shared),
                            dcol.gradient(a, p1, b, p2))
        assert rel(gw, gc) <= DERIV, step
        assert dcol.intersect_cached(a, p1, b, p2, shared) == dcol.intersect(a, p1, b, p2), step
        assert shared.is_warm


def test_is_warm_clear_and_copies():
    p1, p2 = [0, 0, 0, 1, 0, 0, 0], [1.2, 0.1, 0.05, 1, 0.02, 0, 0.01]
    p2b = [1.201, 0.1, 0.05, 1, 0.02, 0, 0.01]
    c = dcol.Cache()
    assert c.is_warm is False
    assert repr(c) == "dcol.Cache(is_warm=False)"
    dcol.proximity_cached(BOX, p1, HULL, p2, c)
    assert c.is_warm is True and repr(c) == "dcol.Cache(is_warm=True)"
    c.clear()
    assert c.is_warm is False
    dcol.distance_cached(BOX, p1, HULL, p2, c)
    assert c.is_warm is True
    c.clear()
    assert not c.is_warm

    # A copy holds the same answer and is independent of the original.
    dcol.proximity_cached(BOX, p1, HULL, p2, c)
    for dup in (copy.copy(c), copy.deepcopy(c)):
        assert isinstance(dup, dcol.Cache) and dup is not c and dup.is_warm
        x = dcol.proximity_cached(BOX, p1, HULL, p2b, dup)
        c2 = copy.copy(c)
        y = dcol.proximity_cached(BOX, p1, HULL, p2b, c2)
        assert x.solver == y.solver == "polish"  # warm from the kept answer
        assert x.alpha == y.alpha and np.array_equal(x.point, y.point)
    c.clear()
    assert not c.is_warm and dup.is_warm and c2.is_warm


def test_cache_cannot_be_pickled():
    with pytest.raises(TypeError, match="pickle"):
        pickle.dumps(dcol.Cache())


CACHED = [
    ("proximity", dcol.proximity, dcol.proximity_cached),
    ("gradient", dcol.gradient, dcol.gradient_cached),
    ("jacobian", dcol.jacobian, dcol.jacobian_cached),
    ("derivatives", dcol.derivatives, dcol.derivatives_cached),
    ("distance", dcol.distance, dcol.distance_cached),
    ("distance_gradient", dcol.distance_gradient, dcol.distance_gradient_cached),
    ("intersect", dcol.intersect, dcol.intersect_cached),
]


@pytest.mark.parametrize("name,plain,cached", CACHED, ids=[c[0] for c in CACHED])
def test_cached_errors_as_plain(name, plain, cached):
    """A wrong cache is a TypeError; a bad pose, bad options or an unconverged solve raise the
    plain query's dcol.Error (its status, its message naming the cached C function), and a
    rejected input leaves the cache as it was."""
    p1, p2 = [0, 0, 0, 1, 0, 0, 0], [1.2, 0.1, 0.05, 1, 0.02, 0, 0.01]
    for wrong in (None, 0, {}, dcol.proximity(BOX, p1, HULL, p2), [dcol.Cache()]):
        with pytest.raises(TypeError, match="not an instance of 'Cache'") as e:
            cached(BOX, p1, HULL, p2, wrong)
        assert e.value.__notes__ == ["while processing 'cache'"]
    with pytest.raises(TypeError):
        cached(BOX, p1, HULL, p2)  # no cache

    c = dcol.Cache()
    bad = [
        ((p1, [1.2, float("nan"), 0, 1, 0, 0, 0]), {}),  # invalid pose: status 3
        ((p1, [1.2, 0, 0, 0, 0, 0, 0]), {}),  # zero quaternion: status 3
        ((p1, p2), {"tolerance": -1.0}),  # invalid options: status 4
        ((p1, p2), {"method": "newton"}),
    ]
    for (q1, q2), kw in bad:
        with pytest.raises(dcol.Error) as plain_error:
            plain(BOX, q1, HULL, q2, **kw)
        with pytest.raises(dcol.Error) as cached_error:
            cached(BOX, q1, HULL, q2, c, **kw)
        pe, ce = plain_error.value, cached_error.value
        assert ce.status == pe.status and pe.status in (3, 4)
        assert ce.message == pe.message.replace(f"dcol_{name}", f"dcol_{name}_cached", 1)
        assert not c.is_warm

    # Not converged (status 5): raised with the last iterate as .result, as the plain query.
    kw = {"method": "interior_point", "max_iterations": 1}
    with pytest.raises(dcol.Error) as plain_error:
        plain(BOX, p1, HULL, p2, **kw)
    with pytest.raises(dcol.Error) as cached_error:
        cached(BOX, p1, HULL, p2, c, **kw)
    pe, ce = plain_error.value, cached_error.value
    assert pe.status == ce.status == 5
    assert ce.message == pe.message.replace(f"dcol_{name}", f"dcol_{name}_cached", 1)
    assert type(ce.result) is type(pe.result)


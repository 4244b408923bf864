"""The derivatives with respect to the shapes' own parameters (``Shape.parameters``, the numbers
given to the constructor): ``shape_gradient``, ``distance_shape_gradient`` and
``signed_distance_shape_gradient``.

- against the C ABI (``dcol_shape_gradient``, ...) through ctypes, bit for bit: results,
  derivatives, statuses and messages, on the reference cases and random pairs of every kind
  (hulls, half-spaces) under the option sets of test_capi.py, and near the largest double;
- against central differences of the constructors' arguments (the shape rebuilt with one
  argument moved) on random shapes of every kind at random poses;
- the parameters' round trip (constructor arguments == ``.parameters``, = the C ABI's), a case
  known in closed form, and bad inputs.
"""

import ctypes as C

import numpy as np
import pytest

import dcol
from capi import DistanceResult, ProximityResult, SignedDistanceResult, v
from helpers import HALFSPACE, ZOO, cases, isclose_bits, make, random_pose, spec_of
from test_capi import (
    CONFIGS,
    OPTIONS,
    compared,
    far_configurations,
    py_call,
    same_distance,
    same_proximity,
    same_status,
    shape,
)

QUERIES = [
    ("dcol_shape_gradient", ProximityResult, dcol.shape_gradient),
    ("dcol_distance_shape_gradient", DistanceResult, dcol.distance_shape_gradient),
    ("dcol_signed_distance_shape_gradient", SignedDistanceResult,
     dcol.signed_distance_shape_gradient),
]


def flat_args(spec):
    """The constructor's numbers of a shape description, in the header's order."""
    kind, args = spec
    return np.concatenate([np.ravel(np.asarray(a, dtype=np.float64)) for a in args])


def c_parameters(capi, spec):
    h = capi.shape(spec)
    n = capi.lib.dcol_shape_parameter_count(h)
    out = (C.c_double * n)()
    st = capi.lib.dcol_shape_parameters(h, out, n)
    assert st == 0, capi.message()
    return n, v(out)


def c_call(capi, name, result, s1, p1, s2, p2, **opts):
    n1 = capi.lib.dcol_shape_parameter_count(capi.shape(s1))
    n2 = capi.lib.dcol_shape_parameter_count(capi.shape(s2))
    return capi.call(name, s1, p1, s2, p2, [result, C.c_double * n1, C.c_double * n2], **opts)


@pytest.mark.parametrize("opts", OPTIONS, ids=[str(o) or "default" for o in OPTIONS])
def test_against_the_c_abi(capi, opts):
    statuses, kinds, compared_count = {}, {}, 0
    for cid, s1, p1, s2, p2 in CONFIGS:
        a, b = shape(s1), shape(s2)
        for name, result, fn in QUERIES:
            st, msg, (res, d1_c, d2_c) = c_call(capi, name, result, s1, p1, s2, p2, **opts)
            st_py, msg_py, out = py_call(fn, a, p1, b, p2, **opts)
            same_status(cid, st, msg, st_py, msg_py)
            statuses[st] = statuses.get(st, 0) + 1
            if not compared(st):
                assert out is None, cid
                continue
            r, d1, d2 = out
            if result is ProximityResult:
                same_proximity(cid, r, res)
                kinds[r.derivatives] = kinds.get(r.derivatives, 0) + 1
            else:
                same_distance(cid, r, res)
            assert d1.shape == (a.parameter_count,) and d2.shape == (b.parameter_count,), cid
            assert isclose_bits(d1, v(d1_c)) and isclose_bits(d2, v(d2_c)), (cid, name)
            compared_count += 1
    if opts.get("max_iterations") == 3:
        assert statuses.get(5, 0) > 0, statuses  # the not-converged path was exercised
    else:
        assert set(statuses) == {0}, statuses
    assert compared_count > 1500, compared_count
    print(f"\n{compared_count} answers equal to the C functions' bit for bit; statuses "
          f"{statuses}; kinds {kinds}")


def test_parameters_are_the_c_abis(capi):
    specs = {repr(c[1]): c[1] for c in CONFIGS} | {repr(c[3]): c[3] for c in CONFIGS}
    for spec in specs.values():
        n, p_c = c_parameters(capi, spec)
        s = shape(spec)
        assert s.parameter_count == n and isclose_bits(s.parameters, p_c), spec[0]
    assert len(specs) > 100


def test_near_the_largest_double(capi):
    """Statuses and messages equal the C functions' at the edge of the doubles (where the C
    functions refuse answers beyond the largest double), and numbers too on status 0."""
    seen = {}
    for cid, s1, p1, s2, p2 in far_configurations():
        a, b = shape(s1), shape(s2)
        for name, result, fn in QUERIES:
            st, msg, (res, d1_c, d2_c) = c_call(capi, name, result, s1, p1, s2, p2)
            st_py, msg_py, out = py_call(fn, a, p1, b, p2)
            same_status(cid, st, msg, st_py, msg_py)
            seen[(name, st)] = seen.get((name, st), 0) + 1
            if st == 0:
                assert isclose_bits(out[1], v(d1_c)) and isclose_bits(out[2], v(d2_c)), cid
                assert np.all(np.isfinite(out[1])) and np.all(np.isfinite(out[2])), cid
    assert seen.get(("dcol_shape_gradient", 0), 0) > 1000, seen
    assert seen.get(("dcol_shape_gradient", 3), 0) > 50, seen
    print(f"\n{seen}")


# Central differences of the constructors' arguments.

TOL = 1e-5  # relative to max(1, |derivative|), as test_derivatives.py holds the pose's
H = 1e-6


def random_spec(kind, rng):
    """A random shape description of `kind` (its constructor and arguments)."""
    u = rng.uniform
    if kind == "sphere":
        return ("sphere", (u(0.2, 1.0),))
    if kind == "ellipsoid":
        q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        p = q @ np.diag(1.0 / u(0.3, 1.0, size=3) ** 2) @ q.T
        return ("ellipsoid", ((p + p.T) / 2,))
    if kind == "box":
        return ("box", tuple(u(0.2, 0.8, size=3)))
    if kind == "polytope":
        n = rng.normal(size=(4, 3))
        a = np.vstack([np.eye(3), -np.eye(3), n / np.linalg.norm(n, axis=1)[:, None]])
        return ("polytope", (a, u(0.3, 0.8, size=10)))
    if kind in ("capsule", "cylinder"):
        return (kind, (u(0.1, 0.5), u(0.3, 1.2)))
    if kind == "cone":
        return ("cone", (u(0.5, 1.5), u(0.2, 1.1)))
    if kind == "polygon":
        m = int(rng.integers(5, 8))
        t = 2 * np.pi * (np.arange(m) + u(-0.2, 0.2, size=m)) / m
        c = np.stack([np.cos(t), np.sin(t)], axis=1)
        return ("polygon", (c, u(0.3, 0.7, size=m), u(0.05, 0.3)))
    if kind in ("hull", "padded_hull"):
        while True:
            pts = rng.normal(size=(int(rng.integers(8, 15)), 3)) * 0.5
            radius = 0.0 if kind == "hull" else u(0.05, 0.2)
            try:
                dcol.ConvexHull(pts, radius)
                return ("convex_hull", (pts, radius))
            except dcol.Error:  # the origin not inside: draw again
                pass
    if kind == "halfspace":
        return ("halfspace", (u(0.2, 1.0),))
    raise ValueError(kind)


KINDS = ["sphere", "ellipsoid", "box", "polytope", "capsule", "cylinder", "cone", "polygon",
         "hull", "padded_hull"]


def rebuild(spec, p):
    """The shape of `spec`'s kind made from the parameter vector `p` (the header's order)."""
    kind, args = spec
    if kind == "ellipsoid":
        return dcol.Ellipsoid(p.reshape(3, 3))
    if kind == "polytope":
        m = len(args[1])
        return dcol.Polytope(p[:3 * m].reshape(m, 3), p[3 * m:])
    if kind == "polygon":
        m = len(args[1])
        return dcol.Polygon(p[:2 * m].reshape(m, 2), p[2 * m:3 * m], p[3 * m])
    if kind == "convex_hull":
        n = len(args[0])
        return dcol.ConvexHull(p[:3 * n].reshape(n, 3), p[3 * n])
    return make((kind, tuple(p)))


def directions(spec):
    """(direction in parameter space, one_sided) pairs and how to read the analytic derivative
    along it: an ellipsoid's off-diagonal entries move in symmetric pairs (P must stay
    symmetric; the derivative along the pair is the sum of the two entries, as documented); an
    unpadded hull's radius (0) only grows (a one-sided difference)."""
    p = flat_args(spec)
    n = len(p)
    out = []
    if spec[0] == "ellipsoid":
        for i in range(3):
            for j in range(i, 3):
                e = np.zeros(9)
                e[3 * i + j] = e[3 * j + i] = 1.0
                out.append((e, False))
        return out
    for k in range(n):
        e = np.zeros(n)
        e[k] = 1.0
        one_sided = spec[0] == "convex_hull" and k == n - 1 and p[k] == 0.0
        out.append((e, one_sided))
    return out


def values(a, p1, b, p2):
    """alpha*, the distance and the signed distance of a posed pair."""
    return np.array([dcol.proximity(a, p1, b, p2).alpha, dcol.distance(a, p1, b, p2).distance,
                     dcol.signed_distance(a, p1, b, p2).distance])


def numeric(spec, which, other, p1, p2):
    """Finite differences of (alpha*, distance, signed distance) along `directions(spec)`, spec
    being shape `which` (1 or 2) of the pair: one row per direction."""
    p = flat_args(spec)
    rows = []
    for e, one_sided in directions(spec):
        def f(t):
            s = rebuild(spec, p + t * e)
            return values(s, p1, other, p2) if which == 1 else values(other, p1, s, p2)
        if one_sided:  # second order: (-3 f(0) + 4 f(h) - f(2h)) / 2h
            rows.append((-3 * f(0.0) + 4 * f(H) - f(2 * H)) / (2 * H))
        else:
            rows.append((f(H) - f(-H)) / (2 * H))
    return np.array(rows)


def along(spec, d):
    """The analytic derivative along each of `directions(spec)`."""
    return np.array([e @ d for e, _ in directions(spec)])


def fd_pairs(seed):
    rng = np.random.default_rng(seed)
    out = []
    for k1 in KINDS + ["halfspace"]:
        for k2 in KINDS + ["halfspace"]:
            if k1 == k2 == "halfspace":
                continue
            out.append((f"{k1}-{k2}", random_spec(k1, rng), random_pose(rng, 1.2),
                        random_spec(k2, rng), random_pose(rng, 1.2)))
    return out


def relative(analytic, numeric_):
    return float(np.max(np.abs(analytic - numeric_) / np.maximum(1.0, np.abs(numeric_))))


@pytest.mark.parametrize("seed", [101, 102, 103])
def test_against_central_differences(seed):
    failures, worst, checked = [], {"alpha": 0.0, "distance": 0.0, "signed": 0.0}, {}
    skipped = {}
    for cid, s1, p1, s2, p2 in fd_pairs(seed):
        a, b = make(s1), make(s2)
        r, a1, a2 = dcol.shape_gradient(a, p1, b, p2)
        d, e1, e2 = dcol.distance_shape_gradient(a, p1, b, p2)
        sd, f1, f2 = dcol.signed_distance_shape_gradient(a, p1, b, p2)
        n1, n2 = numeric(s1, 1, b, p1, p2), numeric(s2, 2, a, p1, p2)
        checks = [("signed", f1, f2, 2)]
        # alpha*: where its derivatives are exact (not a smoothed or sub-gradient answer) and
        # alpha* is not ~0 (an origin inside a half-space).
        if r.derivatives == "exact" and r.alpha > 1e-3:
            checks.append(("alpha", a1, a2, 0))
        else:
            skipped[r.derivatives] = skipped.get(r.derivatives, 0) + 1
        # The distance: apart (a smooth function), or overlapping (0, and so its derivatives).
        if abs(sd.distance) > 1e-3:
            checks.append(("distance", e1, e2, 1))
        for what, g1, g2, col in checks:
            err = max(relative(along(s1, g1), n1[:, col]), relative(along(s2, g2), n2[:, col]))
            worst[what] = max(worst[what], err)
            checked[what] = checked.get(what, 0) + 1
            if err > TOL:
                failures.append(f"{cid}: {what} off by {err:.2e}")
    assert checked["alpha"] > 90 and checked["distance"] > 90 and checked["signed"] == 120, \
        checked
    assert not failures, "\n".join(failures)
    print(f"\n{checked} pairs; worst relative error {worst}; alpha* not exact: {skipped}")


def test_closed_form():
    # A ball of radius R at the origin and a box (hx, hy, hz) at 3 on x: alpha* = 3/(R + hx),
    # d alpha*/dR = d alpha*/dhx = -alpha*/(R + hx); the distance 3 - R - hx.
    a, b = dcol.Sphere(1.0), dcol.Box(0.5, 1.0, 1.0)
    p1, p2 = [0, 0, 0, 1, 0, 0, 0], [3, 0, 0, 1, 0, 0, 0]
    r, g1, g2 = dcol.shape_gradient(a, p1, b, p2)
    assert r.alpha == pytest.approx(2.0, abs=1e-12) and r.derivatives == "exact"
    assert g1 == pytest.approx([-4 / 3], abs=1e-9)
    assert g2 == pytest.approx([-4 / 3, 0, 0], abs=1e-9)
    for fn in (dcol.distance_shape_gradient, dcol.signed_distance_shape_gradient):
        d, g1, g2 = fn(a, p1, b, p2)
        assert d.distance == pytest.approx(1.5, abs=1e-12)
        assert g1 == pytest.approx([-1.0], abs=1e-12)
        assert g2 == pytest.approx([-1.0, 0, 0], abs=1e-12)
    # Overlapping: the distance is 0 and so are its derivatives; the signed distance is not.
    d, g1, g2 = dcol.distance_shape_gradient(a, p1, b, [1.2, 0, 0, 1, 0, 0, 0])
    assert d.distance == 0.0 and not g1.any() and not g2.any()
    sd, g1, g2 = dcol.signed_distance_shape_gradient(a, p1, b, [1.2, 0, 0, 1, 0, 0, 0])
    assert sd.distance == pytest.approx(-0.3, abs=1e-12)
    assert g1 == pytest.approx([-1.0], abs=1e-9) and g2 == pytest.approx([-1, 0, 0], abs=1e-9)


def test_parameters_round_trip():
    """Every constructor's numbers come back from `.parameters` unchanged, in the header's
    order (ellipsoids' P symmetrised), as float64 of `parameter_count` numbers."""
    rng = np.random.default_rng(7)
    specs = [random_spec(k, rng) for k in KINDS + ["halfspace"] for _ in range(5)]
    specs += ZOO + [HALFSPACE] + [spec_of(c["shape1"]) for _, c in cases()[:50]]
    for spec in specs:
        s = make(spec)
        p = s.parameters
        assert p.dtype == np.float64 and p.shape == (s.parameter_count,), spec[0]
        assert isclose_bits(p, flat_args(spec)), spec
        assert isclose_bits(rebuild(spec, p).parameters, p), spec
    # An ellipsoid's P within the constructor's symmetry tolerance: (P + P^T)/2 comes back.
    P = np.array([[2.0, 0.3, 0.1], [0.3 * (1 + 1e-14), 1.5, 0.0], [0.1, 0.0, 1.0]])
    p = dcol.Ellipsoid(P).parameters.reshape(3, 3)
    assert np.array_equal(p, p.T) and np.allclose(p, (P + P.T) / 2, rtol=1e-15, atol=0)
    # Read-only, as the constructors' attributes.
    with pytest.raises(AttributeError):
        s.parameters = p
    assert [make(sp).parameter_count for sp in ZOO] == [1, 9, 3, 28, 2, 2, 2, 13, 91, 25]


def posed():
    return dcol.Box(0.5, 0.4, 0.3), [0, 0, 0, 1, 0, 0, 0], dcol.Sphere(0.5), [2, 0, 0, 1, 0, 0, 0]


@pytest.mark.parametrize("name,result,fn", QUERIES, ids=[q[0] for q in QUERIES])
def test_bad_inputs(capi, name, result, fn):
    a, p1, b, p2 = posed()
    spec1, spec2 = ("box", (0.5, 0.4, 0.3)), ("sphere", (0.5,))
    # Options and poses dcol rejects: the C function's status and message.
    for opts in ({"tolerance": -1.0}, {"tolerance": float("nan")}, {"smoothing": -1e-3},
                 {"max_iterations": 0}, {"method": 2}):
        st, msg, _ = c_call(capi, name, result, spec1, p1, spec2, p2, **opts)
        with pytest.raises(dcol.Error) as e:
            fn(a, p1, b, p2, **opts)
        assert st == 4 and (int(e.value.status), e.value.message) == (st, msg)
    for bad in ([0, float("nan"), 0, 1, 0, 0, 0], [0, 0, 0, 0, 0, 0, 0]):
        st, msg, _ = c_call(capi, name, result, spec1, bad, spec2, p2)
        with pytest.raises(dcol.Error) as e:
            fn(a, bad, b, p2)
        assert st == 3 and (int(e.value.status), e.value.message) == (st, msg)
    # Two half-spaces: the C function's refusal.
    h, hs = dcol.HalfSpace(1.0), ("halfspace", (1.0,))
    st, msg, _ = c_call(capi, name, result, hs, p1, hs, p2)
    with pytest.raises(dcol.Error) as e:
        fn(h, p1, h, p2)
    assert st == 2 and (int(e.value.status), e.value.message) == (st, msg)
    # Python's own mistakes.
    with pytest.raises(TypeError):
        fn(a, p1, "sphere", p2)
    with pytest.raises(TypeError):
        fn(a, p1, b)
    with pytest.raises(ValueError, match="pose2 must be a pose, 7 numbers"):
        fn(a, p1, b, [0, 0, 0, 1, 0, 0])
    with pytest.raises(TypeError, match="method must be"):
        fn(a, p1, b, p2, method=1.5)


def test_not_converged_carries_the_last_iterate():
    a, p1 = dcol.Ellipsoid(np.diag([4.0, 2.0, 1.0])), [0, 0, 0, 1, 0, 0, 0]
    b, p2 = dcol.Cone(1.0, 0.5), [1.2, 0.3, 0.1, 0.9, 0.1, 0.2, 0.3]
    with pytest.raises(dcol.Error) as e:
        dcol.shape_gradient(a, p1, b, p2, method="interior_point", max_iterations=2)
    assert e.value.status == dcol.Status.NOT_CONVERGED
    assert e.value.message.startswith("dcol_shape_gradient: the solver reached the iteration "
                                      "limit after 2 iterations")
    r, d1, d2 = e.value.result
    assert isinstance(r, dcol.Proximity) and not r.converged and r.iterations == 2
    assert d1.shape == (9,) and d2.shape == (2,)
    assert np.all(np.isfinite(d1)) and np.all(np.isfinite(d2))

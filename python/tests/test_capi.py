"""The Python bindings against the C ABI's own answers, bit for bit: the same inputs through
``dcol_*`` (ctypes, see capi.py) and through ``dcol.*`` give the same numbers, the same
iteration counts and solvers, the same statuses and the same messages, on every reference case
and on random configurations of every kind (half-spaces and hulls included), under several
options."""

import ctypes as C

import numpy as np
import pytest

import dcol
from capi import (
    DERIVATIVES,
    SOLVERS,
    Contact,
    DerivativesResult,
    DistanceResult,
    ProximityResult,
    SignedDistanceResult,
    m,
    v,
)
from helpers import HALFSPACE, ZOO, cases, isclose_bits, make, pose_of, random_pose, spec_of

OPTIONS = [
    {},
    {"tolerance": 1e-6},
    {"method": "interior_point"},
    {"smoothing": 1e-3},
    {"method": "interior_point", "max_iterations": 3},  # statuses 5: the last iterate
]


def configurations():
    """(id, spec1, pose1, spec2, pose2): the reference cases, then random poses of every
    ordered pair of the zoo and of each zoo shape with a half-space (both orders)."""
    out = []
    for cid, c in cases():
        out.append((cid, spec_of(c["shape1"]), pose_of(c["pose1"]), spec_of(c["shape2"]),
                    pose_of(c["pose2"])))
    rng = np.random.default_rng(20240611)
    for i, s1 in enumerate(ZOO):
        for j, s2 in enumerate(ZOO):
            for k in range(2):
                out.append((f"zoo-{i}-{j}-{k}", s1, list(random_pose(rng)), s2,
                            list(random_pose(rng))))
        for k in range(2):
            out.append((f"zoo-{i}-half-{k}", s1, list(random_pose(rng)), HALFSPACE,
                        list(random_pose(rng))))
            out.append((f"half-zoo-{i}-{k}", HALFSPACE, list(random_pose(rng)), s1,
                        list(random_pose(rng))))
    return out


CONFIGS = configurations()
SHAPES = {}


def shape(spec):
    key = repr(spec)
    if key not in SHAPES:
        SHAPES[key] = make(spec)
    return SHAPES[key]


def py_call(fn, *args, **kw):
    """(status, message, value) of a Python call; for status 5 the value is the `.result`."""
    try:
        return 0, "", fn(*args, **kw)
    except dcol.Error as e:
        return int(e.status), e.message, e.result


def same_status(cid, st_c, msg_c, st_py, msg_py):
    assert st_py == st_c, f"{cid}: status {st_py} (Python) vs {st_c} (C): {msg_py} | {msg_c}"
    assert msg_py == msg_c, f"{cid}: messages differ:\n  {msg_py}\n  {msg_c}"


def same_proximity(cid, r, c):
    assert isclose_bits(r.alpha, c.alpha), cid
    assert isclose_bits(r.point, v(c.point)), cid
    assert isclose_bits(r.contact1, v(c.contact1)), cid
    assert isclose_bits(r.contact2, v(c.contact2)), cid
    assert r.iterations == c.iterations, cid
    assert r.solver == SOLVERS[c.solver], cid
    assert r.derivatives == DERIVATIVES[c.derivatives], cid


def compared(st):
    """Outputs are compared when the C function wrote them: on success and status 5."""
    return st in (0, 5)


@pytest.mark.parametrize("opts", OPTIONS, ids=[str(o) or "default" for o in OPTIONS])
def test_proximity_gradient_jacobian(capi, opts):
    statuses = set()
    for cid, s1, p1, s2, p2 in CONFIGS:
        a, b = shape(s1), shape(s2)
        st, msg, (res,) = capi.call("dcol_proximity", s1, p1, s2, p2, [ProximityResult], **opts)
        st_py, msg_py, r = py_call(dcol.proximity, a, p1, b, p2, **opts)
        same_status(cid, st, msg, st_py, msg_py)
        statuses.add(st)
        if compared(st):
            same_proximity(cid, r, res)
            assert r.converged == (st == 0)

        g_c = (C.c_double * 14)()
        st, msg, (res, g_c) = capi.call("dcol_gradient", s1, p1, s2, p2,
                                        [ProximityResult, C.c_double * 14], **opts)
        st_py, msg_py, out = py_call(dcol.gradient, a, p1, b, p2, **opts)
        same_status(cid, st, msg, st_py, msg_py)
        if compared(st):
            r, g = out
            same_proximity(cid, r, res)
            if st == 0 or np.all(np.isfinite(g)):
                assert isclose_bits(g, v(g_c)), cid

        st, msg, (res, j_c) = capi.call("dcol_jacobian", s1, p1, s2, p2,
                                        [ProximityResult, C.c_double * 56], **opts)
        st_py, msg_py, out = py_call(dcol.jacobian, a, p1, b, p2, **opts)
        same_status(cid, st, msg, st_py, msg_py)
        if compared(st):
            r, j = out
            same_proximity(cid, r, res)
            if st == 0 or np.all(np.isfinite(j)):
                assert isclose_bits(j, v(j_c).reshape(4, 14)), cid
    if opts.get("max_iterations") == 3:
        assert 5 in statuses  # the not-converged path was exercised
    else:
        assert statuses == {0}


@pytest.mark.parametrize("opts", OPTIONS[:4], ids=[str(o) or "default" for o in OPTIONS[:4]])
def test_derivatives(capi, opts):
    for cid, s1, p1, s2, p2 in CONFIGS:
        st, msg, (res,) = capi.call("dcol_derivatives", s1, p1, s2, p2, [DerivativesResult],
                                    **opts)
        st_py, msg_py, d = py_call(dcol.derivatives, shape(s1), p1, shape(s2), p2, **opts)
        same_status(cid, st, msg, st_py, msg_py)
        if compared(st):
            same_proximity(cid, d.proximity, res.proximity)
            assert isclose_bits(d.gradient, v(res.gradient)), cid
            assert isclose_bits(d.jacobian, m(res.jacobian)), cid
            assert isclose_bits(d.dcontact1, m(res.contact_jacobian1)), cid
            assert isclose_bits(d.dcontact2, m(res.contact_jacobian2)), cid


def same_distance(cid, d, c):
    assert isclose_bits(d.distance, c.distance), cid
    assert isclose_bits(d.closest1, v(c.closest1)), cid
    assert isclose_bits(d.closest2, v(c.closest2)), cid
    assert isclose_bits(d.normal, v(c.normal)), cid
    assert d.iterations == c.iterations, cid


@pytest.mark.parametrize("opts", OPTIONS[:3], ids=[str(o) or "default" for o in OPTIONS[:3]])
def test_distances(capi, opts):
    for cid, s1, p1, s2, p2 in CONFIGS:
        a, b = shape(s1), shape(s2)
        for name, result, fn in [
            ("dcol_distance", DistanceResult, dcol.distance),
            ("dcol_signed_distance", SignedDistanceResult, dcol.signed_distance),
        ]:
            st, msg, (res,) = capi.call(name, s1, p1, s2, p2, [result], **opts)
            st_py, msg_py, d = py_call(fn, a, p1, b, p2, **opts)
            same_status(cid, st, msg, st_py, msg_py)
            if compared(st):
                same_distance(cid, d, res)
            st, msg, (res, g_c) = capi.call(name + "_gradient", s1, p1, s2, p2,
                                            [result, C.c_double * 14], **opts)
            fn_g = getattr(dcol, name[5:] + "_gradient")
            st_py, msg_py, out = py_call(fn_g, a, p1, b, p2, **opts)
            same_status(cid, st, msg, st_py, msg_py)
            if compared(st):
                same_distance(cid, out[0], res)
                assert isclose_bits(out[1], v(g_c)), cid


def test_contacts(capi):
    """The manifold's points as the C function gives them, up to order and 1e-9 l: the C
    function takes closed forms the Rust API's `contact_manifold` does not (two boxes apart
    within the margin: an exact face normal, where the Rust manifold keeps the distance query's
    normal to the last bit), as tests/separating_axes.rs holds them (1e-9 l, any order)."""
    total = exact = 0
    for cid, s1, p1, s2, p2 in CONFIGS:
        a, b = shape(s1), shape(s2)
        ell = max(r for r in (a.bounding_radius, b.bounding_radius) if np.isfinite(r))
        for margin, capacity in [(0.0, 16), (0.05, 4), (1.0, 16)]:
            count = C.c_size_t()
            buf = (Contact * 16)()
            o = capi.options()
            st = capi.lib.dcol_contacts(capi.shape(s1), C.byref(capi.pose(p1)), capi.shape(s2),
                                        C.byref(capi.pose(p2)), margin, C.byref(o), buf,
                                        capacity, C.byref(count))
            msg = capi.message() if st else ""
            st_py, msg_py, cs = py_call(dcol.contacts, a, p1, b, p2, margin, capacity)
            same_status(cid, st, msg, st_py, msg_py)
            if st != 0:
                continue
            assert len(cs) == count.value, cid
            c_points = list(buf)[: count.value]
            for c_py in cs:
                total += 1
                near = min(c_points, key=lambda c: np.linalg.norm(c_py.position - v(c.position)))
                assert np.linalg.norm(c_py.position - v(near.position)) <= 1e-9 * ell, cid
                assert np.linalg.norm(c_py.normal - v(near.normal)) <= 1e-9, cid
                assert abs(c_py.depth - near.depth) <= 1e-9 * ell, cid
                exact += (isclose_bits(c_py.position, v(near.position))
                          and isclose_bits(c_py.normal, v(near.normal))
                          and isclose_bits(c_py.depth, near.depth))
    assert total > 100
    assert exact > 0.9 * total, (exact, total)
    print(f"\n{total} contact points, {exact} equal to the C function's bit for bit")


def test_intersect_and_alpha_below(capi):
    for cid, s1, p1, s2, p2 in CONFIGS:
        out = C.c_int32()
        o = capi.options()
        st = capi.lib.dcol_intersect(capi.shape(s1), C.byref(capi.pose(p1)), capi.shape(s2),
                                     C.byref(capi.pose(p2)), C.byref(o), C.byref(out))
        st_py, msg_py, b = py_call(dcol.intersect, shape(s1), p1, shape(s2), p2)
        same_status(cid, st, capi.message() if st else "", st_py, msg_py)
        assert b == bool(out.value), cid
        for t in (0.7, 1.3):
            st = capi.lib.dcol_alpha_below(capi.shape(s1), C.byref(capi.pose(p1)),
                                           capi.shape(s2), C.byref(capi.pose(p2)), t,
                                           C.byref(o), C.byref(out))
            st_py, msg_py, b = py_call(dcol.alpha_below, shape(s1), p1, shape(s2), p2, t)
            same_status(cid, st, capi.message() if st else "", st_py, msg_py)
            assert b == bool(out.value), cid


def far_configurations():
    """Every pair of kinds (half-spaces too, not two) at positions near the largest double,
    offsets from touching to 1e308 (tests/finite_outputs.rs's grid): where the answer overflows
    a double the C functions return status 3 and write nothing."""
    kinds = ZOO + [HALFSPACE]
    out = []
    for i, s1 in enumerate(kinds):
        for j, s2 in enumerate(kinds):
            if s1 is HALFSPACE and s2 is HALFSPACE:
                continue
            for x in (np.finfo(float).max, -1.7e308, 1e308, -8.99e307, 1e300):
                for off in ([0.3, 0.1, 0.0], [0.0, 0.0, 0.0], [1e300, 0.0, 0.0],
                            [-1e308, 0.0, 0.0]):
                    for axis in (0, 1):
                        r1 = np.array([0.1, -0.2, 0.3])
                        r1[axis] = x
                        with np.errstate(over="ignore"):
                            r2 = r1 + off
                        if not np.all(np.isfinite(r2)):
                            continue
                        out.append((f"far-{i}-{j}-{x:g}-{off[0]:g}-{axis}", s1,
                                    [*r1, 0.9, 0.1, 0.2, 0.3], s2, [*r2, 0.8, -0.3, 0.1, 0.2]))
    return out


def test_near_the_largest_double(capi):
    """Statuses and messages of every query equal the C functions' at the edge of the doubles,
    and what is returned is finite (nothing non-finite on success, as in the C ABI)."""
    seen = {}
    finite = lambda *xs: all(np.all(np.isfinite(np.asarray(x, float))) for x in xs)  # noqa: E731
    for cid, s1, p1, s2, p2 in far_configurations():
        a, b = shape(s1), shape(s2)
        st, msg, (res,) = capi.call("dcol_proximity", s1, p1, s2, p2, [ProximityResult])
        st_py, msg_py, r = py_call(dcol.proximity, a, p1, b, p2)
        same_status(cid, st, msg, st_py, msg_py)
        seen[st] = seen.get(st, 0) + 1
        if st == 0:
            same_proximity(cid, r, res)
            assert finite(r.alpha, r.point, r.contact1, r.contact2), cid
        for name, fn, outs in [
            ("dcol_gradient", dcol.gradient, [ProximityResult, C.c_double * 14]),
            ("dcol_jacobian", dcol.jacobian, [ProximityResult, C.c_double * 56]),
            ("dcol_distance_gradient", dcol.distance_gradient, [DistanceResult,
                                                                C.c_double * 14]),
            ("dcol_signed_distance_gradient", dcol.signed_distance_gradient,
             [SignedDistanceResult, C.c_double * 14]),
        ]:
            st, msg, (res, d_c) = capi.call(name, s1, p1, s2, p2, outs)
            st_py, msg_py, out = py_call(fn, a, p1, b, p2)
            same_status(cid, st, msg, st_py, msg_py)
            if st == 0:
                assert isclose_bits(np.ravel(out[1]), v(d_c)), (cid, name)
                assert finite(out[1]), (cid, name)
        for name, fn, result in [("dcol_distance", dcol.distance, DistanceResult),
                                 ("dcol_signed_distance", dcol.signed_distance,
                                  SignedDistanceResult)]:
            st, msg, (res,) = capi.call(name, s1, p1, s2, p2, [result])
            st_py, msg_py, d = py_call(fn, a, p1, b, p2)
            same_status(cid, st, msg, st_py, msg_py)
            if st == 0:
                same_distance(cid, d, res)
                assert finite(d.distance, d.closest1, d.closest2, d.normal), (cid, name)
        st, msg, (res,) = capi.call("dcol_derivatives", s1, p1, s2, p2, [DerivativesResult])
        st_py, msg_py, d = py_call(dcol.derivatives, a, p1, b, p2)
        same_status(cid, st, msg, st_py, msg_py)
        if st == 0:
            assert isclose_bits(d.gradient, v(res.gradient)), cid
            assert finite(d.gradient, d.jacobian, d.dcontact1, d.dcontact2), cid
    # Both kinds of answer occur: finite ones and the refusals.
    assert seen.get(0, 0) > 1000 and seen.get(3, 0) > 50, seen


def test_batch_near_the_largest_double(capi):
    """The batches give each far pair the single call's status (the C function's, above) and
    finite numbers on status 0."""
    configs = far_configurations()
    s1 = [shape(c[1]) for c in configs]
    s2 = [shape(c[3]) for c in configs]
    p1 = np.array([c[2] for c in configs])
    p2 = np.array([c[4] for c in configs])
    out = dcol.proximity_batch(s1, p1, s2, p2)
    single = [py_call(dcol.proximity, a, x, b, y)[0] for a, x, b, y in zip(s1, p1, s2, p2)]
    assert list(out.status) == single
    ok = out.status == 0
    assert np.all(np.isfinite(out.alpha[ok])) and np.all(np.isfinite(out.point[ok]))
    assert np.all(np.isnan(out.alpha[~ok]))
    g = dcol.gradient_batch(s1, p1, s2, p2)
    single = [py_call(dcol.gradient, a, x, b, y)[0] for a, x, b, y in zip(s1, p1, s2, p2)]
    assert list(g.status) == single
    # dcol_gradient refuses some answers whose proximity numbers are finite (the gradient
    # overflows), so its batch refuses more pairs.
    assert np.all(g.status[out.status != 0] != 0) and np.sum(g.status != 0) > np.sum(~ok)
    assert np.all(np.isfinite(g.gradient[g.status == 0]))
    d = dcol.distance_batch(s1, p1, s2, p2)
    single = [py_call(dcol.distance, a, x, b, y)[0] for a, x, b, y in zip(s1, p1, s2, p2)]
    assert list(d.status) == single
    assert np.all(np.isfinite(d.distance[d.status == 0]))

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

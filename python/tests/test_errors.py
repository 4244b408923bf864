"""Bad inputs: values dcol rejects raise dcol.Error with the C status and the C message (the
same as the C constructors' and queries', compared through ctypes); wrong shapes and types of
arrays raise ValueError / TypeError; nothing crashes."""

import pickle
import re

import numpy as np
import pytest

import dcol
from helpers import REPO, make

NAN, INF = float("nan"), float("inf")
BOX = np.vstack([np.eye(3), -np.eye(3)])
SQUARE = np.array([[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0]])
CUBE = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float)

# Inputs each constructor must reject, as (constructor, args).
BAD_SHAPES = [
    ("sphere", (-1.0,)),
    ("sphere", (0.0,)),
    ("sphere", (NAN,)),
    ("sphere", (INF,)),
    ("ellipsoid", (np.diag([1.0, -2.0, 1.0]),)),
    ("ellipsoid", (np.array([[1.0, 0.5, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]),)),
    ("ellipsoid", (np.diag([1.0, NAN, 1.0]),)),
    ("polytope", (BOX, np.array([1.0, 1.0, 1.0, 1.0, 1.0, -0.5]))),
    ("polytope", (BOX[:5], np.ones(5))),
    ("polytope", (BOX, np.array([1.0, 1.0, NAN, 1.0, 1.0, 1.0]))),
    ("box", (0.5, -0.5, 0.5)),
    ("box", (0.5, 0.5, NAN)),
    ("capsule", (-0.1, 1.0)),
    ("capsule", (0.1, -1.0)),
    ("cylinder", (0.1, 0.0)),
    ("cylinder", (INF, 1.0)),
    ("cone", (1.0, 2.0)),
    ("cone", (-1.0, 0.5)),
    ("polygon", (SQUARE, np.ones(4), -0.1)),
    ("polygon", (SQUARE, np.array([1.0, 1.0, 1.0, -1.0]), 0.1)),
    ("polygon", (SQUARE[:2], np.ones(2), 0.1)),
    ("convex_hull", (CUBE[:3], 0.0)),
    ("convex_hull", (CUBE + 2.0, 0.0)),
    ("convex_hull", (CUBE, -0.5)),
    ("convex_hull", (np.vstack([CUBE, [[NAN, 0.0, 0.0]]]), 0.0)),
    ("convex_hull", (CUBE * [1.0, 1.0, 0.0], 0.0)),
    ("halfspace", (0.0,)),
    ("halfspace", (-1.0,)),
]


@pytest.mark.parametrize("spec", BAD_SHAPES, ids=[f"{k}-{i}" for i, (k, _) in enumerate(BAD_SHAPES)])
def test_constructor_errors_are_the_c_ones(capi, spec):
    st, handle, msg = capi.new_shape(spec)
    assert st != 0 and not handle.value, "the C constructor accepted it"
    with pytest.raises(dcol.Error) as e:
        make(spec)
    assert e.value.status == st
    assert e.value.message == msg == str(e.value)
    assert msg.startswith("dcol_shape_new_" + spec[0])


def posed():
    return dcol.Box(0.5, 0.4, 0.3), [0, 0, 0, 1, 0, 0, 0], dcol.Sphere(0.5), [2, 0, 0, 1, 0, 0, 0]


BAD_POSES = [
    ([0, NAN, 0, 1, 0, 0, 0], "position[1]` = NaN: must be finite"),
    ([INF, 0, 0, 1, 0, 0, 0], "position[0]` = inf: must be finite"),
    ([0, 0, 0, 0, 0, 0, 0], "quaternion` = 0: must not be zero"),
    ([0, 0, 0, 1, 0, -INF, 0], "quaternion[2]` = -inf: must be finite"),
]
QUERIES = ["proximity", "gradient", "jacobian", "derivatives", "distance", "distance_gradient",
           "signed_distance", "signed_distance_gradient", "contacts", "intersect",
           "shape_gradient", "distance_shape_gradient", "signed_distance_shape_gradient"]


@pytest.mark.parametrize("query", QUERIES)
def test_pose_errors(query):
    a, p1, b, p2 = posed()
    fn = getattr(dcol, query)
    for bad, text in BAD_POSES:
        for which in (1, 2):
            args = (a, bad, b, p2) if which == 1 else (a, p1, b, bad)
            with pytest.raises(dcol.Error) as e:
                fn(*args)
            assert e.value.status == dcol.Status.INVALID_POSE
            assert e.value.message.startswith(
                f"dcol_{query}: invalid pose: argument `pose{which}->{text}"), e.value.message


BAD_OPTIONS = [
    ({"tolerance": -1.0}, "`options->tolerance` = -1: must be positive and finite"),
    ({"tolerance": NAN}, "`options->tolerance` = NaN: must be positive and finite"),
    ({"smoothing": -1e-3}, "`options->smoothing` = -0.001: must be zero"),
    ({"max_iterations": 0}, "`options->max_iterations` = 0: must be at least 1"),
    ({"method": 2}, "`options->method` = 2: must be DCOL_METHOD_AUTO (0)"),
    ({"method": "newton"}, '`options->method` = "newton": must be "auto" or "interior_point"'),
]


@pytest.mark.parametrize("opts,text", BAD_OPTIONS, ids=[str(o) for o, _ in BAD_OPTIONS])
def test_option_errors(capi, opts, text):
    a, p1, b, p2 = posed()
    with pytest.raises(dcol.Error) as e:
        dcol.proximity(a, p1, b, p2, **opts)
    assert e.value.status == dcol.Status.INVALID_OPTIONS
    assert e.value.message.startswith("dcol_proximity: invalid options: argument " + text)
    if isinstance(opts.get("method", 0), int):  # the C ABI takes numbers only
        from capi import ProximityResult

        spec1, spec2 = ("box", (0.5, 0.4, 0.3)), ("sphere", (0.5,))
        st, msg, _ = capi.call("dcol_proximity", spec1, p1, spec2, p2, [ProximityResult], **opts)
        assert (st, msg) == (int(e.value.status), e.value.message)


def test_wrong_shapes_and_types_of_arrays():
    a, p1, b, p2 = posed()
    for bad in ([0, 0, 0, 1, 0, 0], np.zeros(8), np.zeros((1, 7)), [[0, 0, 0, 1, 0, 0, 0]]):
        with pytest.raises(ValueError, match="pose2 must be a pose, 7 numbers"):
            dcol.proximity(a, p1, b, bad)
    with pytest.raises(ValueError):
        dcol.proximity(a, ["x", 0, 0, 1, 0, 0, 0], b, p2)
    with pytest.raises(TypeError):
        dcol.proximity(a, p1, "sphere", p2)
    with pytest.raises(TypeError):
        dcol.proximity(a, p1, b)
    with pytest.raises(ValueError, match=r"P must be a 3x3 matrix, got an array of shape \(2, 2\)"):
        dcol.Ellipsoid(np.eye(2))
    with pytest.raises(ValueError, match=r"A must be an \(m, 3\) array"):
        dcol.Polytope(np.ones((4, 2)), np.ones(4))
    with pytest.raises(ValueError, match="A has 6 rows but b has 5 numbers"):
        dcol.Polytope(BOX, np.ones(5))
    with pytest.raises(ValueError, match=r"b must be a 1-D array"):
        dcol.Polytope(BOX, np.ones((6, 1)))
    with pytest.raises(ValueError, match=r"C must be an \(m, 2\) array"):
        dcol.Polygon(np.ones((4, 3)), np.ones(4), 0.1)
    with pytest.raises(ValueError, match=r"points must be an \(n, 3\) array"):
        dcol.ConvexHull(np.ones(12))
    with pytest.raises(TypeError):
        dcol.Sphere("big")
    with pytest.raises(TypeError):
        dcol.Shape()
    with pytest.raises(ValueError, match="max_iterations must be an integer"):
        dcol.proximity(a, p1, b, p2, max_iterations=-3)
    with pytest.raises(TypeError, match="method must be"):
        dcol.proximity(a, p1, b, p2, method=1.5)


def test_two_halfspaces(capi):
    h = dcol.HalfSpace(1.0)
    with pytest.raises(dcol.Error) as e:
        dcol.distance(h, [0, 0, 0, 1, 0, 0, 0], h, [0, 0, 5, 1, 0, 0, 0])
    assert e.value.status == dcol.Status.INVALID_SHAPE
    assert "two half-spaces" in e.value.message


def test_not_converged_carries_the_last_iterate():
    a, p1, b, p2 = dcol.Ellipsoid(np.diag([4.0, 2.0, 1.0])), [0, 0, 0, 1, 0, 0, 0], \
        dcol.Cone(1.0, 0.5), [1.2, 0.3, 0.1, 0.9, 0.1, 0.2, 0.3]
    with pytest.raises(dcol.Error) as e:
        dcol.proximity(a, p1, b, p2, method="interior_point", max_iterations=2)
    err = e.value
    assert err.status == dcol.Status.NOT_CONVERGED
    assert re.match(r"dcol_proximity: the solver reached the iteration limit after 2 iterations "
                    r"without converging \(argument `options->max_iterations` = 2, "
                    r"`options->tolerance` = 1e-9\); the result holds the last iterate$",
                    err.message), err.message
    assert isinstance(err.result, dcol.Proximity) and not err.result.converged
    assert np.isfinite(err.result.alpha) and err.result.iterations == 2
    r = dcol.proximity(a, p1, b, p2, method="interior_point")
    assert r.converged and abs(err.result.alpha - r.alpha) < 0.5 * r.alpha


def test_error_class():
    assert issubclass(dcol.Error, Exception)
    e = dcol.Error("dcol_x: internal error: y", 6)
    assert e.status is dcol.Status.INTERNAL and e.result is None and str(e) == e.message
    e2 = pickle.loads(pickle.dumps(dcol.Error("m", 5, 1.5)))
    assert (e2.message, e2.status, e2.result) == ("m", 5, 1.5)
    assert repr(dcol.Error).startswith("<class 'dcol.Error'>")


def test_status_numbers_are_the_headers():
    header = (REPO / "include" / "dcol.h").read_text()
    values = dict(re.findall(r"\bDCOL_((?:OK|ERROR_\w+)) = (\d+)", header))
    assert len(values) == 7
    for name, number in values.items():
        assert dcol.Status[name.removeprefix("ERROR_")] == int(number)


def test_extreme_values_never_crash():
    """Random extreme sizes and poses: every call returns or raises dcol.Error, nothing else."""
    rng = np.random.default_rng(17)
    mags = [0.0, 5e-324, 1e-300, 1e-12, 1.0, 1e12, 1e300, 1.7e308, INF, NAN]
    def num():
        return float(rng.choice([-1, 1]) * rng.choice(mags))
    outcomes = {"ok": 0, "error": 0}
    for _ in range(300):
        kind = rng.integers(0, 4)
        try:
            if kind == 0:
                shape = dcol.Sphere(num())
            elif kind == 1:
                shape = dcol.Box(num(), abs(num()), 1.0)
            elif kind == 2:
                shape = dcol.Capsule(abs(num()), abs(num()))
            else:
                shape = dcol.Cone(abs(num()), 0.5)
        except dcol.Error as e:
            assert e.status == dcol.Status.INVALID_SHAPE
            outcomes["error"] += 1
            continue
        pose = [num() for _ in range(7)]
        for fn in (dcol.proximity, dcol.gradient, dcol.distance, dcol.signed_distance,
                   dcol.contacts):
            try:
                fn(shape, pose, dcol.Sphere(1.0), [0, 0, 0, 1, 0, 0, 0])
                outcomes["ok"] += 1
            except dcol.Error as e:
                assert e.status in (2, 3, 5), e.message
                outcomes["error"] += 1
    assert outcomes["ok"] > 0 and outcomes["error"] > 0

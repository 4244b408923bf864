"""Batches on numpy arrays: equal to the single calls bit for bit (mixed shapes, broadcasting,
any thread count), equal to the C ABI's dcol_proximity_batch, per-pair statuses, and the
errors for wrong arguments."""

import ctypes as C

import numpy as np
import pytest

import dcol
from capi import Pose, ProximityResult, v
from helpers import HALFSPACE, ZOO, isclose_bits, make, random_pose

N = 500


@pytest.fixture(scope="module")
def mixed():
    """N mixed pairs of the zoo (every kind, hulls included) with random poses; a few pairs
    carry bad poses, two a pair of half-spaces."""
    rng = np.random.default_rng(11)
    specs = ZOO + [HALFSPACE]
    idx1 = rng.integers(0, len(ZOO), size=N)
    idx2 = rng.integers(0, len(specs), size=N)
    idx1[[7, 8]] = len(specs) - 1  # half-space against half-space: status 2
    idx2[[7, 8]] = len(specs) - 1
    built = [make(s) for s in specs]
    shapes1 = [built[i] for i in idx1]
    shapes2 = [built[i] for i in idx2]
    poses1 = np.stack([random_pose(rng) for _ in range(N)])
    poses2 = np.stack([random_pose(rng) for _ in range(N)])
    poses1[3, 1] = np.nan  # status 3
    poses2[4, 3:] = 0.0  # zero quaternion: status 3
    return specs, idx1, idx2, shapes1, poses1, shapes2, poses2


def single(fn, *args, **kw):
    try:
        return 0, fn(*args, **kw)
    except dcol.Error as e:
        return int(e.status), e.result


@pytest.mark.parametrize("threads", [None, 1, 2, 3])
def test_proximity_batch_equals_single_calls(mixed, threads):
    _, _, _, s1, p1, s2, p2 = mixed
    out = dcol.proximity_batch(s1, p1, s2, p2, threads=threads)
    assert out.alpha.shape == (N,) and out.point.shape == (N, 3) and out.status.shape == (N,)
    assert out.status.dtype == np.int32
    for i in range(N):
        st, r = single(dcol.proximity, s1[i], p1[i], s2[i], p2[i])
        assert out.status[i] == st, i
        if st in (0, 5):
            assert isclose_bits(out.alpha[i], r.alpha), i
            assert isclose_bits(out.point[i], r.point), i
            assert isclose_bits(out.contact1[i], r.contact1), i
            assert isclose_bits(out.contact2[i], r.contact2), i
        else:
            assert np.isnan(out.alpha[i]) and np.all(np.isnan(out.point[i])), i
    assert list(out.status[[3, 4, 7, 8]]) == [3, 3, 2, 2]
    assert np.sum(out.status == 0) == N - 4


def test_gradient_and_distance_batches_equal_single_calls(mixed):
    _, _, _, s1, p1, s2, p2 = mixed
    g = dcol.gradient_batch(s1, p1, s2, p2)
    d = dcol.distance_batch(s1, p1, s2, p2)
    assert g.gradient.shape == (N, 14) and d.distance.shape == (N,) and d.normal.shape == (N, 3)
    for i in range(N):
        st, out = single(dcol.gradient, s1[i], p1[i], s2[i], p2[i])
        assert g.status[i] == st, i
        if st == 0:
            r, gi = out
            assert isclose_bits(g.alpha[i], r.alpha) and isclose_bits(g.point[i], r.point), i
            assert isclose_bits(g.gradient[i], gi), i
        st, r = single(dcol.distance, s1[i], p1[i], s2[i], p2[i])
        assert d.status[i] == st, i
        if st == 0:
            assert isclose_bits(d.distance[i], r.distance), i
            assert isclose_bits(d.closest1[i], r.closest1), i
            assert isclose_bits(d.closest2[i], r.closest2), i
            assert isclose_bits(d.normal[i], r.normal), i


def test_equals_the_c_batch(mixed, capi):
    specs, idx1, idx2, s1, p1, s2, p2 = mixed
    handles = [capi.shape(s) for s in specs]
    arr1 = (C.c_void_p * N)(*[handles[i].value for i in idx1])
    arr2 = (C.c_void_p * N)(*[handles[i].value for i in idx2])
    poses1 = (Pose * N)(*[capi.pose(p) for p in p1])
    poses2 = (Pose * N)(*[capi.pose(p) for p in p2])
    results = (ProximityResult * N)()
    statuses = (C.c_int * N)()
    o = capi.options()
    st = capi.lib.dcol_proximity_batch(arr1, poses1, arr2, poses2, N, C.byref(o), 2, results,
                                       statuses)
    assert st == 0
    out = dcol.proximity_batch(s1, p1, s2, p2, threads=2)
    assert list(out.status) == list(statuses)
    for i in range(N):
        if statuses[i] == 0:
            assert isclose_bits(out.alpha[i], results[i].alpha), i
            assert isclose_bits(out.point[i], v(results[i].point)), i
            assert isclose_bits(out.contact1[i], v(results[i].contact1)), i


def test_broadcasting(mixed):
    _, _, _, s1, p1, s2, p2 = mixed
    a, b, pose = s1[0], s2[1], p2[9]
    for args in [(a, p1, b, pose), (s1, p1, b, pose), (a, pose, s2, p2), (a, p1, s2, pose)]:
        out = dcol.proximity_batch(*args)
        for i in range(0, N, 37):
            pick = [x[i] if isinstance(x, list) or np.ndim(x) == 2 else x for x in args]
            st, r = single(dcol.proximity, *pick)
            assert out.status[i] == st
            if st == 0:
                assert isclose_bits(out.alpha[i], r.alpha)
    one = dcol.proximity_batch(a, p1[0], b, pose)
    assert one.alpha.shape == (1,)
    assert isclose_bits(one.alpha[0], dcol.proximity(a, p1[0], b, pose).alpha)


def test_inputs_are_converted(mixed):
    _, _, _, s1, p1, s2, p2 = mixed
    ref = dcol.proximity_batch(s1[:20], p1[:20], s2[:20], p2[:20])
    wide = np.zeros((20, 14))
    wide[:, ::2] = p1[:20]
    # Lists, tuples of shapes, Fortran order and strided views: the same numbers.
    for q1 in (p1[:20].tolist(), np.asfortranarray(p1[:20]), wide[:, ::2]):
        out = dcol.proximity_batch(tuple(s1[:20]), q1, s2[:20], p2[:20])
        assert isclose_bits(out.alpha, ref.alpha) and np.array_equal(out.status, ref.status)
    # float32 poses are converted to float64 (so the numbers are those of the rounded poses).
    q32 = p1[:20].astype(np.float32)
    out = dcol.proximity_batch(s1[:20], q32, s2[:20], p2[:20])
    ref32 = dcol.proximity_batch(s1[:20], q32.astype(np.float64), s2[:20], p2[:20])
    assert isclose_bits(out.alpha, ref32.alpha)
    empty = dcol.proximity_batch([], np.zeros((0, 7)), [], np.zeros((0, 7)))
    assert empty.alpha.shape == (0,) and empty.point.shape == (0, 3)


def test_bad_arguments():
    a = dcol.Sphere(1.0)
    good = np.tile([0, 0, 0, 1, 0, 0, 0.0], (3, 1))
    with pytest.raises(ValueError, match=r"poses1 must be an \(N, 7\) array.*shape \(3, 6\)"):
        dcol.proximity_batch(a, good[:, :6], a, good)
    with pytest.raises(ValueError, match=r"shape \(3, 7, 1\)"):
        dcol.proximity_batch(a, good, a, good[..., None])
    with pytest.raises(ValueError, match="disagree on the number of pairs: poses1 has 3, poses2 has 2"):
        dcol.proximity_batch(a, good, a, good[:2])
    with pytest.raises(ValueError, match="shapes1 has 2, poses1 has 3"):
        dcol.proximity_batch([a, a], good, a, good)
    with pytest.raises(TypeError, match=r"shapes2\[1\] must be a dcol.Shape, got int"):
        dcol.proximity_batch(a, good, [a, 3, a], good)
    # Other sequences than lists go through the iterator protocol: the same message.
    with pytest.raises(TypeError, match=r"shapes1\[2\] must be a dcol.Shape, got str"):
        dcol.proximity_batch((a, a, "x"), good, a, good)
    with pytest.raises(TypeError, match="shapes1 must be a dcol.Shape or a sequence"):
        dcol.proximity_batch(3.0, good, a, good)
    with pytest.raises(dcol.Error, match="dcol_proximity_batch: invalid options: argument "
                       r"`options->tolerance` = -1: must be positive and finite") as e:
        dcol.proximity_batch(a, good, a, good, tolerance=-1.0)
    assert e.value.status == dcol.Status.INVALID_OPTIONS
    with pytest.raises(ValueError, match="threads must be at least 1"):
        dcol.proximity_batch(a, good, a, good, threads=0)
    with pytest.raises(ValueError):
        dcol.gradient_batch(a, good, a, "not numbers")


def test_empty_batches():
    a, pose = dcol.Sphere(1.0), np.array([0, 0, 0, 1, 0, 0, 0.0])
    none = np.zeros((0, 7))
    # An empty shape list against single poses: nothing says the batch is meant to be empty.
    for f in (dcol.proximity_batch, dcol.gradient_batch, dcol.distance_batch):
        with pytest.raises(ValueError, match=r"^shapes1 is an empty sequence and both poses are "
                           r"single poses of shape \(7,\): no pair to compute; for an empty batch "
                           r"pass the poses as arrays of shape \(0, 7\)$"):
            f([], pose, a, pose)
    with pytest.raises(ValueError, match="^shapes2 is an empty sequence and both poses"):
        dcol.proximity_batch(a, pose, (), pose)
    with pytest.raises(ValueError, match="^shapes1 and shapes2 are empty sequences and both"):
        dcol.distance_batch([], pose, [], pose)
    # With pose rows, an empty list disagrees with them.
    with pytest.raises(ValueError, match="disagree on the number of pairs: shapes1 has 0, "
                       "poses1 has 3"):
        dcol.proximity_batch([], np.tile(pose, (3, 1)), a, pose)
    # An empty pose array makes an empty batch, broadcast shapes and poses included (as numpy
    # broadcasts (0, 7) against (7,)): every column has 0 rows, of the right widths.
    for args in ([], none, [], none), (a, none, a, pose), ([], none, a, pose), (a, pose, [], none):
        p = dcol.proximity_batch(*args)
        assert [c.shape for c in p] == [(0,), (0, 3), (0, 3), (0, 3), (0,)]
        g = dcol.gradient_batch(*args)
        assert g.gradient.shape == (0, 14) and g.status.shape == (0,)
        d = dcol.distance_batch(*args)
        assert d.distance.shape == (0,) and d.normal.shape == (0, 3)


def test_releases_the_gil():
    # Another Python thread makes progress while a batch runs.
    import threading
    import time

    rng = np.random.default_rng(2)
    a, b = make(ZOO[1]), make(ZOO[8])
    n = 100_000
    p1 = np.stack([random_pose(rng) for _ in range(2000)])
    p1 = np.tile(p1, (n // 2000, 1))
    p2 = np.tile([0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0], (n, 1))
    ticks = []
    stop = threading.Event()

    def tick():
        while not stop.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.001)

    t = threading.Thread(target=tick)
    t.start()
    time.sleep(0.01)
    start = time.perf_counter()
    dcol.proximity_batch(a, p1, b, p2, threads=1)
    end = time.perf_counter()
    stop.set()
    t.join()
    during = [x for x in ticks if start < x < end]
    # With the GIL held for the whole batch, no tick could happen inside it.
    assert end - start > 0.02 and len(during) >= 3, (end - start, len(during))

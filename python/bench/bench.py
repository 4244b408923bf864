"""Throughput of dcol from Python against Coal and python-fcl, on the same pairs, in one run.

    python python/bench/bench.py            # the table: 100 000 mixed pairs, 7 rounds
    python python/bench/bench.py --smoke    # a few pairs, one round (scripts/test.sh)

Needs the dcol package and the peers: ``pip install ./python coal python-fcl``.

The pairs: the six kinds all three libraries have (sphere, box, capsule, cylinder, cone,
ellipsoid) in random pairs and random poses (fixed seed), about a third of them overlapping.
The same geometry is given to each library in its own conventions (dcol's capsules, cylinders
and cones lie along body x, the peers' along z; dcol's cone has its origin at its centroid,
the peers' at mid-height), and the distances are checked to agree before anything is timed.

What is timed, each in ``--rounds`` rounds interleaved (so load on the machine falls on all
alike), median of the rounds:

- per call: a Python loop over ``--calls`` pairs calling ``dcol.proximity``, ``dcol.distance``,
  ``coal.distance`` and ``fcl.distance`` (the peers' geometries, transforms or collision
  objects built beforehand, so the loop times the call alone; Coal's result is cleared before
  each call, as it keeps the least distance it has seen); and ``coal.distance`` in a loop that
  builds each ``Transform3s`` from the poses (quaternion and translation arrays in Coal's
  conventions), as a loop over pose arrays must;
- batch: ``dcol.proximity_batch`` and ``dcol.distance_batch`` on all ``--pairs`` pairs, whole
  calls (argument conversion, GIL release, output arrays), on every core and on one thread;
- the Rust batch, ``dcol::batch::proximity_batch`` on the same pairs with its poses and pair
  list built beforehand (``dcol._dcol._bench_rust_proximity_batch``, compiled into the same
  extension), the reference for the Python batch's overhead;
- warm starts: per call, ``dcol.proximity`` and ``dcol.distance`` against
  ``dcol.proximity_cached`` and ``dcol.distance_cached`` (one new ``dcol.Cache`` per pair and
  round) along trajectories of three pairs of polytopes (box-hull, hull-hull, box-box; about
  ``--calls`` steps in all), shape 2 moving 1 mm per step (reversing every 250 steps) and both
  turning 1 degree per step, starting at alpha* = 1.2. The cached answers are checked to equal
  the plain ones (alpha within 1e-12 relative, distance within 1e-12) before anything is timed.
"""

import argparse
import math
import os
import statistics
import sys
import time

# numpy's OpenBLAS threads spin for a while after each BLAS call (the 3x3 products below), on
# the cores the batches run on: one BLAS thread, so they do not.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

import dcol  # noqa: E402
from dcol import _dcol  # noqa: E402

KINDS = ["sphere", "box", "capsule", "cylinder", "cone", "ellipsoid"]


def rot_y(angle):
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def quat_matrix(q):
    w, x, y, z = q / np.linalg.norm(q)
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ])


def quat_mul(a, b):
    w1, x1, y1, z1 = a
    w2, x2, y2, z2 = b
    return np.array([
        w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
        w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
        w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
        w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2,
    ])


def quat_y(angle):
    """The quaternion of rot_y(angle)."""
    return np.array([math.cos(angle / 2), 0.0, math.sin(angle / 2), 0.0])


def make_kinds(rng):
    """Per kind: (dcol shape, peer description (name, args), body offset R_b, t_b): the peer's
    body frame sits at `t_b` turned by `R_b` in dcol's body frame."""
    out = []
    for k in KINDS:
        if k == "sphere":
            r = rng.uniform(0.2, 0.5)
            out.append((dcol.Sphere(r), ("Sphere", (r,)), np.eye(3), np.zeros(3)))
        elif k == "box":
            h = rng.uniform(0.15, 0.5, size=3)
            out.append((dcol.Box(*h), ("Box", tuple(2 * h)), np.eye(3), np.zeros(3)))
        elif k == "capsule":
            r, length = rng.uniform(0.1, 0.3), rng.uniform(0.3, 0.8)
            out.append((dcol.Capsule(r, length), ("Capsule", (r, length)), rot_y(math.pi / 2),
                        np.zeros(3)))
        elif k == "cylinder":
            r, length = rng.uniform(0.15, 0.4), rng.uniform(0.3, 0.9)
            out.append((dcol.Cylinder(r, length), ("Cylinder", (r, length)),
                        rot_y(math.pi / 2), np.zeros(3)))
        elif k == "cone":
            h, beta = rng.uniform(0.5, 1.0), rng.uniform(0.3, 0.6)
            # dcol: apex at -3h/4 on x, base at +h/4; peers: along z, apex at +h/2, origin at
            # mid-height, i.e. at x = -h/4 in dcol's body frame.
            out.append((dcol.Cone(h, beta), ("Cone", (h * math.tan(beta), h)),
                        rot_y(-math.pi / 2), np.array([-h / 4, 0.0, 0.0])))
        else:
            a = rng.uniform(0.2, 0.6, size=3)
            out.append((dcol.Ellipsoid(np.diag(1.0 / a**2)), ("Ellipsoid", tuple(a)), np.eye(3),
                        np.zeros(3)))
    return out


def random_poses(rng, n, spread):
    q = rng.normal(size=(n, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    return np.hstack([rng.uniform(-spread, spread, size=(n, 3)), q])


def peer_transform(pose, offset):
    """The peer's rotation and translation for a dcol pose and the kind's body offset."""
    R = quat_matrix(pose[3:])
    R_b, t_b = offset
    return R @ R_b, pose[:3] + R @ t_b


def polytope_trajectories(rng, calls):
    """[(shape1, shape2, [(pose1, pose2), ...])]: three pairs of polytopes, ``calls`` steps in
    all, each pair moving 1 mm and turning 1 degree per step from alpha* = 1.2."""
    d = rng.normal(size=(40, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    hull = dcol.ConvexHull(d * rng.uniform(0.4, 0.6, size=(40, 1)) * np.array([1.2, 1.0, 0.8]))
    box = dcol.Box(0.5, 0.35, 0.25)
    half = math.radians(1.0) / 2
    out = []
    for a, b in ((box, hull), (hull, hull), (box, box)):
        def unit(n):
            v = rng.normal(size=n)
            return v / np.linalg.norm(v)
        q1, q2 = unit(4), unit(4)
        w1, w2 = (np.concatenate([[math.cos(half)], unit(3) * math.sin(half)]) for _ in "12")
        trial = unit(3) * (a.bounding_radius + b.bounding_radius)
        r2 = trial * 1.2 / dcol.proximity(a, np.r_[0, 0, 0, q1], b, np.r_[trial, q2]).alpha
        v = unit(3) * 1e-3
        poses = []
        for k in range(max(calls // 3, 1)):
            poses.append((np.r_[0.0, 0.0, 0.0, q1], np.r_[r2, q2]))
            if k % 250 == 249:
                v = -v
            r2, q1, q2 = r2 + v, quat_mul(w1, q1), quat_mul(w2, q2)
        out.append((a, b, poses))
    return out


def timed(fn):
    t = time.perf_counter()
    fn()
    return time.perf_counter() - t


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--pairs", type=int, default=100_000, help="pairs in the batches")
    ap.add_argument("--calls", type=int, default=20_000, help="pairs in the per-call loops")
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("--threads", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("--smoke", action="store_true", help="2 000 pairs, 500 calls, 1 round")
    args = ap.parse_args()
    if args.smoke:
        args.pairs, args.calls, args.rounds = 2000, 500, 1
    try:
        import coal
        import fcl
    except ImportError as e:
        sys.exit(f"bench.py needs the peers: pip install coal python-fcl ({e})")

    rng = np.random.default_rng(args.seed)
    kinds = make_kinds(rng)
    n = args.pairs
    k1 = rng.integers(0, len(kinds), size=n)
    k2 = rng.integers(0, len(kinds), size=n)
    poses1 = random_poses(rng, n, 0.6)
    poses2 = random_poses(rng, n, 0.6)
    shapes1 = [kinds[k][0] for k in k1]
    shapes2 = [kinds[k][0] for k in k2]
    m = min(args.calls, n)

    # The peers' objects for the per-call pairs, built before the clock starts.
    coal_geoms = [getattr(coal, name)(*a) for _, (name, a), _, _ in kinds]
    fcl_geoms = [getattr(fcl, name)(*a) for _, (name, a), _, _ in kinds]
    coal_pairs, fcl_pairs = [], []
    for i in range(m):
        R1, t1 = peer_transform(poses1[i], kinds[k1[i]][2:])
        R2, t2 = peer_transform(poses2[i], kinds[k2[i]][2:])
        coal_pairs.append((coal_geoms[k1[i]], coal.Transform3s(R1, t1), coal_geoms[k2[i]],
                           coal.Transform3s(R2, t2)))
        fcl_pairs.append((fcl.CollisionObject(fcl_geoms[k1[i]], fcl.Transform(R1, t1)),
                          fcl.CollisionObject(fcl_geoms[k2[i]], fcl.Transform(R2, t2))))
    # The same poses as arrays in Coal's conventions ([t, q] per pair, what a Coal user's code
    # holds), for the loop that builds each transform from them.
    offset_q = {}
    for idx, (_, _, R_b, _) in enumerate(kinds):
        offset_q[idx] = quat_y(math.pi / 2) if R_b[0, 2] > 0.5 else (
            quat_y(-math.pi / 2) if R_b[0, 2] < -0.5 else np.array([1.0, 0.0, 0.0, 0.0]))
    coal_poses = []
    for i in range(m):
        row = []
        for pose, k in ((poses1[i], k1[i]), (poses2[i], k2[i])):
            R, t = peer_transform(pose, kinds[k][2:])
            q = quat_mul(pose[3:] / np.linalg.norm(pose[3:]), offset_q[k])
            assert np.allclose(quat_matrix(q), R)
            row.append((q, t))
        coal_poses.append((coal_geoms[k1[i]], row[0], coal_geoms[k2[i]], row[1]))
    creq, cres = coal.DistanceRequest(), coal.DistanceResult()
    freq, fres = fcl.DistanceRequest(), fcl.DistanceResult()

    # The same geometry: distances of the separated per-call pairs agree.
    ref = dcol.distance_batch(shapes1[:m], poses1[:m], shapes2[:m], poses2[:m])
    assert np.all(ref.status == 0), "dcol failed on a benchmark pair"
    apart = ref.distance > 1e-3
    def coal_distance(p):
        cres.clear()  # a DistanceResult keeps the least distance it has seen unless cleared
        return coal.distance(*p, creq, cres)

    d_coal = np.array([coal_distance(p) for p in coal_pairs])
    d_fcl = np.array([fcl.distance(*p, freq, fres) for p in fcl_pairs])
    dev_coal = float(np.max(np.abs(d_coal[apart] - ref.distance[apart]), initial=0.0))
    dev_fcl = float(np.max(np.abs(d_fcl[apart] - ref.distance[apart]), initial=0.0))
    # FCL's GJK (libccd) is known to be off by up to ~3e-2 at its default tolerance (README),
    # so its geometry is checked on the median.
    med_fcl = float(np.median(np.abs(d_fcl[apart] - ref.distance[apart])))
    assert dev_coal < 1e-3, f"Coal's distance differs from dcol's by {dev_coal}: geometry?"
    assert med_fcl < 1e-4, f"FCL's distance differs from dcol's by {med_fcl} (median): geometry?"

    def dcol_loop(fn):
        def run():
            for i in range(m):
                fn(shapes1[i], poses1[i], shapes2[i], poses2[i])
        return run

    def coal_loop():
        dist, clear = coal.distance, cres.clear
        for g1, t1, g2, t2 in coal_pairs:
            clear()
            dist(g1, t1, g2, t2, creq, cres)

    def coal_loop_from_poses():
        dist, clear, tf, quat = coal.distance, cres.clear, coal.Transform3s, coal.Quaternion
        for g1, (q1, t1), g2, (q2, t2) in coal_poses:
            clear()
            dist(g1, tf(quat(*q1), t1), g2, tf(quat(*q2), t2), creq, cres)

    def fcl_loop():
        dist = fcl.distance
        for o1, o2 in fcl_pairs:
            dist(o1, o2, freq, fres)

    # Warm starts: trajectories of polytopes; the cached answers equal the plain ones.
    trajs = polytope_trajectories(rng, m)
    steps = sum(len(p) for _, _, p in trajs)
    warm = 0
    for a, b, poses in trajs:
        c, cd = dcol.Cache(), dcol.Cache()
        for p1, p2 in poses:
            hot, cold = dcol.proximity_cached(a, p1, b, p2, c), dcol.proximity(a, p1, b, p2)
            assert abs(hot.alpha - cold.alpha) <= 1e-12 * cold.alpha, "cached proximity differs"
            warm += hot.solver == "polish" and cold.solver == "ray_cast"
            dh, dc = dcol.distance_cached(a, p1, b, p2, cd), dcol.distance(a, p1, b, p2)
            assert abs(dh.distance - dc.distance) <= 1e-12, "cached distance differs"

    def trajectory_loop(fn, cached):
        def run():
            for a, b, poses in trajs:
                if cached:
                    c = dcol.Cache()
                    for p1, p2 in poses:
                        fn(a, p1, b, p2, c)
                else:
                    for p1, p2 in poses:
                        fn(a, p1, b, p2)
        return run

    T = args.threads
    methods = {
        ("dcol.proximity", "per call"): (m, dcol_loop(_dcol.proximity)),
        ("dcol.distance", "per call"): (m, dcol_loop(_dcol.distance)),
        ("coal.distance", "per call"): (m, coal_loop),
        ("coal.distance", "per call, from poses"): (m, coal_loop_from_poses),
        ("fcl.distance", "per call"): (m, fcl_loop),
        ("dcol.proximity_batch", f"batch, {T} threads"): (
            n, lambda: dcol.proximity_batch(shapes1, poses1, shapes2, poses2, threads=T)),
        ("dcol.distance_batch", f"batch, {T} threads"): (
            n, lambda: dcol.distance_batch(shapes1, poses1, shapes2, poses2, threads=T)),
        ("dcol.proximity_batch", "batch, 1 thread"): (
            n, lambda: dcol.proximity_batch(shapes1, poses1, shapes2, poses2, threads=1)),
        ("Rust proximity_batch", f"batch, {T} threads"): (
            n, lambda: _dcol._bench_rust_proximity_batch(shapes1, poses1, shapes2, poses2, T, 1)),
        ("Rust proximity_batch", "batch, 1 thread"): (
            n, lambda: _dcol._bench_rust_proximity_batch(shapes1, poses1, shapes2, poses2, 1, 1)),
        ("dcol.proximity", "per call, trajectory"): (
            steps, trajectory_loop(_dcol.proximity, False)),
        ("dcol.proximity_cached", "per call, trajectory"): (
            steps, trajectory_loop(_dcol.proximity_cached, True)),
        ("dcol.distance", "per call, trajectory"): (
            steps, trajectory_loop(_dcol.distance, False)),
        ("dcol.distance_cached", "per call, trajectory"): (
            steps, trajectory_loop(_dcol.distance_cached, True)),
    }
    rust = {"Rust proximity_batch"}
    times = {key: [] for key in methods}
    for count, fn in methods.values():  # one untimed round: the pool's threads, first touches
        fn()
    for _ in range(args.rounds):
        for key, (count, fn) in methods.items():
            if key[0] in rust:
                times[key].append(fn()[0] / count)  # the batch call alone, timed in Rust
            else:
                times[key].append(timed(fn) / count)
    med = {key: statistics.median(v) for key, v in times.items()}
    best = {key: min(v) for key, v in times.items()}

    overlap = float(np.mean(dcol.proximity_batch(shapes1, poses1, shapes2, poses2).alpha < 1))
    print(f"{n} pairs ({m} in the per-call loops) of {', '.join(KINDS)}; {overlap:.0%} "
          f"overlapping; {args.rounds} rounds; {T} threads on {os.cpu_count()} cores")
    print(f"same geometry: separated pairs' distance, max |coal - dcol| = {dev_coal:.1e}, "
          f"|fcl - dcol| = {dev_fcl:.1e} (median {med_fcl:.1e})")
    coal_key = ("coal.distance", "per call")
    print()
    print(f"| {'what':<22} | {'how':<22} | {'median µs/pair':>14} | {'best µs/pair':>12} | "
          f"{'pairs/s (median)':>16} | {'× coal loop':>11} |")
    print(f"|{'-' * 24}|{'-' * 24}|{'-' * 15}:|{'-' * 13}:|{'-' * 17}:|{'-' * 12}:|")
    for key in methods:
        us = med[key] * 1e6
        print(f"| {key[0]:<22} | {key[1]:<22} | {us:>14.3f} | {best[key] * 1e6:>12.3f} | "
              f"{1.0 / med[key]:>16,.0f} | {med[coal_key] / med[key]:>11.2f} |")
    py_batch = med[("dcol.proximity_batch", f"batch, {T} threads")]
    rs_batch = med[("Rust proximity_batch", f"batch, {T} threads")]
    py_1 = med[("dcol.proximity_batch", "batch, 1 thread")]
    rs_1 = med[("Rust proximity_batch", "batch, 1 thread")]
    print()
    print(f"Python batch / Rust batch throughput, {T} threads: {rs_batch / py_batch:.3f} "
          f"(1 thread: {rs_1 / py_1:.3f}); bar: at least 0.8")
    coal_poses_key = ("coal.distance", "per call, from poses")
    print(f"Python batch / Python loop over coal.distance throughput: "
          f"{med[coal_key] / py_batch:.1f} (transforms built in the loop: "
          f"{med[coal_poses_key] / py_batch:.1f}); bar: at least 5")
    traj = "per call, trajectory"
    print(f"Warm starts on {steps} trajectory steps of polytope pairs ({warm} warm): "
          f"dcol.proximity_cached / dcol.proximity time "
          f"{med[('dcol.proximity_cached', traj)] / med[('dcol.proximity', traj)]:.2f}, "
          f"dcol.distance_cached / dcol.distance "
          f"{med[('dcol.distance_cached', traj)] / med[('dcol.distance', traj)]:.2f} (medians)")


if __name__ == "__main__":
    main()

"""Every query against the repository's reference cases (tests/data: 365 cases, 49 pair files
and the stress file, from the independent oracle), with the tolerances of the Rust reference
tests (tests/reference.rs, reference_derivatives.rs, reference_distance.rs)."""

import numpy as np
import pytest

import dcol
from helpers import dist, length_scale, load, make, pose_of, reference_files, spec_of

FILES = reference_files()

ALPHA_TOL = 1e-10  # relative to max(1, alpha_ref); absolute for `coincident`
POINT_TOL = 1e-7  # x* and contact points, relative to the length scale
NEWTON_POINT_TOL = 1e-8  # x* at the default tolerance
DERIV_TOL = 1e-5  # gradient and Jacobian, scaled as the reference README says
DIST_TOL = 1e-8  # distance, relative to the length scale
WITNESS_TOL = 1e-6


def posed(case):
    s1, s2 = make(spec_of(case["shape1"])), make(spec_of(case["shape2"]))
    return s1, pose_of(case["pose1"]), s2, pose_of(case["pose2"])


def test_the_reference_set_is_whole():
    assert len(FILES) == 50
    assert sum(len(load(f)) for f in FILES) == 365


@pytest.mark.parametrize("path", FILES, ids=[f.stem for f in FILES])
def test_proximity(path):
    failures = []
    for case in load(path):
        s1, p1, s2, p2 = posed(case)
        r = dcol.proximity(s1, p1, s2, p2)
        assert r.converged
        a_ref, ell = case["alpha"], length_scale(case)
        coincident = case["category"] == "coincident"
        ea = abs(r.alpha - a_ref) if coincident else abs(r.alpha - a_ref) / max(1.0, a_ref)
        if ea > ALPHA_TOL:
            failures.append(f"{case['id']}: alpha {r.alpha} vs {a_ref} ({ea:.2e})")
        if case["x_unique"] is True:
            ex = dist(r.point, case["x"]) / ell
            if ex > NEWTON_POINT_TOL:
                failures.append(f"{case['id']}: x* off by {ex:.2e} l")
            if case["p1"] is not None and not coincident:
                k = min(a_ref, 1.0)
                ep = max(dist(r.contact1, case["p1"]), dist(r.contact2, case["p2"])) / ell * k
                if ep > POINT_TOL:
                    failures.append(f"{case['id']}: contact off by {ep:.2e} l/min(1, alpha)")
    assert not failures, "\n".join(failures)


@pytest.mark.parametrize("path", FILES, ids=[f.stem for f in FILES])
def test_gradient_and_jacobian(path):
    failures, checked = [], 0
    for case in load(path):
        s1, p1, s2, p2 = posed(case)
        ell = length_scale(case)
        colscale = np.array([ell if c % 7 < 3 else 1.0 for c in range(14)])
        if case["dalpha_dconfig"] is not None:
            r, g = dcol.gradient(s1, p1, s2, p2)
            assert g.shape == (14,)
            for c, ref in enumerate(case["dalpha_dconfig"]):
                if ref is None:
                    continue
                checked += 1
                err = abs((g[c] - ref) * colscale[c]) / max(1.0, abs(ref * colscale[c]))
                if err > DERIV_TOL:
                    failures.append(f"{case['id']}: dalpha[{c}] {g[c]} vs {ref}")
        if case["jacobian"] is not None:
            r, j = dcol.jacobian(s1, p1, s2, p2)
            assert j.shape == (4, 14)
            for row in range(4):
                rs = 1.0 / ell if row < 3 else 1.0
                for c, ref in enumerate(case["jacobian"][row]):
                    if ref is None:
                        continue
                    checked += 1
                    k = rs * colscale[c]
                    err = abs((j[row, c] - ref) * k) / max(1.0, abs(ref * k))
                    if err > DERIV_TOL:
                        failures.append(f"{case['id']}: J[{row}][{c}] {j[row, c]} vs {ref}")
    assert not failures, "\n".join(failures)
    if "parallel" not in {c["category"] for c in load(path)}:
        assert checked > 0


@pytest.mark.parametrize("path", FILES, ids=[f.stem for f in FILES])
def test_distance(path):
    failures = []
    for case in load(path):
        s1, p1, s2, p2 = posed(case)
        ell = length_scale(case)
        d = dcol.distance(s1, p1, s2, p2)
        d_ref = case["distance"]
        err = abs(d.distance - d_ref) / ell
        if d_ref == 0.0:
            if d.distance != 0.0 and err > DIST_TOL:
                failures.append(f"{case['id']}: distance {d.distance} for touching/overlap")
            continue
        if err > DIST_TOL:
            failures.append(f"{case['id']}: distance {d.distance} vs {d_ref} ({err:.2e} l)")
        if case["closest_unique"] is True:
            ew = max(dist(d.closest1, case["closest1"]), dist(d.closest2, case["closest2"])) / ell
            if ew > WITNESS_TOL:
                failures.append(f"{case['id']}: witness off by {ew:.2e} l")
        # The signed distance of a separated pair is the distance.
        sd = dcol.signed_distance(s1, p1, s2, p2)
        if abs(sd.distance - d_ref) / ell > DIST_TOL:
            failures.append(f"{case['id']}: signed distance {sd.distance} vs {d_ref}")
    assert not failures, "\n".join(failures)


@pytest.mark.parametrize("path", FILES, ids=[f.stem for f in FILES])
def test_intersect_and_alpha_below(path):
    for case in load(path):
        s1, p1, s2, p2 = posed(case)
        a_ref = case["alpha"]
        if abs(a_ref - 1.0) > 1e-6:
            assert dcol.intersect(s1, p1, s2, p2) == (a_ref < 1.0), case["id"]
        for t in (0.5 * a_ref, 2.0 * a_ref):
            if t > 0:
                assert dcol.alpha_below(s1, p1, s2, p2, t) == (a_ref < t), case["id"]
        lo, hi = dcol.alpha_bounds(s1, p1, s2, p2)
        assert lo <= a_ref * (1 + 1e-12) + 1e-300 and a_ref <= hi * (1 + 1e-12), case["id"]

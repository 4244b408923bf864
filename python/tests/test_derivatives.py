"""Derivatives against central finite differences of the values, on random configurations of
every kind (boxes, polytopes, hulls and half-spaces included): the gradient and Jacobian of
proximity, the contact points' Jacobians, and the gradients of the distance and the signed
distance. Columns are (r1, q1, r2, q2): pose1 then pose2, 7 numbers each."""

import numpy as np
import pytest

import dcol
from helpers import HALFSPACE, ZOO, make, random_pose

TOL = 1e-5  # relative to max(1, |derivative|), as the reference tests hold derivatives
H = 1e-6


def configurations(seed):
    rng = np.random.default_rng(seed)
    shapes = [make(s) for s in ZOO]
    out = []
    for i, a in enumerate(shapes):
        for j, b in enumerate(shapes):
            out.append((f"{i}-{j}", a, random_pose(rng), b, random_pose(rng)))
        h = make(HALFSPACE)
        out.append((f"{i}-half", a, random_pose(rng), h, random_pose(rng)))
        out.append((f"half-{i}", h, random_pose(rng), a, random_pose(rng)))
    return out


def central(f, p1, p2, h=H):
    """Central differences of f(pose1, pose2) (a number or a vector) over the 14 columns."""
    x = np.concatenate([p1, p2]).astype(float)
    cols = []
    for c in range(14):
        e = np.zeros(14)
        e[c] = h
        fp, fm = f((x + e)[:7], (x + e)[7:]), f((x - e)[:7], (x - e)[7:])
        cols.append((np.asarray(fp) - np.asarray(fm)) / (2 * h))
    return np.stack(cols, axis=-1)


def check(name, analytic, numeric, failures, cid):
    err = np.abs(analytic - numeric) / np.maximum(1.0, np.abs(numeric))
    if err.max() > TOL:
        failures.append(f"{cid}: {name} off by {err.max():.2e}")
    return float(err.max())


@pytest.mark.parametrize("seed", [1, 2])
def test_proximity_derivatives(seed):
    failures, worst, checked = [], 0.0, 0
    for cid, a, p1, b, p2 in configurations(seed):
        d = dcol.derivatives(a, p1, b, p2)
        if d.proximity.derivatives != "exact" or d.proximity.alpha < 1e-3:
            continue
        checked += 1
        r, g = dcol.gradient(a, p1, b, p2)
        r2, j = dcol.jacobian(a, p1, b, p2)
        assert np.array_equal(g, d.gradient) and np.array_equal(j, d.jacobian)

        def f(q1, q2):
            r = dcol.proximity(a, q1, b, q2)
            return np.concatenate([r.point, [r.alpha], r.contact1, r.contact2])

        num = central(f, p1, p2)
        worst = max(worst, check("gradient", g, num[3], failures, cid))
        worst = max(worst, check("jacobian", j, num[:4], failures, cid))
        worst = max(worst, check("dcontact1", d.dcontact1, num[4:7], failures, cid))
        worst = max(worst, check("dcontact2", d.dcontact2, num[7:10], failures, cid))
    assert checked > 100, checked  # alpha ~ 0 (an origin inside a half-space) is left out
    assert not failures, "\n".join(failures)
    print(f"\n{checked} configurations, worst relative error {worst:.1e}")


@pytest.mark.parametrize("seed", [3, 4])
def test_distance_gradients(seed):
    failures, checked = [], {"distance": 0, "signed": 0}
    for cid, a, p1, b, p2 in configurations(seed):
        sd, gs = dcol.signed_distance_gradient(a, p1, b, p2)
        num = central(lambda q1, q2: dcol.signed_distance(a, q1, b, q2).distance, p1, p2)
        check("signed distance gradient", gs, num, failures, cid)
        checked["signed"] += 1
        if sd.distance > 1e-3:
            d, gd = dcol.distance_gradient(a, p1, b, p2)
            num = central(lambda q1, q2: dcol.distance(a, q1, b, q2).distance, p1, p2)
            check("distance gradient", gd, num, failures, cid)
            checked["distance"] += 1
    assert checked["distance"] > 40 and checked["signed"] > 100, checked
    assert not failures, "\n".join(failures)


def test_smoothed_derivatives_are_those_of_the_smoothed_alpha():
    # Flat against flat: x* is not unique, the smoothed derivatives are smooth and exact for
    # the smoothed problem.
    a, b = dcol.Box(0.5, 0.5, 0.5), dcol.Box(0.3, 0.3, 0.3)
    p1, p2 = [0, 0, 0, 1, 0, 0, 0], [0.1, 0.05, 1.2, 1, 0.01, 0.02, 0]
    for mu in (1e-3, 1e-2):
        r, g = dcol.gradient(a, p1, b, p2, smoothing=mu)
        assert r.derivatives == "smoothed"
        num = central(lambda q1, q2: dcol.proximity(a, q1, b, q2, smoothing=mu).alpha, p1, p2,
                      h=1e-5)
        assert np.max(np.abs(g - num) / np.maximum(1, np.abs(num))) < TOL

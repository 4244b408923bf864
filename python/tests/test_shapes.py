"""Shapes from Python: kinds, attributes, radii, and answers known in closed form."""

import math

import numpy as np
import pytest

import dcol

I = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0]


def at(x, y=0.0, z=0.0, q=(1.0, 0.0, 0.0, 0.0)):
    return [x, y, z, *q]


def test_kinds_attributes_and_radii():
    s = dcol.Sphere(0.5)
    assert isinstance(s, dcol.Shape) and s.kind == "sphere" and s.radius == 0.5
    assert s.bounding_radius == 0.5 == s.inscribed_radius
    b = dcol.Box(0.5, 0.4, 0.3)
    assert b.kind == "polytope" and (b.half_x, b.half_y, b.half_z) == (0.5, 0.4, 0.3)
    assert b.bounding_radius == pytest.approx(math.sqrt(0.5**2 + 0.4**2 + 0.3**2), rel=1e-12)
    c = dcol.Capsule(0.5, 2.0)
    assert c.kind == "capsule" and c.bounding_radius == 1.5 and c.length == 2.0
    assert dcol.Cylinder(0.3, 0.8).bounding_radius == pytest.approx(0.5, rel=1e-15)
    cone = dcol.Cone(2.0, 0.5)
    assert (cone.height, cone.half_angle, cone.kind) == (2.0, 0.5, "cone")
    e = dcol.Ellipsoid(np.diag([4.0, 1.0, 0.25]))
    assert e.kind == "ellipsoid" and np.array_equal(e.P, np.diag([4.0, 1.0, 0.25]))
    assert e.bounding_radius == pytest.approx(2.0) and e.inscribed_radius == pytest.approx(0.5)
    A = np.vstack([np.eye(3), -np.eye(3)])
    p = dcol.Polytope(A, np.ones(6))
    assert p.kind == "polytope" and p.A.shape == (6, 3) and np.array_equal(p.b, np.ones(6))
    g = dcol.Polygon([[1, 0], [0, 1], [-1, 0], [0, -1]], [1, 1, 1, 1], 0.1)
    assert g.kind == "polygon" and g.C.shape == (4, 2) and g.radius == 0.1
    h = dcol.HalfSpace(1.0)
    assert h.kind == "halfspace" and h.bounding_radius == math.inf and h.depth == 1.0
    pts = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]) * 0.5
    hull = dcol.ConvexHull(pts, radius=0.1)
    assert hull.kind == "convex_hull" and hull.radius == 0.1 and hull.points.shape == (8, 3)
    assert dcol.ConvexHull(pts).radius == 0.0
    assert repr(s) == "Sphere(0.5)" and repr(b) == "Box(0.5, 0.4, 0.3)"
    assert {s, b} and s != dcol.Sphere(0.5)  # hashable, compared by identity


def test_closed_forms():
    # Two spheres: alpha = d / (r1 + r2), x* on the segment, d alpha / d r2 = unit offset / sum.
    a, b = dcol.Sphere(0.5), dcol.Sphere(0.25)
    r, g = dcol.gradient(a, I, b, at(3.0, 4.0))
    assert r.alpha == pytest.approx(5.0 / 0.75, rel=1e-14)
    assert g[7:10] == pytest.approx(np.array([0.6, 0.8, 0.0]) / 0.75, rel=1e-13)
    assert g[0:3] == pytest.approx(-np.array([0.6, 0.8, 0.0]) / 0.75, rel=1e-13)
    assert np.allclose(r.contact1, [0.3, 0.4, 0.0]) and np.allclose(r.contact2, [2.85, 3.8, 0.0])
    d = dcol.distance(a, I, b, at(3.0, 4.0))
    assert d.distance == pytest.approx(4.25, rel=1e-14)
    assert np.allclose(d.normal, [0.6, 0.8, 0.0])
    # A rounded unit box (hull of a cube's corners padded by 0.1) and a ball: alpha = 2/(0.6+0.4).
    pts = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]) * 0.5
    r = dcol.proximity(dcol.ConvexHull(pts, 0.1), I, dcol.Sphere(0.4), at(2.0))
    assert r.alpha == pytest.approx(2.0, abs=1e-12)
    # A floor (top at z = 0) and a ball 1.5 above: distance 1, alpha = 2.5 / 1.5.
    floor, ball = dcol.HalfSpace(1.0), dcol.Sphere(0.5)
    sd = dcol.signed_distance(floor, at(0, 0, -1.0), ball, at(0, 0, 1.5))
    assert sd.distance == pytest.approx(1.0, abs=1e-15)
    assert dcol.proximity(floor, at(0, 0, -1.0), ball, at(0, 0, 1.5)).alpha == pytest.approx(
        2.5 / 1.5, abs=1e-15)
    # A capsule turned by 90 degrees about z (its axis on y) against a sphere on y.
    q = (math.cos(math.pi / 4), 0.0, 0.0, math.sin(math.pi / 4))
    r = dcol.proximity(dcol.Capsule(0.5, 2.0), at(0, 0, 0, q), dcol.Sphere(0.5), at(0, 4.0))
    assert r.alpha == pytest.approx(4.0 / 2.0, rel=1e-12)
    # Two boxes face to face: a 4-point manifold, depth 0.01.
    box = dcol.Box(0.5, 0.5, 0.5)
    cs = dcol.contacts(box, I, box, at(0, 0, 0.99))
    assert len(cs) == 4 and all(c.depth == pytest.approx(0.01, abs=1e-12) for c in cs)
    assert all(np.allclose(c.normal, [0, 0, 1]) for c in cs)
    assert len(dcol.contacts(box, I, box, at(0, 0, 0.99), max_points=2)) == 2
    assert dcol.contacts(box, I, box, at(0, 0, 1.5)) == []


def test_quaternions_need_not_be_unit():
    a, b = dcol.Box(0.5, 0.3, 0.2), dcol.Cone(1.0, 0.4)
    q = np.array([0.9, 0.1, -0.3, 0.2])
    r1 = dcol.proximity(a, at(0, 0, 0, q), b, at(1.5, 0.2, 0.1))
    r2 = dcol.proximity(a, at(0, 0, 0, 3.0 * q), b, at(1.5, 0.2, 0.1))
    assert r1.alpha == pytest.approx(r2.alpha, rel=1e-14)
    # The gradient is taken with respect to the quaternion as given: scaling q by 3 scales
    # the quaternion columns by 1/3.
    _, g1 = dcol.gradient(a, at(0, 0, 0, q), b, at(1.5, 0.2, 0.1))
    _, g3 = dcol.gradient(a, at(0, 0, 0, 3.0 * q), b, at(1.5, 0.2, 0.1))
    assert g3[3:7] == pytest.approx(g1[3:7] / 3.0, rel=1e-9, abs=1e-14)


def test_pose_forms():
    a, b = dcol.Sphere(0.5), dcol.Sphere(0.5)
    ref = dcol.proximity(a, I, b, at(2.0)).alpha
    for pose in ([2, 0, 0, 1, 0, 0, 0], (2.0, 0, 0, 1, 0, 0, 0), np.array(at(2.0)),
                 np.array(at(2.0), dtype=np.float32), np.arange(14.0)[::2] * 0 + at(2.0)):
        assert dcol.proximity(a, I, b, pose).alpha == ref

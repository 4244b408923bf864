"""Shared test helpers: the repository's reference cases (``tests/data``, made by the
independent oracle of ``tests/generate_reference.rs``), shapes built from one description on
both sides (Python bindings and C ABI), random configurations."""

import json
import os
import pathlib

import numpy as np
import pytest

import dcol

REPO = pathlib.Path(__file__).resolve().parents[2]
DATA = REPO / "tests" / "data"

MAKERS = {
    "sphere": dcol.Sphere,
    "ellipsoid": dcol.Ellipsoid,
    "polytope": dcol.Polytope,
    "box": dcol.Box,
    "capsule": dcol.Capsule,
    "cylinder": dcol.Cylinder,
    "cone": dcol.Cone,
    "polygon": dcol.Polygon,
    "convex_hull": dcol.ConvexHull,
    "halfspace": dcol.HalfSpace,
}


def skip_allowed():
    return os.environ.get("DCOL_ALLOW_SKIP") == "1"


def reference_files():
    """The 50 reference files; missing data fails unless DCOL_ALLOW_SKIP=1 (as the Rust
    tests do)."""
    files = sorted(DATA.glob("cases-*.jsonl"))
    if not files:
        if skip_allowed():
            pytest.skip(f"{DATA} is missing (DCOL_ALLOW_SKIP=1)")
        raise FileNotFoundError(f"{DATA} is missing: the reference cases ship with the repository")
    return files


def load(path):
    with open(path) as f:
        return [json.loads(line) for line in f if line.strip()]


def spec_of(s):
    """A shape description ``(constructor, args)`` from a reference record's shape."""
    k = s["kind"]
    if k == "sphere":
        return ("sphere", (s["R"],))
    if k == "ellipsoid":
        return ("ellipsoid", (np.array(s["P"], dtype=float),))
    if k == "polytope":
        return ("polytope", (np.array(s["A"], dtype=float), np.array(s["b"], dtype=float)))
    if k == "capsule":
        return ("capsule", (s["R"], s["L"]))
    if k == "cylinder":
        return ("cylinder", (s["R"], s["L"]))
    if k == "cone":
        return ("cone", (s["H"], s["beta"]))
    if k == "padded_polygon":
        return (
            "polygon",
            (np.array(s["C"], dtype=float), np.array(s["d"], dtype=float), s["R"]),
        )
    raise ValueError(k)


def make(spec):
    kind, args = spec
    return MAKERS[kind](*args)


def pose_of(p):
    return [*p["r"], *p["q"]]


def cases():
    """Every reference case, as (id, record)."""
    out = []
    for f in reference_files():
        out.extend((c["id"], c) for c in load(f))
    return out


# A fixed zoo of shapes of every kind, for configurations the reference set does not hold
# (half-spaces, hulls, boxes).
def _cube(h):
    return np.array([[sx * h, sy * h, sz * h] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])


ZOO = [
    ("sphere", (0.5,)),
    ("ellipsoid", (np.array([[4.0, 0.0, 0.0], [0.0, 2.0, 0.3], [0.0, 0.3, 1.0]]),)),
    ("box", (0.5, 0.3, 0.4)),
    ("polytope", (np.vstack([np.eye(3), -np.eye(3), [[1, 1, 1]]]) * 1.0,
                  np.array([0.6, 0.5, 0.4, 0.6, 0.5, 0.4, 0.9]))),
    ("capsule", (0.3, 0.8)),
    ("cylinder", (0.35, 0.9)),
    ("cone", (1.0, 0.5)),
    ("polygon", (np.array([[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0]]),
                 np.array([0.5, 0.4, 0.5, 0.4]), 0.1)),
    ("convex_hull", (np.random.default_rng(3).normal(size=(30, 3)) * 0.4, 0.0)),
    ("convex_hull", (_cube(0.4), 0.1)),
]
HALFSPACE = ("halfspace", (0.5,))


def random_quaternion(rng):
    q = rng.normal(size=4)
    return q / np.linalg.norm(q) * rng.uniform(0.5, 2.0)  # not unit: normalised by dcol


def random_pose(rng, scale=1.5):
    return np.concatenate([rng.uniform(-scale, scale, size=3), random_quaternion(rng)])


def length_scale(case):
    return case["solver_notes"]["length_scale"]


def dist(a, b):
    return float(np.linalg.norm(np.asarray(a, dtype=float) - np.asarray(b, dtype=float)))


def rel(x, ref):
    return abs(x - ref) / max(1.0, abs(ref))


def isclose_bits(a, b):
    """Equal bit for bit (NaN equal to NaN)."""
    a = np.asarray(a, dtype=np.float64)
    b = np.asarray(b, dtype=np.float64)
    return a.shape == b.shape and a.tobytes() == b.tobytes()


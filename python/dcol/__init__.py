"""dcol: exact, differentiable collision detection between convex shapes.

Shapes (``Sphere``, ``Ellipsoid``, ``Polytope``, ``Box``, ``Capsule``, ``Cylinder``, ``Cone``,
``Polygon``, ``HalfSpace``, ``ConvexHull``) are posed by 7-vectors ``[x, y, z, qw, qx, qy, qz]``
(position, then the quaternion, scalar first, world from body; it need not be unit length).
One pair at a time: ``proximity``, ``gradient``, ``jacobian``, ``derivatives``, ``distance``,
``distance_gradient``, ``signed_distance``, ``signed_distance_gradient``, ``contacts``,
``intersect``, ``alpha_below``, ``alpha_bounds``; the derivatives with respect to the shapes'
own parameters (``Shape.parameters``): ``shape_gradient``, ``distance_shape_gradient``,
``signed_distance_shape_gradient``. Warm starts for a pair queried again and again on poses
that move a little: ``Cache`` (one per pair) and ``proximity_cached``, ``gradient_cached``,
``jacobian_cached``, ``derivatives_cached``, ``distance_cached``, ``distance_gradient_cached``,
``intersect_cached`` (the plain queries' answers, found faster between polytopes; the
intersection test also for shapes its kept separating normal still separates). Many pairs on numpy arrays,
without the GIL, on dcol's thread pool: ``proximity_batch``, ``gradient_batch``,
``distance_batch``. JAX: ``dcol.jax`` (``pip install dcol[jax]``).

Options are keyword arguments: ``tolerance`` (default 1e-9), ``max_iterations``, ``method``
(``"auto"`` or ``"interior_point"``) and ``smoothing`` (default 0: exact). Every error dcol
reports is a ``dcol.Error`` with the C ABI's ``status`` and message; arrays of the wrong shape
raise ``ValueError``.
"""

from typing import NamedTuple

import numpy as np

from . import _dcol
from ._dcol import (
    MAX_CONTACTS,
    Box,
    Cache,
    Capsule,
    Cone,
    Contact,
    ConvexHull,
    Cylinder,
    Derivatives,
    Distance,
    Ellipsoid,
    HalfSpace,
    Polygon,
    Polytope,
    Proximity,
    Shape,
    SignedDistance,
    Sphere,
    alpha_below,
    alpha_bounds,
    contacts,
    derivatives,
    derivatives_cached,
    distance,
    distance_cached,
    distance_gradient,
    distance_gradient_cached,
    distance_shape_gradient,
    gradient,
    gradient_cached,
    intersect,
    intersect_cached,
    jacobian,
    jacobian_cached,
    proximity,
    proximity_cached,
    shape_gradient,
    signed_distance,
    signed_distance_gradient,
    signed_distance_shape_gradient,
)
from ._errors import Error, Status

__version__ = _dcol.__version__

#: ``method=`` values, as in the C ABI (``DCOL_METHOD_AUTO``, ``DCOL_METHOD_INTERIOR_POINT``).
METHOD_AUTO = 0
METHOD_INTERIOR_POINT = 1


class ProximityBatch(NamedTuple):
    """What ``proximity_batch`` returns, N pairs."""

    alpha: np.ndarray
    """α* of each pair, (N,)."""
    point: np.ndarray
    """x* of each pair, (N, 3)."""
    contact1: np.ndarray
    """The contact point on shape 1, (N, 3)."""
    contact2: np.ndarray
    """The contact point on shape 2, (N, 3)."""
    status: np.ndarray
    """Each pair's ``dcol.Status`` number, (N,) int32: 0 ok, 5 not converged (the last iterate
    is written), 2, 3 or 6 an error (its outputs are NaN)."""


class GradientBatch(NamedTuple):
    """What ``gradient_batch`` returns, N pairs."""

    alpha: np.ndarray
    point: np.ndarray
    contact1: np.ndarray
    contact2: np.ndarray
    gradient: np.ndarray
    """∂α*/∂(r1, q1, r2, q2) of each pair, (N, 14)."""
    status: np.ndarray


class DistanceBatch(NamedTuple):
    """What ``distance_batch`` returns, N pairs."""

    distance: np.ndarray
    closest1: np.ndarray
    closest2: np.ndarray
    normal: np.ndarray
    status: np.ndarray


def proximity_batch(shapes1, poses1, shapes2, poses2, *, threads=None, **options):
    """Proximity of N pairs: ``shapes1``/``shapes2`` a sequence of N shapes or one shape for
    all, ``poses1``/``poses2`` an (N, 7) array or one pose (7,) for all.

    Runs without the GIL on dcol's thread pool (``threads``: at most that many threads;
    default one per core); every number equals ``dcol.proximity``'s on the same pair, bit for
    bit. Each pair has its own ``status``; wrong shapes of arrays raise ``ValueError``, invalid
    options ``dcol.Error``. Options: ``tolerance``, ``max_iterations``, ``method``,
    ``smoothing``.
    """
    return ProximityBatch(
        *_dcol.proximity_batch(shapes1, poses1, shapes2, poses2, threads=threads, **options)
    )


def gradient_batch(shapes1, poses1, shapes2, poses2, *, threads=None, **options):
    """``proximity_batch`` with each pair's gradient ∂α*/∂(r1, q1, r2, q2), (N, 14), equal to
    ``dcol.gradient``'s bit for bit."""
    return GradientBatch(
        *_dcol.gradient_batch(shapes1, poses1, shapes2, poses2, threads=threads, **options)
    )


def distance_batch(shapes1, poses1, shapes2, poses2, *, threads=None, **options):
    """The exact distance of N pairs (as ``proximity_batch`` takes them), with the closest
    points and normals, equal to ``dcol.distance``'s bit for bit."""
    return DistanceBatch(
        *_dcol.distance_batch(shapes1, poses1, shapes2, poses2, threads=threads, **options)
    )


def __getattr__(name):
    # `dcol.jax` on first use (JAX is an optional dependency: `pip install dcol[jax]`).
    if name == "jax":
        import importlib

        return importlib.import_module(".jax", __name__)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


__all__ = [
    "Box",
    "Cache",
    "Capsule",
    "Cone",
    "Contact",
    "ConvexHull",
    "Cylinder",
    "Derivatives",
    "Distance",
    "DistanceBatch",
    "Ellipsoid",
    "Error",
    "GradientBatch",
    "HalfSpace",
    "MAX_CONTACTS",
    "METHOD_AUTO",
    "METHOD_INTERIOR_POINT",
    "Polygon",
    "Polytope",
    "Proximity",
    "ProximityBatch",
    "Shape",
    "SignedDistance",
    "Sphere",
    "Status",
    "alpha_below",
    "alpha_bounds",
    "contacts",
    "derivatives",
    "derivatives_cached",
    "distance",
    "distance_cached",
    "distance_batch",
    "distance_gradient",
    "distance_gradient_cached",
    "distance_shape_gradient",
    "gradient",
    "gradient_cached",
    "gradient_batch",
    "intersect",
    "intersect_cached",
    "jacobian",
    "jacobian_cached",
    "proximity",
    "proximity_cached",
    "proximity_batch",
    "shape_gradient",
    "signed_distance",
    "signed_distance_gradient",
    "signed_distance_shape_gradient",
]

"""Type stubs of the extension module (python/src). See the package's docstrings."""

from typing import Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

ArrayLike = npt.ArrayLike
Method = Union[str, int]

MAX_CONTACTS: int
__version__: str

class Shape:
    @property
    def kind(self) -> str: ...
    @property
    def bounding_radius(self) -> float: ...
    @property
    def inscribed_radius(self) -> float: ...
    @property
    def parameters(self) -> np.ndarray: ...
    @property
    def parameter_count(self) -> int: ...

class Sphere(Shape):
    radius: float
    def __init__(self, radius: float) -> None: ...

class Ellipsoid(Shape):
    P: np.ndarray
    def __init__(self, P: ArrayLike) -> None: ...

class Polytope(Shape):
    A: np.ndarray
    b: np.ndarray
    def __init__(self, A: ArrayLike, b: ArrayLike) -> None: ...

class Box(Shape):
    half_x: float
    half_y: float
    half_z: float
    def __init__(self, half_x: float, half_y: float, half_z: float) -> None: ...

class Capsule(Shape):
    radius: float
    length: float
    def __init__(self, radius: float, length: float) -> None: ...

class Cylinder(Shape):
    radius: float
    length: float
    def __init__(self, radius: float, length: float) -> None: ...

class Cone(Shape):
    height: float
    half_angle: float
    def __init__(self, height: float, half_angle: float) -> None: ...

class Polygon(Shape):
    C: np.ndarray
    d: np.ndarray
    radius: float
    def __init__(self, C: ArrayLike, d: ArrayLike, radius: float) -> None: ...

class HalfSpace(Shape):
    depth: float
    def __init__(self, depth: float) -> None: ...

class ConvexHull(Shape):
    points: np.ndarray
    radius: float
    def __init__(self, points: ArrayLike, radius: float = 0.0) -> None: ...

class Proximity:
    alpha: float
    point: np.ndarray
    contact1: np.ndarray
    contact2: np.ndarray
    iterations: int
    solver: str
    derivatives: str
    converged: bool

class Distance:
    distance: float
    closest1: np.ndarray
    closest2: np.ndarray
    normal: np.ndarray
    iterations: int
    path: str
    converged: bool

class SignedDistance:
    distance: float
    normal: np.ndarray
    closest1: np.ndarray
    closest2: np.ndarray
    iterations: int
    path: str
    converged: bool

class Contact:
    position: np.ndarray
    normal: np.ndarray
    depth: float

class Derivatives:
    proximity: Proximity
    gradient: np.ndarray
    jacobian: np.ndarray
    dcontact1: np.ndarray
    dcontact2: np.ndarray

class Cache:
    """A per-pair warm-start cache, cold when made (see ``proximity_cached``)."""
    def __init__(self) -> None: ...
    @property
    def is_warm(self) -> bool: ...
    def clear(self) -> None: ...
    def __copy__(self) -> Cache: ...
    def __deepcopy__(self, memo: object) -> Cache: ...

# Every query takes the options as keyword arguments.
def proximity(shape1: Shape, pose1: ArrayLike, shape2: Shape, pose2: ArrayLike, *,
              tolerance: Optional[float] = None, max_iterations: Optional[int] = None,
              method: Optional[Method] = None, smoothing: Optional[float] = None) -> Proximity: ...
def gradient(shape1: Shape, pose1: ArrayLike, shape2: Shape, pose2: ArrayLike, *,
             tolerance: Optional[float] = None, max_iterations: Optional[int] = None,
             method: Optional[Method] = None,
             smoothing: Optional[float] = None) -> Tuple[Proximity, np.ndarray]: ...
def jacobian(shape1: Shape, pose1: ArrayLike, shape2: Shape, pose2: ArrayLike, *,
             tolerance: Optional[float] = None, max_iterations: Optional[int] = None,
             method: Optional[Method] = None,
             smoothing: Optional[float] = None) -> Tuple[Proximity, np.ndarray]: ...
def derivatives(shape1: Shape, pose1: ArrayLike, shape2: Shape, pose2: ArrayLike, *,
                tolerance: Optional[float] = None, max_iterations: Optional[int] = None,
                method: Optional[Method] = None,
                smoothing: Optional[float] = None) -> Derivatives: ...
def distance(shape1: Shape, pose1: ArrayLike, shape2: Shape, pose2: ArrayLike, *,
             tolerance: Optional[float] = None, max_iterations: Optional[int] = None,
             method: Optional[Method] = None, smoothing: Optional[float] = None) -> Distance: ...
def distance_gradient(shape1: Shape, pose1: ArrayLike, shape2: Shape, pose2: ArrayLike, *,
                      tolerance: Optional[float] = None, max_iterations: Optional[int] = None,
                      method: Optional[Method] = None,
                      smoothing: Optional[float] = None) -> Tuple[Distance, np.ndarray]: ...
# The warm-started queries: the plain ones' arguments with the pair's cache after the poses.
def proximity_cached(shape1: Shape, pose1: ArrayLike, shape2: Shape, pose2: ArrayLike,
                     cache: Cache, *, tolerance: Optional[float] = None,
                     max_iterations: Optional[int] = None, method: Optional[Method] = None,
                     smoothing: Optional[float] = None) -> Proximity: ...
def gradient_cached(shape1: Shape, pose1: ArrayLike, shape2: Shape, pose2: ArrayLike,
                    cache: Cache, *, tolerance: Optional[float] = None,
                    max_iterations: Optional[int] = None, method: Optional[Method] = None,
                    smoothing: Optional[float] = None) -> Tuple[Proximity, np.ndarray]: ...
def jacobian_cached(shape1: Shape, pose1: ArrayLike, shape2: Shape, pose2: ArrayLike,
                    cache: Cache, *, tolerance: Optional[float] = None,
                    max_iterations: Optional[int] = None, method: Optional[Method] = None,
                    smoothing: Optional[float] = None) -> Tuple[Proximity, np.ndarray]: ...
def derivatives_cached(shape1: Shape, pose1: ArrayLike, shape2: Shape, pose2: ArrayLike,
                       cache: Cache, *, tolerance: Optional[float] = None,
                       max_iterations: Optional[int] = None, method: Optional[Method] = None,
                       smoothing: Optional[float] = None) -> Derivatives: ...
def distance_cached(shape1: Shape, pose1: ArrayLike, shape2: Shape, pose2: ArrayLike,
                    cache: Cache, *, tolerance: Optional[float] = None,
                    max_iterations: Optional[int] = None, method: Optional[Method] = None,
                    smoothing: Optional[float] = None) -> Distance: ...
def distance_gradient_cached(
    shape1: Shape, pose1: ArrayLike, shape2: Shape, pose2: ArrayLike, cache: Cache, *,
    tolerance: Optional[float] = None, max_iterations: Optional[int] = None,
    method: Optional[Method] = None, smoothing: Optional[float] = None,
) -> Tuple[Distance, np.ndarray]: ...
def intersect_cached(shape1: Shape, pose1: ArrayLike, shape2: Shape, pose2: ArrayLike,
                     cache: Cache, *, tolerance: Optional[float] = None,
                     max_iterations: Optional[int] = None, method: Optional[Method] = None,
                     smoothing: Optional[float] = None) -> bool: ...
def signed_distance(shape1: Shape, pose1: ArrayLike, shape2: Shape, pose2: ArrayLike, *,
                    tolerance: Optional[float] = None, max_iterations: Optional[int] = None,
                    method: Optional[Method] = None,
                    smoothing: Optional[float] = None) -> SignedDistance: ...
def signed_distance_gradient(
    shape1: Shape, pose1: ArrayLike, shape2: Shape, pose2: ArrayLike, *,
    tolerance: Optional[float] = None, max_iterations: Optional[int] = None,
    method: Optional[Method] = None, smoothing: Optional[float] = None,
) -> Tuple[SignedDistance, np.ndarray]: ...
def shape_gradient(
    shape1: Shape, pose1: ArrayLike, shape2: Shape, pose2: ArrayLike, *,
    tolerance: Optional[float] = None, max_iterations: Optional[int] = None,
    method: Optional[Method] = None, smoothing: Optional[float] = None,
) -> Tuple[Proximity, np.ndarray, np.ndarray]: ...
def distance_shape_gradient(
    shape1: Shape, pose1: ArrayLike, shape2: Shape, pose2: ArrayLike, *,
    tolerance: Optional[float] = None, max_iterations: Optional[int] = None,
    method: Optional[Method] = None, smoothing: Optional[float] = None,
) -> Tuple[Distance, np.ndarray, np.ndarray]: ...
def signed_distance_shape_gradient(
    shape1: Shape, pose1: ArrayLike, shape2: Shape, pose2: ArrayLike, *,
    tolerance: Optional[float] = None, max_iterations: Optional[int] = None,
    method: Optional[Method] = None, smoothing: Optional[float] = None,
) -> Tuple[SignedDistance, np.ndarray, np.ndarray]: ...
def contacts(shape1: Shape, pose1: ArrayLike, shape2: Shape, pose2: ArrayLike,
             margin: float = 0.0, max_points: int = 16, *, tolerance: Optional[float] = None,
             max_iterations: Optional[int] = None, method: Optional[Method] = None,
             smoothing: Optional[float] = None) -> list[Contact]: ...
def alpha_below(shape1: Shape, pose1: ArrayLike, shape2: Shape, pose2: ArrayLike,
                threshold: float, *, tolerance: Optional[float] = None,
                max_iterations: Optional[int] = None, method: Optional[Method] = None,
                smoothing: Optional[float] = None) -> bool: ...
def intersect(shape1: Shape, pose1: ArrayLike, shape2: Shape, pose2: ArrayLike, *,
              tolerance: Optional[float] = None, max_iterations: Optional[int] = None,
              method: Optional[Method] = None, smoothing: Optional[float] = None) -> bool: ...
def alpha_bounds(shape1: Shape, pose1: ArrayLike, shape2: Shape,
                 pose2: ArrayLike) -> Tuple[float, float]: ...

Shapes = Union[Shape, Sequence[Shape]]

def proximity_batch(shapes1: Shapes, poses1: ArrayLike, shapes2: Shapes, poses2: ArrayLike, *,
                    threads: Optional[int] = None, **options) -> Tuple[np.ndarray, ...]: ...
def gradient_batch(shapes1: Shapes, poses1: ArrayLike, shapes2: Shapes, poses2: ArrayLike, *,
                   threads: Optional[int] = None, **options) -> Tuple[np.ndarray, ...]: ...
def distance_batch(shapes1: Shapes, poses1: ArrayLike, shapes2: Shapes, poses2: ArrayLike, *,
                   threads: Optional[int] = None, **options) -> Tuple[np.ndarray, ...]: ...

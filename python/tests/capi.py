"""The C ABI (``include/dcol.h``) through ctypes: the independent path the Python bindings are
checked against.

The library is ``$DCOL_C_LIBRARY`` when set (``scripts/test.sh`` points it at the
``libdcol.so`` its CMake build made); otherwise the Python extension module itself, which
exports the same ``dcol_*`` functions (they are compiled into it with the Rust crate, and
unlike the bindings they read ``dcol_shape`` handles, ``dcol_pose`` structs and
``dcol_options``, and format their messages at the C boundary).
"""

import ctypes as C
import os

import numpy as np

import dcol

d3 = C.c_double * 3


class Pose(C.Structure):
    _fields_ = [("position", C.c_double * 3), ("quaternion", C.c_double * 4)]


class Options(C.Structure):
    _fields_ = [
        ("tolerance", C.c_double),
        ("max_iterations", C.c_uint32),
        ("method", C.c_uint32),
        ("smoothing", C.c_double),
    ]


class ProximityResult(C.Structure):
    _fields_ = [
        ("alpha", C.c_double),
        ("point", d3),
        ("contact1", d3),
        ("contact2", d3),
        ("iterations", C.c_uint32),
        ("solver", C.c_uint32),
        ("derivatives", C.c_uint32),
    ]


class DistanceResult(C.Structure):
    _fields_ = [
        ("distance", C.c_double),
        ("closest1", d3),
        ("closest2", d3),
        ("iterations", C.c_uint32),
        ("normal", d3),
    ]


class SignedDistanceResult(C.Structure):
    _fields_ = [
        ("distance", C.c_double),
        ("normal", d3),
        ("closest1", d3),
        ("closest2", d3),
        ("iterations", C.c_uint32),
    ]


class Contact(C.Structure):
    _fields_ = [("position", d3), ("normal", d3), ("depth", C.c_double)]


class DerivativesResult(C.Structure):
    _fields_ = [
        ("proximity", ProximityResult),
        ("gradient", C.c_double * 14),
        ("jacobian", (C.c_double * 14) * 4),
        ("contact_jacobian1", (C.c_double * 14) * 3),
        ("contact_jacobian2", (C.c_double * 14) * 3),
    ]


SOLVERS = {0: "interior_point", 1: "ray_cast", 2: "polish", 3: "closed_form"}
DERIVATIVES = {0: "none", 1: "exact", 2: "smoothed", 3: "subgradient"}

P = C.POINTER
dp = P(C.c_double)
sp = C.c_void_p


def library_path():
    return os.environ.get("DCOL_C_LIBRARY") or dcol._dcol.__file__


def load():
    lib = C.CDLL(library_path())
    ret = C.c_int
    sigs = {
        "dcol_shape_new_sphere": [C.c_double, P(sp)],
        "dcol_shape_new_ellipsoid": [dp, P(sp)],
        "dcol_shape_new_polytope": [dp, dp, C.c_size_t, P(sp)],
        "dcol_shape_new_box": [C.c_double, C.c_double, C.c_double, P(sp)],
        "dcol_shape_new_capsule": [C.c_double, C.c_double, P(sp)],
        "dcol_shape_new_cylinder": [C.c_double, C.c_double, P(sp)],
        "dcol_shape_new_cone": [C.c_double, C.c_double, P(sp)],
        "dcol_shape_new_polygon": [dp, dp, C.c_size_t, C.c_double, P(sp)],
        "dcol_shape_new_convex_hull": [dp, C.c_size_t, C.c_double, P(sp)],
        "dcol_shape_new_halfspace": [C.c_double, P(sp)],
    }
    pair = [sp, P(Pose), sp, P(Pose)]
    sigs.update(
        {
            "dcol_proximity": pair + [P(Options), P(ProximityResult)],
            "dcol_gradient": pair + [P(Options), P(ProximityResult), dp],
            "dcol_jacobian": pair + [P(Options), P(ProximityResult), dp],
            "dcol_derivatives": pair + [P(Options), P(DerivativesResult)],
            "dcol_distance": pair + [P(Options), P(DistanceResult)],
            "dcol_distance_gradient": pair + [P(Options), P(DistanceResult), dp],
            "dcol_signed_distance": pair + [P(Options), P(SignedDistanceResult)],
            "dcol_signed_distance_gradient": pair + [P(Options), P(SignedDistanceResult), dp],
            "dcol_shape_gradient": pair + [P(Options), P(ProximityResult), dp, dp],
            "dcol_distance_shape_gradient": pair + [P(Options), P(DistanceResult), dp, dp],
            "dcol_signed_distance_shape_gradient": pair
            + [P(Options), P(SignedDistanceResult), dp, dp],
            "dcol_shape_parameters": [sp, dp, C.c_size_t],
            "dcol_contacts": pair
            + [C.c_double, P(Options), P(Contact), C.c_size_t, P(C.c_size_t)],
            "dcol_alpha_below": pair + [C.c_double, P(Options), P(C.c_int32)],
            "dcol_intersect": pair + [P(Options), P(C.c_int32)],
            "dcol_proximity_batch": [
                P(sp),
                P(Pose),
                P(sp),
                P(Pose),
                C.c_size_t,
                P(Options),
                C.c_uint32,
                P(ProximityResult),
                P(C.c_int),
            ],
        }
    )
    for name, args in sigs.items():
        f = getattr(lib, name)
        f.argtypes = args
        f.restype = ret
    lib.dcol_shape_parameter_count.argtypes = [sp]
    lib.dcol_shape_parameter_count.restype = C.c_size_t
    lib.dcol_shape_free.argtypes = [sp]
    lib.dcol_shape_free.restype = None
    lib.dcol_last_error_message.argtypes = []
    lib.dcol_last_error_message.restype = C.c_char_p
    lib.dcol_options_default.argtypes = []
    lib.dcol_options_default.restype = Options
    return lib


class CApi:
    """Calls the C functions with the same inputs the Python functions take."""

    def __init__(self):
        self.lib = load()
        self._shapes = {}

    def message(self):
        return self.lib.dcol_last_error_message().decode()

    def new_shape(self, spec):
        """A dcol_shape from ``(constructor name, args)``; returns (status, handle, message)."""
        kind, args = spec
        out = sp()
        arr = lambda a: np.ascontiguousarray(a, dtype=np.float64)  # noqa: E731
        keep = []

        def ptr(a):
            a = arr(a)
            keep.append(a)
            return a.ctypes.data_as(dp)

        f = getattr(self.lib, "dcol_shape_new_" + kind)
        if kind == "ellipsoid":
            st = f(ptr(args[0]), C.byref(out))
        elif kind in ("polytope",):
            st = f(ptr(args[0]), ptr(args[1]), len(args[1]), C.byref(out))
        elif kind == "polygon":
            st = f(ptr(args[0]), ptr(args[1]), len(args[1]), args[2], C.byref(out))
        elif kind == "convex_hull":
            st = f(ptr(args[0]), len(args[0]), args[1], C.byref(out))
        else:
            st = f(*args, C.byref(out))
        msg = self.message() if st else ""
        return st, out, msg

    def shape(self, spec):
        key = repr(spec)
        if key not in self._shapes:
            st, h, msg = self.new_shape(spec)
            assert st == 0, msg
            self._shapes[key] = h
        return self._shapes[key]

    def close(self):
        for h in self._shapes.values():
            self.lib.dcol_shape_free(h)
        self._shapes.clear()

    @staticmethod
    def pose(p):
        p = [float(v) for v in p]
        return Pose((C.c_double * 3)(*p[:3]), (C.c_double * 4)(*p[3:]))

    def options(self, tolerance=None, max_iterations=None, method=None, smoothing=None):
        o = self.lib.dcol_options_default()
        if tolerance is not None:
            o.tolerance = tolerance
        if max_iterations is not None:
            o.max_iterations = max_iterations
        if method is not None:
            o.method = {"auto": 0, "interior_point": 1}.get(method, method)
        if smoothing is not None:
            o.smoothing = smoothing
        return o

    def call(self, name, spec1, pose1, spec2, pose2, out_types, extra=(), **opts):
        """Status, message and the output structs/arrays of the C function ``name``."""
        outs = [t() for t in out_types]
        o = self.options(**opts)
        args = [self.shape(spec1), C.byref(self.pose(pose1)), self.shape(spec2)]
        args += [C.byref(self.pose(pose2)), *extra, C.byref(o)]
        args += [C.byref(x) if not isinstance(x, C.Array) else x for x in outs]
        st = getattr(self.lib, name)(*args)
        return st, (self.message() if st else ""), outs


def v(a):
    return np.array(list(a), dtype=np.float64)


def m(a):
    return np.array([list(r) for r in a], dtype=np.float64)

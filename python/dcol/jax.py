"""dcol in JAX: α* as a differentiable function of both poses.

``dcol.jax.alpha(shape1, pose1, shape2, pose2)`` is α* of the two posed shapes, usable under
``jax.grad``, ``jax.jit`` and ``jax.vmap``:

- its derivative is dcol's own gradient ∂α*/∂(r1, q1, r2, q2) (a ``jax.custom_vjp``: the
  forward pass calls ``dcol.gradient`` and keeps the 14 numbers, the backward pass scales
  them), so ``jax.grad`` gives exactly ``dcol.gradient``'s numbers;
- it runs on the host through ``jax.pure_callback``; under ``jax.vmap`` the callback receives
  the whole batch and calls ``dcol.proximity_batch`` (``dcol.gradient_batch`` when
  differentiating), which runs without the GIL on dcol's thread pool.

Shapes are static (not traced): vmap over poses, not over shapes. Poses are 7-vectors
``[x, y, z, qw, qx, qy, qz]``; double precision needs ``jax.config.update("jax_enable_x64",
True)`` (without it JAX hands float32 poses over, and the answer comes back as float32).
Options are keyword arguments, as everywhere in dcol. A pair dcol rejects (a NaN pose, two
half-spaces) or whose solve does not converge raises ``dcol.Error`` from the callback (JAX may
wrap it in its own runtime error, with dcol's message in the text).
"""

import functools
from typing import NamedTuple, Optional

import jax
import jax.numpy as jnp
import numpy as np

from . import _dcol
from ._errors import Error, Status

__all__ = ["alpha"]


class _Options(NamedTuple):
    tolerance: Optional[float]
    max_iterations: Optional[int]
    method: Optional[object]
    smoothing: Optional[float]

    def kwargs(self):
        return {k: v for k, v in self._asdict().items() if v is not None}


def alpha(shape1, pose1, shape2, pose2, *, tolerance=None, max_iterations=None, method=None,
          smoothing=None):
    """α* of ``shape1`` at ``pose1`` and ``shape2`` at ``pose2`` (7-vectors), differentiable
    with respect to both poses; see the module's documentation."""
    opts = _Options(tolerance, max_iterations, method, smoothing)
    return _alpha(shape1, shape2, opts, pose1, pose2)


def _check(status, func):
    bad = np.flatnonzero(status)
    if bad.size:
        i = int(bad[0])
        raise Error(
            f"{func}: pair {i} of {status.size} (and {bad.size - 1} more) failed with status "
            f"{int(status[i])} ({Status(int(status[i])).name}); call dcol.proximity on it for "
            f"the reason",
            int(status[i]),
        )


def _host(shape1, shape2, opts, want_gradient, dtype):
    """The callback: α* (and the gradient) of poses with any leading batch dimensions."""
    kw = opts.kwargs()

    def run(p1, p2):
        p1 = np.asarray(p1, dtype=np.float64)
        p2 = np.asarray(p2, dtype=np.float64)
        batch = np.broadcast_shapes(p1.shape[:-1], p2.shape[:-1])
        if batch == ():
            if want_gradient:
                r, g = _dcol.gradient(shape1, p1, shape2, p2, **kw)
                return np.asarray(r.alpha, dtype), np.asarray(g, dtype)
            r = _dcol.proximity(shape1, p1, shape2, p2, **kw)
            return np.asarray(r.alpha, dtype)
        n = int(np.prod(batch))
        q1 = np.broadcast_to(p1, batch + (7,)).reshape(n, 7)
        q2 = np.broadcast_to(p2, batch + (7,)).reshape(n, 7)
        if want_gradient:
            a, _, _, _, g, status = _dcol.gradient_batch(shape1, q1, shape2, q2, **kw)
            _check(status, "dcol.gradient_batch")
            return a.reshape(batch).astype(dtype), g.reshape(batch + (14,)).astype(dtype)
        a, _, _, _, status = _dcol.proximity_batch(shape1, q1, shape2, q2, **kw)
        _check(status, "dcol.proximity_batch")
        return a.reshape(batch).astype(dtype)

    return run


def _call(shape1, shape2, opts, pose1, pose2, want_gradient):
    pose1 = jnp.asarray(pose1)
    pose2 = jnp.asarray(pose2)
    dtype = jnp.result_type(pose1.dtype, pose2.dtype)
    if not jnp.issubdtype(dtype, jnp.floating):
        dtype = jnp.result_type(float)
    for name, p in (("pose1", pose1), ("pose2", pose2)):
        if p.shape != (7,):
            raise ValueError(
                f"{name} must be a pose, 7 numbers [x, y, z, qw, qx, qy, qz], got an array of "
                f"shape {p.shape} (use jax.vmap for batches)"
            )
    pose1 = pose1.astype(dtype)
    pose2 = pose2.astype(dtype)
    out = jax.ShapeDtypeStruct((), dtype)
    if want_gradient:
        out = (out, jax.ShapeDtypeStruct((14,), dtype))
    host = _host(shape1, shape2, opts, want_gradient, np.dtype(dtype))
    return jax.pure_callback(host, out, pose1, pose2, vmap_method="broadcast_all")


@functools.partial(jax.custom_vjp, nondiff_argnums=(0, 1, 2))
def _alpha(shape1, shape2, opts, pose1, pose2):
    return _call(shape1, shape2, opts, pose1, pose2, want_gradient=False)


def _alpha_fwd(shape1, shape2, opts, pose1, pose2):
    a, g = _call(shape1, shape2, opts, pose1, pose2, want_gradient=True)
    return a, g


def _alpha_bwd(shape1, shape2, opts, g, ct):
    return (ct * g[:7], ct * g[7:])


_alpha.defvjp(_alpha_fwd, _alpha_bwd)

"""dcol.jax: jax.grad of dcol.jax.alpha against dcol.gradient (to 1e-12; the same numbers),
jax.vmap through the batch, jax.jit, errors.

Skipped (and reported as skipped) only when JAX is not installed; with DCOL_REQUIRE_JAX=1 (set
by scripts/test.sh, which installs the jax extra) a missing JAX fails instead."""

import os

import numpy as np
import pytest

if os.environ.get("DCOL_REQUIRE_JAX") == "1":
    import jax
else:
    jax = pytest.importorskip("jax")

import jax.numpy as jnp  # noqa: E402

import dcol  # noqa: E402
import dcol.jax as dj  # noqa: E402
from helpers import HALFSPACE, ZOO, cases, make, pose_of, random_pose, spec_of  # noqa: E402

jax.config.update("jax_enable_x64", True)

GRAD_TOL = 1e-12


def configurations():
    out = []
    # Every fourth reference case (eager jax.grad costs tens of milliseconds a call).
    for cid, c in cases()[::4]:
        if c["dalpha_dconfig"] is not None:
            out.append((cid, make(spec_of(c["shape1"])), pose_of(c["pose1"]),
                        make(spec_of(c["shape2"])), pose_of(c["pose2"])))
    rng = np.random.default_rng(99)
    shapes = [make(s) for s in ZOO]
    for i, a in enumerate(shapes):
        for j, b in enumerate(shapes):
            out.append((f"zoo-{i}-{j}", a, random_pose(rng), b, random_pose(rng)))
        out.append((f"zoo-{i}-half", a, random_pose(rng), make(HALFSPACE), random_pose(rng)))
    return out


CONFIGS = configurations()
grad_both = jax.grad(dj.alpha, argnums=(1, 3))


def test_alpha_and_grad_equal_dcol():
    worst = 0.0
    for cid, a, p1, b, p2 in CONFIGS:
        r, g = dcol.gradient(a, p1, b, p2)
        assert float(dj.alpha(a, jnp.asarray(p1), b, jnp.asarray(p2))) == r.alpha, cid
        g1, g2 = grad_both(a, jnp.asarray(p1, dtype=jnp.float64), b,
                           jnp.asarray(p2, dtype=jnp.float64))
        err = np.max(np.abs(np.concatenate([np.asarray(g1), np.asarray(g2)]) - g))
        worst = max(worst, err)
        assert err <= GRAD_TOL, f"{cid}: |jax.grad - dcol.gradient| = {err:.2e}"
    print(f"\n{len(CONFIGS)} configurations: max |jax.grad - dcol.gradient| = {worst:.1e}")


def test_grad_under_jit_and_value_and_grad():
    cid, a, p1, b, p2 = CONFIGS[0]
    f = jax.jit(jax.value_and_grad(dj.alpha, argnums=(1, 3)), static_argnums=(0, 2))
    val, (g1, g2) = f(a, jnp.asarray(p1), b, jnp.asarray(p2))
    r, g = dcol.gradient(a, p1, b, p2)
    assert float(val) == r.alpha
    assert np.max(np.abs(np.concatenate([g1, g2]) - g)) <= GRAD_TOL


def test_chain_rule_through_a_function_of_the_poses():
    # alpha(pose2(t)) with pose2 moving along a direction: d/dt = grad . direction.
    cid, a, p1, b, p2 = CONFIGS[5]
    d = jnp.asarray(np.random.default_rng(1).normal(size=7))

    def f(t):
        return dj.alpha(a, jnp.asarray(p1), b, jnp.asarray(p2) + t * d)

    _, g = dcol.gradient(a, p1, b, p2)
    assert abs(float(jax.grad(f)(0.0)) - float(np.dot(g[7:], d))) <= GRAD_TOL


def test_options_pass_through():
    cid, a, p1, b, p2 = CONFIGS[10]
    for opts in ({"smoothing": 1e-3}, {"method": "interior_point", "tolerance": 1e-8}):
        r, g = dcol.gradient(a, p1, b, p2, **opts)
        assert float(dj.alpha(a, jnp.asarray(p1), b, jnp.asarray(p2), **opts)) == r.alpha
        g1, g2 = jax.grad(lambda x, y: dj.alpha(a, x, b, y, **opts), argnums=(0, 1))(
            jnp.asarray(p1), jnp.asarray(p2))
        assert np.max(np.abs(np.concatenate([g1, g2]) - g)) <= GRAD_TOL


def test_vmap_goes_through_the_batch(monkeypatch):
    rng = np.random.default_rng(5)
    a, b = make(ZOO[1]), make(ZOO[6])
    p1 = random_pose(rng)
    P2 = np.stack([random_pose(rng) for _ in range(64)])
    calls = []
    for name in ("proximity_batch", "gradient_batch"):
        real = getattr(dcol._dcol, name)

        def spy(*args, _real=real, _name=name, **kw):
            calls.append((_name, len(args[1])))
            return _real(*args, **kw)

        monkeypatch.setattr(dcol._dcol, name, spy)
    alphas = jax.vmap(dj.alpha, in_axes=(None, None, None, 0))(a, jnp.asarray(p1), b,
                                                               jnp.asarray(P2))
    assert calls == [("proximity_batch", 64)]
    calls.clear()
    grads = jax.vmap(jax.grad(dj.alpha, argnums=3), in_axes=(None, None, None, 0))(
        a, jnp.asarray(p1), b, jnp.asarray(P2))
    assert calls == [("gradient_batch", 64)]
    monkeypatch.undo()
    ref = dcol.proximity_batch(a, p1, b, P2)
    assert np.array_equal(np.asarray(alphas), ref.alpha)
    refg = dcol.gradient_batch(a, p1, b, P2)
    assert np.max(np.abs(np.asarray(grads) - refg.gradient[:, 7:])) <= GRAD_TOL
    for i in range(0, 64, 9):
        _, g = dcol.gradient(a, p1, b, P2[i])
        assert np.array_equal(np.asarray(grads[i]), g[7:])


def test_vmap_over_both_poses():
    rng = np.random.default_rng(6)
    a, b = make(ZOO[0]), make(ZOO[4])
    P1 = np.stack([random_pose(rng) for _ in range(10)])
    P2 = np.stack([random_pose(rng) for _ in range(10)])
    g1, g2 = jax.vmap(grad_both, in_axes=(None, 0, None, 0))(a, jnp.asarray(P1), b,
                                                              jnp.asarray(P2))
    for i in range(10):
        _, g = dcol.gradient(a, P1[i], b, P2[i])
        assert np.array_equal(np.concatenate([g1[i], g2[i]]), g)


def test_errors_are_raised():
    cid, a, p1, b, p2 = CONFIGS[0]
    bad = np.array(p2, dtype=float)
    bad[1] = np.nan
    with pytest.raises(Exception, match=r"pose2->position\[1\]` = NaN: must be finite"):
        jax.block_until_ready(dj.alpha(a, jnp.asarray(p1), b, jnp.asarray(bad)))
    with pytest.raises(Exception, match="status 3"):
        P2 = jnp.asarray(np.stack([p2, bad]))
        jax.block_until_ready(jax.vmap(dj.alpha, in_axes=(None, None, None, 0))(
            a, jnp.asarray(p1), b, P2))
    with pytest.raises(ValueError, match="7 numbers"):
        dj.alpha(a, jnp.zeros(6), b, jnp.asarray(p2))
    with pytest.raises(Exception, match="options->tolerance"):
        jax.block_until_ready(dj.alpha(a, jnp.asarray(p1), b, jnp.asarray(p2), tolerance=-1.0))

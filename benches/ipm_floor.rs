// Development aid (the speed bar of `docs/performance-notes.md`): how fast can the solver's algorithm run at best?
// This is the same Nesterov–Todd / Mehrotra predictor-corrector iteration as `solver::Problem`
// (same start, centring, step rule and tolerance), specialised by hand to exactly two
// 4-dimensional cones and four variables (the sphere–sphere problem in proximity's normalised
// frame) and written on locals: no orthant rows, no runtime block counts, no refinement, no
// polish, no residual tests beyond the gap, no problem assembly. Its time per solve is a floor
// for a scalar implementation of the method on the cheapest pair; `dcol::proximity` on the
// same pairs is timed in the same run for the ratio. The cone algebra and the `L D Lᵀ` factor
// are written here again, without the library's checks (finite scaling, weak pivots): built
// from `solver::cones` and `solver::kkt` instead, the floor is 7–10% slower
// (2.62 against 2.37–2.43 µs).
//
//     cargo bench --bench ipm_floor
// Index loops over fixed sizes and NaN-aware negated comparisons, as in the solver itself.
#![allow(clippy::needless_range_loop, clippy::neg_cmp_op_on_partial_ord)]
use std::hint::black_box;
use std::time::Instant;

type V = [f64; 4];
type M = [[f64; 4]; 4];

/// `uᵀ J v`, `J = diag(1, −1, −1, −1)`.
#[inline(always)]
fn jdot(u: &V, v: &V) -> f64 {
    u[0] * v[0] - u[1] * v[1] - u[2] * v[2] - u[3] * v[3]
}
/// `uᵀ v`.
#[inline(always)]
fn dot(u: &V, v: &V) -> f64 {
    u[0] * v[0] + u[1] * v[1] + u[2] * v[2] + u[3] * v[3]
}
/// `G z` for one cone's rows.
#[inline(always)]
fn gmul(g: &M, z: &V) -> V {
    [dot(&g[0], z), dot(&g[1], z), dot(&g[2], z), dot(&g[3], z)]
}
/// `Gᵀ u` for one cone's rows.
#[inline(always)]
fn gtmul(g: &M, u: &V) -> V {
    let mut r = [0.0; 4];
    for i in 0..4 {
        r[i] = g[0][i] * u[0] + g[1][i] * u[1] + g[2][i] * u[2] + g[3][i] * u[3];
    }
    r
}

/// One cone's Nesterov–Todd scaling with the reciprocals an iteration needs (the fields of
/// `cones::SocScaling` and its two step bases: `i…` are reciprocals).
#[derive(Clone, Copy)]
struct Sc {
    w: V,
    ie: f64,
    e: f64,
    ie2: f64,
    i1pw0: f64,
    v: V,
    ivdet: f64,
    iv0: f64,
    sb: V,
    isn: f64,
    isb1: f64,
    lb: V,
    iln: f64,
    ilb1: f64,
}

/// The NT scaling of interior `s`, `l` (`None` if either is not interior).
#[inline(always)]
fn scaling(s: &V, l: &V) -> Option<Sc> {
    let sn2 = jdot(s, s);
    let ln2 = jdot(l, l);
    if !(sn2 > 0.0 && ln2 > 0.0 && s[0] > 0.0 && l[0] > 0.0) {
        return None;
    }
    let sn = sn2.sqrt();
    let ln = ln2.sqrt();
    let (isn, iln) = (1.0 / sn, 1.0 / ln);
    let sb = [s[0] * isn, s[1] * isn, s[2] * isn, s[3] * isn];
    let lb = [l[0] * iln, l[1] * iln, l[2] * iln, l[3] * iln];
    let gamma = ((1.0 + dot(&sb, &lb)) * 0.5).sqrt();
    let i2g = 0.5 / gamma;
    let w = [
        (sb[0] + lb[0]) * i2g,
        (sb[1] - lb[1]) * i2g,
        (sb[2] - lb[2]) * i2g,
        (sb[3] - lb[3]) * i2g,
    ];
    let e = (sn * iln).sqrt();
    let ie = 1.0 / e;
    let mut sc = Sc {
        w,
        ie,
        e,
        ie2: ie * ie,
        i1pw0: 1.0 / (1.0 + w[0]),
        v: [0.0; 4],
        ivdet: isn * iln,
        iv0: ie * iln * 2.0 * i2g,
        sb,
        isn,
        isb1: 1.0 / (sb[0] + 1.0),
        lb,
        iln,
        ilb1: 1.0 / (lb[0] + 1.0),
    };
    sc.v = apply(&sc, l, 1.0, e);
    Some(sc)
}

/// `W u` (`sign` 1, `k` = η) or `W⁻¹ u` (`sign` −1, `k` = 1/η).
#[inline(always)]
fn apply(sc: &Sc, u: &V, sign: f64, k: f64) -> V {
    let w = &sc.w;
    let w1u1 = w[1] * u[1] + w[2] * u[2] + w[3] * u[3];
    let c = sign * u[0] + w1u1 * sc.i1pw0;
    [
        k * (w[0] * u[0] + sign * w1u1),
        k * (u[1] + c * w[1]),
        k * (u[2] + c * w[2]),
        k * (u[3] + c * w[3]),
    ]
}
/// `W⁻² u`.
#[inline(always)]
fn inv_sq(sc: &Sc, u: &V) -> V {
    let e2 = sc.ie2;
    let wju = jdot(&sc.w, u);
    [
        e2 * (2.0 * sc.w[0] * wju - u[0]),
        e2 * (-2.0 * sc.w[1] * wju + u[1]),
        e2 * (-2.0 * sc.w[2] * wju + u[2]),
        e2 * (-2.0 * sc.w[3] * wju + u[3]),
    ]
}
/// The rate at which `u + t du` approaches the cone's boundary, from `ū = u/√(uᵀJu)`.
#[inline(always)]
fn rate(ub: &V, inv_n: f64, inv_ub0p1: f64, du: &V) -> f64 {
    let ub_du = jdot(ub, du);
    let rho0 = ub_du * inv_n;
    let f = (ub_du + du[0]) * inv_ub0p1;
    let a = du[1] - f * ub[1];
    let b = du[2] - f * ub[2];
    let c = du[3] - f * ub[3];
    (a * a + b * b + c * c).sqrt() * inv_n - rho0
}
/// Solves `v ∘ u = r` for `u`.
#[inline(always)]
fn vsolve(sc: &Sc, r: &V) -> V {
    let v = &sc.v;
    let vr = v[1] * r[1] + v[2] * r[2] + v[3] * r[3];
    let u0 = (v[0] * r[0] - vr) * sc.ivdet;
    [
        u0,
        (r[1] - u0 * v[1]) * sc.iv0,
        (r[2] - u0 * v[2]) * sc.iv0,
        (r[3] - u0 * v[3]) * sc.iv0,
    ]
}

/// `H = L D Lᵀ` with `1/D` kept.
struct Ldl {
    l: M,
    id: V,
}
/// Factors `H` (lower triangle), raising pivots below `1e-14 H_jj`.
#[inline(always)]
fn factor(h: &M) -> Ldl {
    let mut l = [[0.0; 4]; 4];
    let mut d = [0.0; 4];
    let mut id = [0.0; 4];
    for j in 0..4 {
        let mut dj = h[j][j];
        for k in 0..j {
            dj -= l[j][k] * l[j][k] * d[k];
        }
        let fl = 1e-14 * h[j][j];
        if !(dj > fl) {
            dj = fl;
        }
        d[j] = dj;
        id[j] = 1.0 / dj;
        for i in (j + 1)..4 {
            let mut v = h[i][j];
            for k in 0..j {
                v -= l[i][k] * l[j][k] * d[k];
            }
            l[i][j] = v * id[j];
        }
    }
    Ldl { l, id }
}
/// Solves `H x = b` in place.
#[inline(always)]
fn solve(f: &Ldl, b: &mut V) {
    for i in 0..4 {
        for k in 0..i {
            b[i] -= f.l[i][k] * b[k];
        }
    }
    for i in 0..4 {
        b[i] *= f.id[i];
    }
    for i in (0..4).rev() {
        for k in (i + 1)..4 {
            b[i] -= f.l[k][i] * b[k];
        }
    }
}

/// The cone program `min α s.t. h_k − G_k z ∈ Q₄, k = 0, 1`.
struct Prob {
    g: [M; 2],
    h: [V; 2],
}

/// `ds`, `dλ` of both cones from `dz` (plus the corrector's extra `dλ` term), and the rate at
/// which the direction approaches the cones' boundaries (the step to it is `1/rate`).
#[inline(always)]
fn directions(
    p: &Prob,
    sc: &[Sc; 2],
    rp: &[V; 2],
    s: &[V; 2],
    dz: &V,
    extra: &[V; 2],
) -> ([V; 2], [V; 2], f64) {
    let mut ds = [[0.0; 4]; 2];
    let mut dl = [[0.0; 4]; 2];
    let mut rate_m: f64 = 0.0;
    for k in 0..2 {
        let gdz = gmul(&p.g[k], dz);
        let mut gt = [0.0; 4];
        for i in 0..4 {
            gt[i] = gdz[i] + rp[k][i] - s[k][i];
            ds[k][i] = -rp[k][i] - gdz[i];
        }
        let d = inv_sq(&sc[k], &gt);
        for i in 0..4 {
            dl[k][i] = d[i] + extra[k][i];
        }
        rate_m = rate_m
            .max(rate(&sc[k].sb, sc[k].isn, sc[k].isb1, &ds[k]))
            .max(rate(&sc[k].lb, sc[k].iln, sc[k].ilb1, &dl[k]));
    }
    (ds, dl, rate_m)
}

/// Solves `p` from `z0` with the dual started at `mu0 · s⁻¹`; returns `z` and the iterations.
fn solve_prob(p: &Prob, z0: V, mu0: f64, tol: f64) -> (V, u32) {
    let c = [0.0, 0.0, 0.0, 1.0];
    let mut z = z0;
    let mut s = [[0.0; 4]; 2];
    let mut l = [[0.0; 4]; 2];
    let mut gjg = [[[0.0; 4]; 4]; 2];
    for k in 0..2 {
        let gz = gmul(&p.g[k], &z);
        for i in 0..4 {
            s[k][i] = p.h[k][i] - gz[i];
        }
        let sn2 = jdot(&s[k], &s[k]);
        l[k] = [
            mu0 * s[k][0] / sn2,
            -mu0 * s[k][1] / sn2,
            -mu0 * s[k][2] / sn2,
            -mu0 * s[k][3] / sn2,
        ];
        for i in 0..4 {
            for j in 0..4 {
                gjg[k][i][j] = p.g[k][0][i] * p.g[k][0][j]
                    - p.g[k][1][i] * p.g[k][1][j]
                    - p.g[k][2][i] * p.g[k][2][j]
                    - p.g[k][3][i] * p.g[k][3][j];
            }
        }
    }
    let mut it = 0;
    loop {
        let mut rd = c;
        let mut gap = 0.0;
        let mut rp = [[0.0; 4]; 2];
        let mut h = [[0.0; 4]; 4];
        let mut rhs = [0.0; 4];
        let mut sc = [None; 2];
        for k in 0..2 {
            let a = gtmul(&p.g[k], &l[k]);
            for i in 0..4 {
                rd[i] += a[i];
            }
            let gz = gmul(&p.g[k], &z);
            for i in 0..4 {
                rp[k][i] = gz[i] + s[k][i] - p.h[k][i];
            }
            gap += dot(&s[k], &l[k]);
            let scv = match scaling(&s[k], &l[k]) {
                Some(v) => v,
                None => return (z, it),
            };
            let jw = [scv.w[0], -scv.w[1], -scv.w[2], -scv.w[3]];
            let a = gtmul(&p.g[k], &jw);
            let e2 = scv.ie2;
            for i in 0..4 {
                for j in 0..=i {
                    h[i][j] += 2.0 * e2 * a[i] * a[j] - e2 * gjg[k][i][j];
                }
            }
            let t = [
                rp[k][0] - s[k][0],
                rp[k][1] - s[k][1],
                rp[k][2] - s[k][2],
                rp[k][3] - s[k][3],
            ];
            let u = gtmul(&p.g[k], &inv_sq(&scv, &t));
            for i in 0..4 {
                rhs[i] -= u[i];
            }
            sc[k] = Some(scv);
        }
        for i in 0..4 {
            rhs[i] -= rd[i];
        }
        if gap <= tol * z[3].abs().max(1.0) || it >= 50 {
            return (z, it);
        }
        let sc = [sc[0].unwrap(), sc[1].unwrap()];
        let f = factor(&h);
        // predictor
        let mut dz = rhs;
        solve(&f, &mut dz);
        let (ds, dl, rate_m) = directions(p, &sc, &rp, &s, &dz, &[[0.0; 4]; 2]);
        let (mut s1, mut s2) = (0.0, 0.0);
        for k in 0..2 {
            s1 += dot(&s[k], &dl[k]) + dot(&l[k], &ds[k]);
            s2 += dot(&ds[k], &dl[k]);
        }
        let t_aff = if rate_m > 1.0 { 1.0 / rate_m } else { 1.0 };
        let mu = gap / 2.0;
        let gap_aff = gap + t_aff * (s1 + t_aff * s2);
        let ratio = (gap_aff / gap).clamp(0.0, 1.0);
        let sm = ratio * ratio * ratio * mu;
        let mut rhs2 = rhs;
        let mut us = [[0.0; 4]; 2];
        for k in 0..2 {
            let a = apply(&sc[k], &ds[k], -1.0, sc[k].ie);
            let b = apply(&sc[k], &dl[k], 1.0, sc[k].e);
            let mut r = [
                -dot(&a, &b),
                -(a[0] * b[1] + b[0] * a[1]),
                -(a[0] * b[2] + b[0] * a[2]),
                -(a[0] * b[3] + b[0] * a[3]),
            ];
            r[0] += sm;
            let u = apply(&sc[k], &vsolve(&sc[k], &r), -1.0, sc[k].ie);
            let gu = gtmul(&p.g[k], &u);
            for i in 0..4 {
                rhs2[i] -= gu[i];
            }
            us[k] = u;
        }
        let mut dz = rhs2;
        solve(&f, &mut dz);
        let (ds, dl, rate_m) = directions(p, &sc, &rp, &s, &dz, &us);
        let t = (0.99 / rate_m).min(1.0);
        for i in 0..4 {
            z[i] += t * dz[i];
        }
        for k in 0..2 {
            for i in 0..4 {
                s[k][i] += t * ds[k][i];
                l[k][i] += t * dl[k][i];
            }
        }
        it += 1;
    }
}

fn main() {
    // Random sphere pairs; the cone program is built in proximity's normalised frame (lengths
    // over the larger radius, offset stretched to the sum of the radii, so α' = 1).
    let mut seed = 12345u64;
    let mut rnd = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    // A fixed rotation: the body axes enter G as in `Placement::fill`.
    let q: [[f64; 3]; 3] = [[0.36, 0.48, -0.8], [-0.8, 0.6, 0.0], [0.48, 0.64, 0.6]];
    let quat = [0.8, 0.4 * 0.8, 0.0, 0.4 * 0.6]; // any unit quaternion will do for spheres
    let mut probs = Vec::new();
    let mut world = Vec::new();
    for _ in 0..200 {
        let (rw1, rw2) = (0.5 + rnd(), 0.5 + rnd());
        let ell = rw1.max(rw2);
        let (r1, r2) = (rw1 / ell, rw2 / ell);
        let kappa = r1 + r2;
        let mut d = [rnd() - 0.5, rnd() - 0.5, rnd() - 0.5];
        let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        let dist = (0.3 + 1.4 * rnd()) * (rw1 + rw2);
        let dw = [d[0] / n * dist, d[1] / n * dist, d[2] / n * dist];
        for v in d.iter_mut() {
            *v *= kappa / n;
        }
        let mut g = [[[0.0; 4]; 4]; 2];
        let mut h = [[0.0; 4]; 2];
        for (k, (rad, c)) in [(r1, [0.0; 3]), (r2, d)].into_iter().enumerate() {
            g[k][0][3] = -rad;
            for i in 0..3 {
                let qf = [q[0][i], q[1][i], q[2][i]];
                g[k][i + 1][0] = -qf[0];
                g[k][i + 1][1] = -qf[1];
                g[k][i + 1][2] = -qf[2];
                h[k][i + 1] = -(qf[0] * c[0] + qf[1] * c[1] + qf[2] * c[2]);
            }
        }
        // proximity's start: α' = 1.2 × the inscribed bound, μ₀ = 10 (α' − 1)/degree.
        let xi = [d[0] * r1 / kappa, d[1] * r1 / kappa, d[2] * r1 / kappa];
        probs.push((Prob { g, h }, [xi[0], xi[1], xi[2], 1.2], 1.0));
        world.push((
            dcol::Shape::sphere(rw1).unwrap(),
            dcol::Pose::new([0.0; 3], quat).unwrap(),
            dcol::Shape::sphere(rw2).unwrap(),
            dcol::Pose::new(dw, quat).unwrap(),
            dist / (rw1 + rw2),
        ));
    }
    let (mut its, mut lib_its) = (0, 0);
    let (mut err, mut lib_err): (f64, f64) = (0.0, 0.0);
    let opts = dcol::Options::default();
    for ((p, z0, mu0), (s1, p1, s2, p2, alpha)) in probs.iter().zip(&world) {
        let (z, it) = solve_prob(p, *z0, *mu0, opts.tolerance);
        its += it;
        err = err.max((z[3] - 1.0).abs());
        let r = dcol::proximity(s1, p1, s2, p2, &opts).unwrap();
        lib_its += r.iterations;
        lib_err = lib_err.max((r.alpha - alpha).abs() / alpha);
    }
    let n = probs.len() as f64;
    let (mut floor, mut lib) = (Vec::new(), Vec::new());
    // Interleaved, pose by pose, so that machine drift affects both alike.
    for _ in 0..20 {
        for ((p, z0, mu0), (s1, p1, s2, p2, _)) in probs.iter().zip(&world) {
            let st = Instant::now();
            for _ in 0..20 {
                black_box(solve_prob(black_box(p), *z0, *mu0, opts.tolerance));
            }
            floor.push(st.elapsed().as_nanos() as f64 / 20.0);
            let st = Instant::now();
            for _ in 0..20 {
                black_box(dcol::proximity(s1, p1, black_box(s2), p2, &opts).unwrap());
            }
            lib.push(st.elapsed().as_nanos() as f64 / 20.0);
        }
    }
    let median = |v: &mut Vec<f64>| {
        v.sort_by(|a, b| a.partial_cmp(b).unwrap());
        v[v.len() / 2]
    };
    let (mf, ml) = (median(&mut floor), median(&mut lib));
    println!(
        "sphere-sphere, {} pairs, tolerance {:e}",
        probs.len(),
        opts.tolerance
    );
    println!("| solver | median ns | mean iterations | ns per iteration | max alpha rel. error |");
    println!("|---|--:|--:|--:|--:|");
    for (name, m, it, e) in [
        ("hand-specialised floor", mf, its as f64 / n, err),
        ("dcol::proximity", ml, lib_its as f64 / n, lib_err),
    ] {
        println!("| {name} | {m:.0} | {it:.2} | {:.0} | {e:.1e} |", m / it);
    }
    println!("ratio proximity / floor: {:.2}", ml / mf);
}

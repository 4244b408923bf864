//! The generator of `tests/data/`, the reference cases the accuracy tests assert on. It is an
//! ignored test, run by hand (about a minute on two cores):
//!
//! ```text
//! cargo test --release --test generate_reference -- --ignored --nocapture
//! ```
//!
//! It rewrites `tests/data/cases-<kind1>-<kind2>.jsonl` (49 ordered pairs) and
//! `tests/data/cases-stress.jsonl` from fixed seeds, so the files come out the same on every
//! run with the same Clarabel version. Every value comes from the independent oracle of
//! `tests/oracle/mod.rs` (Clarabel on the cone programs of `CONVENTIONS.md`, polished and
//! certified by its KKT conditions), never from dcol; a configuration the oracle cannot
//! certify is redrawn. `tests/data/README.md` describes the records.

#![allow(clippy::needless_range_loop)]

mod oracle;

use oracle::{add, norm, rot, scale, sub, Posed, Spec, KINDS, V3};
use serde_json::{json, Value};
use std::f64::consts::PI;
use std::path::PathBuf;

/// Random cases per ordered pair: two of each category (deep, near, separated).
const PER_PAIR: usize = 6;
/// Of these, the first `WITH_JACOBIAN` (one deep, one near) carry the Jacobian, and so does
/// every other stress case; all carry the gradient. (This keeps the committed set at a few
/// hundred kilobytes.)
const WITH_JACOBIAN: usize = 2;

// ---------------------------------------------------------------------------------------------
// Random numbers (SplitMix64) and rounding: inputs are rounded to a few decimals, so that the
// records hold them exactly in a few characters.

struct Rng(u64);

impl Rng {
    fn unif(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
    fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.unif()
    }
    fn index(&mut self, n: usize) -> usize {
        ((self.unif() * n as f64) as usize).min(n - 1)
    }
    fn normal(&mut self) -> f64 {
        let u1 = self.unif().max(1e-300);
        let u2 = self.unif();
        (-2.0 * u1.ln()).sqrt() * (2.0 * PI * u2).cos()
    }
    fn unit(&mut self) -> V3 {
        loop {
            let v = [self.normal(), self.normal(), self.normal()];
            let n = norm(&v);
            if n > 1e-3 {
                return scale(&v, 1.0 / n);
            }
        }
    }
    fn quat(&mut self) -> [f64; 4] {
        loop {
            let q = [self.normal(), self.normal(), self.normal(), self.normal()];
            let n = q.iter().map(|v| v * v).sum::<f64>().sqrt();
            if n > 1e-3 {
                return q.map(|v| rnd(v / n, 4));
            }
        }
    }
}

/// `v` rounded to `d` decimals.
fn rnd(v: f64, d: i32) -> f64 {
    let k = 10f64.powi(d);
    (v * k).round() / k
}

/// `v` to `d` significant digits (derivatives need 8: far more than their finite-difference
/// accuracy and the tests' 1e-5).
fn sig(v: f64, d: usize) -> f64 {
    format!("{v:.*e}", d - 1).parse().unwrap()
}

// ---------------------------------------------------------------------------------------------
// Random shapes.

fn random_spec(kind: &str, rng: &mut Rng) -> Spec {
    match kind {
        "sphere" => Spec::Sphere {
            r: rnd(rng.range(0.3, 1.0), 3),
        },
        "ellipsoid" => loop {
            let axes = [0; 3].map(|_| rng.range(0.3, 1.0));
            let e = rot(&rng.quat());
            let mut p = [[0.0; 3]; 3];
            for i in 0..3 {
                for j in i..3 {
                    let v: f64 = (0..3)
                        .map(|k| e[i][k] * e[j][k] / (axes[k] * axes[k]))
                        .sum();
                    p[i][j] = rnd(v, 4);
                    p[j][i] = p[i][j];
                }
            }
            let m = nalgebra::Matrix3::from_fn(|i, j| p[i][j]);
            if m.symmetric_eigenvalues().min() > 0.5 {
                break Spec::Ellipsoid { p };
            }
        },
        "polytope" => {
            // A randomly turned tetrahedron's normals (they span positively, so the polytope
            // is bounded) and up to five more random ones.
            let q = rot(&rng.quat());
            let s = 1.0 / 3f64.sqrt();
            let tet = [[s, s, s], [s, -s, -s], [-s, s, -s], [-s, -s, s]];
            let mut a: Vec<V3> = tet
                .iter()
                .map(|t| {
                    let v: V3 = std::array::from_fn(|i| (0..3).map(|j| q[i][j] * t[j]).sum());
                    v.map(|x| rnd(x, 3))
                })
                .collect();
            for _ in 0..2 + rng.index(4) {
                a.push(rng.unit().map(|x| rnd(x, 3)));
            }
            let b = a.iter().map(|_| rnd(rng.range(0.3, 0.8), 3)).collect();
            Spec::Polytope { a, b }
        }
        "capsule" => Spec::Capsule {
            r: rnd(rng.range(0.15, 0.5), 3),
            l: rnd(rng.range(0.3, 1.2), 3),
        },
        "cylinder" => Spec::Cylinder {
            r: rnd(rng.range(0.2, 0.6), 3),
            l: rnd(rng.range(0.3, 1.2), 3),
        },
        "cone" => Spec::Cone {
            h: rnd(rng.range(0.6, 1.5), 3),
            beta: rnd(rng.range(0.25, 1.1), 4),
        },
        "padded_polygon" => {
            let phase = rng.range(0.0, 2.0 * PI);
            let m = 3 + rng.index(4);
            let mut c = Vec::new();
            for k in 0..m {
                // The first three at 120° apart (bounded), the rest anywhere.
                let th = if k < 3 {
                    phase + 2.0 * PI * k as f64 / 3.0
                } else {
                    rng.range(0.0, 2.0 * PI)
                };
                c.push([rnd(th.cos(), 3), rnd(th.sin(), 3)]);
            }
            let d = c.iter().map(|_| rnd(rng.range(0.3, 0.8), 3)).collect();
            Spec::Polygon {
                c,
                d,
                r: rnd(rng.range(0.03, 0.2), 3),
            }
        }
        other => panic!("unknown kind {other}"),
    }
}

fn random_position(rng: &mut Rng) -> V3 {
    [0; 3].map(|_| rnd(rng.range(-1.0, 1.0), 4))
}

/// A pair with the second origin placed so that α* is near `target`: α* is proportional to
/// the offset along a ray, so one solve at unit offset gives the distance to use.
fn place(rng: &mut Rng, s1: Spec, s2: Spec, target: f64) -> Option<(Posed, Posed)> {
    let a = Posed {
        spec: s1,
        r: random_position(rng),
        q: rng.quat(),
    };
    let u = rng.unit();
    let mut b = Posed {
        spec: s2,
        r: add(&a.r, &u),
        q: rng.quat(),
    };
    let unit_alpha = oracle::proximity(&a, &b).ok()?.alpha;
    b.r = add(&a.r, &scale(&u, target / unit_alpha)).map(|x| rnd(x, 4));
    Some((a, b))
}

fn category(alpha: f64) -> &'static str {
    if alpha < 0.9 {
        "deep"
    } else if alpha <= 1.1 {
        "near"
    } else {
        "separated"
    }
}

// ---------------------------------------------------------------------------------------------
// One record.

fn pose_json(p: &Posed) -> Value {
    json!({"r": p.r, "q": p.q})
}

/// `((x* − r₁)/ℓ, α*)`, the smooth quantities differentiated.
fn observe(a: &Posed, b: &Posed, ell: f64) -> Option<[f64; 4]> {
    let p = oracle::proximity(a, b).ok()?;
    Some([
        p.x_rel[0] / ell,
        p.x_rel[1] / ell,
        p.x_rel[2] / ell,
        p.alpha,
    ])
}

/// The pair with pose parameter `c` (0..14: r₁, q₁, r₂, q₂) moved by `h`.
fn moved(a: &Posed, b: &Posed, c: usize, h: f64) -> (Posed, Posed) {
    let (mut a, mut b) = (a.clone(), b.clone());
    let p = if c < 7 { &mut a } else { &mut b };
    let k = c % 7;
    if k < 3 {
        p.r[k] += h;
    } else {
        p.q[k - 3] += h;
    }
    (a, b)
}

/// Central differences of the oracle for every column: the α row (`dalpha`) and, when
/// `with_x`, the x rows, in physical units; `None` for entries that fail the tests of the
/// module docs of `tests/data/README.md` (step agreement and a kink test) at every step.
#[allow(clippy::type_complexity)]
fn derivatives(
    a: &Posed,
    b: &Posed,
    ell: f64,
    f0: [f64; 4],
    with_x: bool,
) -> ([Option<f64>; 14], [[Option<f64>; 14]; 3]) {
    let dist = norm(&sub(&b.r, &a.r));
    let h_r = 2f64.powi((1e-5 * ell.min(dist)).log2().round() as i32);
    let h_q = 2f64.powi(-17);
    let mut dalpha = [None; 14];
    let mut dx = [[None; 14]; 3];
    for c in 0..14 {
        let is_r = c % 7 < 3;
        let base = if is_r { h_r } else { h_q };
        // Non-dimensional step: r over ℓ.
        let nd = if is_r { 1.0 / ell } else { 1.0 };
        let rows = if with_x { 0..4 } else { 3..4 };
        let mut pending: Vec<usize> = rows.collect();
        for mult in [1.0, 1.0 / 8.0, 1.0 / 64.0] {
            if pending.is_empty() {
                break;
            }
            let h = base * mult;
            let f: Vec<Option<[f64; 4]>> = [-2.0, -1.0, 1.0, 2.0]
                .iter()
                .map(|s| {
                    let (a2, b2) = moved(a, b, c, s * h);
                    observe(&a2, &b2, ell)
                })
                .collect();
            let (Some(m2), Some(m1), Some(p1), Some(p2)) = (f[0], f[1], f[2], f[3]) else {
                continue;
            };
            let hn = h * nd;
            pending.retain(|&row| {
                let d1 = (p1[row] - m1[row]) / (2.0 * hn);
                let d2 = (p2[row] - m2[row]) / (4.0 * hn);
                let rich = (4.0 * d1 - d2) / 3.0;
                let err = (d1 - d2).abs();
                let kink = (p2[row] + m2[row] - 4.0 * p1[row] - 4.0 * m1[row] + 6.0 * f0[row])
                    .abs()
                    / (2.0 * hn);
                let bound = 1e-6 * rich.abs().max(1.0);
                if !(err <= bound && kink <= bound) {
                    return true;
                }
                // Back to physical units; the x rows differentiate x − r₁.
                if row == 3 {
                    dalpha[c] = Some(sig(rich * nd, 8));
                } else {
                    let id = if c < 3 && row == c { 1.0 } else { 0.0 };
                    dx[row][c] = Some(sig(rich * ell * nd + id, 8));
                }
                false
            });
        }
    }
    (dalpha, dx)
}

/// How a case is made and checked.
enum Make {
    /// Certified by the oracle's polish.
    Oracle,
    /// A flat (face, line) contact: x* is not unique and the polish's KKT system is singular,
    /// so α* and the distance come from closed forms (and Clarabel must agree with them).
    Flat { alpha: f64, distance: f64 },
}

struct Record {
    value: Value,
    x_unique: bool,
    has_jacobian: bool,
}

fn record(
    id: String,
    group: &str,
    cat: Option<&str>,
    (a, b): (&Posed, &Posed),
    make: Make,
    want_jacobian: bool,
) -> Result<Record, String> {
    let ell = oracle::length_scale(a, b);
    let (alpha, x, x_rel, kkt, x_unique, sensitivity) = match make {
        Make::Oracle => {
            let p = oracle::proximity(a, b)?;
            // Uniqueness: the optimum of `α + ε c·ξ` for three directions c and their negatives
            // must stay where it is (ξ in the stretched frame, ε = 1e-8).
            let mut unique = p.regular;
            let mut sens: f64 = 0.0;
            if p.alpha > 0.0 {
                let mut rng = Rng(0x5EED ^ (p.alpha.to_bits() >> 7));
                let stretch = ell / norm(&sub(&b.r, &a.r)); // ξ' = (x − r₁)/ℓ · stretch
                for _ in 0..3 {
                    let c = rng.unit();
                    for sgn in [1.0, -1.0] {
                        match oracle::proximity_eps(a, b, Some((1e-8, scale(&c, sgn)))) {
                            Ok(q) => {
                                let moved = norm(&sub(&q.x_rel, &p.x_rel)) / ell * stretch;
                                sens = sens.max(moved / 1e-8);
                                if moved > 1e-5 {
                                    unique = false;
                                }
                            }
                            Err(_) => unique = false,
                        }
                    }
                }
            }
            (p.alpha, p.x, p.x_rel, p.kkt, unique, sens)
        }
        Make::Flat { alpha, .. } => {
            let z = flat_clarabel(a, b)?;
            if ((z.0 - alpha) / alpha.max(1.0)).abs() > 1e-9 {
                return Err(format!(
                    "Clarabel α {} against the closed form {alpha}",
                    z.0
                ));
            }
            (alpha, z.1, sub(&z.1, &a.r), f64::NAN, false, f64::NAN)
        }
    };
    let cat = cat.unwrap_or_else(|| category(alpha));
    let (p1, p2) = if alpha > 0.0 {
        (
            Some(add(&a.r, &scale(&x_rel, 1.0 / alpha))),
            Some(add(&b.r, &scale(&sub(&x, &b.r), 1.0 / alpha))),
        )
    } else {
        (None, None)
    };
    // Distance: zero when α* < 1 (x* lies in both unscaled shapes) or when the contact points
    // coincide to 1e-10 ℓ (touching); else the distance program.
    let (distance, c1, c2, c_unique) = match make {
        Make::Flat { distance, .. } => (distance, None, None, None),
        Make::Oracle if alpha < 1.0 => (0.0, None, None, None),
        Make::Oracle if norm(&sub(&p1.unwrap(), &p2.unwrap())) <= 1e-10 * ell => {
            (0.0, None, None, None)
        }
        Make::Oracle => {
            let d = oracle::distance(a, b)?;
            let gap = norm(&sub(&p1.unwrap(), &p2.unwrap()));
            if d.distance > gap * (1.0 + 1e-12) + 1e-14 * ell {
                return Err(format!("distance {} above ‖p1 − p2‖ = {gap}", d.distance));
            }
            (d.distance, Some(d.c1), Some(d.c2), Some(d.regular))
        }
    };
    let smooth = matches!(make, Make::Oracle) && alpha > 0.0;
    let (dalpha, jac) = if smooth {
        let f0 = [x_rel[0] / ell, x_rel[1] / ell, x_rel[2] / ell, alpha];
        let (g, dx) = derivatives(a, b, ell, f0, x_unique && want_jacobian);
        let jac = (x_unique && want_jacobian).then(|| {
            let mut j = vec![vec![None; 14]; 4];
            for c in 0..14 {
                for r in 0..3 {
                    j[r][c] = dx[r][c];
                }
                j[3][c] = g[c];
            }
            j
        });
        (Some(g.to_vec()), jac)
    } else {
        (None, None)
    };
    let has_jacobian = jac.is_some();
    let value = json!({
        "id": id,
        "group": group,
        "category": cat,
        "shape1": a.spec.to_json(),
        "pose1": pose_json(a),
        "shape2": b.spec.to_json(),
        "pose2": pose_json(b),
        "alpha": alpha,
        "x": x,
        "x_unique": x_unique,
        "p1": p1,
        "p2": p2,
        "distance": distance,
        "closest1": c1,
        "closest2": c2,
        "closest_unique": c_unique,
        "dalpha_dconfig": dalpha,
        "jacobian": jac,
        "solver_notes": {
            "length_scale": ell,
            "kkt_max": if kkt.is_nan() { Value::Null } else { json!(sig(kkt, 2)) },
            "x_sensitivity": if sensitivity.is_nan() { Value::Null } else { json!(sig(sensitivity, 2)) },
        },
    });
    Ok(Record {
        value,
        x_unique,
        has_jacobian,
    })
}

/// Plain Clarabel (no polish) on a flat contact: `(α*, x*)`.
fn flat_clarabel(a: &Posed, b: &Posed) -> Result<(f64, V3), String> {
    let ell = oracle::length_scale(a, b);
    let delta = scale(&sub(&b.r, &a.r), 1.0 / ell);
    let mut p = oracle::Program::new(4);
    p.cost[3] = 1.0;
    p.nonneg.push(oracle::Aff::var(3, 1.0));
    let xi = [
        oracle::Aff::var(0, 1.0),
        oracle::Aff::var(1, 1.0),
        oracle::Aff::var(2, 1.0),
    ];
    let al = oracle::Aff::var(3, 1.0);
    p.add_shape(&a.spec, xi, [0.0; 3], &rot(&a.q), al, ell);
    p.add_shape(&b.spec, xi, delta, &rot(&b.q), al, ell);
    let (z, _) = p.clarabel()?;
    Ok((z[3], add(&a.r, &scale(&[z[0], z[1], z[2]], ell))))
}

// ---------------------------------------------------------------------------------------------
// The sets.

fn seed_of(name: &str) -> u64 {
    name.bytes().fold(0xCBF2_9CE4_8422_2325, |h, b| {
        (h ^ b as u64).wrapping_mul(0x100_0000_01B3)
    })
}

fn pair_cases(k1: &str, k2: &str) -> Vec<Record> {
    let mut rng = Rng(seed_of(&format!("{k1}-{k2}")));
    let mut out = Vec::new();
    let targets = [(0.05, 0.7), (0.9, 1.1), (1.1, 5.0)];
    let mut attempts = 0;
    while out.len() < PER_PAIR {
        attempts += 1;
        assert!(
            attempts < 20 * PER_PAIR,
            "{k1}-{k2}: too many rejected draws"
        );
        let (lo, hi) = targets[out.len() % 3];
        let target = rng.range(lo, hi);
        let (s1, s2) = (random_spec(k1, &mut rng), random_spec(k2, &mut rng));
        let Some((a, b)) = place(&mut rng, s1, s2, target) else {
            continue;
        };
        let id = format!("own-{k1}-{k2}-{:03}", out.len());
        let jac = out.len() < WITH_JACOBIAN;
        match record(id, "random", None, (&a, &b), Make::Oracle, jac) {
            Ok(r) if r.x_unique => out.push(r),
            Ok(_) => eprintln!("{k1}-{k2}: redrawn (x* not unique)"),
            Err(e) => eprintln!("{k1}-{k2}: redrawn ({e})"),
        }
    }
    out
}

fn identity() -> [f64; 4] {
    [1.0, 0.0, 0.0, 0.0]
}

fn stress_cases() -> Vec<Record> {
    let mut rng = Rng(seed_of("stress"));
    let mut out: Vec<Record> = Vec::new();
    let push = |cat: &str, a: Posed, b: Posed, make: Make, out: &mut Vec<Record>| -> bool {
        let id = format!("own-stress-{:03}", out.len());
        match record(id, "stress", Some(cat), (&a, &b), make, out.len() % 2 == 0) {
            Ok(r) => {
                out.push(r);
                true
            }
            Err(e) => {
                eprintln!("stress {cat}: dropped ({e})");
                false
            }
        }
    };
    let kind = |rng: &mut Rng| KINDS[rng.index(7)];
    // aspect: needles, disks, slabs, thin polygons (aspect up to 50).
    let aspect = [
        Spec::Capsule { r: 0.02, l: 1.0 },
        Spec::Cylinder { r: 0.5, l: 0.02 },
        Spec::Cylinder { r: 0.01, l: 0.8 },
        Spec::Ellipsoid {
            p: [[1.0, 0.0, 0.0], [0.0, 2500.0, 0.0], [0.0, 0.0, 4.0]],
        },
        Spec::Polytope {
            a: vec![
                [1.0, 0.0, 0.0],
                [-1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.0, -1.0, 0.0],
                [0.0, 0.0, 1.0],
                [0.0, 0.0, -1.0],
            ],
            b: vec![0.5, 0.5, 0.01, 0.01, 0.4, 0.4],
        },
        Spec::Polygon {
            c: vec![[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [0.0, -1.0]],
            d: vec![0.6, 0.6, 0.02, 0.02],
            r: 0.005,
        },
    ];
    for (i, s) in aspect.iter().enumerate() {
        for k in 0..2 {
            let other = random_spec(kind(&mut rng), &mut rng);
            let target = [0.6, 1.5][k];
            let (s1, s2) = if i % 2 == 0 {
                (s.clone(), other)
            } else {
                (other, s.clone())
            };
            if let Some((a, b)) = place(&mut rng, s1, s2, target) {
                push("aspect", a, b, Make::Oracle, &mut out);
            }
        }
    }
    // scale_small, scale_large: random pairs with every length times 1e-3 or 1e3.
    for (cat, f) in [("scale_small", 1e-3), ("scale_large", 1e3)] {
        // Draws until six are certified (at most 30).
        let (mut kept, mut k) = (0, 0);
        while kept < 6 && k < 30 {
            k += 1;
            let (s1, s2) = (
                random_spec(kind(&mut rng), &mut rng).scaled(f),
                random_spec(kind(&mut rng), &mut rng).scaled(f),
            );
            let target = [0.5, 1.0, 2.0][k % 3];
            if let Some((mut a, mut b)) = place(&mut rng, s1, s2, target) {
                // Positions scaled as well (rounded to the same relative precision).
                let off = sub(&b.r, &a.r);
                a.r = a.r.map(|v| rnd(v, 4) * f);
                b.r = add(&a.r, &off);
                kept += usize::from(push(cat, a, b, Make::Oracle, &mut out));
            }
        }
    }
    // coincident: r₂ = r₁ exactly.
    for _ in 0..4 {
        let r = random_position(&mut rng);
        let a = Posed {
            spec: random_spec(kind(&mut rng), &mut rng),
            r,
            q: rng.quat(),
        };
        let b = Posed {
            spec: random_spec(kind(&mut rng), &mut rng),
            r,
            q: rng.quat(),
        };
        push("coincident", a, b, Make::Oracle, &mut out);
    }
    // near_coincident: ‖r₂ − r₁‖ from 1e-6 to 1e-2 (α* about as small).
    for k in 0..6 {
        let a = Posed {
            spec: random_spec(kind(&mut rng), &mut rng),
            r: random_position(&mut rng),
            q: rng.quat(),
        };
        let d = 10f64.powi(-6 + 4 * k / 5) * rng.range(1.0, 3.0);
        let b = Posed {
            spec: random_spec(kind(&mut rng), &mut rng),
            r: add(&a.r, &scale(&rng.unit(), d)),
            q: rng.quat(),
        };
        push("near_coincident", a, b, Make::Oracle, &mut out);
    }
    // touching: α* = 1 exactly (dyadic sizes and offsets).
    let touching = [
        (
            Spec::Sphere { r: 0.5 },
            Spec::Sphere { r: 0.25 },
            [0.75, 0.0, 0.0],
            identity(),
        ),
        (
            Spec::Polytope {
                a: vec![
                    [1.0, 0.0, 0.0],
                    [-1.0, 0.0, 0.0],
                    [0.0, 1.0, 0.0],
                    [0.0, -1.0, 0.0],
                    [0.0, 0.0, 1.0],
                    [0.0, 0.0, -1.0],
                ],
                b: vec![0.75, 0.75, 0.5, 0.5, 0.25, 0.25],
            },
            Spec::Sphere { r: 0.5 },
            [1.25, 0.125, 0.0625],
            identity(),
        ),
        (
            Spec::Capsule { r: 0.25, l: 1.0 },
            Spec::Sphere { r: 0.5 },
            [0.0, 0.0, 0.75],
            identity(),
        ),
        (
            Spec::Sphere { r: 0.375 },
            Spec::Capsule { r: 0.125, l: 0.5 },
            [0.0, 0.75, 0.0],
            [1.0, 0.0, 0.0, 1.0],
        ),
        (
            Spec::Cylinder { r: 0.5, l: 1.0 },
            Spec::Sphere { r: 0.25 },
            [0.0, 0.75, 0.0],
            identity(),
        ),
        (
            Spec::Ellipsoid {
                p: [[4.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 16.0]],
            },
            Spec::Sphere { r: 0.5 },
            [0.0, 1.5, 0.0],
            identity(),
        ),
    ];
    for (s1, s2, off, q2) in touching {
        let r1 = [0.5, -0.25, 0.125];
        let a = Posed {
            spec: s1,
            r: r1,
            q: identity(),
        };
        let b = Posed {
            spec: s2,
            r: add(&r1, &off),
            q: q2,
        };
        push("touching", a, b, Make::Oracle, &mut out);
    }
    // parallel: face–face, cap–face, side–face and polygon–face contacts (closed forms).
    parallel_cases(&mut rng, &mut out);
    // thin_cone (5°) and wide_cone (85°).
    for (cat, beta) in [
        ("thin_cone", 5f64.to_radians()),
        ("wide_cone", 85f64.to_radians()),
    ] {
        for k in 0..8 {
            let cone = Spec::Cone {
                h: rnd(rng.range(0.5, 1.5), 3),
                beta: rnd(beta, 6),
            };
            let other = random_spec(kind(&mut rng), &mut rng);
            let target = [0.5, 1.0, 1.8][k % 3];
            let (s1, s2) = if k % 2 == 0 {
                (cone, other)
            } else {
                (other, cone)
            };
            if let Some((a, b)) = place(&mut rng, s1, s2, target) {
                push(cat, a, b, Make::Oracle, &mut out);
            }
        }
    }
    // flat_ellipsoid: smallest axis 1e-3 to 1e-2 of the largest.
    let (mut kept, mut k) = (0, 0);
    while kept < 6 && k < 30 {
        k += 1;
        let thin = [1e-3, 3e-3, 1e-2][k % 3];
        let big = rnd(rng.range(0.5, 1.0), 3);
        let mid = rnd(rng.range(0.3, 1.0), 3);
        let e = Spec::Ellipsoid {
            p: [
                [1.0 / (big * big), 0.0, 0.0],
                [0.0, 1.0 / (mid * mid), 0.0],
                [0.0, 0.0, 1.0 / (thin * big * thin * big)],
            ],
        };
        let other = random_spec(kind(&mut rng), &mut rng);
        let target = [0.6, 1.0, 1.6][k % 3];
        if let Some((a, b)) = place(&mut rng, e, other, target) {
            kept += usize::from(push("flat_ellipsoid", a, b, Make::Oracle, &mut out));
        }
    }
    out
}

/// Flat contacts with closed forms: the second shape sits above the first's top face (world
/// z), its flat or straight part parallel to that face, offset sideways by less than the
/// face allows, so α* = Δz / (top of shape 1 + bottom of shape 2) and the distance is
/// Δz − (both extents) when positive.
fn parallel_cases(rng: &mut Rng, out: &mut Vec<Record>) {
    let boxed = |h: V3| Spec::Polytope {
        a: vec![
            [1.0, 0.0, 0.0],
            [-1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, -1.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.0, 0.0, -1.0],
        ],
        b: vec![h[0], h[0], h[1], h[1], h[2], h[2]],
    };
    // (shape 2, its attitude, its half extent along world z)
    let top = [
        (boxed([0.3, 0.4, 0.25]), identity(), 0.25),
        (
            Spec::Cylinder { r: 0.3, l: 0.5 },
            [1.0, 0.0, -1.0, 0.0],
            0.25,
        ), // cap down
        (Spec::Cylinder { r: 0.25, l: 0.8 }, identity(), 0.25), // side down
        (Spec::Capsule { r: 0.2, l: 0.6 }, identity(), 0.2),    // side down
        (
            Spec::Polygon {
                c: vec![[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [0.0, -1.0]],
                d: vec![0.3, 0.3, 0.2, 0.2],
                r: 0.05,
            },
            identity(),
            0.05,
        ),
    ];
    for (i, (s2, q2, ext2)) in top.into_iter().enumerate() {
        for (k, dz) in [0.5, 1.0, 1.25].into_iter().enumerate() {
            if (i + k) % 2 == 1 && k != 1 {
                continue;
            }
            let h1 = [0.5, 0.5, 0.25];
            let r1 = [
                rnd(rng.range(-0.5, 0.5), 3),
                rnd(rng.range(-0.5, 0.5), 3),
                0.0,
            ];
            let side = [
                rnd(rng.range(-0.05, 0.05), 3),
                rnd(rng.range(-0.05, 0.05), 3),
            ];
            let a = Posed {
                spec: boxed(h1),
                r: r1,
                q: identity(),
            };
            let b = Posed {
                spec: s2.clone(),
                r: [r1[0] + side[0], r1[1] + side[1], dz],
                q: q2,
            };
            let alpha = dz / (h1[2] + ext2);
            let distance = (dz - h1[2] - ext2).max(0.0);
            let id = format!("own-stress-{:03}", out.len());
            let make = Make::Flat { alpha, distance };
            match record(id, "stress", Some("parallel"), (&a, &b), make, false) {
                Ok(r) => out.push(r),
                Err(e) => eprintln!("stress parallel: dropped ({e})"),
            }
        }
    }
}

fn write(path: &PathBuf, recs: &[Record]) {
    let text: String = recs
        .iter()
        .map(|r| serde_json::to_string(&r.value).unwrap() + "\n")
        .collect();
    std::fs::write(path, text).unwrap();
}

#[test]
#[ignore = "writes tests/data; run by hand to regenerate the reference cases"]
fn generate_reference_data() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    std::fs::create_dir_all(&dir).unwrap();
    let pairs: Vec<(&str, &str)> = KINDS
        .iter()
        .flat_map(|a| KINDS.iter().map(move |b| (*a, *b)))
        .collect();
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let next = std::sync::atomic::AtomicUsize::new(0);
    let summary = std::sync::Mutex::new(Vec::new());
    std::thread::scope(|s| {
        for _ in 0..threads {
            s.spawn(|| loop {
                let i = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                if i > pairs.len() {
                    return;
                }
                let (name, recs) = if i == pairs.len() {
                    ("stress".to_string(), stress_cases())
                } else {
                    let (a, b) = pairs[i];
                    (format!("{a}-{b}"), pair_cases(a, b))
                };
                write(&dir.join(format!("cases-{name}.jsonl")), &recs);
                let jac = recs.iter().filter(|r| r.has_jacobian).count();
                summary.lock().unwrap().push((name, recs.len(), jac));
            });
        }
    });
    let mut summary = summary.into_inner().unwrap();
    summary.sort();
    for (name, n, jac) in &summary {
        println!("{name:<32} {n:>4} cases, {jac:>4} with a Jacobian");
    }
    let total: usize = summary.iter().map(|s| s.1).sum();
    println!("{total} cases in {} files", summary.len());
}

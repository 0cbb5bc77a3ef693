//! Buckling references: the clamped–clamped planar elastica beyond buckling (first,
//! symmetric mode), and Greenhill's twist buckling of a straight clamped rod.
//!
//! # Clamped–clamped post-buckling
//!
//! A rod of reference length `L`, clamped at both ends with horizontal tangents, the
//! ends brought together by `Δ` (end distance `L − Δ`). In the first mode the shape is
//! symmetric about the mid-span; the internal force is constant and horizontal,
//! `n = (−P, 0)` with the compressive end force `P > 0` (N).
//!
//! *Inextensible (Euler) elastica* — the classical elliptic-integral solution. The
//! inflection points at `L/4` and `3L/4` cut the rod into pieces equivalent to a
//! pinned–pinned elastica of length `L/2`, so with the modulus `k = sin(α/2)` (`α` the
//! angle at the inflection points):
//!
//! ```text
//! P = 16 K(k)² EI / L²,        (L − Δ)/L = 2 E(k)/K(k) − 1,
//! ```
//!
//! `K, E` the complete elliptic integrals of the first and second kind (computed here
//! by the arithmetic–geometric mean). At `k → 0`, `P → 4π² EI/L²` (Euler's load for
//! clamped ends).
//!
//! *Extensible, shearable (Reissner) rod* — shooting with the planar Reissner
//! equations of [`super::reissner_planar`] under the constant force `(−P, 0)`, from the
//! clamp `r(0) = 0`, `θ(0) = 0` with unknowns `(P, m(0))` and, by symmetry, the two
//! conditions at the mid-span `θ(L/2) = 0`, `x(L/2) = (L − Δ)/2`. Newton with a
//! finite-difference Jacobian; started from the inextensible solution and continued
//! in `Δ` (the straight branch, `P = EA Δ/L`, also satisfies these conditions; the
//! elliptic start selects the buckled one).
//!
//! # Greenhill (twist) buckling, clamped ends
//!
//! A straight rod along its axis, both ends clamped (positions and frames held, the
//! end distance kept at `L`, so no axial force in the straight state), one clamp turned
//! by `φ` about the axis: a uniform twist with twisting moment `M = GJ φ / L`. Writing
//! the lateral tangent perturbation as a complex function `v(s)` and the constant
//! lateral shear force as `F`, the linearised moment balance is
//! `EI v'' − i M v' + F = 0` with `v(0) = v(L) = 0` (clamped directions) and
//! `∫₀ᴸ (v + F/GA) ds = 0` (clamped positions; `F/GA` the shear strain). Eliminating
//! gives, with `x = M L / EI` and `β = EI / (GA L²)`,
//!
//! ```text
//! tan(x/2) = (x/2) / (1 + β x²),
//! ```
//!
//! and for an unshearable rod (`β = 0`) Greenhill's `tan(x/2) = x/2`, first root
//! `x = 8.9868` (Timoshenko & Gere: `M_cr = 2.86 π EI/L`). The straight twisted rod is
//! stable below the first root and unstable beyond. The corresponding clamp rotation is
//! `φ = M L / GJ = x EI / GJ`.
//!
//! # Accuracy
//!
//! Elliptic integrals by AGM to round-off; shooting with the 16th-order [`Gbs`]
//! integrator (64 macro steps), Newton to `1e-13` relative; roots by safeguarded Newton
//! to round-off. The self-checks verify the elliptic solution against the shooting
//! with `EA = GA = ∞`, the Euler load, and the Greenhill root against the determinant
//! of the full complex 3×3 linear system.

use super::ode::Gbs;
use super::reissner_planar::PlanarRod;

/// Complete elliptic integrals `(K(k), E(k))` of modulus `k ∈ [0, 1)` by the
/// arithmetic–geometric mean.
pub fn elliptic_ke(k: f64) -> (f64, f64) {
    assert!((0.0..1.0).contains(&k), "modulus {k} outside [0, 1)");
    let (mut a, mut b) = (1.0, (1.0 - k * k).sqrt());
    let mut c = k;
    let mut sum = 0.5 * c * c;
    let mut pow = 0.5;
    for _ in 0..60 {
        if c.abs() < 1e-17 {
            break;
        }
        let an = 0.5 * (a + b);
        let bn = (a * b).sqrt();
        c = 0.5 * (a - b);
        pow *= 2.0;
        sum += pow * c * c;
        a = an;
        b = bn;
    }
    let kk = std::f64::consts::FRAC_PI_2 / a;
    (kk, kk * (1.0 - sum))
}

/// Inextensible clamped–clamped elastica, first mode: end force `P` (N, compressive)
/// for the end shortening `delta` (m), `0 < Δ < L`.
pub fn inextensible_end_force(length: f64, ei: f64, delta: f64) -> f64 {
    let ratio = (length - delta) / length;
    // (L−Δ)/L = 2E/K − 1 decreases from 1 (k=0) to −1 (k→1): bisection on k.
    let g = |k: f64| {
        let (kk, ee) = elliptic_ke(k);
        2.0 * ee / kk - 1.0
    };
    let (mut lo, mut hi) = (0.0, 1.0 - 1e-15);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if g(mid) > ratio {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let (kk, _) = elliptic_ke(0.5 * (lo + hi));
    16.0 * kk * kk * ei / (length * length)
}

/// Euler's buckling load of a clamped–clamped column, `4π² EI / L²` (N).
pub fn euler_clamped(length: f64, ei: f64) -> f64 {
    4.0 * std::f64::consts::PI.powi(2) * ei / (length * length)
}

/// A buckled clamped–clamped Reissner rod (first mode).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClampedBuckled {
    /// End shortening `Δ` (m).
    pub delta: f64,
    /// Compressive end force `P` (N): the clamps push the rod ends together with `P`.
    pub force: f64,
    /// Internal moment at the clamp at `s = 0`, `m(0)` (N·m).
    pub clamp_moment: f64,
    /// Mid-span deflection `y(L/2)` (m).
    pub mid_deflection: f64,
}

/// Mid-span state `[x, y, θ, m]` of the shooting from the clamp.
fn half_shot(rod: &PlanarRod, force: f64, m0: f64, integ: &Gbs) -> [f64; 4] {
    let f = |_s: f64, y: &[f64; 4]| rod.rhs([-force, 0.0], y);
    integ.integrate(&f, 0.0, 0.5 * rod.length, &[0.0, 0.0, 0.0, m0])
}

/// The clamped–clamped rod `rod` shortened by `delta` (m), buckled in its first mode
/// (upwards, `m(0) > 0`), by shooting (see the module docs).
///
/// # Panics
/// If the shooting fails.
pub fn clamped_buckled(rod: &PlanarRod, delta: f64) -> ClampedBuckled {
    let integ = Gbs::default();
    let (l, ei) = (rod.length, rod.ei);
    let pscale = ei / (l * l);
    let mscale = ei / l;
    // Start: inextensible elastica. The clamp moment of the inextensible solution:
    // at the clamp θ = 0 and the curvature is maximal; m(0) = 2k√(P EI) (first
    // integral ½ m² = P EI (cos θ − cos α) with θ = 0: m² = 2 P EI (1 − cos α)
    // = 4 P EI k²).
    let residual = |p: f64, m0: f64, target: f64| {
        let y = half_shot(rod, p, m0, &integ);
        [y[2], (y[0] - 0.5 * target) / l]
    };
    let mut state: Option<(f64, f64)> = None;
    let steps = 10;
    for step in 1..=steps {
        let d = delta * step as f64 / steps as f64;
        let (mut p, mut m0) = state.unwrap_or_else(|| {
            let p = inextensible_end_force(l, ei, d);
            let ratio = (l - d) / l;
            // k from P = 16 K² EI/L²: invert via bisection on the same relation.
            let (mut lo, mut hi) = (0.0, 1.0 - 1e-15);
            for _ in 0..200 {
                let mid = 0.5 * (lo + hi);
                let (kk, ee) = elliptic_ke(mid);
                if 2.0 * ee / kk - 1.0 > ratio {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            let k = 0.5 * (lo + hi);
            (p, 2.0 * k * (p * ei).sqrt())
        });
        let target = l - d;
        let mut converged = false;
        for _ in 0..60 {
            let r = residual(p, m0, target);
            if r[0].abs() < 1e-13 && r[1].abs() < 1e-13 {
                converged = true;
                break;
            }
            let (hp, hm) = (1e-7 * pscale.max(p.abs()), 1e-7 * mscale.max(m0.abs()));
            let rp = residual(p + hp, m0, target);
            let rm = residual(p, m0 + hm, target);
            let rp2 = residual(p - hp, m0, target);
            let rm2 = residual(p, m0 - hm, target);
            let j = [
                [(rp[0] - rp2[0]) / (2.0 * hp), (rm[0] - rm2[0]) / (2.0 * hm)],
                [(rp[1] - rp2[1]) / (2.0 * hp), (rm[1] - rm2[1]) / (2.0 * hm)],
            ];
            let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
            let dp = (r[0] * j[1][1] - r[1] * j[0][1]) / det;
            let dm = (j[0][0] * r[1] - j[1][0] * r[0]) / det;
            // Damped: keep the step moderate.
            let t = (0.2 * p / dp.abs().max(1e-300)).min(1.0);
            p -= t * dp;
            m0 -= t * dm;
        }
        assert!(converged, "clamped buckling shooting failed at Δ = {d}");
        state = Some((p, m0));
    }
    let (p, m0) = state.unwrap();
    let mid = half_shot(rod, p, m0, &integ);
    ClampedBuckled {
        delta,
        force: p,
        clamp_moment: m0,
        mid_deflection: mid[1],
    }
}

/// Greenhill's condition `f(x) = tan(x/2)(1 + βx²) − x/2` rewritten without poles:
/// `sin(x/2)(1 + βx²) − (x/2) cos(x/2)`.
fn greenhill_function(x: f64, beta: f64) -> (f64, f64) {
    let (s, c) = (0.5 * x).sin_cos();
    let g = 1.0 + beta * x * x;
    let f = s * g - 0.5 * x * c;
    let df = 0.5 * c * g + s * 2.0 * beta * x - 0.5 * c + 0.25 * x * s;
    (f, df)
}

/// First positive root `x = M L / EI` of the clamped–clamped Greenhill condition
/// `tan(x/2) = (x/2)/(1 + βx²)` with `β = EI/(GA L²)` (0 for an unshearable rod),
/// by Newton safeguarded by bisection in `(2π, 3π)`, where the unshearable root lies.
pub fn greenhill_clamped(beta: f64) -> f64 {
    use std::f64::consts::PI;
    // f(2π) = π > 0 and f(3π) = −(1 + 9π²β) < 0: the root of tan(y) = y/(1 + 4βy²),
    // y = x/2, lies in (π, 3π/2).
    let (mut lo, mut hi) = (2.0 * PI + 1e-9, 3.0 * PI - 1e-9);
    assert!(greenhill_function(lo, beta).0 * greenhill_function(hi, beta).0 < 0.0);
    let mut x = 0.5 * (lo + hi);
    for _ in 0..200 {
        let (f, df) = greenhill_function(x, beta);
        if f == 0.0 {
            return x;
        }
        if f * greenhill_function(lo, beta).0 < 0.0 {
            hi = x;
        } else {
            lo = x;
        }
        let newton = x - f / df;
        x = if newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
        if hi - lo < 1e-15 * x {
            break;
        }
    }
    x
}

/// The clamp rotation `φ` (rad) about the axis at which a clamped–clamped straight
/// rod with bending stiffness `ei`, torsional stiffness `gj` (N·m²), shear stiffness
/// `ga` (N, `f64::INFINITY` for unshearable) and length `length` (m) loses
/// stability: `φ = x EI/GJ`.
pub fn greenhill_critical_rotation(length: f64, ei: f64, gj: f64, ga: f64) -> f64 {
    greenhill_clamped(ei / (ga * length * length)) * ei / gj
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn elliptic_integrals_and_euler_load() {
        let (k0, e0) = elliptic_ke(0.0);
        assert!((k0 - PI / 2.0).abs() < 1e-15 && (e0 - PI / 2.0).abs() < 1e-15);
        // K(1/√2) = Γ(1/4)²/(4√π) = 1.8540746773013719.
        let (k, e) = elliptic_ke(0.5f64.sqrt());
        assert!((k - 1.854_074_677_301_371_9).abs() < 1e-14);
        // Legendre's relation at k = 1/√2: 2EK − K² = π/2.
        assert!((2.0 * e * k - k * k - PI / 2.0).abs() < 1e-13);
        let p = inextensible_end_force(1.0, 1.0, 1e-8);
        assert!(((p - euler_clamped(1.0, 1.0)) / p).abs() < 1e-7, "{p}");
        // Post-buckling initial slope: P/P_E ≈ 1 + Δ/(2L) for the elastica.
        let p = inextensible_end_force(1.0, 1.0, 1e-4);
        let ratio = p / euler_clamped(1.0, 1.0) - 1.0;
        assert!((ratio / 1e-4 - 0.5).abs() < 1e-3, "{ratio}");
    }

    #[test]
    fn shooting_reproduces_the_elliptic_solution_when_inextensible() {
        let rod = PlanarRod::new(1.0, 1.0, 1e12, 1e12);
        for delta in [0.05, 0.2, 0.5] {
            let b = clamped_buckled(&rod, delta);
            let p = inextensible_end_force(1.0, 1.0, delta);
            assert!(((b.force - p) / p).abs() < 1e-9, "{} vs {p}", b.force);
            assert!(b.clamp_moment > 0.0 && b.mid_deflection > 0.0);
        }
        // Extensible: the end force is lower than the inextensible one (the rod also
        // shortens elastically) and higher than Euler's load.
        let soft = PlanarRod::new(1.0, 1.0, 1e4, 3e4);
        let b = clamped_buckled(&soft, 0.1);
        assert!(b.force < inextensible_end_force(1.0, 1.0, 0.1));
        assert!(b.force > euler_clamped(1.0, 1.0));
    }

    #[test]
    fn greenhill_constant_is_the_root_of_the_full_linear_system() {
        let x = greenhill_clamped(0.0);
        assert!((x - 8.986_818_916_3).abs() < 1e-9, "{x}");
        // The same root from the determinant of the complex 3×3 system in (A, B, F):
        // v = A + B e^{iμs} − iF s/M, v(0) = 0, v(L) = 0, ∫(v + F/GA) = 0 (L = EI = 1).
        let det = |x: f64, beta: f64| {
            // Rows as complex numbers (re, im) of the columns A, B, F.
            type C = (f64, f64);
            let mul = |a: C, b: C| (a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0);
            let sub = |a: C, b: C| (a.0 - b.0, a.1 - b.1);
            let e = (x.cos(), x.sin());
            let m = x; // M = EI x / L
            let rows: [[C; 3]; 3] = [
                [(1.0, 0.0), (1.0, 0.0), (0.0, 0.0)],
                [(1.0, 0.0), e, (0.0, -1.0 / m)],
                [
                    (1.0, 0.0),
                    // (e^{ix} − 1)/(i x)
                    mul(sub(e, (1.0, 0.0)), (0.0, -1.0 / x)),
                    (beta, -0.5 / m),
                ],
            ];
            let d3 = |r: &[[C; 3]; 3]| {
                let minor = |a: C, b: C, c: C, d: C| sub(mul(a, d), mul(b, c));
                let t0 = mul(r[0][0], minor(r[1][1], r[1][2], r[2][1], r[2][2]));
                let t1 = mul(r[0][1], minor(r[1][0], r[1][2], r[2][0], r[2][2]));
                let t2 = mul(r[0][2], minor(r[1][0], r[1][1], r[2][0], r[2][1]));
                let s = sub(t0, t1);
                (s.0 + t2.0, s.1 + t2.1)
            };
            let d = d3(&rows);
            d.0.hypot(d.1)
        };
        for beta in [0.0, 1e-4, 1e-2] {
            let root = greenhill_clamped(beta);
            let scale = det(root * 0.97, beta);
            assert!(det(root, beta) < 1e-12 * scale.max(1.0), "β={beta}");
            assert!(det(root * 1.001, beta) > 1e-6 * scale, "β={beta}");
        }
        // Shear flexibility lowers the threshold.
        assert!(greenhill_clamped(1e-4) < x);
        let phi = greenhill_critical_rotation(1.0, 1.0, 5.0, f64::INFINITY);
        assert!((phi - x / 5.0).abs() < 1e-15);
    }
}

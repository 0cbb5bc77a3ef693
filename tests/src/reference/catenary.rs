//! The elastic catenary (Irvine, *Cable Structures*, 1981, §2.2): an extensible
//! cable without bending stiffness hanging between two pins.
//!
//! # Model
//!
//! Unstretched length `L` (m), weight `w` per unstretched length (N/m), axial
//! stiffness `EA` (N), linear elastic: the tension `T` stretches an element `ds` of
//! unstretched length to `(1 + T/EA) ds`. The left support A is at the origin, the
//! right support B at `(a, b)` (m; `x` horizontal, `z` up). `s ∈ [0, L]` is the
//! unstretched (Lagrangian) arc length from A.
//!
//! The support A pulls on the cable with `(−H, V)` (N): `H > 0` is the horizontal pull,
//! `V` the vertical reaction at A (positive upwards). The internal force exerted by
//! the part beyond `s` on the part before `s` is, from the equilibrium of `[0, s]`,
//! `n(s) = (H, w s − V)`; the tension is `T = |n|` and the cable is tangent to `n`:
//!
//! ```text
//! x'(s) = (1 + T/EA) H / T,        z'(s) = (1 + T/EA) (w s − V) / T,
//! ```
//!
//! which integrates in closed form (`u(s) = (w s − V)/H`, `u₀ = −V/H`):
//!
//! ```text
//! x(s) = H s/EA + (H/w) [asinh u(s) − asinh u₀]
//! z(s) = (w s²/2 − V s)/EA + (H/w) [√(1+u(s)²) − √(1+u₀²)].
//! ```
//!
//! The boundary conditions `x(L) = a`, `z(L) = b` are two equations for `(H, V)`
//! (Irvine's eqs. 2.34–2.35), solved here by Newton's method with the analytic
//! Jacobian, started from the inextensible catenary (`√(L²−b²) = (2H/w) sinh(wa/2H)`,
//! solved by bisection). The vertical reaction at B is `w L − V`.
//!
//! # Accuracy
//!
//! The closed form is evaluated in double precision; Newton is iterated until the
//! boundary residual is below `1e-14 L` (it converges quadratically in 3–8 steps for
//! spans 0.3–0.999 L). The self-checks below integrate the ODE independently with the
//! 16th-order [`Gbs`] integrator (agreement < 1e-12 m) and recover the inextensible
//! catenary as `EA → ∞`.

#[cfg(test)]
use super::ode::Gbs;

/// An elastic cable between two pins.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cable {
    /// Unstretched length `L` (m).
    pub length: f64,
    /// Weight per unstretched length `w` (N/m).
    pub weight: f64,
    /// Axial stiffness `EA` (N); `f64::INFINITY` for an inextensible cable.
    pub ea: f64,
    /// Horizontal span `a` from A to B (m), `a > 0`.
    pub span: f64,
    /// Height of B above A, `b` (m).
    pub rise: f64,
}

/// The equilibrium of a [`Cable`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Catenary {
    /// The cable.
    pub cable: Cable,
    /// Horizontal pull `H` (N), the same at both supports.
    pub horizontal: f64,
    /// Upward vertical reaction at A (N).
    pub vertical_a: f64,
    /// Upward vertical reaction at B (N): `w L − V_A`.
    pub vertical_b: f64,
    /// Newton iterations used.
    pub iterations: usize,
}

impl Cable {
    /// Position `(x, z)` (m) of the material point `s` (m of unstretched length) for a
    /// horizontal pull `h` (N) and vertical reaction `v` at A (N), with the partial
    /// derivatives `[[∂x/∂H, ∂x/∂V], [∂z/∂H, ∂z/∂V]]`.
    fn position_and_jacobian(&self, s: f64, h: f64, v: f64) -> ([f64; 2], [[f64; 2]; 2]) {
        let w = self.weight;
        let ea = self.ea;
        let u = (w * s - v) / h;
        let u0 = -v / h;
        let (r, r0) = ((1.0 + u * u).sqrt(), (1.0 + u0 * u0).sqrt());
        let x = h * s / ea + (h / w) * (u.asinh() - u0.asinh());
        let z = (0.5 * w * s * s - v * s) / ea + (h / w) * (r - r0);
        let dx_dh = s / ea + (u.asinh() - u0.asinh()) / w - (u / r - u0 / r0) / w;
        let dx_dv = (-1.0 / r + 1.0 / r0) / w;
        let dz_dh = (1.0 / r - 1.0 / r0) / w;
        let dz_dv = -s / ea + (-u / r + u0 / r0) / w;
        ([x, z], [[dx_dh, dx_dv], [dz_dh, dz_dv]])
    }

    /// Horizontal pull (N) of the inextensible catenary with this length, weight and
    /// supports: the root of `√(L²−b²) = (2H/w) sinh(w a / 2H)` (bisection on `ln H`).
    ///
    /// # Panics
    /// If the cable is too short to reach B (`L² ≤ a² + b²`).
    pub fn inextensible_horizontal_pull(&self) -> f64 {
        let (l, a, b, w) = (self.length, self.span, self.rise, self.weight);
        let target = (l * l - b * b).sqrt();
        assert!(target > a, "the cable must be longer than the chord");
        // g(H) = (2H/w) sinh(w a/2H) decreases from ∞ (H→0) to a (H→∞).
        let g = |h: f64| {
            let x = w * a / (2.0 * h);
            // (2H/w) sinh(x) = a sinh(x)/x, evaluated without overflow in log space.
            if x > 700.0 {
                f64::INFINITY
            } else {
                a * x.sinh() / x
            }
        };
        let (mut lo, mut hi) = (1e-12 * w * l, 1e12 * w * l);
        for _ in 0..200 {
            let mid = (lo * hi).sqrt();
            if g(mid) > target {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        (lo * hi).sqrt()
    }

    /// Solves Irvine's equations for `H` and `V_A` by damped Newton.
    ///
    /// # Panics
    /// If the cable is too short to reach B, or Newton fails (not observed for
    /// `0.05 L ≤ a ≤ 0.9999 L`).
    pub fn solve(&self) -> Catenary {
        let (l, w) = (self.length, self.weight);
        // Start: the inextensible catenary.
        let mut h = self.inextensible_horizontal_pull();
        let mut v = 0.5 * w * l;
        // A robust start for V: the value that makes z(L) = b for the start H (scalar
        // Newton in V, z is monotone decreasing in V).
        for _ in 0..100 {
            let ([_, z], jac) = self.position_and_jacobian(l, h, v);
            let dv = (z - self.rise) / jac[1][1];
            v -= dv;
            if dv.abs() <= 1e-15 * w * l {
                break;
            }
        }
        let residual = |h: f64, v: f64| {
            let ([x, z], _) = self.position_and_jacobian(l, h, v);
            [x - self.span, z - self.rise]
        };
        let norm = |r: [f64; 2]| r[0].hypot(r[1]);
        let mut iterations = 0;
        loop {
            let r = residual(h, v);
            if norm(r) <= 1e-14 * l {
                break;
            }
            assert!(iterations < 100, "catenary Newton did not converge: {r:?}");
            iterations += 1;
            let (_, j) = self.position_and_jacobian(l, h, v);
            let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
            let dh = (r[0] * j[1][1] - r[1] * j[0][1]) / det;
            let dv = (j[0][0] * r[1] - j[1][0] * r[0]) / det;
            // Damping: keep H positive and decrease the residual.
            let mut t = 1.0;
            loop {
                let (h1, v1) = (h - t * dh, v - t * dv);
                if h1 > 0.0 && norm(residual(h1, v1)) < norm(r) {
                    (h, v) = (h1, v1);
                    break;
                }
                t *= 0.5;
                if t < 1e-12 {
                    // Round-off floor reached.
                    (h, v) = (h1.max(0.5 * h), v1);
                    break;
                }
            }
            if t < 1e-12 {
                break;
            }
        }
        Catenary {
            cable: *self,
            horizontal: h,
            vertical_a: v,
            vertical_b: w * l - v,
            iterations,
        }
    }
}

impl Catenary {
    /// Position `(x, z)` (m) of the material point at unstretched arc length `s` (m).
    pub fn position(&self, s: f64) -> [f64; 2] {
        self.cable
            .position_and_jacobian(s, self.horizontal, self.vertical_a)
            .0
    }

    /// Tension `T(s)` (N).
    pub fn tension(&self, s: f64) -> f64 {
        self.horizontal
            .hypot(self.cable.weight * s - self.vertical_a)
    }

    /// Force the support A exerts on the cable, `(−H, V_A)` (N).
    pub fn reaction_a(&self) -> [f64; 2] {
        [-self.horizontal, self.vertical_a]
    }

    /// Force the support B exerts on the cable, `(H, w L − V_A)` (N).
    pub fn reaction_b(&self) -> [f64; 2] {
        [self.horizontal, self.vertical_b]
    }

    /// Sag at mid-span: the vertical distance (m) from the chord down to the cable at
    /// `x = a/2` (found by Newton on `s`).
    pub fn mid_span_sag(&self) -> f64 {
        let a = self.cable.span;
        let mut s = 0.5 * self.cable.length;
        for _ in 0..100 {
            let [x, _] = self.position(s);
            let t = self.tension(s);
            let dx_ds = (1.0 + t / self.cable.ea) * self.horizontal / t;
            let ds = (x - 0.5 * a) / dx_ds;
            s -= ds;
            if ds.abs() < 1e-15 * self.cable.length {
                break;
            }
        }
        let [_, z] = self.position(s);
        0.5 * self.cable.rise - z
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cables() -> Vec<Cable> {
        let mut out = vec![];
        for span in [0.3, 0.5, 0.8, 0.95, 0.999] {
            for rise in [0.0, 0.1, -0.2] {
                if span * span + rise * rise >= 0.999 {
                    continue;
                }
                for ea in [1e6, 1e3, 50.0] {
                    out.push(Cable {
                        length: 1.0,
                        weight: 0.5 * 9.81,
                        ea,
                        span,
                        rise,
                    });
                }
            }
        }
        out
    }

    #[test]
    fn closed_form_matches_an_independent_integration_of_the_ode() {
        for cable in cables() {
            let c = cable.solve();
            let (h, v, w, ea) = (c.horizontal, c.vertical_a, cable.weight, cable.ea);
            let f = |s: f64, _y: &[f64; 2]| {
                let nz = w * s - v;
                let t = h.hypot(nz);
                let stretch = 1.0 + t / ea;
                [stretch * h / t, stretch * nz / t]
            };
            let (nodes, states) = Gbs::new(64, 8).integrate_grid(&f, 0.0, 1.0, &[0.0, 0.0]);
            for (s, y) in nodes.iter().zip(&states) {
                let p = c.position(*s);
                assert!(
                    (p[0] - y[0]).abs() < 1e-12 && (p[1] - y[1]).abs() < 1e-12,
                    "{cable:?} at s={s}: {p:?} vs {y:?}"
                );
            }
            let end = states.last().unwrap();
            assert!((end[0] - cable.span).abs() < 1e-12, "{cable:?}");
            assert!((end[1] - cable.rise).abs() < 1e-12, "{cable:?}");
            assert!(c.vertical_a + c.vertical_b - w * cable.length == 0.0);
        }
    }

    #[test]
    fn symmetric_cable_shares_its_weight_and_stiff_cable_is_the_catenary() {
        let cable = Cable {
            length: 1.0,
            weight: 2.0,
            ea: 1e15,
            span: 0.6,
            rise: 0.0,
        };
        let c = cable.solve();
        assert!((c.vertical_a - 1.0).abs() < 1e-12);
        let h0 = cable.inextensible_horizontal_pull();
        assert!(
            ((c.horizontal - h0) / h0).abs() < 1e-9,
            "{} vs {h0}",
            c.horizontal
        );
        // Inextensible catenary sag: (H/w)(cosh(wa/2H) − 1).
        let sag = (h0 / 2.0) * ((2.0 * 0.6 / (2.0 * h0)).cosh() - 1.0);
        assert!(
            (c.mid_span_sag() - sag).abs() < 1e-10,
            "{} vs {sag}",
            c.mid_span_sag()
        );
        // Stretch lowers the pull: a softer cable hangs deeper.
        let soft = Cable { ea: 20.0, ..cable }.solve();
        assert!(soft.horizontal < c.horizontal && soft.mid_span_sag() > sag);
    }
}

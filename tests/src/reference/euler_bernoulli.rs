//! Closed-form linear (Euler–Bernoulli and Timoshenko) beam results.
//!
//! Conventions: the beam lies on `x ∈ [0, L]` (m) and is clamped at
//! `x = 0` (`w(0) = w'(0) = 0`).  Transverse loads and the deflection
//! `w(x)` (m) are measured along the same axis, so a positive load gives a
//! positive deflection.  The bending moment is `M(x) = EI w''(x)` (N·m);
//! for a load `P` at `x = b` it is `M(x) = P (b − x)` for `x < b`, i.e.
//! `M` is the moment `m = EI θ'` of the planar rod in
//! [`super::reissner_planar`] when `w ≡ y` and the loads point along `+y`.
//! Reactions are reported as the forces/moments the supports exert,
//! counted positive when they oppose positive loads.
//!
//! Formulas (EI in N·m², lengths in m, P in N, q in N/m):
//!
//! * cantilever, tip load `P`: `w(L) = P L³/(3EI)`, `w'(L) = P L²/(2EI)`,
//!   clamp moment `P L`, clamp force `P`; Timoshenko adds the shear
//!   deflection `P L/(kGA)` (cross-section rotation unchanged, centreline
//!   slope `+P/(kGA)`);
//! * cantilever, point load `P` at `b`: `w(x) = P x² (3b − x)/(6EI)` for
//!   `x ≤ b`, `w(x) = P b² (3x − b)/(6EI)` for `x ≥ b`;
//! * cantilever, uniform load `q`: `w(x) = q x² (6L² − 4Lx + x²)/(24EI)`;
//! * propped cantilever (extra simple support at `x = a`, `0 < a ≤ L`):
//!   compatibility `w_load(a) = R a³/(3EI)` gives
//!   `R = q (6L² − 4La + a²)/(8a)` (uniform `q`; `= 3qL/8` for `a = L`),
//!   `R = P (3b − a)/(2a)` for a point load at `b ≥ a`,
//!   `R = P b² (3a − b)/(2a³)` for `b ≤ a` (`= 5P/16` for `a = L, b = L/2`).

/// Result for a cantilever with a transverse tip load.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CantileverTipLoad {
    /// Tip deflection `w(L)` (m).
    pub tip_deflection: f64,
    /// Tip cross-section rotation `ψ(L) = P L²/(2EI)` (rad).
    pub tip_rotation: f64,
    /// Tip centreline slope `w'(L)` (rad, small-angle); equals
    /// `tip_rotation` without shear, `tip_rotation + P/(kGA)` with shear.
    pub tip_slope: f64,
    /// Clamp moment `M(0) = P L` (N·m).
    pub clamp_moment: f64,
    /// Clamp reaction force `P` (N).
    pub clamp_force: f64,
}

/// Euler–Bernoulli cantilever of length `length` (m) and bending stiffness
/// `ei` (N·m²) under a perpendicular tip load `load` (N):
/// `w(L) = P L³/(3EI)`, `ψ(L) = P L²/(2EI)`, `M(0) = P L`.
pub fn cantilever_tip_load(length: f64, ei: f64, load: f64) -> CantileverTipLoad {
    cantilever_tip_load_timoshenko(length, ei, f64::INFINITY, load)
}

/// Timoshenko cantilever: as [`cantilever_tip_load`] plus the shear
/// deflection `P L/(kGA)` and shear slope `P/(kGA)`; `kga` (N) is the
/// effective shear stiffness (shear correction factor included, the `GA`
/// of the Reissner rod).  `kga = ∞` gives Euler–Bernoulli.
pub fn cantilever_tip_load_timoshenko(
    length: f64,
    ei: f64,
    kga: f64,
    load: f64,
) -> CantileverTipLoad {
    let rotation = load * length * length / (2.0 * ei);
    CantileverTipLoad {
        tip_deflection: load * length.powi(3) / (3.0 * ei) + load * length / kga,
        tip_rotation: rotation,
        tip_slope: rotation + load / kga,
        clamp_moment: load * length,
        clamp_force: load,
    }
}

/// Cantilever under a tip couple `moment` (N·m): returns
/// `[w(L), w'(L)] = [M L²/(2EI), M L/EI]` (m, rad).
pub fn cantilever_tip_moment(length: f64, ei: f64, moment: f64) -> [f64; 2] {
    [moment * length * length / (2.0 * ei), moment * length / ei]
}

/// Deflection `w(x)` (m) of a cantilever clamped at 0 under a point load
/// `load` (N) at `x = load_position` (m): `P x²(3b − x)/(6EI)` for
/// `x ≤ b`, `P b²(3x − b)/(6EI)` beyond.
pub fn cantilever_point_load_deflection(x: f64, load_position: f64, load: f64, ei: f64) -> f64 {
    let b = load_position;
    if x <= b {
        load * x * x * (3.0 * b - x) / (6.0 * ei)
    } else {
        load * b * b * (3.0 * x - b) / (6.0 * ei)
    }
}

/// Slope `w'(x)` (rad) for [`cantilever_point_load_deflection`]:
/// `P x (2b − x)/(2EI)` for `x ≤ b`, `P b²/(2EI)` beyond.
pub fn cantilever_point_load_slope(x: f64, load_position: f64, load: f64, ei: f64) -> f64 {
    let b = load_position;
    if x <= b {
        load * x * (2.0 * b - x) / (2.0 * ei)
    } else {
        load * b * b / (2.0 * ei)
    }
}

/// Deflection `w(x)` (m) of a cantilever of length `length` (m) under a
/// uniform load `q` (N/m): `q x² (6L² − 4Lx + x²)/(24EI)`.
pub fn cantilever_uniform_load_deflection(x: f64, length: f64, q: f64, ei: f64) -> f64 {
    q * x * x * (6.0 * length * length - 4.0 * length * x + x * x) / (24.0 * ei)
}

/// Slope `w'(x)` (rad) for [`cantilever_uniform_load_deflection`]:
/// `q x (3L² − 3Lx + x²)/(6EI)`.
pub fn cantilever_uniform_load_slope(x: f64, length: f64, q: f64, ei: f64) -> f64 {
    q * x * (3.0 * length * length - 3.0 * length * x + x * x) / (6.0 * ei)
}

/// Transverse load on a beam.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BeamLoad {
    /// Uniform load `q` (N/m) over the whole length.
    Uniform {
        /// Load per unit length (N/m).
        q: f64,
    },
    /// Point load `force` (N) at `x = position` (m).
    Point {
        /// Abscissa of the load (m).
        position: f64,
        /// Load (N).
        force: f64,
    },
}

/// Support reaction `R` (N) of a propped cantilever (clamped at 0, free
/// end at `length`, simple support at `x = support`) under a uniform load
/// `q` (N/m): `R = q (6L² − 4La + a²)/(8a)`.
pub fn propped_reaction_uniform(length: f64, support: f64, q: f64) -> f64 {
    let (l, a) = (length, support);
    q * (6.0 * l * l - 4.0 * l * a + a * a) / (8.0 * a)
}

/// Support reaction `R` (N) of a cantilever clamped at 0 with a simple
/// support at `x = support` (m) under a point load `load` (N) at
/// `x = load_position` (m): `R = P (3b − a)/(2a)` for `b ≥ a`,
/// `R = P b² (3a − b)/(2a³)` for `b ≤ a`.
pub fn propped_reaction_point(support: f64, load_position: f64, load: f64) -> f64 {
    let (a, b) = (support, load_position);
    if b >= a {
        load * (3.0 * b - a) / (2.0 * a)
    } else {
        load * b * b * (3.0 * a - b) / (2.0 * a * a * a)
    }
}

/// Propped cantilever: clamped at `x = 0`, free end at `x = L`, simple
/// (point) support at `x = a`, under one [`BeamLoad`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProppedCantilever {
    /// Length `L` (m).
    pub length: f64,
    /// Bending stiffness `EI` (N·m²).
    pub ei: f64,
    /// Support abscissa `a` (m), `0 < a ≤ L`.
    pub support: f64,
    /// The load.
    pub load: BeamLoad,
    /// Support reaction `R` (N), positive opposing positive loads.
    pub reaction: f64,
    /// Clamp reaction force `V(0) = total load − R` (N).
    pub clamp_force: f64,
    /// Clamp moment `M(0) = EI w''(0) = (moment of the load about 0) − R a`
    /// (N·m).
    pub clamp_moment: f64,
}

impl ProppedCantilever {
    /// Solves the propped cantilever of length `length` (m), stiffness
    /// `ei` (N·m²), support at `support` (m) under `load`.
    pub fn new(length: f64, ei: f64, support: f64, load: BeamLoad) -> Self {
        let (reaction, total, moment) = match load {
            BeamLoad::Uniform { q } => (
                propped_reaction_uniform(length, support, q),
                q * length,
                0.5 * q * length * length,
            ),
            BeamLoad::Point { position, force } => (
                propped_reaction_point(support, position, force),
                force,
                force * position,
            ),
        };
        Self {
            length,
            ei,
            support,
            load,
            reaction,
            clamp_force: total - reaction,
            clamp_moment: moment - reaction * support,
        }
    }

    /// Deflection `w(x)` (m) by superposition of the load and the reaction.
    pub fn deflection(&self, x: f64) -> f64 {
        let w_load = match self.load {
            BeamLoad::Uniform { q } => {
                cantilever_uniform_load_deflection(x, self.length, q, self.ei)
            }
            BeamLoad::Point { position, force } => {
                cantilever_point_load_deflection(x, position, force, self.ei)
            }
        };
        w_load - cantilever_point_load_deflection(x, self.support, self.reaction, self.ei)
    }

    /// Slope `w'(x)` (rad).
    pub fn slope(&self, x: f64) -> f64 {
        let s_load = match self.load {
            BeamLoad::Uniform { q } => cantilever_uniform_load_slope(x, self.length, q, self.ei),
            BeamLoad::Point { position, force } => {
                cantilever_point_load_slope(x, position, force, self.ei)
            }
        };
        s_load - cantilever_point_load_slope(x, self.support, self.reaction, self.ei)
    }

    /// Bending moment `M(x) = EI w''(x)` (N·m) from statics of the part
    /// `[x, L]`.
    pub fn bending_moment(&self, x: f64) -> f64 {
        let m_load = match self.load {
            BeamLoad::Uniform { q } => 0.5 * q * (self.length - x).powi(2),
            BeamLoad::Point { position, force } => force * (position - x).max(0.0),
        };
        m_load - self.reaction * (self.support - x).max(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::super::ode::Gbs;
    use super::*;

    /// Independent check: integrates `EI w'' = M(x)`, `w(0) = w'(0) = 0`
    /// numerically (piecewise between the kinks of `M`) and returns
    /// `[w, w']` at `x`.
    fn integrate_beam(moment: impl Fn(f64) -> f64, ei: f64, kinks: &[f64], x: f64) -> [f64; 2] {
        // y = [w, w']: w' = y[1], y[1]' = M/EI.
        let g = |s: f64, y: &[f64; 2]| [y[1], moment(s) / ei];
        let mut knots: Vec<f64> = kinks
            .iter()
            .copied()
            .filter(|&k| k > 0.0 && k < x)
            .collect();
        knots.push(0.0);
        knots.push(x);
        knots.sort_by(f64::total_cmp);
        knots.dedup();
        let mut y = [0.0, 0.0];
        for w in knots.windows(2) {
            y = Gbs::new(8, 6).integrate(&g, w[0], w[1], &y);
        }
        y
    }

    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol * (1.0 + b.abs())
    }

    #[test]
    fn cantilever_tip_load_matches_integration() {
        let (l, ei, p) = (1.7, 2.3, 0.9);
        let c = cantilever_tip_load(l, ei, p);
        let [w, dw] = integrate_beam(|x| p * (l - x), ei, &[], l);
        assert!(close(c.tip_deflection, w, 1e-13) && close(c.tip_slope, dw, 1e-13));
        assert!(close(c.tip_rotation, dw, 1e-13));
        assert!(close(c.clamp_moment, p * l, 1e-15) && c.clamp_force == p);
        for x in [0.3, 0.8, 1.7] {
            let [w, dw] = integrate_beam(|s| p * (l - s), ei, &[], x);
            assert!(close(
                cantilever_point_load_deflection(x, l, p, ei),
                w,
                1e-13
            ));
            assert!(close(cantilever_point_load_slope(x, l, p, ei), dw, 1e-13));
        }
    }

    #[test]
    fn timoshenko_matches_integration() {
        // ψ' = M/EI, w' = ψ + V/kGA with V = P.
        let (l, ei, kga, p) = (2.0, 3.0, 40.0, 1.5);
        let c = cantilever_tip_load_timoshenko(l, ei, kga, p);
        let f = |x: f64, y: &[f64; 2]| [y[1] + p / kga, p * (l - x) / ei];
        let [w, psi] = Gbs::new(8, 6).integrate(&f, 0.0, l, &[0.0, 0.0]);
        assert!(close(c.tip_deflection, w, 1e-13));
        assert!(close(c.tip_rotation, psi, 1e-13));
        assert!(close(c.tip_slope, psi + p / kga, 1e-13));
        let eb = cantilever_tip_load(l, ei, p);
        assert!(close(
            c.tip_deflection - eb.tip_deflection,
            p * l / kga,
            1e-13
        ));
    }

    #[test]
    fn tip_moment_matches_integration() {
        let (l, ei, m) = (1.3, 0.7, 0.4);
        let [w, dw] = integrate_beam(|_| m, ei, &[], l);
        let [wc, dwc] = cantilever_tip_moment(l, ei, m);
        assert!(close(wc, w, 1e-13) && close(dwc, dw, 1e-13));
    }

    #[test]
    fn point_and_uniform_cantilever_deflections() {
        let (l, ei, p, b, q) = (2.0, 1.3, 0.7, 1.2, 0.45);
        for x in [0.2, 1.0, 1.2, 1.5, 2.0] {
            let [w, dw] = integrate_beam(|s| p * (b - s).max(0.0), ei, &[b], x);
            assert!(close(
                cantilever_point_load_deflection(x, b, p, ei),
                w,
                1e-13
            ));
            assert!(close(cantilever_point_load_slope(x, b, p, ei), dw, 1e-13));
            let [w, dw] = integrate_beam(|s| 0.5 * q * (l - s).powi(2), ei, &[], x);
            assert!(close(
                cantilever_uniform_load_deflection(x, l, q, ei),
                w,
                1e-13
            ));
            assert!(close(cantilever_uniform_load_slope(x, l, q, ei), dw, 1e-13));
        }
        // Maxwell–Betti reciprocity.
        let (x1, x2) = (0.6, 1.7);
        assert!(close(
            cantilever_point_load_deflection(x1, x2, 1.0, ei),
            cantilever_point_load_deflection(x2, x1, 1.0, ei),
            1e-15
        ));
    }

    #[test]
    fn classic_propped_cantilever_values() {
        let (l, q, p) = (3.0, 2.0, 5.0);
        assert!(close(
            propped_reaction_uniform(l, l, q),
            3.0 * q * l / 8.0,
            1e-15
        ));
        assert!(close(
            propped_reaction_point(l, l / 2.0, p),
            5.0 * p / 16.0,
            1e-15
        ));
        let u = ProppedCantilever::new(l, 1.0, l, BeamLoad::Uniform { q });
        assert!(close(u.clamp_force, 5.0 * q * l / 8.0, 1e-15));
        assert!(close(u.clamp_moment, q * l * l / 8.0, 1e-15));
        let c = ProppedCantilever::new(
            l,
            1.0,
            l,
            BeamLoad::Point {
                position: l / 2.0,
                force: p,
            },
        );
        assert!(close(c.clamp_force, 11.0 * p / 16.0, 1e-15));
        assert!(close(c.clamp_moment, 3.0 * p * l / 16.0, 1e-15));
        // Load applied at the support: carried entirely by the support.
        assert!(close(propped_reaction_point(1.3, 1.3, p), p, 1e-15));
    }

    /// Compatibility solved numerically: `R = w_load(a) / w_unit(a)` with
    /// both deflections from ODE integration, then the full deflection
    /// curve of the propped beam is integrated with that `R`.
    fn check_propped(beam: ProppedCantilever, load_moment: impl Fn(f64) -> f64, kinks: &[f64]) {
        let (a, ei) = (beam.support, beam.ei);
        let w_load = integrate_beam(&load_moment, ei, kinks, a)[0];
        let w_unit = integrate_beam(|s| (a - s).max(0.0), ei, &[a], a)[0];
        let r = w_load / w_unit;
        assert!(close(beam.reaction, r, 1e-12), "{} vs {r}", beam.reaction);
        assert!(beam.deflection(a).abs() < 1e-13);
        let total = |s: f64| load_moment(s) - r * (a - s).max(0.0);
        let mut all_kinks = kinks.to_vec();
        all_kinks.push(a);
        for x in [0.25, 0.5, a, 0.5 * (a + beam.length), beam.length] {
            let [w, dw] = integrate_beam(total, ei, &all_kinks, x);
            assert!(close(beam.deflection(x), w, 1e-12));
            assert!(close(beam.slope(x), dw, 1e-12));
            assert!(close(beam.bending_moment(x), total(x), 1e-13));
        }
        assert!(close(beam.clamp_moment, total(0.0), 1e-13));
    }

    #[test]
    fn propped_cantilever_uniform_load() {
        let (l, ei, q) = (2.0, 1.7, 0.8);
        for a in [0.7, 1.5, 2.0] {
            let beam = ProppedCantilever::new(l, ei, a, BeamLoad::Uniform { q });
            check_propped(beam, |s| 0.5 * q * (l - s).powi(2), &[]);
            assert!(close(beam.clamp_force + beam.reaction, q * l, 1e-15));
        }
    }

    #[test]
    fn propped_cantilever_point_load() {
        let (l, ei, p) = (2.0, 0.9, 1.3);
        for (a, b) in [(1.5, 0.6), (1.5, 1.9), (2.0, 1.0), (1.0, 1.0)] {
            let load = BeamLoad::Point {
                position: b,
                force: p,
            };
            let beam = ProppedCantilever::new(l, ei, a, load);
            check_propped(beam, |s| p * (b - s).max(0.0), &[b]);
            assert!(close(beam.clamp_force + beam.reaction, p, 1e-15));
        }
    }
}

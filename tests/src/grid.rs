//! The convergence map: a deterministic sample of single-rod problems spanning the
//! parameter ranges the solver must handle with default settings (issue 9).
//!
//! The grid is plain data (no dependency on the rest of the workspace, like the
//! references): the validation test `convergence_map` turns each [`GridCase`] into a
//! `strand_system::System`. Every case is a rod of length [`GridCase::LENGTH`] whose
//! start is held at the origin with its tangent along `+x` and whose end is held at
//! `(span·L, 0, 0)` (tangent `+x`) or free, possibly with a clip at the middle vertex,
//! gravity along `−z`, a dead force at a free end, and an initial-guess route.
//!
//! Factors and levels:
//! * ends: start ∈ {clamp, pin, port (clamped) on a fixed body, port (ball) on a fixed
//!   body}; end ∈ the same plus free;
//! * `EI` ∈ {10, 1, 0.1, 1e-2, 1e-4, 1e-6} N·m², `GJ = EI/1.5`;
//! * `EA/EI` ∈ {1e2, 1e4, …, 1e12} 1/m², restricted to `1e2 ≤ EA ≤ 1e10` N,
//!   `GA = EA/3`;
//! * edges ∈ {10, 20, 50, 100, 200} and, rarely (1 case in 25), 1000;
//! * span/L ∈ {0.3, 0.6, 0.9, 0.99, 0.999} (held ends only);
//! * gravity on/off (0.5 kg/m); a dead force at a free end (always when the end is
//!   free and there is no gravity, so that the problem has a unique solution);
//! * route on/off; clip at the middle vertex: none, fixed, revolute (about `y`),
//!   spherical.
//!
//! The levels are combined by a fixed pseudo-random sequence (SplitMix64, seed
//! constant), so the sample is reproducible and covers every level of every factor.

/// How a rod end is held.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EndKind {
    /// Clamped to a connector (position and frame).
    Clamp,
    /// Pinned to a connector (position only).
    Pin,
    /// Free end.
    Free,
    /// Clamped to the port of a fixed body.
    PortClamp,
    /// Ball-jointed to the port of a fixed body.
    PortPin,
}

/// The joint of a clip at the middle vertex.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ClipKind {
    /// A rigid clip.
    Fixed,
    /// A hinge about the world `y` axis.
    Revolute,
    /// A ball joint.
    Spherical,
}

/// One problem of the convergence map.
#[derive(Clone, Debug, PartialEq)]
pub struct GridCase {
    /// Index in the grid.
    pub index: usize,
    /// Start support (never [`EndKind::Free`]).
    pub start: EndKind,
    /// End support.
    pub end: EndKind,
    /// Bending stiffness `EI` (N·m²).
    pub ei: f64,
    /// Axial stiffness `EA` (N).
    pub ea: f64,
    /// Number of edges (even).
    pub segments: usize,
    /// End distance as a fraction of the length (held ends only; 1 for a free end).
    pub span: f64,
    /// Gravity `(0, 0, −9.81)` m/s² with 0.5 kg/m.
    pub gravity: bool,
    /// A dead force of 1 N along `(0.3, 0.4, −0.866)` at a free end.
    pub dead_load: bool,
    /// Whether the initial guess follows a route (a bent polyline of length `L`).
    pub route: bool,
    /// A clip at the middle vertex.
    pub clip: Option<ClipKind>,
}

impl GridCase {
    /// Rod length (m).
    pub const LENGTH: f64 = 1.0;
    /// Mass per length with gravity (kg/m).
    pub const MASS_PER_LENGTH: f64 = 0.5;

    /// A short label, e.g. `clamp-pin EI=1e-6 EA/EI=1e12 N=200 span=0.99 g load route clip=fixed`.
    pub fn label(&self) -> String {
        let end = |e: EndKind| match e {
            EndKind::Clamp => "clamp",
            EndKind::Pin => "pin",
            EndKind::Free => "free",
            EndKind::PortClamp => "portclamp",
            EndKind::PortPin => "portpin",
        };
        let mut s = format!(
            "#{:03} {}-{} EI={:.0e} EA/EI={:.0e} N={}",
            self.index,
            end(self.start),
            end(self.end),
            self.ei,
            self.ea / self.ei,
            self.segments
        );
        if self.end != EndKind::Free {
            s += &format!(" span={}", self.span);
        }
        if self.gravity {
            s += " g";
        }
        if self.dead_load {
            s += " load";
        }
        if self.route {
            s += " route";
        }
        if let Some(c) = self.clip {
            s += match c {
                ClipKind::Fixed => " clip=fixed",
                ClipKind::Revolute => " clip=hinge",
                ClipKind::Spherical => " clip=ball",
            };
        }
        s
    }
}

/// SplitMix64: a tiny reproducible generator.
struct SplitMix(u64);

impl SplitMix {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    fn pick<T: Copy>(&mut self, levels: &[T]) -> T {
        levels[(self.next() % levels.len() as u64) as usize]
    }
}

/// The convergence map: `count` cases (the test uses 200).
pub fn convergence_grid(count: usize) -> Vec<GridCase> {
    use EndKind::*;
    let starts = [Clamp, Pin, PortClamp, PortPin];
    let ends = [Clamp, Pin, Free, PortClamp, PortPin];
    let eis = [10.0, 1.0, 0.1, 1e-2, 1e-4, 1e-6];
    let ratios = [1e2, 1e4, 1e6, 1e8, 1e10, 1e12];
    let meshes = [10, 20, 50, 100, 200];
    let spans = [0.3, 0.6, 0.9, 0.99, 0.999];
    let clips = [
        None,
        None,
        Some(ClipKind::Fixed),
        Some(ClipKind::Revolute),
        Some(ClipKind::Spherical),
    ];
    let mut rng = SplitMix(0x5354_5241_4E44_0009);
    let mut out = Vec::with_capacity(count);
    while out.len() < count {
        let index = out.len();
        let start = rng.pick(&starts);
        let end = rng.pick(&ends);
        let ei = rng.pick(&eis);
        let feasible: Vec<f64> = ratios
            .iter()
            .map(|r| r * ei)
            .filter(|ea| (1e2..=1e10).contains(ea))
            .collect();
        let ea = rng.pick(&feasible);
        let segments = if index % 25 == 24 {
            1000
        } else {
            rng.pick(&meshes)
        };
        let span = if end == Free { 1.0 } else { rng.pick(&spans) };
        let gravity = rng.next().is_multiple_of(2);
        let dead_load = end == Free && (!gravity || rng.next().is_multiple_of(2));
        let route = rng.next().is_multiple_of(2);
        let clip = rng.pick(&clips);
        out.push(GridCase {
            index,
            start,
            end,
            ei,
            ea,
            segments,
            span,
            gravity,
            dead_load,
            route,
            clip,
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_covers_every_level_and_is_reproducible() {
        let grid = convergence_grid(200);
        assert_eq!(grid, convergence_grid(200));
        for kind in [
            EndKind::Clamp,
            EndKind::Pin,
            EndKind::Free,
            EndKind::PortClamp,
            EndKind::PortPin,
        ] {
            assert!(grid.iter().any(|c| c.end == kind), "{kind:?}");
        }
        for ei in [10.0, 1.0, 0.1, 1e-2, 1e-4, 1e-6] {
            assert!(grid.iter().any(|c| c.ei == ei));
        }
        assert!(grid.iter().any(|c| c.ea / c.ei >= 1e12 * 0.999));
        assert!(grid.iter().any(|c| c.span == 0.999));
        let big = grid.iter().filter(|c| c.segments == 1000).count();
        assert!((5..=10).contains(&big), "{big}");
        assert!(
            grid.iter()
                .all(|c| c.segments % 2 == 0 && c.start != EndKind::Free)
        );
        assert!(
            grid.iter()
                .all(|c| c.end != EndKind::Free || c.gravity || c.dead_load)
        );
    }
}

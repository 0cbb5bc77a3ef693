//! Reference geometry of a discrete rod and its configurations.

use nalgebra::{UnitQuaternion, Vector3};

use crate::Section;

/// A discrete rod: its section and the stress-free reference (edge lengths `h_{j-1/2}`,
/// rest strains `Γ0` per edge, rest curvatures `K0` per vertex).
#[derive(Clone, Debug, PartialEq)]
pub struct Rod {
    section: Section,
    edge_lengths: Vec<f64>,
    rest_strains: Vec<Vector3<f64>>,
    rest_curvatures: Vec<Vector3<f64>>,
    /// Sum of the edge lengths in m, computed once ([`Rod::length`] is called per
    /// edge in places; summing there made model building quadratic).
    length: f64,
}

/// A configuration of one rod: `N+1` vertices and `N` edge frames.
///
/// Positions carry a compensation term (the low-order part of a double-double sum):
/// edge vectors `r_{j+1} − r_j` of short edges far from the origin would otherwise lose
/// digits to the rounding of absolute coordinates, which caps the attainable force
/// residual at about `EA · ulp(|r|) / h` (3e-9 N for EA = 30 kN, h = 1 mm). With it,
/// the force residual can be driven to `EA · 1e-16`.
#[derive(Debug, PartialEq)]
pub struct RodState {
    /// Vertex positions `r_0..r_N` in m.
    pub positions: Vec<Vector3<f64>>,
    /// Edge frames `q_{1/2}..q_{N-1/2}` (`a3 = q e3` is the section normal).
    pub frames: Vec<UnitQuaternion<f64>>,
    /// Low-order parts of the positions in m (`r = positions + compensation`).
    compensation: Vec<Vector3<f64>>,
}

impl Clone for RodState {
    fn clone(&self) -> Self {
        Self {
            positions: self.positions.clone(),
            frames: self.frames.clone(),
            compensation: self.compensation.clone(),
        }
    }

    /// Reuses the allocations of `self` (the line search clones states per trial).
    fn clone_from(&mut self, source: &Self) {
        self.positions.clone_from(&source.positions);
        self.frames.clone_from(&source.frames);
        self.compensation.clone_from(&source.compensation);
    }
}

/// `a + b = s + e` exactly (Knuth's TwoSum).
#[inline]
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// Why a rod could not be built.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum RodError {
    /// Length or an edge length is not a finite positive number.
    #[error("rod length must be a finite number > 0 m (got {0} m)")]
    Length(f64),
    /// Fewer than one edge.
    #[error("a rod needs at least 1 segment (got {0})")]
    Segments(usize),
    /// Array sizes do not match the number of edges / vertices.
    #[error("{what}: expected {expected} entries, got {got}")]
    Size {
        /// Which array.
        what: &'static str,
        /// Expected count.
        expected: usize,
        /// Given count.
        got: usize,
    },
    /// A rest strain or curvature is not finite.
    #[error("{0} contains a value that is not finite")]
    NotFinite(&'static str),
}

impl Rod {
    /// A straight, stress-free rod of `length` m cut into `segments` equal edges
    /// (`Γ0 = e3`, `K0 = 0`).
    pub fn try_straight(section: Section, length: f64, segments: usize) -> Result<Self, RodError> {
        if segments == 0 {
            return Err(RodError::Segments(segments));
        }
        if !(length.is_finite() && length > 0.0) {
            return Err(RodError::Length(length));
        }
        let h = length / segments as f64;
        Self::try_new(
            section,
            vec![h; segments],
            vec![Vector3::z(); segments],
            vec![Vector3::zeros(); segments + 1],
        )
    }

    /// A rod from explicit reference data: `N` edge lengths (m), `N` rest strains and
    /// `N+1` rest curvatures (1/m).
    pub fn try_new(
        section: Section,
        edge_lengths: Vec<f64>,
        rest_strains: Vec<Vector3<f64>>,
        rest_curvatures: Vec<Vector3<f64>>,
    ) -> Result<Self, RodError> {
        let n = edge_lengths.len();
        if n == 0 {
            return Err(RodError::Segments(0));
        }
        if let Some(&bad) = edge_lengths.iter().find(|h| !(h.is_finite() && **h > 0.0)) {
            return Err(RodError::Length(bad));
        }
        if rest_strains.len() != n {
            return Err(RodError::Size {
                what: "rest strains",
                expected: n,
                got: rest_strains.len(),
            });
        }
        if rest_curvatures.len() != n + 1 {
            return Err(RodError::Size {
                what: "rest curvatures",
                expected: n + 1,
                got: rest_curvatures.len(),
            });
        }
        if rest_strains
            .iter()
            .any(|g| !g.iter().all(|x| x.is_finite()))
        {
            return Err(RodError::NotFinite("rest strains"));
        }
        if rest_curvatures
            .iter()
            .any(|k| !k.iter().all(|x| x.is_finite()))
        {
            return Err(RodError::NotFinite("rest curvatures"));
        }
        let length = edge_lengths.iter().sum();
        Ok(Self {
            section,
            edge_lengths,
            rest_strains,
            rest_curvatures,
            length,
        })
    }

    /// The same rod (reference lengths, rest strains and curvatures) with another
    /// cross section.
    pub fn with_section(&self, section: Section) -> Self {
        Self {
            section,
            ..self.clone()
        }
    }

    /// How many real numbers [`Rod::visit_reals`] visits: the section's eight, one per
    /// edge length and three per rest strain and rest curvature.
    pub fn real_count(&self) -> usize {
        8 + self.edge_lengths.len() + 3 * (self.rest_strains.len() + self.rest_curvatures.len())
    }

    /// Visits every real number of the reference data in a fixed order — the
    /// section's stiffnesses (N, N·m²), mass per length (kg/m) and outer radius (m),
    /// then the edge lengths (m), rest strains and rest curvatures (1/m) — letting `f`
    /// change them; the length is recomputed after. The order depends only on the
    /// number of edges, so two rods of the same segments can be combined value by
    /// value (a design's model moved along a parameter, `strand_system::System::reals`).
    ///
    /// Errors if a changed edge length is not finite and positive or a strain or
    /// curvature not finite (the rod is then left as `f` made it).
    pub fn visit_reals(&mut self, f: &mut dyn FnMut(&mut f64)) -> Result<(), RodError> {
        let s = &mut self.section;
        for x in [
            &mut s.shear_stiffness_1,
            &mut s.shear_stiffness_2,
            &mut s.axial_stiffness,
            &mut s.bending_stiffness_1,
            &mut s.bending_stiffness_2,
            &mut s.torsional_stiffness,
            &mut s.mass_per_length,
            &mut s.outer_radius,
        ] {
            f(x);
        }
        self.edge_lengths.iter_mut().for_each(&mut *f);
        for v in self
            .rest_strains
            .iter_mut()
            .chain(&mut self.rest_curvatures)
        {
            v.iter_mut().for_each(&mut *f);
        }
        self.length = self.edge_lengths.iter().sum();
        if let Some(&bad) = self
            .edge_lengths
            .iter()
            .find(|h| !(h.is_finite() && **h > 0.0))
        {
            return Err(RodError::Length(bad));
        }
        let finite = |v: &[Vector3<f64>]| v.iter().all(|g| g.iter().all(|x| x.is_finite()));
        if !finite(&self.rest_strains) {
            return Err(RodError::NotFinite("rest strains"));
        }
        if !finite(&self.rest_curvatures) {
            return Err(RodError::NotFinite("rest curvatures"));
        }
        Ok(())
    }

    /// The shortest reference edge length in m.
    pub fn shortest_edge(&self) -> f64 {
        self.edge_lengths
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min)
    }

    /// The cross section.
    pub fn section(&self) -> &Section {
        &self.section
    }

    /// Number of edges `N`.
    pub fn segments(&self) -> usize {
        self.edge_lengths.len()
    }

    /// Number of vertices `N + 1`.
    pub fn vertex_count(&self) -> usize {
        self.edge_lengths.len() + 1
    }

    /// Reference length `L` in m (the sum of the edge lengths, stored: O(1)).
    pub fn length(&self) -> f64 {
        self.length
    }

    /// Reference edge length `h_{e+1/2}` of edge `e` (0-based) in m.
    pub fn edge_length(&self, edge: usize) -> f64 {
        self.edge_lengths[edge]
    }

    /// All reference edge lengths in m.
    pub fn edge_lengths(&self) -> &[f64] {
        &self.edge_lengths
    }

    /// Vertex weight `h̄_j` in m: the mean of the adjacent edge lengths inside, half
    /// the edge length at the ends (paper eq. 6).
    pub fn vertex_weight(&self, vertex: usize) -> f64 {
        let before = if vertex > 0 {
            self.edge_lengths[vertex - 1]
        } else {
            0.0
        };
        let after = self.edge_lengths.get(vertex).copied().unwrap_or(0.0);
        0.5 * (before + after)
    }

    /// Lumped vertex mass `h̄_j ρ_L` in kg (paper eq. 7).
    pub fn vertex_mass(&self, vertex: usize) -> f64 {
        self.vertex_weight(vertex) * self.section.mass_per_length
    }

    /// Total mass in kg.
    pub fn mass(&self) -> f64 {
        self.length() * self.section.mass_per_length
    }

    /// Rest strain `Γ0` of edge `e`.
    pub fn rest_strain(&self, edge: usize) -> &Vector3<f64> {
        &self.rest_strains[edge]
    }

    /// Rest curvature `K0` of vertex `j` in 1/m.
    pub fn rest_curvature(&self, vertex: usize) -> &Vector3<f64> {
        &self.rest_curvatures[vertex]
    }

    /// Reference arc length `s_j` of every vertex in m.
    pub fn arc_lengths(&self) -> Vec<f64> {
        let mut s = Vec::with_capacity(self.vertex_count());
        let mut acc = 0.0;
        s.push(0.0);
        for h in &self.edge_lengths {
            acc += h;
            s.push(acc);
        }
        s
    }
}

impl RodState {
    /// A straight configuration from `start` along the unit `frame`'s `a3` with the
    /// rod's reference edge lengths (its stress-free shape when `Γ0 = e3`, `K0 = 0`).
    pub fn straight(rod: &Rod, start: Vector3<f64>, frame: UnitQuaternion<f64>) -> Self {
        let tangent = frame * Vector3::z();
        let positions = rod
            .arc_lengths()
            .iter()
            .map(|s| start + tangent * *s)
            .collect();
        Self::new(positions, vec![frame; rod.segments()])
    }

    /// A configuration from vertex positions (m) and edge frames.
    pub fn new(positions: Vec<Vector3<f64>>, frames: Vec<UnitQuaternion<f64>>) -> Self {
        let compensation = vec![Vector3::zeros(); positions.len()];
        Self {
            positions,
            frames,
            compensation,
        }
    }

    /// The edge vector `r_{e+1} − r_e` of edge `e` in m, including the compensation.
    #[inline]
    pub fn edge_vector(&self, edge: usize) -> Vector3<f64> {
        (self.positions[edge + 1] - self.positions[edge])
            + (self.compensation[edge + 1] - self.compensation[edge])
    }

    /// The low-order part of vertex `vertex`'s position (m): the position is
    /// `positions[vertex] + compensation(vertex)` to about twice double precision.
    pub fn compensation(&self, vertex: usize) -> Vector3<f64> {
        self.compensation[vertex]
    }

    /// Sets vertex `vertex` to `position` (m), clearing its compensation.
    pub fn set_position(&mut self, vertex: usize, position: Vector3<f64>) {
        self.positions[vertex] = position;
        self.compensation[vertex] = Vector3::zeros();
    }

    /// Moves vertex `vertex` by `delta` (m) with compensated summation.
    pub fn translate_vertex(&mut self, vertex: usize, delta: &Vector3<f64>) {
        let (hi, lo) = (&mut self.positions[vertex], &mut self.compensation[vertex]);
        for i in 0..3 {
            let (s, e) = two_sum(hi[i], delta[i]);
            let (s2, e2) = two_sum(s, lo[i] + e);
            hi[i] = s2;
            lo[i] = e2;
        }
    }

    /// Whether every coordinate is finite.
    pub fn is_finite(&self) -> bool {
        self.positions
            .iter()
            .all(|p| p.iter().all(|x| x.is_finite()))
            && self
                .frames
                .iter()
                .all(|q| q.coords.iter().all(|x| x.is_finite()))
    }
}

//! Frictionless contact of rods with environment meshes and with each other, as the
//! inequality constraints `gap ≥ 0` of the minimisation (DESIGN §2–3). Each rod edge is
//! a capsule of the rod's outer radius; [`strand_contact`] finds the pairs within a
//! search margin and their exact closest points, and each pair becomes a [`Row`]
//! linearised in the positions of the vertices involved (through bodies and clips
//! where those vertices are held). The multipliers of the rows are the contact forces.

use std::hash::{Hash, Hasher};
use std::sync::Arc;

use nalgebra::{Point3, Vector3};
use strand_contact::{Gap, MeshIndex, Obstacle, ObstacleMesh, RodGeometry};
use strand_system::{Model, SystemState};

use crate::constraints::{ConstraintError, Constraints, FarVertex, Row, RowKey};

mod advance;
mod curvature;
mod exclusion;
mod least_mesh_gaps;
#[cfg(test)]
mod least_mesh_gaps_tests;
mod mesh_gaps;
mod mesh_path;
#[cfg(test)]
mod mesh_path_tests;
mod nearby;
mod proximity_cache;
#[cfg(test)]
mod proximity_tests;
#[cfg(test)]
mod scaling_tests;
mod start;
#[cfg(test)]
mod tests;

use curvature::Feature;
use exclusion::Exclusion;
use proximity_cache::ProximityCache;

/// A feature whose gaps to a mesh are all above this many search margins is left out
/// of the rows of [`Constraints::rows_leaving_far`]: the solver checks that each step
/// keeps the feature's vertices within their clearances, else it brings the rows in, so
/// the value only trades rows made against rows brought in. Measured (instructions of
/// the solve, the same 12 iterations; every row: 117.2 M and 227.1 M): 0.02 / 0.05 /
/// 0.1 / 0.25 / 0.5 / 1 margins give 94.0 / 99.7 / 99.4 / 100.7 / 110.0 / 115.7 M on
/// `cooler_hose_contact` and 161.5 / 165.9 / 166.8 / 183.7 / 208.9 M with the 1M
/// surface. A quarter, not less: the drop family (`tests/validation/drop.rs`, chaotic:
/// rounding in the QPs' row order settles a hose into another contact set) keeps its
/// median of 23 iterations with it (three of twelve cases change: 392 → 375 in all),
/// while at 0.1 one case at the median took 30 and so did the median.
pub const FAR_MARGINS: f64 = 0.25;
pub use proximity_cache::ProximitySettings;

/// What tells the gaps of one rod feature (vertex or edge) against one obstacle
/// apart, for the row keys: the mesh's smooth patch (0 for a rod) and which end of a
/// stretch of nearest points on an edge (0: not a stretch end; 1: low; 2: high; 3, 4:
/// the low and high ends of its nearly tied stretch); and
/// the obstacle feature of the nearest point (for the gap's curvature, not the key).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Tag {
    patch: usize,
    end: u8,
    feature: Feature,
}

impl Tag {
    pub(crate) fn new(patch: usize, end: u8, feature: Feature) -> Self {
        Self {
            patch,
            end,
            feature,
        }
    }
}

/// Contact of a model's rods with meshes and with each other.
#[derive(Clone)]
pub struct Contact {
    meshes: Vec<Arc<ObstacleMesh>>,
    /// The meshes' bounding boxes in a BVH: each rod asks only the meshes near it.
    index: MeshIndex,
    margin_m: f64,
    /// Whether a step's reach towards the meshes is measured along its path
    /// (`Contact::mesh_advancement`) rather than from its start alone.
    sampled_advancement: bool,
    /// How the meshes are asked for the triangles near each rod feature.
    proximity: ProximitySettings,
    /// Each feature's candidate triangles from its last search (incremental proximity).
    kept: ProximityCache,
}

/// One contact pair at a state, with its force.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactForce {
    /// The gap's geometry (rod, edge, parameter, points, normal, gap in m).
    pub gap: Gap,
    /// Force on the rod along `gap.normal`, N (≥ 0; 0 for an open pair).
    pub force_n: f64,
    /// The key of the pair's row (its multiplier's key in
    /// [`crate::Solution::constraints`]).
    pub key: RowKey,
}

impl Contact {
    /// Contact against `meshes`, with pairs closer than `margin_m` (surface to surface,
    /// m) entering as constraints. No step carries an edge's centreline through a mesh
    /// (the step is sampled along its path) or two pieces of rod towards each other by
    /// more than half of the larger of the margin and their gap, so nothing beyond the
    /// margin is passed through within one step.
    pub fn new(meshes: Vec<Arc<ObstacleMesh>>, margin_m: f64) -> Self {
        Self {
            index: MeshIndex::new(&meshes),
            meshes,
            margin_m,
            sampled_advancement: true,
            proximity: ProximitySettings::default(),
            kept: ProximityCache::default(),
        }
    }

    /// The same contact asking the meshes as `settings` say (incremental proximity by
    /// default; [`ProximitySettings::full_queries`] searches every feature's triangles
    /// at every evaluation, for comparison). The contacts are the same either way.
    pub fn with_proximity(mut self, settings: ProximitySettings) -> Self {
        self.proximity = settings;
        self.kept = ProximityCache::default();
        self
    }

    /// How the meshes are asked for the triangles near each rod feature.
    pub fn proximity(&self) -> &ProximitySettings {
        &self.proximity
    }

    /// The same contact with the step's reach towards the meshes measured from the
    /// start of the step alone (each edge moves by at most half of the larger of the
    /// margin and its clearance, as before the path was sampled; for comparison) when
    /// `sampled` is false.
    pub fn with_sampled_advancement(mut self, sampled: bool) -> Self {
        self.sampled_advancement = sampled;
        self
    }

    /// A margin suited to `model`: twice its largest outer radius, at least 5 mm.
    pub fn default_margin_m(model: &Model) -> f64 {
        let largest = model
            .system()
            .rods
            .iter()
            .map(|r| r.rod.section().outer_radius)
            .fold(0.0, f64::max);
        (2.0 * largest).max(0.005)
    }

    /// The meshes.
    pub fn meshes(&self) -> &[Arc<ObstacleMesh>] {
        &self.meshes
    }

    /// The contact gaps of `state` within `margin_m` (m).
    ///
    /// Against meshes, every vertex is a sphere of the rod's radius (a gap with `s` = 0,
    /// or 1 for the last vertex) with one gap per local contact — per smooth patch of
    /// the mesh it is near (both flanks of a groove, the faces of a corner; one for a
    /// tessellated plane) — and an edge adds a gap of its own only where its nearest
    /// point on a patch lies strictly inside it and nearer than both its vertices (the
    /// edge crosses a convex feature of the mesh). An edge lying flat on a surface is
    /// thus held at its vertices, where its weight is lumped. Between rods, a pair of
    /// edges within the margin gives a gap where it is a local minimum along the other
    /// rod's edges (one per crossing, one per edge and side of hoses lying along each
    /// other), except near neighbours along one rod (by the current centreline length,
    /// see `Exclusion`).
    pub fn gaps(
        &self,
        model: &Model,
        state: &SystemState,
        margin_m: f64,
    ) -> Result<Vec<Gap>, ConstraintError> {
        untagged(self.tagged_gaps(model, state, margin_m))
    }

    /// The clearances at `state` within `margin_m` (m): the gaps to the meshes as
    /// [`Contact::gaps`] lists them, but only on the edges that may hold a rod's least
    /// gap to each mesh (the least is the same, at the same place), and of every pair
    /// of rods (a rod with itself too) only the least
    /// ([`strand_contact::rod_rod_clearances`]: a search whose reach shrinks to the
    /// least gap found, linear in the edges where listing every pair within a
    /// report's reach is quadratic).
    pub fn clearances(
        &self,
        model: &Model,
        state: &SystemState,
        margin_m: f64,
    ) -> Result<Vec<Gap>, ConstraintError> {
        untagged(self.gaps_of(model, state, margin_m, RodPairs::Least, None, None))
    }

    /// [`Contact::gaps`] with the [`Tag`] that tells the gaps of one feature apart
    /// (for the row keys).
    fn tagged_gaps(
        &self,
        model: &Model,
        state: &SystemState,
        margin_m: f64,
    ) -> Result<Vec<(Gap, Tag)>, ConstraintError> {
        self.gaps_of(model, state, margin_m, RodPairs::LocalMinima, None, None)
    }

    /// The gaps to the meshes and the rod–rod gaps of `pairs` within `margin_m` (m);
    /// with `edges` (per rod, per edge), only the gaps to the meshes of the edges it
    /// marks and their vertices, and the rod–rod gaps whose own (lower) edge it marks
    /// (each kept or dropped as a local minimum among all of that edge's partners:
    /// as without `edges`). With `far`, the mesh gaps of features far from the meshes
    /// are left out and their vertices listed there ([`Constraints::rows_leaving_far`]).
    fn gaps_of(
        &self,
        model: &Model,
        state: &SystemState,
        margin_m: f64,
        pairs: RodPairs,
        edges: Option<&EdgesTouching>,
        far: Option<&mut Vec<FarVertex>>,
    ) -> Result<Vec<(Gap, Tag)>, ConstraintError> {
        let centrelines = centrelines(state);
        let rods = rod_geometries(model, &centrelines);
        let mesh_edges = edges.map(|e| &e.mesh[..]);
        let mut gaps = self.mesh_part(model, &rods, margin_m, pairs, mesh_edges, far)?;
        // Arc lengths once per evaluation, not per candidate pair.
        let exclusion = Exclusion::new(model, state);
        let exclude = |rod_a: usize, edge_a: usize, rod_b: usize, edge_b: usize| {
            exclusion.excluded(rod_a, edge_a, rod_b, edge_b)
        };
        let between_rods = match pairs {
            RodPairs::LocalMinima => strand_contact::rod_rod_minima_of(
                &rods,
                margin_m,
                exclude,
                edges.map(|e| &e.pairs[..]),
            ),
            RodPairs::Least => strand_contact::rod_rod_clearances(&rods, margin_m, exclude),
        }
        .map_err(|e| describe_error(model, e))?;
        gaps.extend(
            between_rods
                .into_iter()
                .map(|gap| (gap, Tag::new(0, 0, Feature::Point))),
        );
        add_low_order(state, &mut gaps);
        Ok(gaps)
    }

    /// The gaps of every rod to the meshes within `margin_m` (m): with
    /// [`RodPairs::Least`], only those of the edges that may hold the rod's least gap
    /// to each mesh ([`Contact::least_gap_edges`]); else those of the edges `edges`
    /// marks where given.
    fn mesh_part(
        &self,
        model: &Model,
        rods: &[RodGeometry<'_>],
        margin_m: f64,
        pairs: RodPairs,
        edges: Option<&[Vec<bool>]>,
        far: Option<&mut Vec<FarVertex>>,
    ) -> Result<Vec<(Gap, Tag)>, ConstraintError> {
        let mut gaps = Vec::new();
        let slack_m = self.proximity.slack_margins.max(0.0) * self.margin_m;
        // A search beyond the solver's margin (a report's clearances) is a one-off: its
        // features are searched afresh with no slack (the least list, the same gaps)
        // and neither use nor replace the solve's kept lists. A search of some edges
        // only (the rows near a sensitivity's active rows, at states near the base)
        // keeps and reuses lists like a solve's iterates: the same gaps either way.
        let one_off = ProximityCache::default();
        let mut lists = self.proximity.incremental.then(|| {
            if margin_m > self.margin_m {
                one_off.begin(0.0)
            } else {
                self.kept.begin(slack_m)
            }
        });
        // Far features are told apart by their kept lists, so only with those.
        if let (Some(lists), Some(_)) = (lists.as_mut(), &far) {
            lists.leave_far(FAR_MARGINS * self.margin_m);
        }
        for (rod, geometry) in rods.iter().enumerate() {
            let reach = geometry.radius + margin_m;
            for index in self.meshes_near(geometry.vertices, reach) {
                let mesh = &self.meshes[index];
                // The least gaps: only the edges that may hold them, searched only as
                // far as them.
                let (only, margin_m) = match pairs {
                    RodPairs::LocalMinima => (edges.map(|edges| edges[rod].clone()), margin_m),
                    RodPairs::Least => match Self::least_gap_edges(mesh, geometry, reach) {
                        Some((edges, within)) => (Some(edges), within - geometry.radius),
                        None => continue,
                    },
                };
                let lists = lists.as_mut();
                self.mesh_gaps(
                    model,
                    rod,
                    geometry,
                    index,
                    mesh,
                    margin_m,
                    lists,
                    only.as_deref(),
                    &mut gaps,
                )?;
            }
        }
        if let (Some(lists), Some(far)) = (lists.as_mut(), far) {
            far.append(&mut lists.far_vertices());
        }
        Ok(gaps)
    }

    /// The contact pairs at the end of a solve with their forces (the multipliers of
    /// `constraints`, as in [`crate::Solution::constraints`]).
    pub fn forces(
        &self,
        model: &Model,
        state: &SystemState,
        constraints: &[(Row, f64)],
    ) -> Result<Vec<ContactForce>, ConstraintError> {
        let gaps = self.tagged_gaps(model, state, self.margin_m)?;
        Ok(with_forces(gaps, constraints))
    }

    /// The pairs of [`Contact::forces`] that carry a force (a positive multiplier in
    /// `constraints`), in its order, with the same numbers: only the edges whose rows
    /// may be those with a force are searched (next to the vertices those rows move,
    /// as [`Constraints::rows_touching`] finds them), not every feature within the
    /// margin.
    pub fn pressing_forces(
        &self,
        model: &Model,
        state: &SystemState,
        constraints: &[(Row, f64)],
    ) -> Result<Vec<ContactForce>, ConstraintError> {
        let mut unknowns = vec![false; model.dofs().len()];
        let mut pressing = false;
        for (row, _) in constraints.iter().filter(|(_, l)| *l > 0.0) {
            pressing = true;
            for &(k, _) in &row.gradient {
                unknowns[k] = true;
            }
        }
        if !pressing {
            return Ok(Vec::new());
        }
        let gaps = match edges_touching(model, &unknowns) {
            Some(edges) => self.gaps_of(
                model,
                state,
                self.margin_m,
                RodPairs::LocalMinima,
                Some(&edges),
                None,
            )?,
            None => self.tagged_gaps(model, state, self.margin_m)?,
        };
        let mut forces = with_forces(gaps, constraints);
        forces.retain(|f| f.force_n > 0.0);
        Ok(forces)
    }

    /// The gaps of rod `rod` to mesh `mesh` within `band` (m) of the rod's least gap
    /// to it, among those within `margin_m` (m): the listing of [`Contact::gaps`] on
    /// the edges that may hold them (the same gaps, with the same numbers; farther
    /// gaps of those edges may be left out), e.g. the rivals of a least gap that may
    /// take its place when the rod moves.
    pub fn mesh_gaps_near_least(
        &self,
        model: &Model,
        state: &SystemState,
        rod: usize,
        mesh: usize,
        margin_m: f64,
        band: f64,
    ) -> Result<Vec<Gap>, ConstraintError> {
        let centrelines = centrelines(state);
        let rods = rod_geometries(model, &centrelines);
        let geometry = &rods[rod];
        let reach = geometry.radius + margin_m;
        let Some((edges, within)) = Self::edges_within(&self.meshes[mesh], geometry, reach, band)
        else {
            return Ok(Vec::new());
        };
        let margin_m = within - geometry.radius;
        let one_off = ProximityCache::default();
        let mut lists = self.proximity.incremental.then(|| one_off.begin(0.0));
        let mut gaps = Vec::new();
        self.mesh_gaps(
            model,
            rod,
            geometry,
            mesh,
            &self.meshes[mesh],
            margin_m,
            lists.as_mut(),
            Some(&edges),
            &mut gaps,
        )?;
        add_low_order(state, &mut gaps);
        Ok(gaps.into_iter().map(|(gap, _)| gap).collect())
    }

    /// Whether rod–rod gap `gap` is at the edge of the pairs the contact search
    /// excludes (near neighbours along one rod, rod ends a junction holds together):
    /// a pair one edge nearer along either rod is excluded. The least gap of such a
    /// pair is set by the exclusion: as the rods move (or their reference arc lengths
    /// change) the next pair enters, so its derivative holds on one side only. `false`
    /// for a mesh gap.
    pub fn at_exclusion(&self, model: &Model, state: &SystemState, gap: &Gap) -> bool {
        let Obstacle::Rod { rod, edge, .. } = gap.with else {
            return false;
        };
        let exclusion = Exclusion::new(model, state);
        let edges = |r: usize| model.system().rods[r].rod.segments();
        let excluded = |(ra, ea): (usize, isize), (rb, eb): (usize, isize)| {
            let inside = |r: usize, e: isize| e >= 0 && (e as usize) < edges(r);
            inside(ra, ea)
                && inside(rb, eb)
                && (ra, ea) != (rb, eb)
                && exclusion.excluded(ra, ea as usize, rb, eb as usize)
        };
        let (a, b) = ((gap.rod, gap.edge as isize), (rod, edge as isize));
        [-1, 1]
            .into_iter()
            .any(|step| excluded((a.0, a.1 + step), b) || excluded(a, (b.0, b.1 + step)))
    }

    /// A readable name of what a gap touches: the mesh's name or `rod '<name>'`.
    pub fn obstacle_name(&self, model: &Model, with: &Obstacle) -> String {
        match with {
            Obstacle::Mesh(i) => self.meshes[*i].name().to_string(),
            Obstacle::Rod { rod, .. } => model.system().rods[*rod].name.clone(),
        }
    }
}

/// Every rod's centreline at `state` (vertex positions, m).
fn centrelines(state: &SystemState) -> Vec<Vec<Point3<f64>>> {
    state
        .rods
        .iter()
        .map(|r| r.positions.iter().map(|p| Point3::from(*p)).collect())
        .collect()
}

/// Every rod as capsules of its outer radius along `centrelines`.
fn rod_geometries<'a>(model: &Model, centrelines: &'a [Vec<Point3<f64>>]) -> Vec<RodGeometry<'a>> {
    model
        .system()
        .rods
        .iter()
        .zip(centrelines)
        .map(|(spec, vertices)| RodGeometry {
            vertices,
            radius: spec.rod.section().outer_radius,
        })
        .collect()
}

/// A gap error in the rods' names, lengths in mm.
fn describe_error(model: &Model, error: strand_contact::GapError) -> ConstraintError {
    match error {
        strand_contact::GapError::CentrelineTouches {
            rod,
            edge,
            what,
            point,
        } => ConstraintError::CentrelineTouches {
            rod: model.system().rods[rod].name.clone(),
            what: format!("edge {edge} {what}"),
            point_mm: [point.x * 1e3, point.y * 1e3, point.z * 1e3],
        },
        other => ConstraintError::Gaps(other),
    }
}

/// Largest overlap (m) of a starting configuration with an obstacle that is not
/// reported as starting inside it: a warm start from a neighbouring solution that rests
/// on an obstacle may overlap it by round-off; the solve closes that.
pub const START_OVERLAP_M: f64 = 1e-6;

/// The row key of a contact pair: the rod's vertex (`s` = 0 or 1) or edge and what it
/// touches (a mesh and its smooth patch, or the other rod's edge), hashed. Stable while
/// the contact stays on its patch.
fn key_of(gap: &Gap, tag: Tag) -> RowKey {
    let mut hasher = std::hash::DefaultHasher::new();
    let at = if gap.s == 0.0 {
        (0u8, gap.edge)
    } else if gap.s == 1.0 {
        (0u8, gap.edge + 1)
    } else {
        (1u8 + tag.end, gap.edge)
    };
    (gap.rod, at).hash(&mut hasher);
    match gap.with {
        Obstacle::Mesh(i) => (0u8, i, tag.patch).hash(&mut hasher),
        Obstacle::Rod { rod, edge, .. } => (1u8, rod, edge).hash(&mut hasher),
    }
    RowKey::Contact(hasher.finish())
}

impl Constraints for Contact {
    fn rows(
        &self,
        model: &Model,
        state: &SystemState,
        out: &mut Vec<Row>,
    ) -> Result<(), ConstraintError> {
        let gaps = self.tagged_gaps(model, state, self.margin_m)?;
        push_rows(model, state, gaps, out);
        Ok(())
    }

    /// The rows of [`Contact::rows`] less those of the vertex spheres and edge capsules
    /// whose kept candidate lists put them farther than [`FAR_MARGINS`] search margins
    /// from a mesh beyond their radius (a lower bound from where they were last
    /// searched and how far they moved since: no search), unless they are the
    /// vertices of an edge whose rows are made (an edge's rows depend on its
    /// vertices' contacts). Their vertices go to `far` with that bound where it is
    /// within the margin (farther features make no rows at all).
    fn rows_leaving_far(
        &self,
        model: &Model,
        state: &SystemState,
        out: &mut Vec<Row>,
        far: &mut Vec<FarVertex>,
    ) -> Result<(), ConstraintError> {
        let gaps = self.gaps_of(
            model,
            state,
            self.margin_m,
            RodPairs::LocalMinima,
            None,
            Some(far),
        )?;
        push_rows(model, state, gaps, out);
        Ok(())
    }

    /// The rows of the gaps of the edges next to the rod vertices whose unknowns
    /// `unknowns` flags or which have none (held in space): the same rows, with the
    /// same numbers, as [`Contact::rows`] makes for them (`Contact::mesh_gaps` lists
    /// only those edges, and the rod–rod gaps are searched from those edges, which
    /// hold the lower edge of every pair whose row touches only flagged unknowns);
    /// every row where a flagged unknown is not a rod vertex's (a body's, which
    /// carries vertices).
    fn rows_touching(
        &self,
        model: &Model,
        state: &SystemState,
        unknowns: &[bool],
        out: &mut Vec<Row>,
    ) -> Result<(), ConstraintError> {
        let Some(edges) = edges_touching(model, unknowns) else {
            return self.rows(model, state, out);
        };
        let gaps = self.gaps_of(
            model,
            state,
            self.margin_m,
            RodPairs::LocalMinima,
            Some(&edges),
            None,
        )?;
        push_rows(model, state, gaps, out);
        Ok(())
    }

    /// A contact row reads the positions of the vertices of its edges (held ones
    /// included) and the rods' outer radii, and the geometry that carries a held or
    /// clipped vertex (the bodies' poses and ports, the clips); the meshes are the
    /// contact's own. So only a moved vertex next to a flagged one (a row of an edge
    /// with a held end touches only its other end's unknowns), next to another
    /// vertex without unknowns (an edge whose row touches only its partner's), or
    /// within a rod–rod row's reach of a flagged vertex (a pair whose point sits on
    /// the moved vertex touches only its partner's unknowns) can move a flagged row;
    /// anything else moved may move any. (The exclusion of near rod–rod pairs reads
    /// the reference lengths too, but only to list a pair, not for its row.)
    fn rows_may_differ(
        &self,
        model: &Model,
        state: &SystemState,
        (moved, moved_state): (&Model, &SystemState),
        unknowns: &[bool],
    ) -> bool {
        let (a, b) = (model.system(), moved.system());
        let radii = |s: &strand_system::System| {
            s.rods
                .iter()
                .map(|r| r.rod.section().outer_radius)
                .collect::<Vec<_>>()
        };
        let same_bodies = a.bodies.len() == b.bodies.len()
            && a.bodies
                .iter()
                .zip(&b.bodies)
                .all(|(x, y)| x.pose == y.pose && x.ports == y.ports && x.fixed == y.fixed);
        if !(same_bodies
            && a.clips == b.clips
            && radii(a) == radii(b)
            && state.bodies == moved_state.bodies
            && state.clips == moved_state.clips
            && state.rods.len() == moved_state.rods.len())
        {
            return true;
        }
        let dofs = model.dofs();
        let flagged = |block: usize| unknowns[3 * block..3 * block + 3].iter().any(|&u| u);
        // The flagged vertices' positions and how far a rod–rod row reaches from a
        // point to its partner edge's vertices (margin, both radii, an edge).
        let mut flagged_points = Vec::new();
        let mut longest_edge: f64 = 0.0;
        for (r, rod) in state.rods.iter().enumerate() {
            for (j, p) in rod.positions.iter().enumerate() {
                if dofs.vertex(r, j).is_some_and(flagged) {
                    flagged_points.push(*p);
                }
            }
            for pair in rod.positions.windows(2) {
                longest_edge = longest_edge.max((pair[1] - pair[0]).norm());
            }
        }
        let largest_radius = radii(a).into_iter().fold(0.0, f64::max);
        let pair_reach = self.margin_m + 2.0 * largest_radius + longest_edge;
        for (r, (x, y)) in state.rods.iter().zip(&moved_state.rods).enumerate() {
            if x.positions.len() != y.positions.len() {
                return true;
            }
            for (j, _) in x
                .positions
                .iter()
                .zip(&y.positions)
                .enumerate()
                .filter(|(_, (p, q))| p != q)
            {
                if dofs.vertex(r, j).is_some() {
                    return true; // a vertex with unknowns of its own moved
                }
                let neighbours = [
                    j.checked_sub(1),
                    Some(j + 1).filter(|&k| k < x.positions.len()),
                ];
                for k in neighbours.into_iter().flatten() {
                    match dofs.vertex(r, k) {
                        Some(block) if flagged(block) => return true,
                        Some(_) => {}
                        None => return true, // an edge without unknowns of its own
                    }
                }
                let near = |p: &Vector3<f64>| {
                    (p - x.positions[j]).norm() <= pair_reach
                        || (p - y.positions[j]).norm() <= pair_reach
                };
                if flagged_points.iter().any(near) {
                    return true;
                }
            }
        }
        false
    }

    fn check_start(&self, model: &Model, state: &SystemState) -> Result<(), ConstraintError> {
        self.check_held_ends(model, state)?;
        self.check_overlap(model, state)?;
        self.check_enclosed(model, state)
    }

    fn max_translation_m(&self) -> f64 {
        0.5 * self.margin_m
    }

    fn advancement(
        &self,
        model: &Model,
        state: &SystemState,
        target: &SystemState,
    ) -> Result<f64, ConstraintError> {
        Contact::advancement(self, model, state, target)
    }
}

/// Every gap of `gaps` with its force: the multiplier of its row's key in
/// `constraints`, 0 for a pair without one.
fn with_forces(gaps: Vec<(Gap, Tag)>, constraints: &[(Row, f64)]) -> Vec<ContactForce> {
    // Multipliers by key, looked up by bisection (not a scan per gap: thousands of
    // rod–rod pairs at fine discretisations).
    let mut by_key: Vec<(RowKey, f64)> = constraints.iter().map(|(row, l)| (row.key, *l)).collect();
    by_key.sort_by_key(|(k, _)| *k);
    gaps.into_iter()
        .map(|(gap, tag)| {
            let key = key_of(&gap, tag);
            let force_n = by_key
                .binary_search_by_key(&key, |(k, _)| *k)
                .map_or(0.0, |i| by_key[i].1);
            ContactForce { gap, force_n, key }
        })
        .collect()
}

/// Appends the row of every gap of `gaps` whose point is not held fixed in space.
fn push_rows(model: &Model, state: &SystemState, gaps: Vec<(Gap, Tag)>, out: &mut Vec<Row>) {
    for (gap, tag) in gaps {
        let normal: Vector3<f64> = gap.normal.into_inner();
        let mut gradient = Vec::new();
        let mut add = |rod: usize, vertex: usize, weight: f64| {
            if weight != 0.0 {
                let direction = weight * normal;
                gradient.extend(model.vertex_direction_gradient(state, rod, vertex, &direction));
            }
        };
        add(gap.rod, gap.edge, 1.0 - gap.s);
        add(gap.rod, gap.edge + 1, gap.s);
        if let Obstacle::Rod { rod, edge, t } = gap.with {
            add(rod, edge, -(1.0 - t));
            add(rod, edge + 1, -t);
        }
        gradient.sort_by_key(|&(k, _)| k);
        gradient.dedup_by(|next, kept| {
            if next.0 == kept.0 {
                kept.1 += next.1;
                true
            } else {
                false
            }
        });
        // A point held fixed in space cannot open or close its gap: no row.
        if gradient.is_empty() {
            continue;
        }
        out.push(Row {
            key: key_of(&gap, tag),
            value: gap.gap,
            gradient,
            curvature: curvature::row_curvature(model, state, &gap, tag.feature),
        });
    }
}

/// The edges whose gaps may give rows touching only flagged unknowns
/// ([`edges_touching`]), per rod, per edge.
struct EdgesTouching {
    /// Edges next to a vertex whose unknowns are flagged: a mesh row touches the
    /// unknowns of every vertex of its edge with a weight (a held vertex has none, and
    /// a row with no unknowns at all is not made), so only these can give one.
    mesh: Vec<Vec<bool>>,
    /// Those and the edges next to a vertex with no unknowns of its own (held in
    /// space, or carried by a body or a clip): a rod–rod pair is searched from its
    /// lower edge, whose point may sit on such a vertex with the row touching only the
    /// partner's unknowns.
    pairs: Vec<Vec<bool>>,
}

/// The edges next to the rod vertices whose unknowns `unknowns` flags or which have
/// none; `None` where a flagged unknown is not a rod vertex's.
fn edges_touching(model: &Model, unknowns: &[bool]) -> Option<EdgesTouching> {
    let dofs = model.dofs();
    let mut claimed = vec![false; unknowns.len()];
    let rods = model.system().rods.len();
    let (mut mesh, mut pairs) = (Vec::with_capacity(rods), Vec::with_capacity(rods));
    for (r, spec) in model.system().rods.iter().enumerate() {
        let n = spec.rod.segments();
        let (mut by_mesh, mut by_pair) = (vec![false; n], vec![false; n]);
        for j in 0..=n {
            let (flagged, held) = match dofs.vertex(r, j) {
                Some(block) => {
                    let range = 3 * block..3 * block + 3;
                    claimed[range.clone()].iter_mut().for_each(|c| *c = true);
                    (unknowns[range].iter().any(|&u| u), false)
                }
                None => (false, true),
            };
            for e in [j.saturating_sub(1), j.min(n - 1)] {
                by_mesh[e] |= flagged;
                by_pair[e] |= flagged || held;
            }
        }
        mesh.push(by_mesh);
        pairs.push(by_pair);
    }
    let all_claimed = unknowns.iter().zip(&claimed).all(|(&u, &c)| !u || c);
    all_claimed.then_some(EdgesTouching { mesh, pairs })
}

/// The gaps without their tags.
fn untagged(gaps: Result<Vec<(Gap, Tag)>, ConstraintError>) -> Result<Vec<Gap>, ConstraintError> {
    Ok(gaps?.into_iter().map(|(gap, _)| gap).collect())
}

/// Which rod–rod gaps [`Contact::gaps_of`] lists.
#[derive(Clone, Copy)]
enum RodPairs {
    /// Every pair of edges at a local minimum along the partner rod (the contact rows).
    LocalMinima,
    /// The least of every pair of rods (a report's clearances).
    Least,
}

/// Adds the positions' low-order parts (compensated summation) to `gaps`, to first
/// order: a gap then resolves the vertex positions beyond double precision, as the
/// elastic forces do, and stiff rods in contact converge to the force tolerance.
fn add_low_order(state: &SystemState, gaps: &mut [(Gap, Tag)]) {
    let low = |rod: usize, edge: usize, s: f64| {
        let r = &state.rods[rod];
        (1.0 - s) * r.compensation(edge) + s * r.compensation(edge + 1)
    };
    for (gap, _) in gaps {
        let mut shift = low(gap.rod, gap.edge, gap.s);
        if let Obstacle::Rod { rod, edge, t } = gap.with {
            shift -= low(rod, edge, t);
        }
        gap.gap += gap.normal.dot(&shift);
    }
}

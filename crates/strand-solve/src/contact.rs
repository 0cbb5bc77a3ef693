//! Frictionless contact of rods with environment meshes and with each other, as the
//! inequality constraints `gap ≥ 0` of the minimisation (DESIGN §2–3). Each rod edge is
//! a capsule of the rod's outer radius; [`strand_contact`] finds the pairs within a
//! search margin and their exact closest points, and each pair becomes a [`Row`]
//! linearised in the positions of the vertices involved (through bodies and clips
//! where those vertices are held). The multipliers of the rows are the contact forces.

use std::hash::{Hash, Hasher};
use std::sync::Arc;

use nalgebra::{Point3, Vector3};
use strand_contact::{Gap, Obstacle, ObstacleMesh, Proximity, RodGeometry};
use strand_system::{Model, Support, SystemState};

use crate::constraints::{Constraints, Row, RowKey};

/// Contact of a model's rods with meshes and with each other.
#[derive(Clone)]
pub struct Contact {
    meshes: Vec<Arc<ObstacleMesh>>,
    margin_m: f64,
}

/// One contact pair at a state, with its force.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactForce {
    /// The gap's geometry (rod, edge, parameter, points, normal, gap in m).
    pub gap: Gap,
    /// Force on the rod along `gap.normal`, N (≥ 0; 0 for an open pair).
    pub force_n: f64,
}

impl Contact {
    /// Contact against `meshes`, with pairs closer than `margin_m` (surface to surface,
    /// m) entering as constraints. Steps are limited to half the margin, so nothing
    /// beyond it can be reached within one step.
    pub fn new(meshes: Vec<Arc<ObstacleMesh>>, margin_m: f64) -> Self {
        Self { meshes, margin_m }
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
    /// or 1 for the last vertex), and an edge adds a gap of its own only where its
    /// nearest point lies strictly inside it and nearer than both its vertices (the
    /// edge crosses a convex feature of the mesh). An edge lying flat on a surface is
    /// thus held at its vertices, where its weight is lumped. Between rods, each pair
    /// of edges within the margin gives one gap.
    pub fn gaps(
        &self,
        model: &Model,
        state: &SystemState,
        margin_m: f64,
    ) -> Result<Vec<Gap>, String> {
        Ok(self
            .tagged_gaps(model, state, margin_m)?
            .into_iter()
            .map(|(gap, _)| gap)
            .collect())
    }

    /// [`Contact::gaps`] with a tag that tells the two ends of a stretch of nearest
    /// points on one edge apart (for the row keys).
    fn tagged_gaps(
        &self,
        model: &Model,
        state: &SystemState,
        margin_m: f64,
    ) -> Result<Vec<(Gap, u8)>, String> {
        let centrelines: Vec<Vec<Point3<f64>>> = state
            .rods
            .iter()
            .map(|r| r.positions.iter().map(|p| Point3::from(*p)).collect())
            .collect();
        let rods: Vec<RodGeometry> = model
            .system()
            .rods
            .iter()
            .zip(&centrelines)
            .map(|(spec, vertices)| RodGeometry {
                vertices,
                radius: spec.rod.section().outer_radius,
            })
            .collect();
        let mut gaps = Vec::new();
        for (rod, geometry) in rods.iter().enumerate() {
            for (index, mesh) in self.meshes.iter().enumerate() {
                self.mesh_gaps(model, rod, geometry, index, mesh, margin_m, &mut gaps)?;
            }
        }
        let exclude = |rod_a: usize, edge_a: usize, rod_b: usize, edge_b: usize| {
            excluded(model, rod_a, edge_a, rod_b, edge_b)
        };
        let between_rods = strand_contact::rod_rod_gaps(&rods, margin_m, exclude)
            .map_err(|e| describe_error(model, &e))?;
        gaps.extend(between_rods.into_iter().map(|gap| (gap, 0)));
        // The positions' low-order parts (compensated summation), to first order: a gap
        // then resolves the vertex positions beyond double precision, as the elastic
        // forces do, and stiff rods in contact converge to the force tolerance.
        let low = |rod: usize, edge: usize, s: f64| {
            let r = &state.rods[rod];
            (1.0 - s) * r.compensation(edge) + s * r.compensation(edge + 1)
        };
        for (gap, _) in &mut gaps {
            let mut shift = low(gap.rod, gap.edge, gap.s);
            if let Obstacle::Rod { rod, edge, t } = gap.with {
                shift -= low(rod, edge, t);
            }
            gap.gap += gap.normal.dot(&shift);
        }
        Ok(gaps)
    }

    /// Vertex and edge gaps of one rod against one mesh.
    #[allow(clippy::too_many_arguments)]
    fn mesh_gaps(
        &self,
        model: &Model,
        rod: usize,
        geometry: &RodGeometry,
        index: usize,
        mesh: &ObstacleMesh,
        margin_m: f64,
        out: &mut Vec<(Gap, u8)>,
    ) -> Result<(), String> {
        let reach = geometry.radius + margin_m;
        let vertices = geometry.vertices;
        let last_edge = vertices.len() - 2;
        let touches = |point: &Point3<f64>| {
            format!(
                "rod '{}' touches mesh '{}' with its centreline at ({:.1}, {:.1}, {:.1}) mm",
                model.system().rods[rod].name,
                mesh.name(),
                point.x * 1e3,
                point.y * 1e3,
                point.z * 1e3
            )
        };
        let mut vertex_distance = vec![f64::INFINITY; vertices.len()];
        for (j, p) in vertices.iter().enumerate() {
            let Some(near) = Self::nearest(mesh, p, p, reach) else {
                continue;
            };
            let normal = near.normal.ok_or_else(|| touches(&near.point_on_mesh))?;
            vertex_distance[j] = near.distance;
            let (edge, s) = if j <= last_edge {
                (j, 0.0)
            } else {
                (last_edge, 1.0)
            };
            let gap = Gap {
                rod,
                edge,
                s,
                with: Obstacle::Mesh(index),
                point: *p,
                witness: near.point_on_mesh,
                normal,
                gap: near.distance - geometry.radius,
            };
            out.push((gap, 0));
        }
        for edge in 0..=last_edge {
            let (a, b) = (&vertices[edge], &vertices[edge + 1]);
            let Some(near) = Self::nearest(mesh, a, b, reach) else {
                continue;
            };
            // Where the edge runs along the mesh over a stretch (lying on a face and
            // overhanging its ridge), the stretch's inner ends hold it; otherwise an
            // interior point nearer than both vertices (the edge crosses a ridge).
            let [low, high] = near.tie;
            let band = EDGE_BAND * (1.0 + (b - a).norm());
            let interior = near.s > 0.0 && near.s < 1.0;
            let nearer =
                near.distance + band < vertex_distance[edge].min(vertex_distance[edge + 1]);
            let points: Vec<(f64, u8)> = if high - low > 1e-9 {
                [(low, 1), (high, 2)]
                    .into_iter()
                    .filter(|(s, _)| *s > 0.0 && *s < 1.0)
                    .collect()
            } else if interior && nearer {
                vec![(near.s, 0)]
            } else {
                vec![]
            };
            for (s, tag) in points {
                let point = a + (b - a) * s;
                let Some(at) = mesh.point_proximity(&point, reach) else {
                    continue;
                };
                let normal = at.normal.ok_or_else(|| touches(&at.point_on_mesh))?;
                let gap = Gap {
                    rod,
                    edge,
                    s,
                    with: Obstacle::Mesh(index),
                    point,
                    witness: at.point_on_mesh,
                    normal,
                    gap: at.distance - geometry.radius,
                };
                out.push((gap, tag));
            }
        }
        Ok(())
    }

    /// The contact pairs at the end of a solve with their forces (the multipliers of
    /// `constraints`, as in [`crate::Solution::constraints`]).
    pub fn forces(
        &self,
        model: &Model,
        state: &SystemState,
        constraints: &[(Row, f64)],
    ) -> Result<Vec<ContactForce>, String> {
        let gaps = self.tagged_gaps(model, state, self.margin_m)?;
        Ok(gaps
            .into_iter()
            .map(|(gap, tag)| {
                let key = key_of(&gap, tag);
                let force_n = constraints
                    .iter()
                    .find(|(row, _)| row.key == key)
                    .map_or(0.0, |(_, l)| *l);
                ContactForce { gap, force_n }
            })
            .collect())
    }

    /// The nearest point of `mesh` to segment `[a, b]` within `reach` (m).
    fn nearest(
        mesh: &ObstacleMesh,
        a: &Point3<f64>,
        b: &Point3<f64>,
        reach: f64,
    ) -> Option<Proximity> {
        // Most features are far from most meshes: the mesh's bounding box rules them out
        // without a BVH search.
        let [low, high] = mesh.bounding_box();
        let outside = (0..3)
            .map(|k| {
                (low[k] - a[k].max(b[k]))
                    .max(a[k].min(b[k]) - high[k])
                    .max(0.0)
            })
            .fold(0.0, |sum: f64, d| sum + d * d);
        if outside > reach * reach {
            return None;
        }
        mesh.segment_proximity(a, b, reach)
    }

    /// A readable name of what a gap touches: the mesh's name or `rod '<name>'`.
    pub fn obstacle_name(&self, model: &Model, with: &Obstacle) -> String {
        match with {
            Obstacle::Mesh(i) => self.meshes[*i].name().to_string(),
            Obstacle::Rod { rod, .. } => model.system().rods[*rod].name.clone(),
        }
    }
}

/// A gap error in the rods' names, lengths in mm.
fn describe_error(model: &Model, error: &strand_contact::GapError) -> String {
    let rods = &model.system().rods;
    match error {
        strand_contact::GapError::CentrelineTouches {
            rod,
            edge,
            what,
            point,
        } => format!(
            "rod '{}' edge {edge} {what}: its centreline passes through ({:.1}, {:.1}, {:.1}) mm",
            rods[*rod].name,
            point.x * 1e3,
            point.y * 1e3,
            point.z * 1e3
        ),
        other => other.to_string(),
    }
}

/// Pairs that are not contact: edges of one rod closer along it than half a turn of
/// the tube (π r), and edges of two rods that meet at a body within the sum of their
/// radii from it.
fn excluded(model: &Model, rod_a: usize, edge_a: usize, rod_b: usize, edge_b: usize) -> bool {
    let rods = &model.system().rods;
    let (a, b) = (&rods[rod_a], &rods[rod_b]);
    let (ra, rb) = (a.rod.section().outer_radius, b.rod.section().outer_radius);
    if rod_a == rod_b {
        let s = a.rod.arc_lengths();
        let (first, second) = (edge_a.min(edge_b), edge_a.max(edge_b));
        return s[second] - s[first + 1] < std::f64::consts::PI * ra.max(rb);
    }
    // Arc length from the end of each rod attached to a shared body.
    let reach = ra + rb;
    let body_of = |support: &Support| match support {
        Support::Port { body, .. } => Some(body.0),
        _ => None,
    };
    for (end_a, at_end_a) in [(&a.start, false), (&a.end, true)] {
        for (end_b, at_end_b) in [(&b.start, false), (&b.end, true)] {
            let (Some(body_a), Some(body_b)) = (body_of(&end_a.support), body_of(&end_b.support))
            else {
                continue;
            };
            if body_a != body_b {
                continue;
            }
            let from_end = |rod: &strand_system::RodSpec, edge: usize, at_end: bool| {
                let s = rod.rod.arc_lengths();
                if at_end {
                    rod.rod.length() - s[edge + 1]
                } else {
                    s[edge]
                }
            };
            if from_end(a, edge_a, at_end_a) < reach && from_end(b, edge_b, at_end_b) < reach {
                return true;
            }
        }
    }
    false
}

/// Largest overlap (m) of a starting configuration with an obstacle that is not
/// reported as starting inside it: a warm start from a neighbouring solution that rests
/// on an obstacle may overlap it by round-off; the solve closes that.
pub const START_OVERLAP_M: f64 = 1e-6;

/// How much nearer than both its vertices (relative to `1 + edge length`, m) an edge's
/// interior point must be to give a gap of its own.
const EDGE_BAND: f64 = 1e-12;

/// The row key of a contact pair: the rod's vertex (`s` = 0 or 1) or edge and what it
/// touches (a mesh, or the other rod's edge), hashed.
fn key_of(gap: &Gap, tag: u8) -> RowKey {
    let mut hasher = std::hash::DefaultHasher::new();
    let at = if gap.s == 0.0 {
        (0u8, gap.edge)
    } else if gap.s == 1.0 {
        (0u8, gap.edge + 1)
    } else {
        (1u8 + tag, gap.edge)
    };
    (gap.rod, at).hash(&mut hasher);
    match gap.with {
        Obstacle::Mesh(i) => (0u8, i).hash(&mut hasher),
        Obstacle::Rod { rod, edge, .. } => (1u8, rod, edge).hash(&mut hasher),
    }
    RowKey::Contact(hasher.finish())
}

impl Constraints for Contact {
    fn rows(&self, model: &Model, state: &SystemState, out: &mut Vec<Row>) -> Result<(), String> {
        for (gap, tag) in self.tagged_gaps(model, state, self.margin_m)? {
            let normal: Vector3<f64> = gap.normal.into_inner();
            let mut gradient = Vec::new();
            let mut add = |rod: usize, vertex: usize, weight: f64| {
                if weight != 0.0 {
                    let direction = weight * normal;
                    gradient
                        .extend(model.vertex_direction_gradient(state, rod, vertex, &direction));
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
            });
        }
        Ok(())
    }

    fn check_start(&self, model: &Model, state: &SystemState) -> Result<(), String> {
        let gaps = self.gaps(model, state, self.margin_m)?;
        let deepest = gaps
            .iter()
            .filter(|g| g.gap < -START_OVERLAP_M)
            .min_by(|a, b| a.gap.total_cmp(&b.gap));
        match deepest {
            None => Ok(()),
            Some(g) => {
                let rod = &model.system().rods[g.rod];
                let s = rod.rod.arc_lengths();
                let at = s[g.edge] + g.s * (s[g.edge + 1] - s[g.edge]);
                Err(format!(
                    "rod '{}' starts inside {} '{}': the hose surface overlaps it by {:.3} mm at \
                     s = {:.1} mm, centreline point ({:.1}, {:.1}, {:.1}) mm\n  hint: move the \
                     rod's route, supports or the obstacle so that the hose starts clear of it",
                    rod.name,
                    match g.with {
                        Obstacle::Mesh(_) => "mesh",
                        Obstacle::Rod { .. } => "rod",
                    },
                    self.obstacle_name(model, &g.with),
                    -g.gap * 1e3,
                    at * 1e3,
                    g.point.x * 1e3,
                    g.point.y * 1e3,
                    g.point.z * 1e3,
                ))
            }
        }
    }

    fn max_translation_m(&self) -> f64 {
        0.5 * self.margin_m
    }
}

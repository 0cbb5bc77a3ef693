//! The distances the step's sampled advancement ([`Contact::mesh_advancement`]) asks
//! of the meshes, looked for only as far as a decision needs them.
//!
//! The advancement takes two kinds of decision from the edges' distance bounds at its
//! samples: the stride (the least `PATH_STRIDE · max(d, r) / move` over the edges) and
//! whether every edge's move fits between two samples (`path_room`, nondecreasing in
//! both distances). An edge far from every mesh decides neither, yet finding its
//! bound `⌊d⌋` on a finely tessellated surface costs a search of the disc of triangles
//! within `d / 16` of its distance: the disc grows with `d` and with the density.
//!
//! So each edge is first searched only within a threshold (at the first sample a few
//! of its radii, at the next twice its move between the samples, where the move then
//! fits whatever lies beyond): what it finds there is its exact bound; finding nothing
//! gives the threshold's grid floor, a lower bound of it ([`EdgeBound::exact`] false).
//! A decision taken on lower bounds is kept only where it is the decision the exact
//! bounds give: the stride's edge must hold an exact bound (a lower one is made exact
//! and the least taken again: every other edge's exact value is at least its lower
//! one), and a move that does not fit with a lower bound is checked again with the
//! exact one (fitting with lower bounds implies fitting with exact ones). The
//! advancement is therefore the same, bit for bit, as with every bound exact.

use nalgebra::{Point3, Vector3};
use strand_contact::distance_grid_floor;

use super::Contact;
use super::advance::{PATH_SAMPLES, PATH_STRIDE, path_room};
use super::proximity_cache::Candidates;

/// Threshold of an edge's first search at the path's start, in its rod's radii: edges
/// in or near contact (about a radius away) get exact bounds at once, those farther
/// decide the stride only when the whole rod is far from every mesh.
const FIRST_SAMPLE_RADII: f64 = 4.0;

/// Threshold of an edge's search at a later sample, in its move since the sample
/// before: beyond it the move fits ([`path_room`] exceeds the move when the new
/// distance alone does) and the next stride is hardly this edge's.
const NEXT_SAMPLE_MOVES: f64 = 2.0;

/// A lower bound of an edge's centreline distance to the meshes at one sample, m.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct EdgeBound {
    /// The bound, m: `⌊d⌋` (or the edge's reach) when `exact`, else at most that.
    pub(super) value: f64,
    /// Whether `value` is what a search within the whole reach finds.
    pub(super) exact: bool,
}

/// The bounds of every rod edge at one multiple `t` of the step.
pub(super) struct Sample {
    /// The step's multiple.
    t: f64,
    /// Every rod's vertices moved by `t` times their move, m.
    shifted: Vec<Vec<Point3<f64>>>,
    /// The meshes near each rod there, coarse ones first.
    near: Vec<Vec<usize>>,
    /// Every rod edge's bound.
    pub(super) bounds: Vec<Vec<EdgeBound>>,
}

/// The path of one step and the searches along it (see the [module docs](self)).
pub(super) struct MeshPath<'a> {
    contact: &'a Contact,
    centrelines: &'a [Vec<Point3<f64>>],
    deltas: &'a [Vec<Vector3<f64>>],
    /// Each edge's larger end move over the whole step, m.
    moves: &'a [Vec<f64>],
    /// Each rod's outer radius, m.
    radii: Vec<f64>,
    /// The step's last multiple looked at.
    end: f64,
    /// The nearest triangle of each edge's last search of each mesh (per rod: edge
    /// times mesh count plus mesh): prunes the next search, never changes its bound.
    hints: Vec<Vec<Option<usize>>>,
    /// The rows' kept candidate lists (incremental proximity): each bounds its edge's
    /// distance to its mesh from below without a search.
    kept: Candidates<'a>,
    /// Search every edge within its whole reach at once and every mesh within it
    /// (the reference the thresholds and the least-so-far limits are tested against).
    pub(super) exact_only: bool,
}

impl<'a> MeshPath<'a> {
    /// The path of the step moving every rod vertex of `centrelines` (m) by `deltas`
    /// (m); `moves` each edge's larger end move (m), `radii` each rod's outer radius
    /// (m).
    pub(super) fn new(
        contact: &'a Contact,
        centrelines: &'a [Vec<Point3<f64>>],
        deltas: &'a [Vec<Vector3<f64>>],
        moves: &'a [Vec<f64>],
        radii: Vec<f64>,
    ) -> Self {
        let mesh_count = contact.meshes.len();
        Self {
            contact,
            centrelines,
            deltas,
            moves,
            radii,
            end: PATH_SAMPLES as f64,
            hints: moves
                .iter()
                .map(|edges| vec![None; edges.len() * mesh_count])
                .collect(),
            kept: contact.kept.begin(0.0),
            exact_only: false,
        }
    }

    /// The largest multiple `t` of the step (up to [`PATH_SAMPLES`] samples; above 1 a
    /// lower bound) for which no edge's centreline reaches a mesh
    /// ([`Contact::mesh_advancement`]).
    pub(super) fn advance(&mut self) -> f64 {
        let end = self.end;
        let moves = self.moves;
        let first: Vec<f64> = self.radii.iter().map(|&r| FIRST_SAMPLE_RADII * r).collect();
        let mut t = 0.0;
        let mut here = self.sample(0.0, |rod, _| first[rod]);
        for _ in 0..PATH_SAMPLES {
            // The next sample: every edge moves by at most `PATH_STRIDE` of its
            // distance (and, in contact, of its radius), then checked against the
            // distance found there.
            let mut next = (t + self.stride(&mut here)).min(end);
            let threshold = |next: f64| {
                move |rod: usize, edge: usize| NEXT_SAMPLE_MOVES * (next - t) * moves[rod][edge]
            };
            let mut there = self.sample(next, threshold(next));
            // Shorten the stride until every edge's move fits between the distances.
            let mut tries = 0;
            while !self.fits(&mut here, &mut there) {
                tries += 1;
                if tries > 4 {
                    return t.max(f64::MIN_POSITIVE);
                }
                next = t + 0.5 * (next - t);
                there = self.sample(next, threshold(next));
            }
            t = next;
            here = there;
            if t >= 1.0 {
                break;
            }
        }
        t
    }

    /// The bounds at multiple `t`, each edge searched within `threshold(rod, edge)`
    /// (m) at most.
    pub(super) fn sample(&mut self, t: f64, threshold: impl Fn(usize, usize) -> f64) -> Sample {
        let shifted: Vec<Vec<Point3<f64>>> = self
            .centrelines
            .iter()
            .zip(self.deltas)
            .map(|(vertices, delta)| vertices.iter().zip(delta).map(|(v, d)| v + t * d).collect())
            .collect();
        let near: Vec<Vec<usize>> = shifted
            .iter()
            .zip(self.moves)
            .map(|(vertices, edges)| {
                let farthest = edges.iter().copied().fold(0.0, f64::max);
                let mut near = self
                    .contact
                    .meshes_near(vertices, farthest * (self.end - t) + f64::MIN_POSITIVE);
                // Coarse meshes first: each search then looks only within the least
                // bound found so far ([`MeshPath::edge_bound`]), so a fine mesh behind
                // a nearer coarse part is ruled out near the root of its tree.
                near.sort_by_key(|&index| (self.contact.meshes[index].triangle_count(), index));
                near
            })
            .collect();
        let mut sample = Sample {
            t,
            shifted,
            near,
            bounds: Vec::with_capacity(self.moves.len()),
        };
        for rod in 0..self.moves.len() {
            let bounds = (0..self.moves[rod].len())
                .map(|edge| self.edge_bound(&sample, rod, edge, threshold(rod, edge)))
                .collect();
            sample.bounds.push(bounds);
        }
        sample
    }

    /// The largest multiple of the step from `here` that moves no edge by more than
    /// [`PATH_STRIDE`] of its distance (at least its radius) there: the least over the
    /// moving edges, each made exact before it is taken (every other edge's exact
    /// bound is at least its lower one, so the least is the exact bounds' least).
    fn stride(&mut self, here: &mut Sample) -> f64 {
        let radii = self.radii.clone();
        let stride_of =
            move |rod: usize, value: f64, moved: f64| PATH_STRIDE * value.max(radii[rod]) / moved;
        // Every moving edge's stride by its bound, least first: an edge whose lower
        // bound's stride is already above the least exact one cannot lower it, so the
        // walk stops there (one sort, not a rescan per refinement).
        let mut candidates: Vec<(f64, usize, usize)> = Vec::new();
        for (rod, (edges, bounds)) in self.moves.iter().zip(&here.bounds).enumerate() {
            for (edge, (&moved, bound)) in edges.iter().zip(bounds).enumerate() {
                if moved > 0.0 {
                    candidates.push((stride_of(rod, bound.value, moved), rod, edge));
                }
            }
        }
        candidates.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
        let mut least = f64::INFINITY;
        for (stride, rod, edge) in candidates {
            if stride >= least {
                break;
            }
            self.refine(here, rod, edge);
            let exact = here.bounds[rod][edge].value;
            least = least.min(stride_of(rod, exact, self.moves[rod][edge]));
        }
        least
    }

    /// Whether every edge's move from `here` to `there` fits between its distances
    /// there ([`path_room`]); a move that does not fit with a lower bound is checked
    /// again with the exact ones (the room only grows with either distance).
    fn fits(&mut self, here: &mut Sample, there: &mut Sample) -> bool {
        let span = there.t - here.t;
        for rod in 0..self.moves.len() {
            let radius = self.radii[rod];
            for edge in 0..self.moves[rod].len() {
                let moved = self.moves[rod][edge];
                let fits = |here: &Sample, there: &Sample| {
                    let (d0, d1) = (here.bounds[rod][edge], there.bounds[rod][edge]);
                    moved == 0.0 || span * moved < path_room(d0.value, d1.value, radius)
                };
                if fits(here, there) {
                    continue;
                }
                if here.bounds[rod][edge].exact && there.bounds[rod][edge].exact {
                    return false;
                }
                self.refine(here, rod, edge);
                self.refine(there, rod, edge);
                if !fits(here, there) {
                    return false;
                }
            }
        }
        true
    }

    /// Makes the bound of `edge` of `rod` at `sample` exact.
    pub(super) fn refine(&mut self, sample: &mut Sample, rod: usize, edge: usize) {
        if !sample.bounds[rod][edge].exact {
            sample.bounds[rod][edge] = self.edge_bound(sample, rod, edge, f64::INFINITY);
        }
    }

    /// The bound of one edge at `sample`, searched within `threshold` (m) at most.
    ///
    /// Each mesh is searched within the least bound found so far (at first the
    /// threshold or the edge's remaining move, whichever is less): a mesh farther than
    /// a found bound `g` has `⌊d⌋ ≥ g` (a grid point is its own floor, the floor is
    /// monotone), so it would not lower the least. Found anything: the least is the
    /// exact bound. Found nothing within a threshold below the reach: every mesh has
    /// `⌊d⌋ ≥ ⌊threshold⌋`, a lower bound.
    fn edge_bound(
        &mut self,
        sample: &Sample,
        rod: usize,
        edge: usize,
        threshold: f64,
    ) -> EdgeBound {
        let moved = self.moves[rod][edge];
        let reach = moved * (self.end - sample.t) + f64::MIN_POSITIVE;
        let near = &sample.near[rod];
        if moved == 0.0 || near.is_empty() || threshold >= reach || self.exact_only {
            return EdgeBound {
                value: self.search(sample, rod, edge, reach).unwrap_or(reach),
                exact: true,
            };
        }
        match self.search(sample, rod, edge, threshold) {
            Some(found) => EdgeBound {
                value: found,
                exact: true,
            },
            None => EdgeBound {
                value: distance_grid_floor(threshold),
                exact: false,
            },
        }
    }

    /// The least bound of the meshes near the edge within `limit` (m), if any.
    fn search(&mut self, sample: &Sample, rod: usize, edge: usize, limit: f64) -> Option<f64> {
        let mesh_count = self.contact.meshes.len();
        let (a, b) = (&sample.shifted[rod][edge], &sample.shifted[rod][edge + 1]);
        let mut least: Option<f64> = None;
        for &index in &sample.near[rod] {
            super::nearby::count_mesh_pair();
            let hint = &mut self.hints[rod][edge * mesh_count + index];
            // (The reference searches every mesh within the whole limit.)
            let within = if self.exact_only {
                limit
            } else {
                least.unwrap_or(limit)
            };
            // A mesh the edge's kept list puts beyond the limit has nothing within it.
            let kept = self.kept.edge_distance_lower_bound(rod, index, edge, a, b);
            if !self.exact_only && kept.is_some_and(|lower| lower > within) {
                continue;
            }
            if let Some(found) =
                self.contact.meshes[index].segment_distance_bound_from(a, b, within, *hint)
            {
                *hint = Some(found.nearest_tested);
                least = Some(least.map_or(found.bound, |l: f64| l.min(found.bound)));
            }
        }
        least
    }
}

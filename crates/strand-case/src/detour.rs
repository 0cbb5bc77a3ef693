//! A start routed around the parts for a rod held at both ends: the shortest clear
//! way between its nozzles found on a lattice, pulled taut. Between two parts of an
//! engine bay a hose's hanging guess, its bows, its arch and the straight chord all
//! pass through whatever lies between the connectors (a block, a bracket, a shroud)
//! as often as not: of 200 generated cables between random faces of the bundled
//! engine bay, 28 were refused with every guess through a part, 8 with the detour
//! (none of which fits a way in its length). The detour leaves a clamped nozzle along
//! its clamp for one edge (a pinned one straight on), searches the lattice (A*, nodes
//! kept clear of every mesh by the hose's radius, half an edge and half the lattice
//! diagonal, so that the segment between neighbouring clear nodes stays clear; the
//! ends link to nodes a few spacings away by tested segments; the way is bounded by
//! the rod's length: a node farther from the two nozzles together than
//! [`LATTICE_ALLOWANCE`] times the rod's length is never visited), refines the
//! lattice twice where the coarse one finds no way, then pulls the way taut (each
//! corner dropped where the segment past it stays clear). A taut way longer than the
//! rod is none. The rod is laid compressed along it, as the straight start is, and
//! the solve settles it.
//!
//! A clear way stays outside every closed part: it starts at a nozzle outside them
//! (the start check names a held end inside or too close first) and no segment of
//! it comes within the hose's radius of a face, so none crosses one.

use std::cmp::Ordering;
use std::collections::{BinaryHeap, HashMap};
use std::sync::Arc;

use nalgebra::Vector3;
use strand_contact::ObstacleMesh;
use strand_system::{Support, System, SystemState};

use crate::clearance::{RADIUS_SLACK, clear, needed_from};

/// Lattice nodes a search expands at most, per rod and lattice.
pub(crate) const MAX_EXPANSIONS: usize = 40_000;

/// How far (in lattice spacings along each axis) the way's ends link straight to
/// lattice nodes: a nozzle in a pocket narrower than a node's clearance leaves it.
const END_REACH: i32 = 3;

/// The coarsest lattice spacing, as a fraction of the rod's length.
const COARSE_SPACING: f64 = 1.0 / 24.0;

/// How much longer than the rod a way may be on the lattice: a lattice way is longer
/// than the way it stands for (its steps go along 26 directions, about 8 % at most
/// on a straight stretch), so the search allows this much and the way pulled taut
/// must fit the rod.
const LATTICE_ALLOWANCE: f64 = 1.1;

/// Lattices tried per rod, each half the spacing of the one before.
const LATTICES: usize = 3;

/// Of `system`, with every rod held at both ends (no route, no clip) whose `hanging`
/// guess passes within its radius of a mesh given a route around the `environment`
/// ([`detour`]): from a clamped end one reference edge along the clamp, from a pinned
/// one straight on. The way keeps the radius and 5 % from the meshes, and with
/// `corners` half a reference edge more (the rod's edges cut the way's corners by up
/// to that). `None` when no rod needs one or one finds no clear way within its
/// length.
pub(crate) fn detoured(
    system: &System,
    hanging: &SystemState,
    environment: &[Arc<ObstacleMesh>],
    corners: bool,
) -> Option<System> {
    if environment.is_empty() {
        return None;
    }
    let mut out = system.clone();
    let mut any = false;
    for (r, spec) in out.rods.iter_mut().enumerate() {
        if spec.route.is_some()
            || !spec.start.support.is_held()
            || !spec.end.support.is_held()
            || system.clips.iter().any(|c| c.rod.0 == r)
        {
            continue;
        }
        let p = &hanging.rods[r].positions;
        let radius = spec.rod.section().outer_radius;
        let through = p
            .windows(2)
            .any(|w| !clear(environment, &w[0], &w[1], radius));
        if !through {
            continue;
        }
        let n = p.len() - 1;
        let (a, b) = (p[0], p[n]);
        let clamped = |s: &Support| {
            matches!(
                s,
                Support::Clamped { .. } | Support::Port { clamped: true, .. }
            )
        };
        let stub = |s: &Support, e: usize| {
            if clamped(s) {
                spec.rod.edge_length(e)
            } else {
                0.0
            }
        };
        let (first, last) = (stub(&spec.start.support, 0), stub(&spec.end.support, n - 1));
        let (ta, tb) = ((p[1] - a).normalize(), (b - p[n - 1]).normalize());
        let (from, to) = (a + ta * first, b - tb * last);
        let edge = spec.rod.length() / spec.rod.segments() as f64;
        let corner = if corners { 0.5 * edge } else { 0.0 };
        let clearance = radius * (1.0 + RADIUS_SLACK) + corner;
        let available = spec.rod.length() - first - last;
        let way = detour(environment, &from, &to, clearance, available)?;
        let mut route = vec![a];
        route.extend(way);
        route.push(b);
        route.dedup();
        if route.iter().any(|v| !v.iter().all(|x| x.is_finite())) {
            return None;
        }
        spec.route = Some(route);
        any = true;
    }
    any.then_some(out)
}

/// The shortest way found from `from` to `to` (both included) whose segments keep
/// `clearance` (m) from every mesh (or, next to an end closer than that, no less than
/// the end itself) and whose length is at most `length` (m), pulled taut; `None` when
/// no lattice finds one.
pub(crate) fn detour(
    environment: &[Arc<ObstacleMesh>],
    from: &Vector3<f64>,
    to: &Vector3<f64>,
    clearance: f64,
    length: f64,
) -> Option<Vec<Vector3<f64>>> {
    if (to - from).norm() > length || !(length.is_finite() && clearance.is_finite()) {
        return None;
    }
    let mut spacing = length * COARSE_SPACING;
    for _ in 0..LATTICES {
        let search = Search {
            environment,
            origin: *from,
            to: *to,
            spacing,
            clearance,
            length: length * LATTICE_ALLOWANCE,
        };
        let (found, expansions) = search.run();
        if std::env::var_os("STRAND_TRACE").is_some() {
            eprintln!(
                "detour: lattice {:.1} mm, clearance {:.1} mm, length {:.1} mm, {expansions} nodes expanded: {}",
                spacing * 1e3,
                clearance * 1e3,
                length * 1e3,
                match &found {
                    Some(way) => format!("a way of {} nodes", way.len()),
                    None => "no way".into(),
                }
            );
        }
        // Pulled taut, the way must fit the length itself.
        if let Some(way) = found.map(|way| taut(environment, way, clearance)) {
            let taut_length: f64 = way.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
            if taut_length <= length {
                return Some(way);
            }
        }
        spacing *= 0.5;
    }
    None
}

/// One A* search over the lattice `origin + spacing · (i, j, k)`.
struct Search<'a> {
    environment: &'a [Arc<ObstacleMesh>],
    origin: Vector3<f64>,
    to: Vector3<f64>,
    spacing: f64,
    clearance: f64,
    length: f64,
}

/// A node's lattice index.
type Node = [i32; 3];

/// A node on the open list, ordered by its estimated total length (least first).
struct Open {
    estimate: f64,
    node: Node,
}

impl PartialEq for Open {
    fn eq(&self, other: &Self) -> bool {
        self.estimate == other.estimate
    }
}
impl Eq for Open {}
impl PartialOrd for Open {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Open {
    fn cmp(&self, other: &Self) -> Ordering {
        other.estimate.total_cmp(&self.estimate)
    }
}

impl Search<'_> {
    fn at(&self, node: Node) -> Vector3<f64> {
        self.origin + Vector3::new(node[0] as f64, node[1] as f64, node[2] as f64) * self.spacing
    }

    /// The way from the origin to `to` through clear lattice nodes, `None` when the
    /// lattice has none within the length and the expansion budget.
    fn run(&self) -> (Option<Vec<Vector3<f64>>>, usize) {
        // A node is clear when the mesh is farther than the clearance plus half the
        // lattice diagonal: every point of a segment to a neighbour is within that of
        // one of its ends.
        let node_clearance = self.clearance + 0.5 * 3f64.sqrt() * self.spacing;
        let mut clear_nodes: HashMap<Node, bool> = HashMap::new();
        let mut best: HashMap<Node, (f64, Node)> = HashMap::new();
        let mut open = BinaryHeap::new();
        let start: Node = [0, 0, 0];
        best.insert(start, (0.0, start));
        open.push(Open {
            estimate: (self.to - self.origin).norm(),
            node: start,
        });
        let mut expansions = 0;
        while let Some(Open { node, .. }) = open.pop() {
            let here = self.at(node);
            let walked = best[&node].0;
            // The last leg straight to the goal, when it is near and clear.
            let left = (self.to - here).norm();
            if left <= END_REACH as f64 * self.spacing
                && walked + left <= self.length
                && self.leg_clear(&here, &self.to)
            {
                return (Some(self.way_to(node, &best)), expansions);
            }
            expansions += 1;
            if expansions > MAX_EXPANSIONS {
                return (None, expansions);
            }
            // The origin may lie in a pocket narrower than a node's clearance: it links
            // to every clear node within a few spacings whose leg is clear.
            let reach = if node == start { END_REACH } else { 1 };
            for di in -reach..=reach {
                for dj in -reach..=reach {
                    for dk in -reach..=reach {
                        if di == 0 && dj == 0 && dk == 0 {
                            continue;
                        }
                        let next = [node[0] + di, node[1] + dj, node[2] + dk];
                        let there = self.at(next);
                        let reached = walked + (there - here).norm();
                        let estimate = reached + (self.to - there).norm();
                        if estimate > self.length
                            || best.get(&next).is_some_and(|(g, _)| *g <= reached)
                        {
                            continue;
                        }
                        // The origin's legs are tested as segments.
                        let ok = self.node_clear(&mut clear_nodes, next, node_clearance)
                            && (node != start || self.leg_clear(&here, &there));
                        if !ok {
                            continue;
                        }
                        best.insert(next, (reached, node));
                        open.push(Open {
                            estimate,
                            node: next,
                        });
                    }
                }
            }
        }
        (None, expansions)
    }

    fn node_clear(&self, cache: &mut HashMap<Node, bool>, node: Node, needed: f64) -> bool {
        *cache.entry(node).or_insert_with(|| {
            let p = self.at(node);
            clear(self.environment, &p, &p, needed)
        })
    }

    /// Whether segment `[a, b]` keeps the clearance, or, next to an end closer than
    /// that (a nozzle a hose's radius from a flank), no less than that end does.
    fn leg_clear(&self, a: &Vector3<f64>, b: &Vector3<f64>) -> bool {
        let needed = needed_from(self.environment, a, self.clearance).min(needed_from(
            self.environment,
            b,
            self.clearance,
        ));
        clear(self.environment, a, b, needed)
    }

    fn way_to(&self, last: Node, best: &HashMap<Node, (f64, Node)>) -> Vec<Vector3<f64>> {
        let mut way = vec![self.to];
        let mut node = last;
        loop {
            way.push(self.at(node));
            let parent = best[&node].1;
            if parent == node {
                break;
            }
            node = parent;
        }
        way.reverse();
        way
    }
}

/// `way` with each corner dropped where the segment past it stays clear (greedily,
/// the farthest point reachable from each kept one).
fn taut(
    environment: &[Arc<ObstacleMesh>],
    way: Vec<Vector3<f64>>,
    clearance: f64,
) -> Vec<Vector3<f64>> {
    let mut kept = vec![way[0]];
    let mut i = 0;
    while i + 1 < way.len() {
        let needed = needed_from(environment, &way[i], clearance);
        let mut j = way.len() - 1;
        while j > i + 1 {
            let needed = needed.min(needed_from(environment, &way[j], clearance));
            if clear(environment, &way[i], &way[j], needed) {
                break;
            }
            j -= 1;
        }
        kept.push(way[j]);
        i = j;
    }
    kept
}

#[cfg(test)]
mod tests {
    use nalgebra::Point3;

    use super::*;

    /// A closed axis-aligned box (m) from `min` to `max`.
    fn closed_box(min: [f64; 3], max: [f64; 3]) -> Arc<ObstacleMesh> {
        let corner = |k: u32| {
            Point3::new(
                if k & 1 == 0 { min[0] } else { max[0] },
                if k & 2 == 0 { min[1] } else { max[1] },
                if k & 4 == 0 { min[2] } else { max[2] },
            )
        };
        let vertices = (0..8).map(corner).collect();
        let faces = [
            [0, 2, 3, 1], // z min
            [4, 5, 7, 6], // z max
            [0, 1, 5, 4], // y min
            [2, 6, 7, 3], // y max
            [0, 4, 6, 2], // x min
            [1, 3, 7, 5], // x max
        ];
        let triangles: Vec<[u32; 3]> = faces
            .iter()
            .flat_map(|[a, b, c, d]| [[*a, *b, *c], [*a, *c, *d]])
            .collect();
        Arc::new(ObstacleMesh::try_from_triangles("box", vertices, &triangles).unwrap())
    }

    /// The distance (m) from `p` to the box `min..max` (zero inside), in closed form.
    fn box_distance(p: &Vector3<f64>, min: [f64; 3], max: [f64; 3]) -> f64 {
        (0..3)
            .map(|i| (min[i] - p[i]).max(p[i] - max[i]).max(0.0).powi(2))
            .sum::<f64>()
            .sqrt()
    }

    const WALL_MIN: [f64; 3] = [-0.05, -0.3, -0.3];
    const WALL_MAX: [f64; 3] = [0.05, 0.3, 0.3];

    /// Between two points either side of a wall 0.6 m square, the way goes around it:
    /// every point of it (densely sampled) keeps the clearance from the wall (by the
    /// box's closed-form distance), it is no longer than allowed, no shorter than any
    /// way around the wall can be (`2·√(0.1² + 0.3²)` m), and taut (a few corners, not
    /// a lattice staircase). A bound below the shortest way finds none.
    #[test]
    fn a_way_between_two_points_either_side_of_a_wall_goes_around_it_clear_and_taut() {
        let wall = [closed_box(WALL_MIN, WALL_MAX)];
        let (from, to) = (Vector3::new(-0.15, 0.0, 0.0), Vector3::new(0.15, 0.0, 0.0));
        let clearance = 0.01;
        let way = detour(&wall, &from, &to, clearance, 1.0).expect("a way around the wall");
        assert_eq!((way[0], way[way.len() - 1]), (from, to));
        let length: f64 = way.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
        let around = 2.0 * (0.1f64.powi(2) + 0.3f64.powi(2)).sqrt();
        assert!(
            around <= length && length <= 1.0,
            "length {length} m (around {around})"
        );
        assert!(way.len() <= 6, "{} points: not taut", way.len());
        for w in way.windows(2) {
            for k in 0..=1000 {
                let p = w[0] + (w[1] - w[0]) * (k as f64 / 1000.0);
                let d = box_distance(&p, WALL_MIN, WALL_MAX);
                assert!(d >= clearance * (1.0 - 1e-6), "{p} is {d} m from the wall");
            }
        }
        assert!(detour(&wall, &from, &to, clearance, 0.6).is_none());
    }

    /// A goal inside a closed box cannot be reached: the search ends within its
    /// budget of expansions (it counts them), not by visiting the whole lattice.
    #[test]
    fn a_search_that_finds_no_way_stops_at_its_budget() {
        let min = [0.1, -0.1, -0.1];
        let max = [0.3, 0.1, 0.1];
        let shut = [closed_box(min, max)];
        let search = Search {
            environment: &shut,
            origin: Vector3::new(-0.5, 0.0, 0.0),
            to: Vector3::new(0.2, 0.0, 0.0),
            spacing: 0.005,
            clearance: 0.002,
            length: 3.0,
        };
        let (found, expansions) = search.run();
        assert!(found.is_none());
        assert_eq!(expansions, MAX_EXPANSIONS + 1);
    }
}

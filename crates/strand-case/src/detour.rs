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
//! A clipped rod is routed from station to station (its held ends and clips, in
//! arc-length order): each stretch whose hanging guess passes through a part gets
//! its own way within its own length (leaving and reaching a clip along the cable's
//! direction through it for at least [`CLIP_LEAD_RADII`] radii, as a clamp for one
//! edge), the others keep the hanging guess, and each way keeps twice its clearance
//! from the stretches laid before it and from the clips' leads still to come (else
//! the hose would start inside itself where a way doubles back past a clip). Where no
//! way fits from one edge along the clamps (long edges turned away from each other
//! eat the length), the way leaves the stations themselves. A free end's stretch
//! beyond its last clip keeps its hanging guess where that clears, else is draped
//! over the parts from the clip ([`crate::drape`]). Of 120 clipped cables generated
//! between random faces of the engine bay (seeds 2–4), 34 converged before (every
//! other guess through a part), 77 with the ways from clip to clip; of 120 whose end
//! dangles 150–900 mm beyond the last clip, 51 before the free stretch was draped,
//! 83 after.
//!
//! A clear way stays outside every closed part: it starts at a nozzle outside them
//! (the start check names a held end inside or too close first) and no segment of
//! it comes within the hose's radius of a face, so none crosses one.

use std::cmp::Ordering;
use std::collections::{BinaryHeap, HashMap};
use std::sync::Arc;

use nalgebra::{Point3, Vector3};
use strand_contact::{ObstacleMesh, closest_segment_segment};
use strand_rod::RodState;
use strand_solve::{StartHint, WayAround};
use strand_system::{RodSpec, Station, System, SystemState, rod_state_along, rod_stations};

use crate::clearance::{RADIUS_SLACK, clear, needed_from};
use crate::drape::drape;

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

/// Segments of a laid piece a later way is kept apart from, at most.
const LAID_SEGMENTS: usize = 128;

/// How much longer than its stretch a way may be that the search for a too short
/// stretch's shortest way looks for ([`shortfall`]).
const SHORTFALL_REACH: f64 = 3.0;

/// How far (in hose radii) a way leaves a clip and reaches it along the cable's
/// direction through it, at least: a way that reached a clip's back from its front
/// would double back past it, and the hose would start inside itself.
const CLIP_LEAD_RADII: f64 = 4.0;

/// The rods of `system` laid from station to station ([`laid_by_stations`]) whose
/// `hanging` guess passes within their radius of a mesh, each laid along ways around
/// the `environment` ([`detour`]) between its stations (held ends and clips,
/// [`rod_stations`]) where the hanging guess between them is not clear, and along the
/// hanging guess where it is: leaving and reaching its stations along their leads
/// ([`Leads`]: a clamp's edge, a clip's few radii; a pinned end directly). A free
/// end's stretch beyond the last station hangs from it, or where that passes through
/// a part is draped over the parts ([`drape`], its first heading turned by the first
/// right angle that clears). The ways keep the radius and 5 % from the meshes, and
/// with `corners` half a reference edge more (the rod's edges cut the ways' corners by
/// up to that). `None` when no rod needs one or one finds no clear way within its
/// length between two stations.
pub(crate) fn detoured(
    system: &System,
    hanging: &SystemState,
    environment: &[Arc<ObstacleMesh>],
    corners: bool,
) -> Option<Vec<(usize, RodState)>> {
    if environment.is_empty() {
        return None;
    }
    let mut laid = Vec::new();
    for (r, spec) in system.rods.iter().enumerate() {
        if !laid_by_stations(system, r) {
            continue;
        }
        let (start_held, end_held) = (spec.start.support.is_held(), spec.end.support.is_held());
        let p = &hanging.rods[r].positions;
        let radius = spec.rod.section().outer_radius;
        let clear_between = |from: usize, to: usize| {
            p[from..=to]
                .windows(2)
                .all(|w| clear(environment, &w[0], &w[1], radius))
        };
        if clear_between(0, p.len() - 1) {
            continue;
        }
        let edge = spec.rod.length() / spec.rod.segments() as f64;
        let corner = if corners { 0.5 * edge } else { 0.0 };
        let clearance = radius * (1.0 + RADIUS_SLACK) + corner;
        let stations = rod_stations(system, r, &hanging.bodies);
        let leads = Leads::of(spec, &stations, environment);
        let arc = spec.rod.arc_lengths();
        // A free end's stretch: its hanging guess where it clears, else draped.
        let tail = |from: usize, to: usize, reversed: bool| {
            if clear_between(from, to) {
                return Some(p[from..=to].to_vec());
            }
            let g = system.gravity;
            let down = (g.norm() > 0.0).then(|| g.normalize())?;
            let mut hang = p[from..=to].to_vec();
            if reversed {
                hang.reverse();
            }
            let shape = [radius, edge, arc[to] - arc[from]];
            let mut piece = (0..4).find_map(|turn| drape(shape, &hang, down, environment, turn))?;
            if reversed {
                piece.reverse();
            }
            Some(piece)
        };
        let mut pieces: Vec<Vec<Vector3<f64>>> = Vec::with_capacity(stations.len() + 1);
        if !start_held {
            pieces.push(tail(0, stations[0].vertex, true)?);
        }
        for (k, pair) in stations.windows(2).enumerate() {
            let (a, b) = (&pair[0], &pair[1]);
            if b.vertex <= a.vertex {
                return None;
            }
            if clear_between(a.vertex, b.vertex) {
                pieces.push(p[a.vertex..=b.vertex].to_vec());
                continue;
            }
            // The stretches laid before and, leading out of their stations, those to
            // come: the way keeps apart from them.
            let mut apart = Laid {
                segments: Vec::new(),
                separation: 2.0 * clearance,
            };
            for piece in &pieces {
                apart.extend(piece);
            }
            let way = |from, to, available, apart: &Laid| {
                let way = detour(environment, apart, &from, &to, clearance, available)?;
                let mut piece = vec![a.position];
                piece.extend(way);
                piece.push(b.position);
                piece.dedup();
                Some(piece)
            };
            // Leave a clamp or a clip along its direction, arrive at the next the
            // same way; where no way fits from there (long edges turned away from each
            // other eat the length), from the stations themselves.
            let (from, to) = (leads.from(k), leads.to(k + 1));
            let mut led = apart.clone();
            led.segments.extend(leads.others(k));
            let available = b.s - a.s - (from - a.position).norm() - (b.position - to).norm();
            let piece = way(from, to, available, &led)
                .or_else(|| way(a.position, b.position, b.s - a.s, &apart))?;
            if piece.iter().any(|v| !v.iter().all(|x| x.is_finite())) {
                return None;
            }
            pieces.push(piece);
        }
        if !end_held {
            let last = stations[stations.len() - 1].vertex;
            pieces.push(tail(last, p.len() - 1, false)?);
        }
        laid.push((r, rod_state_along(system, r, &hanging.bodies, &pieces)?));
    }
    (!laid.is_empty()).then_some(laid)
}

/// Whether rod `r` of `system` is one the routed start lays from station to station:
/// no route, and held at both ends or by a clip (a rod dangling from one held end
/// without clips is the drape's, [`crate::drape`]).
fn laid_by_stations(system: &System, r: usize) -> bool {
    let spec = &system.rods[r];
    let held = spec.start.support.is_held() && spec.end.support.is_held();
    spec.route.is_none() && (held || system.clips.iter().any(|c| c.rod.0 == r))
}

/// For the first rod laid from station to station ([`laid_by_stations`]) with a
/// stretch between two stations whose hanging guess passes through a part and that is
/// shorter than the shortest way around the parts found between them (leaving and
/// reaching its stations along their leads; searched up to [`SHORTFALL_REACH`] times
/// the stretch on the coarsest lattice), the rod and what to tell the user
/// ([`StartHint::Lengthen`]). `None` when every way found fits or none is found.
pub(crate) fn shortfall(
    system: &System,
    hanging: &SystemState,
    environment: &[Arc<ObstacleMesh>],
) -> Option<(usize, StartHint)> {
    system.rods.iter().enumerate().find_map(|(r, spec)| {
        if !laid_by_stations(system, r) {
            return None;
        }
        let p = &hanging.rods[r].positions;
        let radius = spec.rod.section().outer_radius;
        let clearance = radius * (1.0 + RADIUS_SLACK);
        let stations = rod_stations(system, r, &hanging.bodies);
        let leads = Leads::of(spec, &stations, environment);
        stations.windows(2).enumerate().find_map(|(k, pair)| {
            let (a, b) = (&pair[0], &pair[1]);
            let through = p
                .get(a.vertex..=b.vertex)?
                .windows(2)
                .any(|w| !clear(environment, &w[0], &w[1], radius));
            if !through {
                return None;
            }
            let (from, to) = (leads.from(k), leads.to(k + 1));
            let stretch = b.s - a.s;
            let search = Search {
                environment,
                laid: &Laid::nothing(),
                origin: from,
                to,
                spacing: stretch * COARSE_SPACING,
                clearance,
                length: SHORTFALL_REACH * stretch,
            };
            let (found, expansions) = search.run();
            let way = taut(environment, &Laid::nothing(), found?, clearance);
            let length = (from - a.position).norm()
                + way.windows(2).map(|w| (w[1] - w[0]).norm()).sum::<f64>()
                + (b.position - to).norm();
            let mm = |x: f64| (x * 1e3).round() as u32;
            if std::env::var_os("STRAND_TRACE").is_some() {
                eprintln!(
                    "detour: the shortest way between s = {:.1} and {:.1} mm: {:.1} mm \
                     ({expansions} nodes expanded)",
                    a.s * 1e3,
                    b.s * 1e3,
                    length * 1e3
                );
            }
            (length > stretch).then(|| {
                let hint = StartHint::Lengthen(Box::new(WayAround {
                    from_s_mm: mm(a.s),
                    to_s_mm: mm(b.s),
                    way_mm: (length * 1e3).ceil() as u32,
                }));
                (r, hint)
            })
        })
    })
}

/// The shortest way found from `from` to `to` (both included) whose segments keep
/// `clearance` (m) from every mesh and `laid`'s separation from its segments (or, next
/// to an end closer than that, no less than the end itself) and whose length is at
/// most `length` (m), pulled taut; `None` when no lattice finds one.
pub(crate) fn detour(
    environment: &[Arc<ObstacleMesh>],
    laid: &Laid,
    from: &Vector3<f64>,
    to: &Vector3<f64>,
    clearance: f64,
    length: f64,
) -> Option<Vec<Vector3<f64>>> {
    if (to - from).norm() > length || !(length.is_finite() && clearance.is_finite()) {
        if std::env::var_os("STRAND_TRACE").is_some() {
            eprintln!(
                "detour: {:.1} mm apart, longer than the {:.1} mm between them",
                (to - from).norm() * 1e3,
                length * 1e3
            );
        }
        return None;
    }
    let mut spacing = length * COARSE_SPACING;
    for _ in 0..LATTICES {
        let search = Search {
            environment,
            laid,
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
        if let Some(way) = found.map(|way| taut(environment, laid, way, clearance)) {
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
    laid: &'a Laid,
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

    /// Whether `node` keeps `needed` (m) from every mesh and, beyond that, what the
    /// clearance asks more of the laid pieces' separation.
    fn node_clear(&self, cache: &mut HashMap<Node, bool>, node: Node, needed: f64) -> bool {
        let apart = self.laid.separation + needed - self.clearance;
        *cache.entry(node).or_insert_with(|| {
            let p = self.at(node);
            clear(self.environment, &p, &p, needed) && self.laid.apart(&p, &p, apart)
        })
    }

    /// Whether segment `[a, b]` keeps the clearance (and the laid pieces'
    /// separation), or, next to an end closer than that (a nozzle a hose's radius from
    /// a flank), no less than that end does.
    fn leg_clear(&self, a: &Vector3<f64>, b: &Vector3<f64>) -> bool {
        leg_clear(self.environment, self.laid, a, b, self.clearance)
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
    laid: &Laid,
    way: Vec<Vector3<f64>>,
    clearance: f64,
) -> Vec<Vector3<f64>> {
    let mut kept = vec![way[0]];
    let mut i = 0;
    while i + 1 < way.len() {
        let mut j = way.len() - 1;
        while j > i + 1 && !leg_clear(environment, laid, &way[i], &way[j], clearance) {
            j -= 1;
        }
        kept.push(way[j]);
        i = j;
    }
    kept
}

/// Whether segment `[a, b]` keeps `clearance` (m) from every mesh and `laid`'s
/// separation from its segments, or, next to an end closer than that, no less than
/// that end does.
fn leg_clear(
    environment: &[Arc<ObstacleMesh>],
    laid: &Laid,
    a: &Vector3<f64>,
    b: &Vector3<f64>,
    clearance: f64,
) -> bool {
    let needed = needed_from(environment, a, clearance).min(needed_from(environment, b, clearance));
    let apart = laid.needed_from(a).min(laid.needed_from(b));
    clear(environment, a, b, needed) && laid.apart(a, b, apart)
}

/// Where the ways of a rod leave and reach its stations: along the cable's direction
/// through a clamp or a clip, one edge from a clamped end, at least
/// [`CLIP_LEAD_RADII`] radii (and one edge) from a clip where that stretch clears the
/// parts by the radius (else one edge); a pinned end directly.
struct Leads {
    /// Per station, the lead segment arriving at it and the one leaving it (m).
    segments: Vec<[Option<[Vector3<f64>; 2]>; 2]>,
    positions: Vec<Vector3<f64>>,
}

impl Leads {
    fn of(spec: &RodSpec, stations: &[Station], environment: &[Arc<ObstacleMesh>]) -> Self {
        let radius = spec.rod.section().outer_radius;
        let last = stations.len() - 1;
        let segments = stations
            .iter()
            .enumerate()
            .map(|(k, station)| {
                let Some(t) = station.tangent else {
                    return [None, None];
                };
                let p = station.position;
                // From a clip the longer lead where it clears the parts.
                let lead = |edge: f64, along: Vector3<f64>| {
                    let long = p + along * edge.max(CLIP_LEAD_RADII * radius);
                    if k == 0 || k == last || !clear(environment, &p, &long, radius) {
                        p + along * edge
                    } else {
                        long
                    }
                };
                let behind =
                    (k > 0).then(|| [lead(spec.rod.edge_length(station.vertex - 1), -t), p]);
                let ahead = (k < last).then(|| [p, lead(spec.rod.edge_length(station.vertex), t)]);
                [behind, ahead]
            })
            .collect();
        Leads {
            segments,
            positions: stations.iter().map(|s| s.position).collect(),
        }
    }

    /// Where a way leaves station `k`.
    fn from(&self, k: usize) -> Vector3<f64> {
        self.segments[k][1].map_or(self.positions[k], |[_, tip]| tip)
    }

    /// Where a way reaches station `k`.
    fn to(&self, k: usize) -> Vector3<f64> {
        self.segments[k][0].map_or(self.positions[k], |[tip, _]| tip)
    }

    /// The leads the way from station `k` to the next keeps apart from: all but the
    /// two it joins.
    fn others(&self, k: usize) -> impl Iterator<Item = [Vector3<f64>; 2]> + '_ {
        self.segments
            .iter()
            .enumerate()
            .flat_map(move |(j, [behind, ahead])| {
                let behind = behind.filter(|_| j != k + 1);
                let ahead = ahead.filter(|_| j != k);
                behind.into_iter().chain(ahead)
            })
    }
}

/// The pieces of a rod laid before the one searched (their centrelines' segments, m),
/// and how far (m) a way keeps from them so that the hose does not start inside
/// itself.
#[derive(Clone)]
pub(crate) struct Laid {
    segments: Vec<[Vector3<f64>; 2]>,
    separation: f64,
}

impl Laid {
    /// Nothing laid yet.
    pub(crate) fn nothing() -> Self {
        Laid {
            segments: Vec::new(),
            separation: 0.0,
        }
    }

    /// `piece`'s segments added, at most [`LAID_SEGMENTS`] of them (a long hanging
    /// piece by every so many of its points).
    fn extend(&mut self, piece: &[Vector3<f64>]) {
        let stride = piece.len().div_ceil(LAID_SEGMENTS).max(1);
        let mut points: Vec<Vector3<f64>> = piece.iter().step_by(stride).copied().collect();
        if let Some(last) = piece
            .last()
            .filter(|_| !(piece.len() - 1).is_multiple_of(stride))
        {
            points.push(*last);
        }
        self.segments
            .extend(points.windows(2).map(|w| [w[0], w[1]]));
    }

    /// The least distance (m) from segment `[a, b]` to a laid segment (infinite when
    /// nothing is laid).
    fn distance(&self, a: &Vector3<f64>, b: &Vector3<f64>) -> f64 {
        let (a, b) = (Point3::from(*a), Point3::from(*b));
        self.segments
            .iter()
            .map(|[p, q]| {
                closest_segment_segment(&a, &b, &Point3::from(*p), &Point3::from(*q)).distance
            })
            .fold(f64::INFINITY, f64::min)
    }

    /// Whether segment `[a, b]` keeps `needed` (m) from every laid segment.
    fn apart(&self, a: &Vector3<f64>, b: &Vector3<f64>, needed: f64) -> bool {
        self.segments.is_empty() || self.distance(a, b) >= needed
    }

    /// The separation a segment from `a` keeps: the whole, or where `a` itself is
    /// closer, no less than `a` is.
    fn needed_from(&self, a: &Vector3<f64>) -> f64 {
        if self.segments.is_empty() {
            return 0.0;
        }
        self.separation.min(self.distance(a, a) * (1.0 - 1e-9))
    }
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
        let way = detour(&wall, &Laid::nothing(), &from, &to, clearance, 1.0)
            .expect("a way around the wall");
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
        assert!(detour(&wall, &Laid::nothing(), &from, &to, clearance, 0.6).is_none());
    }

    /// The way between two clips keeps apart from the piece of the same rod laid
    /// before it: across a laid segment lying between its ends it passes at no less
    /// than the separation (the hose would otherwise start inside itself), where with
    /// nothing laid it is the straight chord.
    #[test]
    fn a_way_keeps_the_separation_from_the_pieces_laid_before_it() {
        let (from, to) = (Vector3::new(-0.15, 0.0, 0.0), Vector3::new(0.15, 0.0, 0.0));
        let chord = detour(&[], &Laid::nothing(), &from, &to, 0.01, 1.0).unwrap();
        assert_eq!(chord, vec![from, to]);
        let (p, q) = (Vector3::new(0.0, -0.3, 0.0), Vector3::new(0.0, 0.3, 0.0));
        let separation = 0.05;
        let laid = Laid {
            segments: vec![[p, q]],
            separation,
        };
        let way = detour(&[], &laid, &from, &to, 0.01, 1.0).expect("a way over the piece");
        assert_eq!((way[0], way[way.len() - 1]), (from, to));
        for w in way.windows(2) {
            for k in 0..=1000 {
                let x = Point3::from(w[0] + (w[1] - w[0]) * (k as f64 / 1000.0));
                let d =
                    closest_segment_segment(&x, &x, &Point3::from(p), &Point3::from(q)).distance;
                assert!(
                    d >= separation * (1.0 - 1e-6),
                    "{x} is {d} m from the laid piece"
                );
            }
        }
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
            laid: &Laid::nothing(),
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

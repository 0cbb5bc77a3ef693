//! A start place for a free junction whose given `position` holds a hose's end inside
//! a part or against one. A free body's pose is only the initial guess of where it
//! hangs, yet every start of the hoses leaves from its ports: a T placed at the middle
//! of its connectors in an engine bay sits inside the engine block as often as not,
//! and every guess is refused. The body is moved (not turned) to the nearest place on
//! a lattice around its given position where each of its ports holding a hose stands
//! outside every closed part, clear of every mesh by the hose's radius and 5 %, and
//! the hose's first edge along the port stays as clear; the starts are then tried
//! from there, and the terminal says where it started.

use std::sync::Arc;

use nalgebra::{Point3, Vector3};
use strand_contact::ObstacleMesh;
use strand_system::{Support, System};

use crate::clearance::{RADIUS_SLACK, clear};

/// The radius, in lattice spacings, of the ball of places a placement search tests
/// per lattice (about 17,000 places).
pub(crate) const BALL: i32 = 16;

/// The lattices a placement search tries, as multiples of the finest spacing: the
/// largest hose diameter at the body's ports, at least [`FINEST_SPACING`].
const COARSENING: [f64; 2] = [1.0, 4.0];

/// The finest placement lattice's spacing at least, m.
const FINEST_SPACING: f64 = 0.005;

/// A free body moved away from its given position for the starts.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyMove {
    /// The body's (junction's) name.
    pub name: String,
    /// Its given position, m.
    pub from: Vector3<f64>,
    /// Where the starts put it, m.
    pub to: Vector3<f64>,
}

/// One port of a body holding a hose end: its position and direction in the body
/// frame, the hose's radius and first edge (m).
struct HeldPort {
    position: Vector3<f64>,
    direction: Vector3<f64>,
    radius: f64,
    edge: f64,
}

/// Of `system`, with every free body whose ports hold a hose end inside or against a
/// part of `environment` moved to the nearest clear place (lattice spacing the
/// largest such hose's diameter, at least 5 mm, within [`BALL`] spacings, else on a
/// lattice four times as coarse), and the moves. `None` when no body needs a move or one finds no clear place.
pub(crate) fn placed_bodies(
    system: &System,
    environment: &[Arc<ObstacleMesh>],
) -> Option<(System, Vec<BodyMove>)> {
    if environment.is_empty() {
        return None;
    }
    let mut placed = system.clone();
    let mut moves = Vec::new();
    for (b, body) in system.bodies.iter().enumerate() {
        if body.fixed {
            continue;
        }
        let held = held_ports(system, b);
        let clear_at = |origin: &Vector3<f64>| {
            held.iter().all(|port| {
                let p = origin + body.pose.orientation * port.position;
                let out = p + body.pose.orientation * port.direction * port.edge;
                let needed = port.radius * (1.0 + RADIUS_SLACK);
                let point = Point3::from(p);
                environment.iter().all(|mesh| !mesh.encloses(&point))
                    && clear(environment, &p, &out, needed)
            })
        };
        let from = body.pose.position;
        if held.is_empty() || clear_at(&from) {
            continue;
        }
        let largest = held.iter().map(|p| p.radius).fold(0.0, f64::max);
        let finest = (2.0 * largest).max(FINEST_SPACING);
        // Of places as near, the one nearest to where the hoses come from.
        let anchor = far_ends(system, b).unwrap_or(from - system.gravity);
        let to = nearest_clear(&from, &anchor, &COARSENING.map(|c| c * finest), clear_at);
        if std::env::var_os("STRAND_TRACE").is_some() {
            eprintln!(
                "placement: body '{}' at {:?} mm: {}",
                body.name,
                (from * 1e3).as_slice(),
                match &to {
                    Some(to) => format!("clear {:.1} mm away", (to - from).norm() * 1e3),
                    None => "no clear place".to_string(),
                }
            );
        }
        let to = to?;
        placed.bodies[b].pose.position = to;
        moves.push(BodyMove {
            name: body.name.clone(),
            from,
            to,
        });
    }
    (!moves.is_empty()).then_some((placed, moves))
}

/// The ports of body `b` holding a hose end, with the hose's radius and the length
/// of its edge at that end.
fn held_ports(system: &System, b: usize) -> Vec<HeldPort> {
    let mut held = Vec::new();
    for spec in &system.rods {
        let n = spec.rod.segments();
        for (end, edge) in [(&spec.start, 0), (&spec.end, n - 1)] {
            if let Support::Port { body, port, .. } = end.support
                && body.0 == b
            {
                let frame = &system.bodies[b].ports[port];
                held.push(HeldPort {
                    position: frame.position,
                    direction: frame.frame * Vector3::z(),
                    radius: spec.rod.section().outer_radius,
                    edge: spec.rod.edge_length(edge),
                });
            }
        }
    }
    held
}

/// The mean position (m) of the held far ends of the hoses at body `b`'s ports (their
/// connectors, pins and clamps), `None` when none is held in place.
fn far_ends(system: &System, b: usize) -> Option<Vector3<f64>> {
    let ends: Vec<Vector3<f64>> = system
        .rods
        .iter()
        .filter_map(|spec| match (spec.start.support, spec.end.support) {
            (Support::Port { body, .. }, other) | (other, Support::Port { body, .. })
                if body.0 == b =>
            {
                other.position()
            }
            _ => None,
        })
        .collect();
    (!ends.is_empty()).then(|| ends.iter().sum::<Vector3<f64>>() / ends.len() as f64)
}

/// The point nearest to `from` where `clear` holds among the lattice points
/// `from + spacing · (i, j, k)` within [`BALL`] spacings of it, tested nearest first
/// (of points as near, nearest to `anchor` first), for each spacing of `spacings` in
/// turn (a finer lattice first, a coarser one to reach farther); `None` when no tested
/// point is clear.
fn nearest_clear(
    from: &Vector3<f64>,
    anchor: &Vector3<f64>,
    spacings: &[f64],
    clear: impl Fn(&Vector3<f64>) -> bool,
) -> Option<Vector3<f64>> {
    let mut offsets: Vec<Vector3<f64>> = Vec::new();
    for i in -BALL..=BALL {
        for j in -BALL..=BALL {
            for k in -BALL..=BALL {
                if (1..=BALL * BALL).contains(&(i * i + j * j + k * k)) {
                    offsets.push(Vector3::new(i as f64, j as f64, k as f64));
                }
            }
        }
    }
    spacings.iter().find_map(|spacing| {
        let to_anchor = |offset: &Vector3<f64>| (from + offset * *spacing - anchor).norm_squared();
        offsets.sort_by(|a, b| {
            a.norm_squared()
                .total_cmp(&b.norm_squared())
                .then(to_anchor(a).total_cmp(&to_anchor(b)))
        });
        offsets
            .iter()
            .map(|offset| from + offset * *spacing)
            .find(|place| clear(place))
    })
}

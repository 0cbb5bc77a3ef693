//! A draped start for a dangling rod: one end held, the other free, no route and no
//! clip. Its hanging guess falls straight down from the held end, through whatever
//! part lies below (a cable dangling into a groove, onto a box); bowing it sideways or
//! up leaves the free tail sticking out into the flanks as often as not. The draped
//! start keeps the hanging guess from the held end as far as it stays clear of the
//! environment and then lets the rest fall as a chain would, one step at a time: down
//! where it can, else sliding down along its heading or turning up to 90° from it,
//! else along the heading or a turn of it, else climbing over what is in the way, never
//! turning back onto itself. The solve then settles it where it comes to rest.

use std::f64::consts::FRAC_PI_4;
use std::sync::Arc;

use nalgebra::{Rotation3, Unit, Vector3};
use strand_contact::ObstacleMesh;
use strand_system::{System, SystemState};

use crate::clearance::{RADIUS_SLACK, clear, needed_from};

/// Steps of a drape per rod at most (the step is the rod's mean edge length, or its
/// length over this many steps when that is longer).
const MAX_STEPS: f64 = 2000.0;

/// Of `system`, with every dangling rod (one end held, the other free, no route, no
/// clip) given a route draped from its held end over the `environment`: the hanging
/// guess `hanging` from the held end while it stays clear, then a chain's fall, with
/// the first horizontal heading the hanging guess's last one turned by `turn` right
/// angles about gravity. `None` without gravity, when no rod dangles, or when a drape
/// finds no clear way.
pub(crate) fn draped(
    system: &System,
    hanging: &SystemState,
    environment: &[Arc<ObstacleMesh>],
    turn: usize,
) -> Option<System> {
    let g = system.gravity;
    if environment.is_empty() || g.norm() == 0.0 || !g.iter().all(|x| x.is_finite()) {
        return None;
    }
    let down = g.normalize();
    let mut out = system.clone();
    let mut any = false;
    for (r, spec) in out.rods.iter_mut().enumerate() {
        let (start_held, end_held) = (spec.start.support.is_held(), spec.end.support.is_held());
        if spec.route.is_some()
            || start_held == end_held
            || system.clips.iter().any(|c| c.rod.0 == r)
        {
            continue;
        }
        let mut hang = hanging.rods[r].positions.clone();
        if end_held {
            hang.reverse();
        }
        let length = spec.rod.length();
        let shape = [
            spec.rod.section().outer_radius,
            length / spec.rod.segments() as f64,
            length,
        ];
        let mut route = drape(shape, &hang, down, environment, turn)?;
        if end_held {
            route.reverse();
        }
        spec.route = Some(route);
        any = true;
    }
    any.then_some(out)
}

/// The route of a dangling stretch of `length` (m) of a rod of `radius` and mean
/// `edge` (m) from where it is held (`hang[0]`, its hanging guess ordered from there),
/// `None` when no clear way is found or the hanging guess clears.
pub(crate) fn drape(
    [radius, edge, length]: [f64; 3],
    hang: &[Vector3<f64>],
    down: Vector3<f64>,
    environment: &[Arc<ObstacleMesh>],
    turn: usize,
) -> Option<Vec<Vector3<f64>>> {
    let step = edge.max(length / MAX_STEPS);
    // A rod edge cuts a corner of the draped polyline by up to about half its length;
    // the hanging part keeps the same clearance, so that the drape can leave it.
    let clearance = radius * (1.0 + RADIUS_SLACK) + 0.5 * edge;
    // The hanging guess from the held end while its edges stay clear.
    let mut route = vec![hang[0]];
    let mut walked = 0.0;
    for w in hang.windows(2) {
        let needed = needed_from(environment, &w[0], clearance);
        if !clear(environment, &w[0], &w[1], needed) {
            break;
        }
        walked += (w[1] - w[0]).norm();
        route.push(w[1]);
    }
    if route.len() == hang.len() {
        return None; // the hanging guess clears: nothing to drape
    }
    let last = route.len() - 1;
    let mut previous = if last > 0 {
        (route[last] - route[last - 1]).normalize()
    } else {
        down
    };
    let horizontal = |v: Vector3<f64>| v - down * v.dot(&down);
    let axis = Unit::new_normalize(down);
    let mut heading = horizontal(previous);
    if heading.norm() < 1e-6 {
        let side = down.cross(&Vector3::x());
        heading = if side.norm() > 0.5 {
            side
        } else {
            down.cross(&Vector3::y())
        };
    }
    let turned = |h: Vector3<f64>, angle: f64| Rotation3::from_axis_angle(&axis, angle) * h;
    heading = turned(heading.normalize(), turn as f64 * 2.0 * FRAC_PI_4);
    let mut position = route[last];
    while walked < length {
        let this_step = step.min(length - walked);
        let slope = |h: Vector3<f64>, elevation: f64| {
            (h * elevation.cos() - down * elevation.sin()).normalize()
        };
        let mut candidates = vec![down];
        for angle in [0.0, 1.0, -1.0, 2.0, -2.0] {
            let h = turned(heading, angle * FRAC_PI_4);
            candidates.push(slope(h, -FRAC_PI_4));
            candidates.push(h);
        }
        for angle in [0.0, 1.0, -1.0, 2.0, -2.0] {
            let h = turned(heading, angle * FRAC_PI_4);
            candidates.push(slope(h, FRAC_PI_4));
            candidates.push(slope(h, 1.4));
        }
        let needed = needed_from(environment, &position, clearance);
        let chosen = candidates.into_iter().find(|d| {
            d.dot(&previous) > -0.3
                && clear(environment, &position, &(position + d * this_step), needed)
        })?;
        let h = horizontal(chosen);
        if h.norm() > 1e-6 {
            heading = h.normalize();
        }
        position += chosen * this_step;
        previous = chosen;
        walked += this_step;
        route.push(position);
    }
    Some(route)
}

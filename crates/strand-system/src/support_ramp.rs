//! Supports moved part of the way from where a start state holds the rod ends: the
//! systems of a support ramp (continuation in prescribed end positions). A warm start
//! from another design (a connector moved by 100 mm, turned by 90°) puts the end
//! vertices where they were; snapping them onto the new supports would strain the end
//! edges enormously, while a ramp of supports from the old placement to the new one
//! keeps every step a small change of an equilibrium.

use nalgebra::{UnitQuaternion, Vector3};

use crate::system::{Support, System, SystemState};

impl System {
    /// This system with every clamp and pin of a rod end, and every fixed body, moved
    /// the fraction `factor` (0 → where `start` has them, 1 → this system's own) of the
    /// way: positions along the straight line, frames by slerp (the shorter way). At
    /// `factor` 0 `start` satisfies the supports; at 1 the result is this system. Ports
    /// follow their bodies; clips, loads and gravity are unchanged.
    ///
    /// `start` must have this system's shape (one state per rod and body).
    pub fn supports_from(&self, start: &SystemState, factor: f64) -> System {
        let mut moved = self.clone();
        if factor >= 1.0 {
            return moved;
        }
        for (spec, rod) in moved.rods.iter_mut().zip(&start.rods) {
            let last = rod.positions.len() - 1;
            for (end, vertex, edge) in [
                (&mut spec.start, 0, 0),
                (&mut spec.end, last, rod.frames.len() - 1),
            ] {
                match &mut end.support {
                    Support::Pinned { position } => {
                        *position = lerp(&rod.positions[vertex], position, factor);
                    }
                    Support::Clamped { position, frame } => {
                        *position = lerp(&rod.positions[vertex], position, factor);
                        *frame = slerp(&rod.frames[edge], frame, factor);
                    }
                    Support::Free | Support::Port { .. } => {}
                }
            }
        }
        for (body, pose) in moved.bodies.iter_mut().zip(&start.bodies) {
            if body.fixed {
                body.pose.position = lerp(&pose.position, &body.pose.position, factor);
                body.pose.orientation = slerp(&pose.orientation, &body.pose.orientation, factor);
            }
        }
        moved
    }

    /// How far `start` holds the rod ends and fixed bodies from this system's supports:
    /// the largest distance (m) of a clamped or pinned end vertex or fixed body origin,
    /// and the largest angle (rad) between a clamped end's first or last edge frame, or
    /// a fixed body's orientation, and the prescribed one.
    pub fn support_offset(&self, start: &SystemState) -> (f64, f64) {
        let (mut distance, mut angle) = (0.0f64, 0.0f64);
        for (spec, rod) in self.rods.iter().zip(&start.rods) {
            let last = rod.positions.len() - 1;
            for (end, vertex, edge) in
                [(&spec.start, 0, 0), (&spec.end, last, rod.frames.len() - 1)]
            {
                match &end.support {
                    Support::Pinned { position } => {
                        distance = distance.max((rod.positions[vertex] - position).norm());
                    }
                    Support::Clamped { position, frame } => {
                        distance = distance.max((rod.positions[vertex] - position).norm());
                        angle = angle.max(rod.frames[edge].angle_to(frame));
                    }
                    Support::Free | Support::Port { .. } => {}
                }
            }
        }
        for (body, pose) in self.bodies.iter().zip(&start.bodies) {
            if body.fixed {
                distance = distance.max((pose.position - body.pose.position).norm());
                angle = angle.max(pose.orientation.angle_to(&body.pose.orientation));
            }
        }
        (distance, angle)
    }
}

fn lerp(from: &Vector3<f64>, to: &Vector3<f64>, factor: f64) -> Vector3<f64> {
    from + (to - from) * factor
}

fn slerp(from: &UnitQuaternion<f64>, to: &UnitQuaternion<f64>, factor: f64) -> UnitQuaternion<f64> {
    // The shorter way: q and −q are the same rotation.
    let to = if from.coords.dot(&to.coords) < 0.0 {
        UnitQuaternion::new_unchecked(-to.into_inner())
    } else {
        *to
    };
    from.try_slerp(&to, factor, 1e-12).unwrap_or(to)
}

#[cfg(test)]
mod tests {
    use nalgebra::{UnitQuaternion, Vector3};
    use strand_rod::{Rod, Section};

    use crate::initial_state;
    use crate::system::{End, RodSpec, System};

    #[test]
    fn a_support_ramp_runs_from_the_start_placement_to_the_system() {
        let section = Section::try_explicit(1e4, 1e4, 1.0, 1.0, 0.0, 0.0).unwrap();
        let turned = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 1.2);
        let system = System {
            rods: vec![RodSpec {
                name: "r".into(),
                rod: Rod::try_straight(section, 1.0, 10).unwrap(),
                start: End::pinned(Vector3::zeros()),
                end: End::clamped(Vector3::new(0.8, 0.3, 0.0), turned),
                route: None,
            }],
            bodies: vec![],
            clips: vec![],
            gravity: Vector3::zeros(),
        };
        // The start of another design: the end clamped elsewhere, turned differently.
        let mut other = system.clone();
        other.rods[0].end = End::clamped(Vector3::new(0.6, -0.2, 0.1), UnitQuaternion::identity());
        let start = initial_state(&other);
        let at_zero = system.supports_from(&start, 0.0);
        let (distance, angle) = at_zero.support_offset(&start);
        assert!(
            distance < 1e-12 && angle < 1e-9,
            "{distance} m, {angle} rad"
        );
        let (d1, a1) = system.support_offset(&start);
        assert!(
            (d1 - Vector3::<f64>::new(0.2, 0.5, -0.1).norm()).abs() < 1e-12,
            "{d1}"
        );
        assert!(a1 > 0.5, "{a1}");
        // Half way: half the distance and half the angle.
        let half = system.supports_from(&start, 0.5);
        let (d, a) = half.support_offset(&start);
        assert!(
            (d - 0.5 * d1).abs() < 1e-12 && (a - 0.5 * a1).abs() < 1e-9,
            "{d} {a}"
        );
        assert_eq!(
            system.supports_from(&start, 1.0).rods[0].end.support,
            system.rods[0].end.support
        );
    }
}

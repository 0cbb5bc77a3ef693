//! Rigid translation of a system and of its states.
//!
//! The energy is invariant under a translation (gravity changes by a constant), but
//! round-off is not: coordinates of 1 km carry an ulp of 1e-13 m, which the stiff axial
//! springs turn into residual forces. Solvers therefore work in local coordinates
//! ([`System::translated`] by minus a system origin) and move the result back
//! ([`SystemState::translate`]).

use nalgebra::Vector3;

use crate::system::{Support, System, SystemState};

impl System {
    /// The same system moved by `offset` (m): supports, routes, body poses and the
    /// bases of clips fixed in the world. Gravity, loads and rotations are unchanged.
    pub fn translated(&self, offset: &Vector3<f64>) -> System {
        let mut moved = self.clone();
        for spec in &mut moved.rods {
            for end in [&mut spec.start, &mut spec.end] {
                match &mut end.support {
                    Support::Pinned { position } | Support::Clamped { position, .. } => {
                        *position += offset;
                    }
                    Support::Free | Support::Port { .. } => {}
                }
            }
            if let Some(route) = &mut spec.route {
                for point in route {
                    *point += offset;
                }
            }
        }
        for body in &mut moved.bodies {
            body.pose.position += offset;
        }
        for clip in &mut moved.clips {
            if clip.body.is_none() && clip.parent.is_none() {
                clip.base.position += offset;
            }
        }
        moved
    }

    /// A point near the middle of the system's held points (supports, fixed and free
    /// bodies, clip bases in the world), m, rounded to whole metres so that moving by it
    /// is exact in floating point for any coordinate below 2⁵² m.
    pub fn local_origin(&self) -> Vector3<f64> {
        let mut sum = Vector3::zeros();
        let mut count = 0.0;
        let mut add = |p: &Vector3<f64>| {
            sum += p;
            count += 1.0;
        };
        for spec in &self.rods {
            for end in [&spec.start, &spec.end] {
                if let Some(position) = end.support.position() {
                    add(&position);
                }
            }
        }
        for body in &self.bodies {
            add(&body.pose.position);
        }
        for clip in &self.clips {
            if clip.body.is_none() && clip.parent.is_none() {
                add(&clip.base.position);
            }
        }
        if count == 0.0 {
            return Vector3::zeros();
        }
        (sum / count).map(f64::round)
    }
}

impl SystemState {
    /// Moves every vertex and body by `offset` (m); vertex positions keep their
    /// compensated low-order parts.
    pub fn translate(&mut self, offset: &Vector3<f64>) {
        for rod in &mut self.rods {
            for vertex in 0..rod.positions.len() {
                rod.translate_vertex(vertex, offset);
            }
        }
        for pose in &mut self.bodies {
            pose.position += offset;
        }
    }
}

//! Every real number of a [`System`] as one vector: a system moved along a design
//! parameter is `base + t · direction` value by value wherever the parameter enters
//! the system affinely (lengths, positions, masses, loads, stiffnesses), which a
//! design checks against full builds before relying on it.

use nalgebra::{UnitQuaternion, Vector3};

use crate::system::{Joint, Support, System, SystemError};

impl System {
    /// Every real number of the system in a fixed order (rods: section, edge lengths,
    /// rest strains and curvatures, held positions and frames, end loads, route
    /// points; bodies: mass, centre of mass, pose, ports; clips: base, joint axis,
    /// offset, limits; gravity). Quaternions enter by their four components. Units
    /// are the fields' (m, kg, N, N·m, N·m², 1/m, rad, m/s²). Two systems of the same
    /// structure (rods, segments, bodies, ports, clips, supports' kinds) have vectors
    /// of the same length whose entries mean the same.
    pub fn reals(&self) -> Vec<f64> {
        let mut copy = self.clone();
        let mut out = Vec::new();
        // Reading leaves every value as it is: a valid rod stays valid.
        let _ = visit(&mut copy, &mut |x| out.push(*x));
        out
    }

    /// The system with its real numbers replaced by `values` (in the order of
    /// [`System::reals`]), every other field kept. Errors if `values` has the wrong
    /// length or makes a rod's reference data invalid (an edge length not positive).
    /// Quaternion components are taken as given: use it only where they are unit
    /// (equal to the base's, as for a parameter that does not turn a frame).
    pub fn with_reals(&self, values: &[f64]) -> Result<System, SystemError> {
        let mut out = self.clone();
        let mut next = values.iter();
        let mut short = false;
        visit(&mut out, &mut |x| match next.next() {
            Some(v) => *x = *v,
            None => short = true,
        })?;
        if short || next.next().is_some() {
            return Err(SystemError::NotFinite {
                rod: "-".into(),
                what: format!(
                    "a system's real values ({} given, {} expected)",
                    values.len(),
                    self.reals().len()
                ),
            });
        }
        Ok(out)
    }
}

/// Visits every real number of `system` in the order of [`System::reals`].
fn visit(system: &mut System, f: &mut dyn FnMut(&mut f64)) -> Result<(), SystemError> {
    fn vector(v: &mut Vector3<f64>, f: &mut dyn FnMut(&mut f64)) {
        v.iter_mut().for_each(f);
    }
    fn quaternion(q: &mut UnitQuaternion<f64>, f: &mut dyn FnMut(&mut f64)) {
        q.as_mut_unchecked().coords.iter_mut().for_each(f);
    }
    for spec in &mut system.rods {
        spec.rod
            .visit_reals(&mut *f)
            .map_err(|e| SystemError::NotFinite {
                rod: spec.name.clone(),
                what: format!("the reference data ({e})"),
            })?;
        for end in [&mut spec.start, &mut spec.end] {
            match &mut end.support {
                Support::Free | Support::Port { .. } => {}
                Support::Pinned { position } => vector(position, f),
                Support::Clamped { position, frame } => {
                    vector(position, f);
                    quaternion(frame, f);
                }
            }
            vector(&mut end.load.force, f);
            vector(&mut end.load.moment, f);
            quaternion(&mut end.load.moment_reference, f);
        }
        for point in spec.route.iter_mut().flatten() {
            vector(point, f);
        }
    }
    for body in &mut system.bodies {
        f(&mut body.mass);
        vector(&mut body.center_of_mass, f);
        vector(&mut body.pose.position, f);
        quaternion(&mut body.pose.orientation, f);
        for port in &mut body.ports {
            vector(&mut port.position, f);
            quaternion(&mut port.frame, f);
        }
    }
    for clip in &mut system.clips {
        vector(&mut clip.base.position, f);
        quaternion(&mut clip.base.orientation, f);
        match &mut clip.joint {
            Joint::Fixed | Joint::Spherical => {}
            Joint::Revolute { axis } | Joint::Prismatic { axis } => vector(axis, f),
        }
        vector(&mut clip.offset.position, f);
        quaternion(&mut clip.offset.orientation, f);
        if let Some((lo, hi)) = &mut clip.limits {
            f(lo);
            f(hi);
        }
    }
    vector(&mut system.gravity, f);
    Ok(())
}

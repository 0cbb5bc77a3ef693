//! Every real number of a [`System`] as one vector: a system moved along a design
//! parameter is `base + t · direction` value by value wherever the parameter enters
//! the system affinely (lengths, positions, masses, loads, stiffnesses), which a
//! design checks against full builds before relying on it.

use std::cell::Cell;

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
        let _ = visit(&mut copy, &mut |x| out.push(*x), &|_| false);
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
        visit(
            &mut out,
            &mut |x| match next.next() {
                Some(v) => *x = *v,
                None => short = true,
            },
            &|_| false,
        )?;
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

impl System {
    /// The system with the real numbers at the indices `changed` (in the order of
    /// [`System::reals`], ascending, each once) set to `value(index)`, every other
    /// field kept: [`System::with_reals`] of values that differ from
    /// [`System::reals`] only there, without visiting the rods' reference data none of
    /// the indices falls in (a design moved along a parameter that changes a few
    /// numbers: a connector's position, a mass, one rod's lengths). Errors as
    /// [`System::with_reals`] does for a rod made invalid, and for an index past the
    /// last real number.
    pub fn with_reals_changed(
        &self,
        changed: &[usize],
        value: &dyn Fn(usize) -> f64,
    ) -> Result<System, SystemError> {
        let mut out = self.clone();
        out.set_reals_changed(changed, value)?;
        Ok(out)
    }

    /// Sets the real numbers at the indices `changed` (in the order of
    /// [`System::reals`], ascending, each once) to `value(index)` in place, as
    /// [`System::with_reals_changed`] does on a copy: a system moved again and again
    /// along one parameter (every point of a path sets the same indices) is not
    /// copied per point. Errors as [`System::with_reals_changed`] (the system is then
    /// left as far as it was changed).
    pub fn set_reals_changed(
        &mut self,
        changed: &[usize],
        value: &dyn Fn(usize) -> f64,
    ) -> Result<(), SystemError> {
        // The index of the next real number visited, and of the next change in
        // `changed`.
        let (index, pending) = (Cell::new(0usize), Cell::new(0usize));
        let mut set = |x: &mut f64| {
            let (i, p) = (index.get(), pending.get());
            if changed.get(p) == Some(&i) {
                *x = value(i);
                pending.set(p + 1);
            }
            index.set(i + 1);
        };
        let skip_rod = |count: usize| {
            let i = index.get();
            let untouched = changed.get(pending.get()).is_none_or(|&k| k >= i + count);
            if untouched {
                index.set(i + count);
            }
            untouched
        };
        visit(self, &mut set, &skip_rod)?;
        if pending.get() < changed.len() {
            return Err(SystemError::NotFinite {
                rod: "-".into(),
                what: format!(
                    "a system's real values (index {} of {})",
                    changed[pending.get()],
                    index.get()
                ),
            });
        }
        Ok(())
    }
}

/// Visits every real number of `system` in the order of [`System::reals`], except the
/// reference data of each rod for which `skip_rod` (given how many real numbers that
/// data holds, [`strand_rod::Rod::real_count`]) says so.
fn visit(
    system: &mut System,
    f: &mut dyn FnMut(&mut f64),
    skip_rod: &dyn Fn(usize) -> bool,
) -> Result<(), SystemError> {
    fn vector(v: &mut Vector3<f64>, f: &mut dyn FnMut(&mut f64)) {
        v.iter_mut().for_each(f);
    }
    fn quaternion(q: &mut UnitQuaternion<f64>, f: &mut dyn FnMut(&mut f64)) {
        q.as_mut_unchecked().coords.iter_mut().for_each(f);
    }
    for spec in &mut system.rods {
        if !skip_rod(spec.rod.real_count()) {
            spec.rod
                .visit_reals(&mut *f)
                .map_err(|e| SystemError::NotFinite {
                    rod: spec.name.clone(),
                    what: format!("the reference data ({e})"),
                })?;
        }
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

#[cfg(test)]
mod tests {
    use crate::tests::{clipped_system, junction_system};

    /// Changing a few real numbers — an edge length of the first rod, numbers past
    /// its reference data (its ends), and near the end (bodies, clips, gravity) — gives the system `with_reals` makes of the
    /// whole vector with those entries changed; the rods no index falls in are kept.
    #[test]
    fn changing_a_few_reals_is_replacing_all_of_them_with_those_changed() {
        for system in [junction_system(), clipped_system()] {
            let reals = system.reals();
            let first_rod = system.rods[0].rod.real_count();
            let last = reals.len() - 1;
            // The first rod's second edge length (after its section's eight numbers),
            // the first number past its reference data, and the last (gravity's z).
            let mut changed = vec![9, first_rod + 1, last - 4, last];
            changed.sort_unstable();
            changed.dedup();
            let value = |k: usize| reals[k] * 1.25 + 1e-3;
            let mut all = reals.clone();
            for &k in &changed {
                all[k] = value(k);
            }
            let expected = system.with_reals(&all).unwrap();
            let sparse = system.with_reals_changed(&changed, &value).unwrap();
            assert_eq!(sparse, expected);
            assert_eq!(sparse.reals(), all);
            // In place, again and again: the last values set.
            let mut scratch = system.clone();
            for scale in [2.0, 0.5] {
                scratch
                    .set_reals_changed(&changed, &|k| reals[k] * scale)
                    .unwrap();
            }
            let mut halved = reals.clone();
            for &k in &changed {
                halved[k] *= 0.5;
            }
            assert_eq!(scratch, system.with_reals(&halved).unwrap());
            // Nothing changed is the system itself; an index past the end is an error.
            assert_eq!(system.with_reals_changed(&[], &value).unwrap(), system);
            assert!(system.with_reals_changed(&[last + 1], &value).is_err());
        }
    }
}

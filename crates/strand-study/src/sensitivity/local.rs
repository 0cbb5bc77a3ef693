//! The output table read locally: each output of [`super::outputs_at`] computed from
//! the few elements it depends on (a peak from the two edges and the curvature
//! element at its base vertex, a reaction from its end's elements, a junction's pose
//! from its state) instead of the whole result document. The derivatives along the
//! first-order path ([`strand_solve::sensitivity::Sensitivities::derivative_at`])
//! evaluate the outputs a dozen times per parameter; read locally, each evaluation
//! costs a few elements instead of every rod's sectional quantities.
//!
//! A plan is made only where every output has a local reading that reproduces the
//! whole table at the base exactly: rods' peaks and bend radii, connector and port
//! reactions, free junctions' poses and the energy (where the table has it). A case
//! with clips keeps the whole table ([`LocalOutputs::plan`] is `None`); so does a
//! case with contact, except for the exact derivatives
//! ([`LocalOutputs::plan_exact`]), which read its clearances from their least gaps
//! and its contact forces from their multipliers.

mod path;
mod tangent;

use nalgebra::{UnitQuaternion, Vector3};
use strand_case::DesignedCase;
use strand_report::{ContactOutputs, LeastClearance, OutputValue, magnitude, ties};
use strand_rod::sectional::BoundaryFrames;
use strand_rod::sectional_at::sectional_at;
use strand_solve::RowKey;
use strand_solve::Solution;
use strand_solve::sensitivity::{PathPlace, Sample};
use strand_system::{Model, System, SystemState};

use super::ENERGY;
pub use path::LocalPath;
use path::Window;
pub use tangent::{ExactDerivatives, LocalTangents, PEAK_MARGIN, SECOND_ORDER};

/// What a local reading reads.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Reading {
    /// `|f̄|` at a vertex of a rod, N.
    Force { rod: usize, vertex: usize },
    /// `|m|` at a vertex of a rod, N·m.
    Moment { rod: usize, vertex: usize },
    /// `1 / |K_⊥|` at a vertex of a rod, m.
    BendRadius { rod: usize, vertex: usize },
    /// A component of a reaction's force (N) or moment (N·m), in the order of
    /// [`Model::reactions`].
    Reaction {
        index: usize,
        moment: bool,
        axis: usize,
    },
    /// A component of a body's position, m.
    Position { body: usize, axis: usize },
    /// A component of a body's rotation vector, rad.
    Rotation { body: usize, axis: usize },
    /// The total potential energy, J.
    Energy,
    /// A rod's clearance to one obstacle (the plan's least gap `index`), m.
    Clearance { index: usize },
    /// A rod's least clearance over its obstacles (the plan's least gaps of the rod),
    /// m; its arg is the obstacle's place among them.
    MinClearance { rod: usize },
    /// A contact's force (the multiplier of the plan's contact key `index`), N.
    ContactForce { index: usize },
}

/// The local readings of every output of a base table, in its order.
#[derive(Clone, Debug)]
pub struct LocalOutputs {
    readings: Vec<Reading>,
    /// The base's args (the vertex of a peak; 0 for a smooth output).
    args: Vec<usize>,
    /// Per reaction (in the order of [`Model::reactions`]): its rod and whether it
    /// holds the rod's end (vertex N) rather than its start.
    reaction_ends: Vec<(usize, bool)>,
    /// Per rod, the vertices and edges the readings look at.
    windows: Vec<Window>,
    /// The least gaps the clearance readings read, at the base.
    clearances: Vec<LeastClearance>,
    /// Per rod, its least gaps (indices into `clearances`, in the table's order).
    rod_clearances: Vec<Vec<usize>>,
    /// The row keys of the contacts whose forces are read.
    contact_keys: Vec<RowKey>,
    /// The case's contact, for the rivals of a clearance's least gap.
    contact: Option<PlanContact>,
}

/// A plan's contact (shown by name only).
#[derive(Clone)]
struct PlanContact(strand_solve::contact::Contact);

impl std::fmt::Debug for PlanContact {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Contact")
    }
}

/// Largest relative difference between a local reading and the whole table at the
/// base that a plan accepts (the two compute the same numbers in the same order; the
/// margin is for a different summation order only).
pub const LOCAL_AGREEMENT: f64 = 1e-12;

impl LocalOutputs {
    /// The plan that reads `outputs` (the whole table of `built` at `solution`, from
    /// [`super::outputs_at`] without pins) locally, or `None` where some output has no
    /// local reading (clips, contacts, clearances) or a reading does not reproduce
    /// its value at the base to [`LOCAL_AGREEMENT`].
    pub fn plan(
        built: &DesignedCase,
        solution: &Solution,
        outputs: &[OutputValue],
    ) -> Option<Self> {
        if built.contact.is_some() {
            return None;
        }
        Self::plan_exact(built, solution, outputs, None)
    }

    /// [`LocalOutputs::plan`], also of a case with contact: its clearances and contact
    /// forces are read at the base only (each clearance from its least gap, each
    /// contact force from its row's multiplier: `contacts`, those the base's outputs
    /// were read from, found here where not given), so that the plan serves the exact
    /// derivatives ([`LocalTangents`]) and nothing read along a path
    /// ([`LocalOutputs::reads_contacts`]).
    pub fn plan_exact(
        built: &DesignedCase,
        solution: &Solution,
        outputs: &[OutputValue],
        contacts: Option<ContactOutputs>,
    ) -> Option<Self> {
        let model = &built.built.model;
        let system = model.system();
        if !system.clips.is_empty() {
            return None;
        }
        let ContactOutputs {
            pressing: contacts,
            clearances,
        } = match (contacts, &built.contact) {
            (Some(found), _) => found,
            (None, Some(contact)) => ContactOutputs::of(model, solution, contact).ok()?,
            (None, None) => ContactOutputs {
                pressing: Vec::new(),
                clearances: Vec::new(),
            },
        };
        let rod_clearances: Vec<Vec<usize>> = (0..system.rods.len())
            .map(|rod| {
                (0..clearances.len())
                    .filter(|&k| clearances[k].rod == rod)
                    .collect()
            })
            .collect();
        let mut readings = Vec::with_capacity(outputs.len());
        let mut next = 0;
        let mut take = |name: &str, reading: &dyn Fn(usize) -> Reading| -> bool {
            match outputs.get(next) {
                Some(o) if o.name == name => {
                    readings.push(reading(o.arg));
                    next += 1;
                    true
                }
                _ => false,
            }
        };
        for (rod, spec) in system.rods.iter().enumerate() {
            let name = &spec.name;
            let peaks = take(&format!("{name}.peak_force_N"), &|vertex| Reading::Force {
                rod,
                vertex,
            }) && take(&format!("{name}.peak_moment_Nm"), &|vertex| {
                Reading::Moment { rod, vertex }
            });
            if !peaks {
                return None;
            }
            // Absent where the rod is straight everywhere (no finite radius).
            take(&format!("{name}.min_bend_radius_m"), &|vertex| {
                Reading::BendRadius { rod, vertex }
            });
            // The least clearance, then each obstacle's, where the rod has any.
            if !rod_clearances[rod].is_empty()
                && !take(&format!("{name}.min_clearance_m"), &|_| {
                    Reading::MinClearance { rod }
                })
            {
                return None;
            }
            for &index in &rod_clearances[rod] {
                let with = &clearances[index].with;
                if !take(&format!("{name}.clearance_m.{with}"), &|_| {
                    Reading::Clearance { index }
                }) {
                    return None;
                }
            }
        }
        // Reactions and bodies carry their document names (connectors renamed); their
        // order is the document's, checked by the values below.
        let mut rest = outputs[next..].iter();
        let reaction_ends: Vec<(usize, bool)> = model
            .reactions(&solution.state)
            .iter()
            .map(|r| (r.rod, r.at_end))
            .collect();
        for index in 0..reaction_ends.len() {
            for (moment, axis) in (0..6).map(|c| (c >= 3, c % 3)) {
                let stem = if moment { ".moment_Nm." } else { ".force_N." };
                let o = rest.next()?;
                if !o
                    .name
                    .ends_with(&format!("{stem}{}", ["x", "y", "z"][axis]))
                {
                    return None;
                }
                readings.push(Reading::Reaction {
                    index,
                    moment,
                    axis,
                });
            }
        }
        for (body, spec) in system.bodies.iter().enumerate() {
            if spec.fixed {
                continue;
            }
            for component in 0..6 {
                let axis = component % 3;
                let (stem, reading) = if component < 3 {
                    ("position_m", Reading::Position { body, axis })
                } else {
                    ("rotation_vector_rad", Reading::Rotation { body, axis })
                };
                let o = rest.next()?;
                if o.name != format!("{}.{stem}.{}", spec.name, ["x", "y", "z"][axis]) {
                    return None;
                }
                readings.push(reading);
            }
        }
        // Each pressing contact's force, numbered per rod and obstacle.
        let mut counts: std::collections::BTreeMap<(&str, &str), usize> = Default::default();
        for (index, (result, _)) in contacts.iter().enumerate() {
            let k = counts.entry((&result.rod, &result.with)).or_insert(0);
            let o = rest.next()?;
            if o.name != format!("{}.contact_force_N.{}.{k}", result.rod, result.with) {
                return None;
            }
            readings.push(Reading::ContactForce { index });
            *k += 1;
        }
        // The energy, last, where the table has it ([`super::EnergyOutput`]).
        match rest.next() {
            None => {}
            Some(o) if o.name == ENERGY && rest.next().is_none() => {
                readings.push(Reading::Energy);
            }
            Some(_) => return None,
        }
        let mut windows = vec![Window::default(); system.rods.len()];
        let segments = |rod: usize| system.rods[rod].rod.segments();
        for (reading, o) in readings.iter().zip(outputs) {
            match *reading {
                // The two edges around the vertex and their vertices.
                Reading::Force { rod, .. }
                | Reading::Moment { rod, .. }
                | Reading::BendRadius { rod, .. } => {
                    windows[rod].add(o.arg.saturating_sub(1), o.arg + 1, segments(rod));
                }
                // The end edge and its vertices.
                Reading::Reaction { index, .. } => {
                    let (rod, at_end) = reaction_ends[index];
                    let n = segments(rod);
                    if at_end {
                        windows[rod].add(n - 1, n, n);
                    } else {
                        windows[rod].add(0, 1, n);
                    }
                }
                Reading::Position { .. }
                | Reading::Rotation { .. }
                | Reading::Energy
                | Reading::Clearance { .. }
                | Reading::MinClearance { .. }
                | Reading::ContactForce { .. } => {}
            }
        }
        windows.iter_mut().for_each(Window::finish);
        let plan = Self {
            readings,
            args: outputs.iter().map(|o| o.arg).collect(),
            reaction_ends,
            windows,
            clearances,
            rod_clearances,
            contact_keys: contacts.into_iter().map(|(_, key)| key).collect(),
            contact: built.contact.clone().map(PlanContact),
        };
        let local = plan.read(model, solution, PathPlace::Base);
        let agrees = local.iter().zip(outputs).all(|(l, o)| {
            let scale = l.value.abs().max(o.value.abs());
            (l.value - o.value).abs() <= LOCAL_AGREEMENT * scale && l.arg == o.arg
        });
        agrees.then_some(plan)
    }

    /// The outputs of `model` at `solution`, read at the base's args; at the
    /// [`PathPlace::Outermost`] points each peak's and minimum's own arg is found
    /// from the whole rod (elsewhere the base's is reported).
    pub fn read(&self, model: &Model, solution: &Solution, place: PathPlace) -> Vec<Sample> {
        let state = &solution.state;
        let frames: Vec<_> = (0..model.system().rods.len())
            .map(|r| model.boundary_frames(r, state))
            .collect();
        let mut samples = self.read_with(model.system(), state, &frames, place);
        if let Some(k) = self.readings.iter().position(|r| *r == Reading::Energy) {
            samples[k].value = model.energy(state);
        }
        if !self.contact_keys.is_empty() {
            // The multipliers by key, looked up by bisection (not a scan per contact).
            let mut by_key: Vec<(RowKey, f64)> = solution
                .constraints
                .iter()
                .map(|(row, force)| (row.key, *force))
                .collect();
            by_key.sort_by_key(|(k, _)| *k);
            for (sample, reading) in samples.iter_mut().zip(&self.readings) {
                if let Reading::ContactForce { index } = *reading {
                    let key = self.contact_keys[index];
                    sample.value = by_key
                        .binary_search_by_key(&key, |(k, _)| *k)
                        .map_or(0.0, |i| by_key[i].1);
                }
            }
        }
        samples
    }

    /// Whether the plan reads clearances or contact forces: those are read at the
    /// base only (the least gaps and the contacts found there), so the plan serves
    /// only exact derivatives ([`LocalTangents`]), no reading along a path.
    pub fn reads_contacts(&self) -> bool {
        self.readings.iter().any(|r| {
            matches!(
                r,
                Reading::Clearance { .. }
                    | Reading::MinClearance { .. }
                    | Reading::ContactForce { .. }
            )
        })
    }

    /// The least clearance of rod `rod` and its place among the rod's obstacles (the
    /// first of equal ones), m.
    fn min_clearance(&self, rod: usize) -> (f64, usize) {
        let mut best = (f64::INFINITY, 0);
        for (k, &index) in self.rod_clearances[rod].iter().enumerate() {
            let distance = self.clearances[index].distance_m();
            if distance < best.0 {
                best = (distance, k);
            }
        }
        best
    }

    /// [`LocalOutputs::read`] of `system` in `state` with every rod's boundary frames
    /// `frames` (the energy, which needs the model, as NaN).
    fn read_with(
        &self,
        system: &System,
        state: &SystemState,
        frames: &[BoundaryFrames],
        place: PathPlace,
    ) -> Vec<Sample> {
        let mut reactions = vec![None; self.reaction_ends.len()];
        // Each rod's peaks' own args, at the outermost points only.
        let whole: Vec<Option<PeakArgs>> = match place {
            PathPlace::Outermost => (0..system.rods.len())
                .map(|r| Some(PeakArgs::of(system, state, &frames[r], r)))
                .collect(),
            _ => vec![None; system.rods.len()],
        };
        let at = |rod: usize, vertex: usize| {
            sectional_at(
                &system.rods[rod].rod,
                &state.rods[rod],
                &frames[rod],
                vertex,
            )
        };
        // A peak's value at vertex `j` (where the whole rod found it).
        let found_value = |reading: Reading, j: usize| match reading {
            Reading::Force { rod, .. } => norm(&at(rod, j).force),
            Reading::Moment { rod, .. } => norm(&at(rod, j).moment),
            Reading::BendRadius { rod, .. } => radius(&at(rod, j).curvature),
            Reading::MinClearance { rod } => {
                self.clearances[self.rod_clearances[rod][j]].distance_m()
            }
            _ => f64::NAN,
        };
        self.readings
            .iter()
            .zip(&self.args)
            .map(|(reading, &arg)| {
                let (value, found) = match *reading {
                    Reading::Force { rod, vertex } => {
                        (norm(&at(rod, vertex).force), whole[rod].map(|a| a.force))
                    }
                    Reading::Moment { rod, vertex } => {
                        (norm(&at(rod, vertex).moment), whole[rod].map(|a| a.moment))
                    }
                    Reading::BendRadius { rod, vertex } => (
                        radius(&at(rod, vertex).curvature),
                        whole[rod].map(|a| a.bend_radius),
                    ),
                    Reading::Reaction {
                        index,
                        moment,
                        axis,
                    } => {
                        let (force, torque) = *reactions[index].get_or_insert_with(|| {
                            let (rod, at_end) = self.reaction_ends[index];
                            system.end_reaction(rod, at_end, &state.rods[rod], &frames[rod])
                        });
                        ((if moment { torque } else { force })[axis], None)
                    }
                    Reading::Position { body, axis } => (state.bodies[body].position[axis], None),
                    Reading::Rotation { body, axis } => {
                        (rotation_vector(&state.bodies[body].orientation)[axis], None)
                    }
                    Reading::Energy => (f64::NAN, None),
                    // The base's (see `reads_contacts`); a contact force from the
                    // solution's multipliers (`read`).
                    Reading::Clearance { index } => (self.clearances[index].distance_m(), None),
                    Reading::MinClearance { rod } => {
                        let (value, k) = self.min_clearance(rod);
                        (value, Some(k))
                    }
                    Reading::ContactForce { .. } => (f64::NAN, None),
                };
                // The base's place stays the arg where the place found ties with it
                // (`strand_report::ARG_TIE`), as in the whole table.
                let found = found.filter(|&j| j != arg && !ties(value, found_value(*reading, j)));
                Sample {
                    value,
                    arg: found.unwrap_or(arg),
                }
            })
            .collect()
    }
}

/// Where a rod's peaks are: the vertices of its largest `|f̄|` and `|m|` and of its
/// smallest bend radius, as the whole table finds them from every vertex's sectional
/// quantities ([`sectional_at`] per vertex: the numbers of the whole rod's
/// [`strand_rod::sectional::sectional`] without the quantities no peak reads).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct PeakArgs {
    force: usize,
    moment: usize,
    bend_radius: usize,
}

impl PeakArgs {
    /// The peaks' vertices of rod `rod` of `system` in `state` with its `frames`.
    fn of(system: &System, state: &SystemState, frames: &BoundaryFrames, rod: usize) -> Self {
        let spec = &system.rods[rod];
        let n = spec.rod.segments();
        let (mut forces, mut moments, mut radii) = (
            Vec::with_capacity(n + 1),
            Vec::with_capacity(n + 1),
            Vec::with_capacity(n + 1),
        );
        for j in 0..=n {
            let s = sectional_at(&spec.rod, &state.rods[rod], frames, j);
            forces.push(norm(&s.force));
            moments.push(norm(&s.moment));
            radii.push(radius(&s.curvature));
        }
        Self {
            force: largest(forces.into_iter()),
            moment: largest(moments.into_iter()),
            bend_radius: smallest(radii.into_iter()),
        }
    }
}

/// `|v|` as the whole table computes a peak's magnitude.
fn norm(v: &Vector3<f64>) -> f64 {
    magnitude(&[v.x, v.y, v.z])
}

/// The bend radius `1 / |K_⊥|` (m) of a material curvature `k` (1/m).
fn radius(k: &Vector3<f64>) -> f64 {
    1.0 / k.x.hypot(k.y)
}

/// The vertex of the largest value (the first on ties; NaN wins), as the whole table
/// finds a peak.
fn largest(values: impl Iterator<Item = f64>) -> usize {
    let mut best = (f64::NEG_INFINITY, 0);
    for (j, m) in values.enumerate() {
        if m > best.0 || m.is_nan() && !best.0.is_nan() {
            best = (m, j);
        }
    }
    best.1
}

/// The vertex of the smallest value (the first on ties), as the whole table finds
/// the smallest bend radius.
fn smallest(values: impl Iterator<Item = f64>) -> usize {
    let mut best = (f64::INFINITY, 0);
    for (j, r) in values.enumerate() {
        if r < best.0 {
            best = (r, j);
        }
    }
    best.1
}

/// The rotation vector (rad) of `q`, as the whole table writes a junction's rotation
/// (through the document's quaternion).
fn rotation_vector(q: &UnitQuaternion<f64>) -> Vector3<f64> {
    let q = UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(q.w, q.i, q.j, q.k));
    q.scaled_axis()
}

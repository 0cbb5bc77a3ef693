//! The exact derivatives of a plan's local readings along an affine parameter's
//! first-order path, without evaluating them along it: each rod is linearised once
//! per equilibrium ([`SectionalLinearisation`]) and every parameter is one tangent
//! per rod — the state's part from `dδ/dp` (free vertices, edge frames, bodies and the
//! held ends and port frames they carry), the model's part from the rod's reference
//! data moved along the parameter's line (edge lengths, rest strains and curvatures,
//! stiffnesses, lumped end loads, supports' positions: affine, at most quadratic,
//! along the line, so their central differences are exact). The readings' derivatives follow by
//! the chain rule: no design, no path point, no ladder of steps.
//!
//! Where a peak could move (the one-sided marks of
//! [`strand_solve::sensitivity::Sensitivities::derivative_along`], which look for the
//! arg at the outermost points `±2h`), the first-order changes at the base rule out
//! every vertex whose gap to the peak cannot close within `±2h`: a gap closes at
//! the rate the two vertices' values part, and a vertex stays a candidate while its
//! gap is within twice that change over `2h`, a second-order allowance
//! ([`SECOND_ORDER`]) and [`PEAK_MARGIN`]; only the remaining candidates
//! are evaluated at `±2h` ([`LocalPath`]), so the work grows with the candidates, not
//! with the segments.

use nalgebra::{UnitQuaternion, Vector3};
use strand_case::AffineLine;
use strand_contact::{Gap, Obstacle};
use strand_report::{LeastClearance, ties};
use strand_rod::sectional::BoundaryFrames;
use strand_rod::sectional_at::VertexSectional;
use strand_rod::sectional_tangent::{RodTangent, SectionalLinearisation, SectionalSize, SizeRates};
use strand_rod::so3;
use strand_solve::RowKey;
use strand_solve::sensitivity::OutputDerivative;
use strand_system::{Model, Pose, Support, System, SystemError, SystemState};

use super::{LocalOutputs, LocalPath, Reading, largest, smallest};

/// The margin, relative to a peak's value, within which a vertex stays a candidate
/// for the peak at the outermost points `±2h` beyond what the first-order changes of
/// the gap allow (covering the second-order change of a gap whose first-order change
/// vanishes: `(2h/L)²` for a parameter that changes the output by its own size over
/// `L`, below 1e-5 for `L` above 7 % of the parameter's scale).
pub const PEAK_MARGIN: f64 = 1e-5;

/// The second-order allowance of a gap at `±2h`, in units of `(2h·rate)² / peak`:
/// ten times the second-order change of an output whose relative rate is constant
/// (a size proportional to a power of the parameter).
pub const SECOND_ORDER: f64 = 10.0;

/// A plan's readings linearised at a base equilibrium.
pub struct LocalTangents<'a> {
    plan: &'a LocalOutputs,
    model: &'a Model,
    base: &'a SystemState,
    /// Per rod, its linearisation.
    rods: Vec<SectionalLinearisation>,
    /// Per rod, the base values of every vertex's sectional quantities.
    values: Vec<Vec<VertexSectional>>,
    /// Per rod, the rate coefficients of the sizes its peaks compare (force, moment,
    /// curvature; `None` for a size no peak of the rod reads).
    sizes: Vec<[Option<SizeRates>; 3]>,
    /// Per rod, its boundary frames at the base (a line that turns one is not carried).
    frames: Vec<[Option<UnitQuaternion<f64>>; 2]>,
    /// The base system, moved along a parameter's line and back for its model's part.
    system: System,
    /// Per clearance of the plan, its rivals listed so far and the band (m) they were
    /// listed within: a later parameter whose band is no wider reuses them.
    rivals: Vec<Option<(f64, Vec<Gap>)>>,
}

/// The derivatives of a plan's readings with respect to one parameter.
#[derive(Clone, Debug)]
pub struct ExactDerivatives {
    /// One per output of the plan, in its order.
    pub outputs: Vec<OutputDerivative>,
    /// Vertices whose sectional quantities were evaluated at the outermost points
    /// (both sides counted): the candidates the first-order bound left.
    pub outer_vertices: usize,
}

/// The rod's reference data and supports that a parameter's line moves, at one point.
struct RodInputs {
    numbers: Vec<f64>,
    frames: [Option<UnitQuaternion<f64>>; 2],
}

impl<'a> LocalTangents<'a> {
    /// Linearises `plan`'s rods in `model` at the base equilibrium `base`; `None`
    /// where a rod cannot be linearised (clips).
    pub fn new(plan: &'a LocalOutputs, model: &'a Model, base: &'a SystemState) -> Option<Self> {
        let system = model.system();
        let mut rods = Vec::with_capacity(system.rods.len());
        let mut values = Vec::with_capacity(system.rods.len());
        let mut sizes = Vec::with_capacity(system.rods.len());
        for r in 0..system.rods.len() {
            let frames = model.boundary_frames(r, base);
            let lin = SectionalLinearisation::new(&system.rods[r].rod, &base.rods[r], &frames)?;
            let rod_values = lin.values();
            sizes.push(Quantity::ALL.map(|quantity| {
                plan.readings
                    .iter()
                    .any(|reading| Quantity::of(reading) == Some((r, quantity)))
                    .then(|| lin.size_rates(quantity.size(), &rod_values))
            }));
            values.push(rod_values);
            rods.push(lin);
        }
        let bodies = poses(system, &base.bodies);
        let frames = (0..system.rods.len())
            .map(|r| inputs(system, r, &bodies).frames)
            .collect();
        Some(Self {
            plan,
            model,
            base,
            rods,
            values,
            sizes,
            frames,
            system: system.clone(),
            rivals: vec![None; plan.clearances.len()],
        })
    }

    /// The derivatives of the plan's readings with respect to the parameter whose
    /// design moves along `line`, with `tangent` its `dδ/dp` and `step` its output
    /// step `h` (the outermost points are `±2h`). `None` where the line moves
    /// something the tangents do not carry (a boundary frame, a body that is neither
    /// free nor fixed): the caller then differentiates along the path.
    ///
    /// A contact force's derivative is its row's multiplier's, `multipliers` per
    /// `active` key (`dμ/dp`); a clearance's is that of its least gap at the base,
    /// `n · (dP − dQ) − dr` (`P` the rod's point, `Q` the other rod's or fixed on the
    /// mesh, which the line does not move, `r` the radii), 0 where the surfaces
    /// overlap (the clearance is held at 0); a rod's least clearance is marked
    /// one-sided where another obstacle's clearance comes within twice its
    /// first-order change over `±2h` (and [`PEAK_MARGIN`]) of it; a clearance to a
    /// mesh is one-sided where another gap of the rod to it may take its place within
    /// `±2h` to first order, and a clearance set by the exclusion of near pairs (a
    /// rod's to itself along a stretch,
    /// [`strand_report::LeastClearance::at_exclusion`]) is one-sided.
    pub fn derivatives(
        &mut self,
        line: &AffineLine<'_>,
        tangent: &[f64],
        multipliers: (&[RowKey], &[f64]),
        step: f64,
    ) -> Result<Option<ExactDerivatives>, SystemError> {
        let Some(rod_tangents) = self.tangents(line, tangent, step)? else {
            return Ok(None);
        };
        let (tangents, reaction_loads, radius_rates) = rod_tangents;
        // The multipliers' rates by key, looked up by bisection.
        let mut multiplier_rates: Vec<(RowKey, f64)> = multipliers
            .0
            .iter()
            .copied()
            .zip(multipliers.1.iter().copied())
            .collect();
        multiplier_rates.sort_by_key(|(k, _)| *k);
        // Each clearance's derivative, where the plan reads clearances.
        let clearance_rates: Vec<f64> = self
            .plan
            .clearances
            .iter()
            .map(|least| clearance_rate(least, &tangents, &radius_rates))
            .collect();
        // The change of a peak's vertex.
        let change =
            |rod: usize, vertex: usize| self.rods[rod].vertex_tangent(vertex, &tangents[rod]).1;
        let dofs = self.model.dofs();
        let mut outputs = Vec::with_capacity(self.plan.readings.len());
        // Each reaction's terms once for its six components.
        let mut ends = vec![None; self.plan.reaction_ends.len()];
        for (reading, &arg) in self.plan.readings.iter().zip(&self.plan.args) {
            let derivative = match *reading {
                Reading::Force { rod, vertex } => {
                    let (v, d) = (&self.values[rod][vertex].force, &change(rod, vertex).force);
                    v.dot(d) / v.norm()
                }
                Reading::Moment { rod, vertex } => {
                    let (v, d) = (
                        &self.values[rod][vertex].moment,
                        &change(rod, vertex).moment,
                    );
                    v.dot(d) / v.norm()
                }
                Reading::BendRadius { rod, vertex } => {
                    let (k, d) = (
                        &self.values[rod][vertex].curvature,
                        &change(rod, vertex).curvature,
                    );
                    let squared = k.x * k.x + k.y * k.y;
                    -(k.x * d.x + k.y * d.y) / (squared * squared.sqrt())
                }
                Reading::Reaction {
                    index,
                    moment,
                    axis,
                } => {
                    let (rod, at_end) = self.plan.reaction_ends[index];
                    let d = *ends[index].get_or_insert_with(|| {
                        self.rods[rod].end_terms_tangent(at_end, &tangents[rod]).1
                    });
                    if moment {
                        d.moment[axis]
                    } else {
                        d.edge_force[axis] - reaction_loads[rod][usize::from(at_end)][axis]
                    }
                }
                Reading::Position { body, axis } => match dofs.body(body) {
                    Some((translation, _)) => tangent[3 * translation + axis],
                    None => return Ok(None),
                },
                Reading::Rotation { body, axis } => match dofs.body(body) {
                    Some((_, rotation)) => {
                        let phi = so3::log(&self.base.bodies[body].orientation);
                        let omega = block(tangent, rotation);
                        match so3::right_jacobian(&phi).try_inverse() {
                            Some(inverse) => (inverse * omega)[axis],
                            None => return Ok(None),
                        }
                    }
                    None => return Ok(None),
                },
                // No local reading: the caller differentiates it along the path.
                Reading::Energy => f64::NAN,
                Reading::Clearance { index } => clearance_rates[index],
                Reading::MinClearance { rod } => {
                    clearance_rates[self.plan.rod_clearances[rod][arg]]
                }
                Reading::ContactForce { index } => {
                    let key = self.plan.contact_keys[index];
                    multiplier_rates
                        .binary_search_by_key(&key, |(k, _)| *k)
                        .map_or(0.0, |i| multiplier_rates[i].1)
                }
            };
            outputs.push(OutputDerivative {
                derivative,
                one_sided: false,
            });
        }
        let outer_vertices = self.mark_one_sided(line, tangent, step, &tangents, &mut outputs)?;
        self.mark_least_clearances(step, &clearance_rates, &mut outputs);
        let moving = self.clearance_rivals(step, &tangents, &radius_rates, &clearance_rates);
        // A clearance set by the exclusion of near pairs holds on one side only.
        for ((reading, &arg), output) in self
            .plan
            .readings
            .iter()
            .zip(&self.plan.args)
            .zip(&mut outputs)
        {
            let index = match *reading {
                Reading::Clearance { index } => index,
                Reading::MinClearance { rod } => self.plan.rod_clearances[rod][arg],
                _ => continue,
            };
            if self.plan.clearances[index].at_exclusion || moving[index] {
                output.one_sided = true;
            }
        }
        Ok(Some(ExactDerivatives {
            outputs,
            outer_vertices,
        }))
    }

    /// Marks the peaks whose arg differs from the base's at `±2·step`: the candidates
    /// the first-order bound leaves are evaluated there exactly; returns how many
    /// vertex evaluations that took.
    fn mark_one_sided(
        &self,
        line: &AffineLine<'_>,
        tangent: &[f64],
        step: f64,
        tangents: &[RodTangent],
        outputs: &mut [OutputDerivative],
    ) -> Result<usize, SystemError> {
        let outer = 2.0 * step;
        let rods = self.values.len();
        // Per peak output: its rod and its candidates.
        let mut peaks: Vec<(usize, usize, Quantity, Vec<usize>)> = Vec::new();
        let mut wanted: Vec<Vec<usize>> = vec![Vec::new(); rods];
        // Per rod and size, every vertex's rate (from the size's coefficients) and
        // whether it is one (a zero size has only a bound of its growth).
        let mut rates: Vec<[Option<VertexRates>; 3]> = vec![[None, None, None]; rods];
        for (k, (reading, &arg)) in self.plan.readings.iter().zip(&self.plan.args).enumerate() {
            let Some((rod, quantity)) = Quantity::of(reading) else {
                continue;
            };
            let coefficients = self.sizes[rod][quantity as usize]
                .as_ref()
                .expect("the plan's peaks have coefficients");
            let sizes = coefficients.sizes();
            let size = |j: usize| sizes[j];
            let rod_rates = rates[rod][quantity as usize]
                .get_or_insert_with(|| coefficients.rates(&self.rods[rod], &tangents[rod]));
            let rate = |j: usize| rod_rates[j];
            let peak = size(arg);
            let (peak_rate, _) = rate(arg);
            let all_finite =
                (0..self.values[rod].len()).all(|j| size(j).is_finite() && rate(j).0.is_finite());
            let candidates: Vec<usize> = (0..self.values[rod].len())
                .filter(|&j| {
                    if !all_finite || j == arg {
                        return true;
                    }
                    let (r, exact) = rate(j);
                    let apart = if exact {
                        (r - peak_rate).abs()
                    } else {
                        r.abs() + peak_rate.abs()
                    };
                    let second =
                        SECOND_ORDER * (outer * r.abs().max(peak_rate.abs())).powi(2) / peak.abs();
                    peak - size(j) <= 2.0 * outer * apart + second + PEAK_MARGIN * peak.abs()
                })
                .collect();
            if candidates.len() > 1 {
                wanted[rod].extend(&candidates);
                peaks.push((k, rod, quantity, candidates));
            }
        }
        if peaks.is_empty() {
            return Ok(0);
        }
        for list in &mut wanted {
            list.sort_unstable();
            list.dedup();
        }
        let mut path = LocalPath::new(self.plan, line.clone(), self.base, tangent);
        let mut evaluated = 0;
        let mut sides = Vec::with_capacity(2);
        for t in [outer, -outer] {
            sides.push(path.sectional_at_vertices(t, &wanted)?);
            evaluated += wanted.iter().map(Vec::len).sum::<usize>();
        }
        for (k, rod, quantity, candidates) in peaks {
            let arg = self.plan.args[k];
            for side in &sides {
                let at = |j: usize| {
                    let x = wanted[rod]
                        .binary_search(&j)
                        .expect("a candidate is wanted");
                    &side[rod][x]
                };
                let value = |j: usize| match quantity {
                    Quantity::Force => norm(&at(j).force),
                    Quantity::Moment => norm(&at(j).moment),
                    Quantity::BendRadius => super::radius(&at(j).curvature),
                };
                let found = match quantity {
                    Quantity::BendRadius => smallest(candidates.iter().map(|&j| value(j))),
                    _ => largest(candidates.iter().map(|&j| value(j))),
                };
                // A place that only ties with the base's (`strand_report::ARG_TIE`)
                // does not move the arg, as in the whole table.
                let found = candidates[found];
                if found != arg && !ties(value(arg), value(found)) {
                    outputs[k].one_sided = true;
                }
            }
        }
        Ok(evaluated)
    }

    /// Per rod, the tangent of the parameter whose design moves along `line` (state
    /// part from `tangent`, model part from the line at `±step`, `±2·step`), and the
    /// derivative of the loads a reaction subtracts at each end (`h̄ ρ_L g` and the dead
    /// end load, N); `None` where the line turns a boundary frame or a body the
    /// tangent does not carry holds an end.
    #[allow(clippy::type_complexity)]
    fn tangents(
        &mut self,
        line: &AffineLine<'_>,
        tangent: &[f64],
        step: f64,
    ) -> Result<Option<(Vec<RodTangent>, Vec<[Vector3<f64>; 2]>, Vec<f64>)>, SystemError> {
        let base_system = self.model.system();
        let dofs = self.model.dofs();
        // The model's part: the inputs at ±s, differenced (exact: they are affine, at
        // most quadratic, along the line), of the rods whose inputs the line moves.
        let system = &mut self.system;
        let same_bodies = |a: &System| {
            a.bodies.len() == base_system.bodies.len()
                && a.bodies
                    .iter()
                    .zip(&base_system.bodies)
                    .all(|(x, y)| x.pose == y.pose && x.ports == y.ports && x.fixed == y.fixed)
        };
        let mut sides: Vec<Vec<Option<RodInputs>>> = Vec::with_capacity(2);
        let mut radius_rates = vec![0.0; base_system.rods.len()];
        for (t, sign) in [(step, 1.0), (-step, -1.0)] {
            line.move_system(system, t)?;
            for (rate, spec) in radius_rates.iter_mut().zip(&system.rods) {
                *rate += sign * spec.rod.section().outer_radius / (2.0 * step);
            }
            let everything = system.gravity != base_system.gravity || !same_bodies(system);
            let bodies = poses(system, &self.base.bodies);
            sides.push(
                (0..system.rods.len())
                    .map(|r| {
                        (everything || system.rods[r] != base_system.rods[r])
                            .then(|| inputs(system, r, &bodies))
                    })
                    .collect(),
            );
        }
        line.move_system(system, 0.0)?;
        let mut tangents = Vec::with_capacity(base_system.rods.len());
        let mut loads = Vec::with_capacity(base_system.rods.len());
        for (r, spec) in base_system.rods.iter().enumerate() {
            let d: Vec<f64> = match (&sides[0][r], &sides[1][r]) {
                (Some(plus), Some(minus)) => {
                    if plus.frames != self.frames[r] || minus.frames != self.frames[r] {
                        return Ok(None);
                    }
                    plus.numbers
                        .iter()
                        .zip(&minus.numbers)
                        .map(|(a, b)| (a - b) / (2.0 * step))
                        .collect()
                }
                _ => vec![0.0; 3 * (2 * spec.rod.segments() + 9) + spec.rod.segments()],
            };
            let n = spec.rod.segments();
            let mut rod = RodTangent::zero(n);
            let mut at = 0;
            let mut take3 = || {
                let v = Vector3::new(d[at], d[at + 1], d[at + 2]);
                at += 3;
                v
            };
            let held = [take3(), take3()];
            rod.end_loads = [take3(), take3()];
            let reaction = [take3(), take3()];
            rod.strain_stiffness = take3();
            rod.curvature_stiffness = take3();
            for e in 0..n {
                rod.rest_strains[e] = take3();
            }
            for j in 0..=n {
                rod.rest_curvatures[j] = take3();
            }
            rod.edge_lengths.copy_from_slice(&d[at..at + n]);
            // The state's part.
            for e in 0..n {
                rod.frames[e] = block(tangent, dofs.edge(r, e));
            }
            for j in 0..=n {
                rod.positions[j] = match dofs.vertex(r, j) {
                    Some(b) => block(tangent, b),
                    None => {
                        let (end, k) = if j == 0 {
                            (&spec.start, 0)
                        } else {
                            (&spec.end, 1)
                        };
                        match carried(
                            base_system,
                            end.support,
                            j == n,
                            tangent,
                            dofs,
                            &self.base.bodies,
                        ) {
                            Some((dr, _)) => dr + held[k],
                            None => return Ok(None),
                        }
                    }
                };
            }
            for (k, end) in [&spec.start, &spec.end].into_iter().enumerate() {
                match carried(
                    base_system,
                    end.support,
                    k == 1,
                    tangent,
                    dofs,
                    &self.base.bodies,
                ) {
                    Some((_, omega)) => rod.boundary[k] = omega,
                    None => return Ok(None),
                }
            }
            tangents.push(rod);
            loads.push(reaction);
        }
        Ok(Some((tangents, loads, radius_rates)))
    }

    /// Per clearance of the plan, whether its least gap to a mesh may move to another
    /// feature within `±2·step`: a rival gap of the same rod and mesh (the listing's,
    /// [`strand_solve::contact::Contact::mesh_gaps_near_least`], within the band any
    /// feature's first-order change allows) comes within twice the first-order change
    /// of their difference (and [`PEAK_MARGIN`]) of it. Where the rivals cannot be
    /// listed (a centreline touching the mesh), the place may move. The rivals are
    /// listed again only for a band wider than any listed before, and then within eight
    /// times the band asked for: a wider listing costs little more (the grid bounds of
    /// every edge are the same work; only the edges within the band add), so most
    /// clearances are listed once for all the parameters (cooler_hose_contact's ten:
    /// 6 listings instead of 11 with twice the band).
    fn clearance_rivals(
        &mut self,
        step: f64,
        tangents: &[RodTangent],
        radius_rates: &[f64],
        rates: &[f64],
    ) -> Vec<bool> {
        let outer = 2.0 * step;
        let mut moving = vec![false; self.plan.clearances.len()];
        let plan = self.plan;
        let Some(super::PlanContact(contact)) = &plan.contact else {
            return moving;
        };
        for (index, least) in plan.clearances.iter().enumerate() {
            let gap = &least.gap;
            let Obstacle::Mesh(mesh) = gap.with else {
                continue;
            };
            if gap.gap < 0.0 {
                continue;
            }
            let fastest = tangents[gap.rod]
                .positions
                .iter()
                .fold(0.0f64, |m, p| m.max(p.norm()))
                + radius_rates[gap.rod].abs();
            let margin = PEAK_MARGIN * gap.gap;
            let band = 2.0 * outer * (fastest + rates[index].abs()) * (1.0 + 1e-9) + margin;
            let listed = self.rivals[index]
                .as_ref()
                .is_some_and(|(within, _)| *within >= band);
            if !listed {
                let within = 8.0 * band;
                let Ok(found) = contact.mesh_gaps_near_least(
                    self.model,
                    self.base,
                    gap.rod,
                    mesh,
                    strand_report::CLEARANCE_SEARCH_M,
                    within,
                ) else {
                    moving[index] = true;
                    continue;
                };
                self.rivals[index] = Some((within, found));
            }
            let (_, rivals) = self.rivals[index].as_ref().expect("listed");
            // Rates that differ by their rounding only (a rival and the least both
            // held at contact, both rates zero but for rounding) cannot change places.
            let rounding = RATE_ROUNDING * fastest;
            moving[index] = rivals.iter().any(|rival| {
                let same = rival.edge == gap.edge
                    && rival.s.to_bits() == gap.s.to_bits()
                    && rival.gap.to_bits() == gap.gap.to_bits();
                let apart = (gap_rate(rival, tangents, radius_rates) - rates[index]).abs();
                let reach = 2.0 * outer * (apart - rounding).max(0.0) + margin;
                !same && reach > 0.0 && rival.gap - gap.gap <= reach
            });
        }
        moving
    }

    /// Marks each rod's least clearance one-sided where another of its obstacles'
    /// clearances comes within twice its first-order change over `±2·step` (and
    /// [`PEAK_MARGIN`] of the least) of it: its arg-min may move there.
    fn mark_least_clearances(&self, step: f64, rates: &[f64], outputs: &mut [OutputDerivative]) {
        let outer = 2.0 * step;
        for (k, (reading, &arg)) in self.plan.readings.iter().zip(&self.plan.args).enumerate() {
            let Reading::MinClearance { rod } = *reading else {
                continue;
            };
            let indices = &self.plan.rod_clearances[rod];
            let least = indices[arg];
            let value = |i: usize| self.plan.clearances[i].distance_m();
            let margin = PEAK_MARGIN * value(least);
            if indices.iter().any(|&i| {
                i != least
                    && value(i) - value(least)
                        <= 2.0 * outer * (rates[i] - rates[least]).abs() + margin
            }) {
                outputs[k].one_sided = true;
            }
        }
    }
}

/// The rounding of a gap's rate (m per unit of the parameter) relative to the fastest
/// vertex's rate of its rod: rates within this of each other are equal for
/// [`LocalTangents::clearance_rivals`] (a hose held at contact on
/// `cooler_hose_contact`'s bracket: its gap's rate along hose 3's length came out
/// 1.8e-18, where it is 0, once the solve's rows were made in another order).
const RATE_ROUNDING: f64 = 1e-12;

/// Per vertex, the rate of a size and whether it is one ([`SizeRates::rates`]).
type VertexRates = Vec<(f64, bool)>;

/// Which sectional quantity a peak reads (the index of its size's coefficients).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Quantity {
    Force = 0,
    Moment = 1,
    BendRadius = 2,
}

impl Quantity {
    const ALL: [Self; 3] = [Self::Force, Self::Moment, Self::BendRadius];

    /// The rod and quantity of a peak's reading; `None` for any other reading.
    fn of(reading: &Reading) -> Option<(usize, Self)> {
        match *reading {
            Reading::Force { rod, .. } => Some((rod, Self::Force)),
            Reading::Moment { rod, .. } => Some((rod, Self::Moment)),
            Reading::BendRadius { rod, .. } => Some((rod, Self::BendRadius)),
            _ => None,
        }
    }

    /// The size compared between vertices (largest wins): `|f̄|`, `|m|`, `|K_⊥|`.
    fn size(self) -> SectionalSize {
        match self {
            Self::Force => SectionalSize::Force,
            Self::Moment => SectionalSize::Moment,
            Self::BendRadius => SectionalSize::Curvature,
        }
    }
}

/// The derivative (m per parameter unit) of the least gap `least` along the rods'
/// tangents `tangents` and the rods' radii's rates `radius_rates`: `n · (dP − dQ)` less
/// the radii's change (the mesh is not moved by an affine line), 0 where the surfaces
/// overlap (the clearance is held at 0 there).
fn clearance_rate(least: &LeastClearance, tangents: &[RodTangent], radius_rates: &[f64]) -> f64 {
    if least.gap.gap < 0.0 {
        return 0.0;
    }
    gap_rate(&least.gap, tangents, radius_rates)
}

/// The derivative (m per parameter unit) of gap `gap` at its points: `n · (dP − dQ)`
/// less the radii's change.
fn gap_rate(gap: &Gap, tangents: &[RodTangent], radius_rates: &[f64]) -> f64 {
    let along = |rod: usize, edge: usize, s: f64| {
        let p = &tangents[rod].positions;
        p[edge] * (1.0 - s) + p[edge + 1] * s
    };
    let mut moved = along(gap.rod, gap.edge, gap.s);
    let mut radii = radius_rates[gap.rod];
    if let Obstacle::Rod { rod, edge, t } = gap.with {
        moved -= along(rod, edge, t);
        radii += radius_rates[rod];
    }
    gap.normal.dot(&moved) - radii
}

fn norm(v: &Vector3<f64>) -> f64 {
    super::norm(v)
}

/// The 3-vector of block `b` of `x`.
fn block(x: &[f64], b: usize) -> Vector3<f64> {
    Vector3::new(x[3 * b], x[3 * b + 1], x[3 * b + 2])
}

/// The base poses with the fixed bodies' poses of `system` (the model's part of a
/// body's pose: a fixed body is placed by the model).
fn poses(system: &System, base: &[Pose]) -> Vec<Pose> {
    base.iter()
        .zip(&system.bodies)
        .map(|(pose, spec)| if spec.fixed { spec.pose } else { *pose })
        .collect()
}

/// The numbers of rod `r` of `system` that a parameter's line may move (the held
/// vertices' positions, the lumped end loads, the loads a reaction subtracts, the
/// stiffnesses, rest strains and curvatures, edge lengths, in this order) and its
/// boundary frames, with the bodies at `bodies`.
fn inputs(system: &System, r: usize, bodies: &[Pose]) -> RodInputs {
    let spec = &system.rods[r];
    let rod = &spec.rod;
    let n = rod.segments();
    let boundary: BoundaryFrames = system.ends_boundary(r, bodies);
    let mut numbers = Vec::with_capacity(3 * (2 * n + 9) + n);
    let mut push = |v: &Vector3<f64>| numbers.extend_from_slice(v.as_slice());
    for (end, at_end) in [(&spec.start, false), (&spec.end, true)] {
        push(
            &system
                .end_placement(end, at_end, bodies)
                .0
                .unwrap_or_default(),
        );
    }
    push(&boundary.end_loads[0]);
    push(&boundary.end_loads[1]);
    for (end, vertex) in [(&spec.start, 0), (&spec.end, n)] {
        push(&(rod.vertex_mass(vertex) * system.gravity + end.load.force));
    }
    push(&rod.section().strain_stiffness());
    push(&rod.section().curvature_stiffness());
    for e in 0..n {
        push(rod.rest_strain(e));
    }
    for j in 0..=n {
        push(rod.rest_curvature(j));
    }
    numbers.extend_from_slice(rod.edge_lengths());
    RodInputs {
        numbers,
        frames: [boundary.start, boundary.end],
    }
}

/// The state's part of a held end's motion (`dr`, m, and the material increment of
/// its boundary frame, rad, per unit of the parameter) for the support `support` at
/// the rod's end (`at_end`) or start: zero on a connector or a fixed body, the body's
/// motion on a free body's port; `None` for a body that is neither.
fn carried(
    system: &System,
    support: Support,
    at_end: bool,
    tangent: &[f64],
    dofs: &strand_system::Dofs,
    bodies: &[Pose],
) -> Option<(Vector3<f64>, Vector3<f64>)> {
    match support {
        Support::Port { body, port, .. } => match dofs.body(body.0) {
            Some((translation, rotation)) => {
                let omega = block(tangent, rotation);
                let pose = &bodies[body.0];
                let lever =
                    pose.orientation * omega.cross(&system.bodies[body.0].ports[port].position);
                let offset = system.port_offset(body, port, at_end);
                Some((
                    block(tangent, translation) + lever,
                    offset.inverse_transform_vector(&omega),
                ))
            }
            None if system.bodies[body.0].fixed => Some((Vector3::zeros(), Vector3::zeros())),
            None => None,
        },
        _ => Some((Vector3::zeros(), Vector3::zeros())),
    }
}

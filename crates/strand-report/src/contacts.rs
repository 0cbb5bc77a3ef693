//! Contacts and clearances of a solved case for `result.json`.

use strand_contact::gaps::Aabb;
use strand_contact::{Gap, MeshIndex, Obstacle};
use strand_solve::contact::Contact;
use strand_solve::{RowKey, Solution};
use strand_system::{Model, SystemState};

use crate::{ClearanceResult, ContactResult, ResultDoc};

/// How far (surface to surface, m) clearances are searched: obstacles farther from a
/// rod than this get no `clearance` entry.
pub const CLEARANCE_SEARCH_M: f64 = 0.1;

/// How far (surface to surface, m) clearances are searched when rods require the
/// clearances `required` (m): [`CLEARANCE_SEARCH_M`], or 1 % (and 1 µm) beyond the
/// largest requirement, so that a pair just outside it is listed as fine.
pub fn clearance_search_m(required: impl IntoIterator<Item = f64>) -> f64 {
    required
        .into_iter()
        .map(|c| 1.01 * c + 1e-6)
        .fold(CLEARANCE_SEARCH_M, f64::max)
}

fn arr(v: &nalgebra::Vector3<f64>) -> [f64; 3] {
    [v.x, v.y, v.z]
}

/// Fills `doc.contacts` (every pair that carries a force, on the rod that is
/// touched; a rod–rod contact is listed for both rods) and `doc.clearance` (per rod
/// and obstacle, the smallest surface distance within [`CLEARANCE_SEARCH_M`]; see
/// [`collect_clearances`] for a wider search).
pub fn collect_contacts(
    doc: &mut ResultDoc,
    model: &Model,
    solution: &Solution,
    contact: &Contact,
) -> Result<(), strand_solve::ConstraintError> {
    collect_contact_outputs(doc, model, solution, contact)?;
    vertex_clearances(doc, model, solution, contact, CLEARANCE_SEARCH_M);
    Ok(())
}

/// The contacts and the least clearances of a solution as `result.json` lists them
/// (`doc.contacts`, `doc.clearance`), computed once: filled into a document
/// ([`ContactOutputs::fill`]) and read by a sensitivity's local plan.
#[derive(Clone, Debug)]
pub struct ContactOutputs {
    /// Every pair that carries a force, with its row key ([`pressing_contacts`]).
    pub pressing: Vec<(ContactResult, RowKey)>,
    /// The least gap of every rod and obstacle within [`CLEARANCE_SEARCH_M`]
    /// ([`least_clearances`]).
    pub clearances: Vec<LeastClearance>,
}

impl ContactOutputs {
    /// The contacts and least clearances of `solution` of `model`.
    pub fn of(
        model: &Model,
        solution: &Solution,
        contact: &Contact,
    ) -> Result<Self, strand_solve::ConstraintError> {
        Ok(Self {
            pressing: pressing_contacts(model, solution, contact)?,
            clearances: least_clearances(model, &solution.state, contact, CLEARANCE_SEARCH_M)?,
        })
    }

    /// Fills `doc.contacts` and `doc.clearance` (rods of `model`).
    pub fn fill(&self, doc: &mut ResultDoc, model: &Model) {
        doc.contacts = self
            .pressing
            .iter()
            .map(|(result, _)| result.clone())
            .collect();
        doc.clearance = clearance_results(model, &self.clearances);
    }
}

/// The contacts of `doc.contacts` ([`collect_contacts`]: every pair that carries a
/// force, on the rod that is touched; a rod–rod contact for both rods), in its order,
/// each with the key of its row (its multiplier's in `solution.constraints`).
pub fn pressing_contacts(
    model: &Model,
    solution: &Solution,
    contact: &Contact,
) -> Result<Vec<(ContactResult, RowKey)>, strand_solve::ConstraintError> {
    let rods = &model.system().rods;
    // Reference arc lengths once per rod, not once per contact.
    let lengths: Vec<Vec<f64>> = rods.iter().map(|r| r.rod.arc_lengths()).collect();
    let arc = |rod: usize, edge: usize, s: f64| {
        let a = &lengths[rod];
        a[edge] + s * (a[edge + 1] - a[edge])
    };
    let mut contacts = Vec::new();
    for force in contact.pressing_forces(model, &solution.state, &solution.constraints)? {
        let gap = &force.gap;
        let normal = gap.normal.into_inner();
        contacts.push((
            ContactResult {
                rod: rods[gap.rod].name.clone(),
                s_m: arc(gap.rod, gap.edge, gap.s),
                point_m: arr(&gap.point.coords),
                normal: arr(&normal),
                force_n: force.force_n,
                with: contact.obstacle_name(model, &gap.with),
            },
            force.key,
        ));
        if let Obstacle::Rod { rod, edge, t } = gap.with {
            contacts.push((
                ContactResult {
                    rod: rods[rod].name.clone(),
                    s_m: arc(rod, edge, t),
                    point_m: arr(&gap.witness.coords),
                    normal: arr(&-normal),
                    force_n: force.force_n,
                    with: rods[gap.rod].name.clone(),
                },
                force.key,
            ));
        }
    }
    Ok(contacts)
}

/// [`collect_contacts`] without the rods' per-vertex clearances (`clearance_m`, left
/// empty): the contacts and the clearance of every rod and obstacle, what the named
/// outputs of a design read ([`crate::design_outputs`]) at every point of a
/// sensitivity's path.
pub fn collect_contact_outputs(
    doc: &mut ResultDoc,
    model: &Model,
    solution: &Solution,
    contact: &Contact,
) -> Result<(), strand_solve::ConstraintError> {
    ContactOutputs::of(model, solution, contact)?.fill(doc, model);
    Ok(())
}

/// Fills `doc.clearance`: per rod and obstacle (mesh or other rod), the smallest
/// surface distance within `search_m` (m; at least [`CLEARANCE_SEARCH_M`] is
/// searched), e.g. the largest required clearance, so that every closer approach is
/// listed. Needs no contact forces: works for a solve without contact too.
pub fn collect_clearances(
    doc: &mut ResultDoc,
    model: &Model,
    solution: &Solution,
    contact: &Contact,
    search_m: f64,
) -> Result<(), strand_solve::ConstraintError> {
    pair_clearances(doc, model, solution, contact, search_m)?;
    vertex_clearances(
        doc,
        model,
        solution,
        contact,
        search_m.max(CLEARANCE_SEARCH_M),
    );
    Ok(())
}

/// Fills `doc.clearance` (see [`collect_clearances`]).
fn pair_clearances(
    doc: &mut ResultDoc,
    model: &Model,
    solution: &Solution,
    contact: &Contact,
    search_m: f64,
) -> Result<(), strand_solve::ConstraintError> {
    let least = least_clearances(model, &solution.state, contact, search_m)?;
    doc.clearance = clearance_results(model, &least);
    Ok(())
}

/// `doc.clearance` of the least gaps `least` (rods of `model`).
fn clearance_results(model: &Model, least: &[LeastClearance]) -> Vec<ClearanceResult> {
    let rods = &model.system().rods;
    let lengths: Vec<Vec<f64>> = rods.iter().map(|r| r.rod.arc_lengths()).collect();
    let arc = |rod: usize, edge: usize, s: f64| {
        let a = &lengths[rod];
        a[edge] + s * (a[edge + 1] - a[edge])
    };
    least
        .iter()
        .map(|least| {
            let gap = &least.gap;
            let s_m = match gap.with {
                Obstacle::Rod { rod, edge, t } if least.partner => arc(rod, edge, t),
                _ => arc(gap.rod, gap.edge, gap.s),
            };
            ClearanceResult {
                rod: rods[least.rod].name.clone(),
                distance_m: least.distance_m(),
                with: least.with.clone(),
                s_m,
            }
        })
        .collect()
}

/// The least gap of one rod to one obstacle ([`least_clearances`]).
#[derive(Clone, Debug)]
pub struct LeastClearance {
    /// The rod's index.
    pub rod: usize,
    /// The obstacle's name: a mesh's, or another rod's (the rod's own for its
    /// self-clearance).
    pub with: String,
    /// The gap (m) as the contact search found it: of `rod` to the obstacle, or, where
    /// `partner`, of the other rod to `rod` (`gap.with` is then `rod`).
    pub gap: Gap,
    /// Whether `rod` is the gap's partner rod (`gap.with`) rather than `gap.rod`.
    pub partner: bool,
    /// Whether the gap is set by the contact search's exclusion of near pairs
    /// ([`Contact::at_exclusion`]: a rod's clearance to itself along a stretch): its
    /// derivative holds on one side only.
    pub at_exclusion: bool,
}

impl LeastClearance {
    /// The clearance (m): the gap, or 0 where the surfaces overlap.
    pub fn distance_m(&self) -> f64 {
        self.gap.gap.max(0.0)
    }
}

/// Per rod and obstacle (mesh or rod) within `search_m` (m; at least
/// [`CLEARANCE_SEARCH_M`]), the least gap at `state`, in the order of
/// `doc.clearance` ([`collect_clearances`]: by rod name, then obstacle name; of equal
/// clearances the first found).
pub fn least_clearances(
    model: &Model,
    state: &SystemState,
    contact: &Contact,
    search_m: f64,
) -> Result<Vec<LeastClearance>, strand_solve::ConstraintError> {
    let rods = &model.system().rods;
    // The least gap of every pair of rods, not every pair of edges within the reach.
    let gaps = contact.clearances(model, state, search_m.max(CLEARANCE_SEARCH_M))?;
    let mut least: Vec<LeastClearance> = Vec::new();
    // Where along `rod` a gap is (edge index plus the fraction along it).
    let place = |gap: &Gap, partner: bool| match (partner, gap.with) {
        (true, Obstacle::Rod { edge, t, .. }) => edge as f64 + t,
        _ => gap.edge as f64 + gap.s,
    };
    let mut record = |rod: usize, with: String, gap: &Gap, partner: bool| {
        let distance = gap.gap.max(0.0);
        // Ties (several touching points, all at 0) go to the first along the rod, so
        // that the rounding of their gaps does not choose.
        let first = |entry: &LeastClearance| {
            (entry.distance_m(), place(&entry.gap, entry.partner))
                <= (distance, place(gap, partner))
        };
        match least.iter_mut().find(|c| c.rod == rod && c.with == with) {
            Some(entry) if first(entry) => {}
            Some(entry) => {
                entry.gap = *gap;
                entry.partner = partner;
            }
            None => least.push(LeastClearance {
                rod,
                with,
                gap: *gap,
                partner,
                at_exclusion: false,
            }),
        }
    };
    for gap in &gaps {
        record(gap.rod, contact.obstacle_name(model, &gap.with), gap, false);
        if let Obstacle::Rod { rod, .. } = gap.with {
            record(rod, rods[gap.rod].name.clone(), gap, true);
        }
    }
    least.sort_by(|a, b| (&rods[a.rod].name, &a.with).cmp(&(&rods[b.rod].name, &b.with)));
    for entry in &mut least {
        entry.at_exclusion = contact.at_exclusion(model, state, &entry.gap);
    }
    Ok(least)
}

/// Fills every rod's per-vertex `clearance_m`: the distance from each vertex to the
/// nearest mesh of `contact` minus the rod's outer radius (at least 0), `None` beyond
/// `search_m` (m) surface to surface; left empty without meshes.
fn vertex_clearances(
    doc: &mut ResultDoc,
    model: &Model,
    solution: &Solution,
    contact: &Contact,
    search_m: f64,
) {
    let meshes = contact.meshes();
    // Each rod asks only the meshes whose boxes come within the search of its own.
    let index = MeshIndex::new(meshes);
    for ((rod, spec), state) in doc
        .rods
        .iter_mut()
        .zip(&model.system().rods)
        .zip(&solution.state.rods)
    {
        rod.clearance_m.clear();
        if meshes.is_empty() {
            continue;
        }
        let radius = spec.rod.section().outer_radius;
        let points: Vec<nalgebra::Point3<f64>> = state
            .positions
            .iter()
            .map(|p| nalgebra::Point3::from(*p))
            .collect();
        // 1 nm more: a mesh's box and a distance in its own frame differ by rounding.
        let near = Aabb::of_points(&points, search_m + radius + 1e-9)
            .map_or_else(Vec::new, |region| index.overlapping(&region));
        rod.clearance_m = points
            .iter()
            .map(|point| {
                near.iter()
                    .map(|&k| &meshes[k])
                    .filter_map(|m| m.point_proximity(point, search_m + radius))
                    .map(|near| near.distance)
                    .reduce(f64::min)
                    .map(|d| (d - radius).max(0.0))
            })
            .collect();
    }
}

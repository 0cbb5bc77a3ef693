//! The objective and the constraints at one design point as smooth pieces with exact
//! gradients: the objective is the largest of its pieces (one per rod for
//! `peak_force`, one per support for `max_reaction`: a min–max in epigraph form), and
//! every constraint is one row per rod and obstacle (clearances) or per rod (bend
//! radii), `value ≥ 0` when satisfied.

use strand_case::BuiltCase;

use super::OptimizeError;
use super::evaluate::Evaluation;
use super::problem::{Bound, Bounded, Objective, Problem};
use crate::sensitivity::{ENERGY, EnergyOutput};

/// A smooth function of the variables at a point: value and gradient per variable
/// (in the function's unit per item unit).
#[derive(Clone, Debug, PartialEq)]
pub struct Piece {
    /// What it is (`hose2.peak_force_N`, `hose3.clearance_m.brackets`).
    pub label: String,
    /// Its value (the objective's unit; for rows `value − bound`, or `bound − value`
    /// for `<=`, in SI units, ≥ 0 when satisfied).
    pub value: f64,
    /// Its gradient per variable.
    pub gradient: Vec<f64>,
    /// Whether its derivative is one-sided for some variable (its arg-max/arg-min
    /// moves within the difference steps).
    pub one_sided: bool,
}

/// A constraint row at a point.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// The index of its [`Limit`] in the problem.
    pub limit: usize,
    /// The row's slack `value − bound` (or `bound − value` for `<=`) and gradient.
    pub piece: Piece,
    /// The output's value, SI.
    pub output: f64,
    /// The bound, SI.
    pub bound: f64,
    /// Scale of the row in the merit (its bound, or 1 in SI units for a zero bound).
    pub scale: f64,
    /// The rod is pressed against the obstacle of this clearance row: the row is the
    /// total contact force instead (`−1 − F/F_ref` in normalised units, continuous
    /// with the clearance row at lift-off), since a clearance in contact is zero with
    /// a zero gradient.
    pub in_contact: bool,
}

/// The piece of output `name` of `at`, with `sign` (+1 or −1) and `shift` applied.
fn piece(at: &Evaluation, name: &str, sign: f64, shift: f64) -> Option<Piece> {
    let k = at.table.find(name)?;
    Some(Piece {
        label: name.to_string(),
        value: sign * at.table.outputs[k].value + shift,
        gradient: at.table.derivatives[k].iter().map(|d| sign * d).collect(),
        one_sided: at.table.one_sided[k].iter().any(|&b| b),
    })
}

/// `|v|` of the three outputs `stem.x|y|z` with its gradient.
fn norm(at: &Evaluation, stem: &str) -> Option<Piece> {
    let parts: Vec<Piece> = ["x", "y", "z"]
        .iter()
        .map(|a| piece(at, &format!("{stem}.{a}"), 1.0, 0.0))
        .collect::<Option<_>>()?;
    let value = parts.iter().map(|p| p.value * p.value).sum::<f64>().sqrt();
    let n = parts[0].gradient.len();
    let gradient = (0..n)
        .map(|j| {
            if value > 0.0 {
                parts.iter().map(|p| p.value * p.gradient[j]).sum::<f64>() / value
            } else {
                0.0
            }
        })
        .collect();
    Some(Piece {
        label: stem.to_string(),
        value,
        gradient,
        one_sided: parts.iter().any(|p| p.one_sided),
    })
}

fn missing(option: &str, text: &str, name: &str, at: &Evaluation) -> OptimizeError {
    let mut names: Vec<&str> = at
        .table
        .outputs
        .iter()
        .map(|o| o.name.as_str())
        .filter(|n| !n.contains(".contact_force_N."))
        .collect();
    names.truncate(40);
    OptimizeError::input(
        option,
        text,
        &format!("names no output of the case ('{name}')"),
        &format!("outputs include: {}", names.join(", ")),
    )
}

fn rod_names(built: &BuiltCase) -> Vec<String> {
    built
        .model
        .system()
        .rods
        .iter()
        .map(|r| r.name.clone())
        .collect()
}

/// Checks that every rod named in the objective or the constraints exists (before any
/// solve), and that `bend_radius>=min` has a `min_bend_radius` to take.
pub fn check_names(problem: &Problem, built: &BuiltCase) -> Result<(), OptimizeError> {
    let rods = rod_names(built);
    let known = |option: &str, text: &str, rod: &str| {
        if rods.iter().any(|r| r == rod) {
            Ok(())
        } else {
            Err(OptimizeError::input(
                option,
                text,
                &format!("there is no rod '{rod}'"),
                &format!("rods: {}", rods.join(", ")),
            ))
        }
    };
    if let Objective::PeakForceOf(rod) | Objective::PeakMomentOf(rod) = &problem.objective {
        known("--minimize", &problem.objective.name(), rod)?;
    }
    for limit in &problem.limits {
        match &limit.bounded {
            Bounded::ClearanceOf(rod) | Bounded::BendRadiusOf(rod) => {
                known("--subject-to", &limit.text, rod)?
            }
            Bounded::Clearance if built.environment.is_empty() => {
                return Err(OptimizeError::input(
                    "--subject-to",
                    &limit.text,
                    "the case has no environment: there is no clearance to keep",
                    "add environment meshes to the case, or drop the constraint",
                ));
            }
            _ => {}
        }
        if limit.bound == Bound::CaseMinimum {
            let any = match &limit.bounded {
                Bounded::BendRadiusOf(rod) => rods
                    .iter()
                    .position(|r| r == rod)
                    .is_some_and(|k| built.min_bend_radius[k].is_some()),
                _ => built.min_bend_radius.iter().any(Option::is_some),
            };
            if !any {
                return Err(OptimizeError::input(
                    "--subject-to",
                    &limit.text,
                    "the case gives no min_bend_radius for these rods' sections",
                    "add min_bend_radius to the section in the case, or give a value, e.g. bend_radius>=60mm",
                ));
            }
        }
    }
    Ok(())
}

/// The objective's pieces at `at` (the objective is their maximum).
pub fn objective_pieces(
    objective: &Objective,
    at: &Evaluation,
    supports: &[String],
) -> Result<Vec<Piece>, OptimizeError> {
    let b = &at.built.built;
    // One rod's peak (`output`: `peak_force_N` or `peak_moment_Nm`), or every rod's.
    let peak = |rod: &str, output: &str| piece(at, &format!("{rod}.{output}"), 1.0, 0.0);
    let every_rod = |output: &str| -> Vec<Piece> {
        rod_names(b)
            .iter()
            .filter_map(|r| peak(r, output))
            .collect()
    };
    let pieces: Vec<Piece> = match objective {
        Objective::PeakForce => every_rod("peak_force_N"),
        Objective::PeakForceOf(rod) => peak(rod, "peak_force_N").into_iter().collect(),
        Objective::PeakMoment => every_rod("peak_moment_Nm"),
        Objective::PeakMomentOf(rod) => peak(rod, "peak_moment_Nm").into_iter().collect(),
        Objective::MaxReaction => supports
            .iter()
            .filter_map(|s| norm(at, &format!("{s}.force_N")))
            .collect(),
        Objective::Energy => piece(at, crate::sensitivity::ENERGY, 1.0, 0.0)
            .into_iter()
            .collect(),
        Objective::Output(name) => piece(at, name, 1.0, 0.0).into_iter().collect(),
    };
    if pieces.is_empty() {
        let name = objective.name();
        return Err(missing("--minimize", &name, &name, at));
    }
    Ok(pieces)
}

/// The constraint rows of `problem` at `at`; `contact_scale_n` is `F_ref` of the rows
/// in contact (N).
pub fn constraint_rows(
    problem: &Problem,
    at: &Evaluation,
    contact_scale_n: f64,
) -> Result<Vec<Row>, OptimizeError> {
    let b = &at.built.built;
    let rods = rod_names(b);
    let mut rows = Vec::new();
    for (l, limit) in problem.limits.iter().enumerate() {
        let sign = if limit.at_least { 1.0 } else { -1.0 };
        // (output name, bound) pairs of this limit.
        let targets: Vec<(String, f64)> = match &limit.bounded {
            Bounded::Clearance | Bounded::ClearanceOf(_) => {
                let only = match &limit.bounded {
                    Bounded::ClearanceOf(rod) => Some(rod.as_str()),
                    _ => None,
                };
                let Bound::Value(bound) = limit.bound else {
                    unreachable!("checked by parse")
                };
                at.table
                    .outputs
                    .iter()
                    .filter(|o| {
                        o.name.split_once(".clearance_m.").is_some_and(|(rod, _)| {
                            only.is_none_or(|r| r == rod) && rods.iter().any(|x| x == rod)
                        })
                    })
                    .map(|o| (o.name.clone(), bound))
                    .collect()
            }
            Bounded::BendRadius | Bounded::BendRadiusOf(_) => rods
                .iter()
                .enumerate()
                .filter(|(_, r)| match &limit.bounded {
                    Bounded::BendRadiusOf(rod) => rod == *r,
                    _ => true,
                })
                .filter_map(|(k, r)| {
                    let bound = match limit.bound {
                        Bound::Value(v) => Some(v),
                        Bound::CaseMinimum => b.min_bend_radius[k],
                    }?;
                    // A straight rod has no finite bend radius: nothing to bound.
                    let name = format!("{r}.min_bend_radius_m");
                    at.table.find(&name).map(|_| (name, bound))
                })
                .collect(),
            Bounded::Output(name) => {
                let Bound::Value(bound) = limit.bound else {
                    unreachable!("checked by parse")
                };
                if at.table.find(name).is_none() {
                    return Err(missing("--subject-to", &limit.text, name, at));
                }
                vec![(name.clone(), bound)]
            }
        };
        for (name, bound) in targets {
            let scale = if bound != 0.0 { bound.abs() } else { 1.0 };
            let mut p = piece(at, &name, sign, -sign * bound).expect("found above");
            let output = at.table.outputs[at.table.find(&name).expect("found above")].value;
            let mut in_contact = false;
            if let Some((rod, with)) = name.split_once(".clearance_m.") {
                let stem = format!("{rod}.contact_force_N.{with}.");
                let forces: Vec<Piece> = at
                    .table
                    .outputs
                    .iter()
                    .filter(|o| o.name.starts_with(&stem) && o.value > 0.0)
                    .filter_map(|o| piece(at, &o.name, 1.0, 0.0))
                    .collect();
                if !forces.is_empty() {
                    // Normalised: −1 − F/F_ref, times the row's scale.
                    in_contact = true;
                    let total: f64 = forces.iter().map(|f| f.value).sum();
                    p.value = -scale * (1.0 + total / contact_scale_n);
                    for (j, g) in p.gradient.iter_mut().enumerate() {
                        *g = -scale * forces.iter().map(|f| f.gradient[j]).sum::<f64>()
                            / contact_scale_n;
                    }
                    p.one_sided = forces.iter().any(|f| f.one_sided);
                }
            }
            rows.push(Row {
                limit: l,
                piece: p,
                output,
                bound,
                scale,
                in_contact,
            });
        }
    }
    Ok(rows)
}

/// The supports whose reactions `max_reaction` takes: the case's connectors and clips.
pub fn supports(problem_case: &strand_case::Case) -> Vec<String> {
    let f = &problem_case.file;
    f.connectors
        .iter()
        .map(|(n, _)| n.clone())
        .chain(f.clips.iter().map(|(n, _)| n.clone()))
        .collect()
}

/// Whether `problem` reads the energy ([`ENERGY`]: the `energy` objective, or an
/// objective or constraint naming it): only then do the output tables compute it
/// along the sensitivities' paths ([`EnergyOutput`]).
pub fn energy_output(problem: &Problem) -> EnergyOutput {
    let objective = match &problem.objective {
        Objective::Energy => true,
        Objective::Output(name) => name == ENERGY,
        _ => false,
    };
    let limit = problem
        .limits
        .iter()
        .any(|l| matches!(&l.bounded, Bounded::Output(name) if name == ENERGY));
    if objective || limit {
        EnergyOutput::Included
    } else {
        EnergyOutput::Omitted
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optimize::problem::Limit;

    fn problem(objective: &str, limits: &[&str]) -> Problem {
        Problem {
            variables: Vec::new(),
            objective: Objective::parse(objective).unwrap(),
            limits: limits.iter().map(|l| Limit::parse(l).unwrap()).collect(),
        }
    }

    #[test]
    fn only_a_problem_that_reads_the_energy_has_it_computed() {
        let included = EnergyOutput::Included;
        assert_eq!(energy_output(&problem("energy", &[])), included);
        assert_eq!(energy_output(&problem(ENERGY, &[])), included);
        let on_energy = format!("{ENERGY}<=2");
        assert_eq!(
            energy_output(&problem("peak_force", &[on_energy.as_str()])),
            included
        );
        let omitted = EnergyOutput::Omitted;
        assert_eq!(energy_output(&problem("peak_force", &[])), omitted);
        assert_eq!(
            energy_output(&problem("max_reaction", &["bend_radius>=min"])),
            omitted
        );
        assert_eq!(
            energy_output(&problem("hose2.peak_moment_Nm", &[])),
            omitted
        );
    }
}

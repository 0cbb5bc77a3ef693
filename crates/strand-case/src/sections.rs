//! Named sections of a case file → [`strand_rod::Section`] in SI units.

use strand_rod::{Section, TubeMaterial};

use crate::error::{CaseError, Reporter};
use crate::schema::{CaseFile, SectionDef};
use crate::units::LengthUnit;

/// Converts and validates every section, keeping the file order.
pub(crate) fn build_sections(
    report: &Reporter,
    unit: LengthUnit,
    defs: &[(String, SectionDef)],
) -> Result<Vec<(String, Section)>, CaseError> {
    defs.iter()
        .map(|(name, def)| {
            let item = format!("sections '{name}'");
            if name.trim().is_empty() {
                return Err(report.invalid(
                    "sections",
                    "a section has an empty name",
                    "give every section a name",
                ));
            }
            build_section(report, &item, unit, def).map(|s| (name.clone(), s))
        })
        .collect()
}

fn build_section(
    report: &Reporter,
    item: &str,
    unit: LengthUnit,
    def: &SectionDef,
) -> Result<Section, CaseError> {
    let u = format!(" {unit}");
    let section = match *def {
        SectionDef::Explicit {
            ea,
            ga,
            ei,
            gj,
            mass_per_length,
            outer_radius,
            ..
        } => {
            let ea = report.positive(&format!("{item}.ea"), ea, " N")?;
            let ga = report.positive(&format!("{item}.ga"), ga, " N")?;
            let ei = report.positive(&format!("{item}.ei"), ei, " N·m²")?;
            let gj = report.positive(&format!("{item}.gj"), gj, " N·m²")?;
            let rho_l = report.non_negative(
                &format!("{item}.mass_per_length"),
                mass_per_length,
                " kg/m",
            )?;
            let radius = match outer_radius {
                Some(r) => {
                    report.non_negative(&format!("{item}.outer_radius"), r, &u)? * unit.metres()
                }
                None => 0.0,
            };
            Section::try_explicit(ea, ga, ei, gj, rho_l, radius)
        }
        SectionDef::Tube {
            youngs_modulus,
            poisson_ratio,
            density,
            inner_radius,
            outer_radius,
            ..
        } => {
            let e = report.positive(&format!("{item}.youngs_modulus"), youngs_modulus, " Pa")?;
            let nu = report.finite(&format!("{item}.poisson_ratio"), poisson_ratio, "")?;
            let rho = report.non_negative(&format!("{item}.density"), density, " kg/m³")?;
            let ri = report.non_negative(&format!("{item}.inner_radius"), inner_radius, &u)?;
            let ro = report.positive(&format!("{item}.outer_radius"), outer_radius, &u)?;
            if ri >= ro {
                return Err(report.invalid(
                    item,
                    format!("inner_radius {ri}{u} must be smaller than outer_radius {ro}{u}"),
                    "swap the radii or correct one of them",
                ));
            }
            let material = TubeMaterial {
                youngs_modulus: e,
                poisson_ratio: nu,
                density: rho,
            };
            Section::try_tube(&material, ri * unit.metres(), ro * unit.metres())
        }
    };
    section.map_err(|e| report.invalid(item, e.to_string(), "correct the section's data"))
}

/// The allowed minimum bend radius of every rod's section, m (`None` where the
/// section states none), in rod order. Rods naming an undefined section get `None`
/// (the build reports them).
pub(crate) fn min_bend_radii(
    report: &Reporter,
    unit: LengthUnit,
    file: &CaseFile,
) -> Result<Vec<Option<f64>>, CaseError> {
    file.rods
        .iter()
        .map(|rod| {
            let Some((name, def)) = file.sections.iter().find(|(n, _)| *n == rod.section) else {
                return Ok(None);
            };
            let radius = match def {
                SectionDef::Explicit {
                    min_bend_radius, ..
                }
                | SectionDef::Tube {
                    min_bend_radius, ..
                } => *min_bend_radius,
            };
            radius
                .map(|r| {
                    report
                        .positive(
                            &format!("sections '{name}'.min_bend_radius"),
                            r,
                            &format!(" {unit}"),
                        )
                        .map(|r| r * unit.metres())
                })
                .transpose()
        })
        .collect()
}

/// Lists section names for messages: `a, b, c` or `(none)`.
pub(crate) fn names(sections: &[(String, Section)]) -> String {
    if sections.is_empty() {
        "(none)".to_string()
    } else {
        sections
            .iter()
            .map(|(n, _)| n.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    }
}

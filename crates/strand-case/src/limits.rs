//! Design limits a case states for its hoses, checked after the solve (the
//! `findings` of `result.json`): the allowed minimum bend radius of a section
//! (`min_bend_radius`, see [`crate::sections`]), the required clearance of a rod
//! (`min_clearance`) and the allowed load of a named connector (`max_force`,
//! `max_moment`).

use crate::error::{CaseError, Reporter};
use crate::schema::CaseFile;
use crate::units::LengthUnit;

/// The required clearance of every rod, m (`None` where the rod states no
/// `min_clearance`), in rod order: the smallest allowed surface-to-surface distance
/// between the rod and every environment mesh and every other rod. Zero is allowed
/// (it forbids only contact).
pub(crate) fn min_clearances(
    report: &Reporter,
    unit: LengthUnit,
    file: &CaseFile,
) -> Result<Vec<Option<f64>>, CaseError> {
    file.rods
        .iter()
        .enumerate()
        .map(|(i, rod)| {
            rod.min_clearance
                .map(|c| {
                    report
                        .non_negative(
                            &format!("rods[{i}] '{}'.min_clearance", rod.name),
                            c,
                            &format!(" {unit}"),
                        )
                        .map(|c| c * unit.metres())
                })
                .transpose()
        })
        .collect()
}

/// The allowed load of a named connector (`connectors.<name>.max_force`, `max_moment`).
#[derive(Clone, Debug, PartialEq)]
pub struct ConnectorLimit {
    /// The connector's name (also its reaction's name in the results).
    pub name: String,
    /// Largest allowed force magnitude on the connector, N.
    pub max_force_n: Option<f64>,
    /// Largest allowed moment magnitude on the connector (about the held end), N·m.
    pub max_moment_nm: Option<f64>,
}

/// The connectors of `file` that state a load limit, in file order; every limit a
/// finite number ≥ 0.
pub(crate) fn connector_limits(
    report: &Reporter,
    file: &CaseFile,
) -> Result<Vec<ConnectorLimit>, CaseError> {
    let mut limits = Vec::new();
    for (name, connector) in &file.connectors {
        if connector.max_force.is_none() && connector.max_moment.is_none() {
            continue;
        }
        let check = |field: &str, value: Option<f64>, unit: &str| {
            value
                .map(|v| report.non_negative(&format!("connectors.{name}.{field}"), v, unit))
                .transpose()
        };
        limits.push(ConnectorLimit {
            name: name.clone(),
            max_force_n: check("max_force", connector.max_force, " N")?,
            max_moment_nm: check("max_moment", connector.max_moment, " N·m")?,
        });
    }
    Ok(limits)
}

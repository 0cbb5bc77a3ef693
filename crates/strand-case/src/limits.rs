//! Design limits a case states for its hoses, checked after the solve (the
//! `findings` of `result.json`): the allowed minimum bend radius of a section
//! (`min_bend_radius`, see [`crate::sections`]) and the required clearance of a rod
//! (`min_clearance`).

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

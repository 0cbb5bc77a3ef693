//! The stiffness items of a section (`sections.<section>.ei`, `.youngs_modulus`, …):
//! reading and changing the field of a [`SectionDef`] as written in the case file.

use super::SectionStiffness;
use crate::schema::SectionDef;

/// The written value of `stiffness` in `def` (N, N·m² or Pa); `None` when the
/// section is not of the kind that has the field (`ei` of a `Tube`).
pub(crate) fn stiffness_of(def: &SectionDef, stiffness: SectionStiffness) -> Option<f64> {
    match (def, stiffness) {
        (SectionDef::Explicit { ea, .. }, SectionStiffness::Ea) => Some(*ea),
        (SectionDef::Explicit { ga, .. }, SectionStiffness::Ga) => Some(*ga),
        (SectionDef::Explicit { ei, .. }, SectionStiffness::Ei) => Some(*ei),
        (SectionDef::Explicit { gj, .. }, SectionStiffness::Gj) => Some(*gj),
        (SectionDef::Tube { youngs_modulus, .. }, SectionStiffness::YoungsModulus) => {
            Some(*youngs_modulus)
        }
        _ => None,
    }
}

/// Replaces the written value `v` of `stiffness` in `def` by `new(v)`; a field the
/// section does not have is left alone (the item's parser rejects it first).
pub(crate) fn change(def: &mut SectionDef, stiffness: SectionStiffness, new: impl Fn(f64) -> f64) {
    let field = match (def, stiffness) {
        (SectionDef::Explicit { ea, .. }, SectionStiffness::Ea) => ea,
        (SectionDef::Explicit { ga, .. }, SectionStiffness::Ga) => ga,
        (SectionDef::Explicit { ei, .. }, SectionStiffness::Ei) => ei,
        (SectionDef::Explicit { gj, .. }, SectionStiffness::Gj) => gj,
        (SectionDef::Tube { youngs_modulus, .. }, SectionStiffness::YoungsModulus) => {
            youngs_modulus
        }
        _ => return,
    };
    *field = new(*field);
}

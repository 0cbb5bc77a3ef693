//! Design limits of a solved case into its result document: the case's allowed bend
//! radii and required clearances on the rods, clearances searched far enough to
//! see every violation, and the `findings` (see [`strand_report::find`]) that `strand
//! solve` prints and `result.json` carries.

use strand_case::BuiltCase;
use strand_report::{CLEARANCE_SEARCH_M, ResultDoc, collect_clearances, find};
use strand_solve::Solution;
use strand_solve::contact::Contact;

use crate::error::{Result, StudyError};

/// Copies the limits of `built` onto `doc`'s rods (`min_bend_radius_m`,
/// `min_clearance_m`) and connector reactions (`max_force_n`, `max_moment_nm`), searches the clearances out to the largest required clearance
/// (rod–rod only when the case has no environment), and sets `doc.findings`. Call
/// after the contacts are collected.
pub fn add_findings(doc: &mut ResultDoc, built: &BuiltCase, solution: &Solution) -> Result<()> {
    for (k, rod) in doc.rods.iter_mut().enumerate() {
        rod.min_bend_radius_m = built.min_bend_radius.get(k).copied().flatten();
        rod.min_clearance_m = built.min_clearance.get(k).copied().flatten();
        if let Some((section, inner)) = built.sections.get(k) {
            rod.section = Some(section.clone());
            rod.inner_radius_m = *inner;
        }
    }
    doc.provenance = Some(strand_report::Provenance::now(
        &built.origin,
        &built.settings,
    ));
    // Connector loads: the reactions carry their connectors' names from here on.
    strand_report::name_connectors(doc, &built.connector_names);
    for reaction in doc.reactions.iter_mut().filter(|r| r.kind == "connector") {
        if let Some(limit) = built
            .connector_limits
            .iter()
            .find(|l| l.name == reaction.name)
        {
            reaction.max_force_n = limit.max_force_n;
            reaction.max_moment_nm = limit.max_moment_nm;
        }
    }
    let required = built
        .min_clearance
        .iter()
        .flatten()
        .copied()
        .fold(None, |a: Option<f64>, c| Some(a.map_or(c, |a| a.max(c))));
    if let Some(required) = required {
        let search = strand_report::clearance_search_m([required]);
        let contact = match built.contact() {
            // The contacts' own search already covers the requirement.
            Some(_) if search <= CLEARANCE_SEARCH_M => None,
            Some(contact) => Some(contact),
            None => Some(Contact::new(
                Vec::new(),
                Contact::default_margin_m(&built.model),
            )),
        };
        if let Some(contact) = contact {
            collect_clearances(doc, &built.model, solution, &contact, search)
                .map_err(|e| StudyError::Io(format!("{}: clearances: {e}", built.origin)))?;
        }
    }
    doc.findings = find(doc);
    Ok(())
}

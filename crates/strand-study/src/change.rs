//! One change of a case in the grammar of `strand batch --vary` with a single value:
//! what [`strand_case::Case::with_changes`] applies (the Python package's
//! `case.with_changes({"hose2.length": "+30mm"})`).

use strand_case::Case;
use strand_case::schema::VariantChange;

use crate::batch::spec::Vary;
use crate::error::{Result, StudyError};

/// The change `ITEM=VALUE` of `case` (`hose2.length=+30mm`: an offset;
/// `tee.mass=1.5kg`: a value; a vector component as `oil_cooler.position.z=+5mm`), in
/// the case's units, with exactly one value. The error names the case file and says
/// what to write, as `strand batch` does.
///
/// ```
/// use strand_case::Case;
/// use strand_case::schema::{Amount, Change};
/// let case = Case::from_path(concat!(env!("CARGO_MANIFEST_DIR"), "/../../cases/study_demo.ron"))?;
/// let change = strand_study::change::parse_change(&case, "hose.length=+0.05m")?;
/// assert_eq!(change.item, "rods.hose.length");
/// // The case is in mm: 0.05 m is an offset of 50 mm.
/// assert!(matches!(change.change, Change::Add(Amount::Number(x)) if (x - 50.0).abs() < 1e-12));
/// let range = strand_study::change::parse_change(&case, "hose.length=+0mm..+10mm:5mm");
/// assert!(range.unwrap_err().to_string().contains("a change takes one value, not 3"));
/// # Ok::<(), strand_study::StudyError>(())
/// ```
pub fn parse_change(case: &Case, text: &str) -> Result<VariantChange> {
    let vary = Vary::parse(text, &case.file).map_err(|source| StudyError::Vary {
        origin: case.origin.clone(),
        source,
    })?;
    if vary.values.len() != 1 {
        return Err(StudyError::Input(format!(
            "{}: {text}: a change takes one value, not {} (hint: run a batch over a range of values)",
            case.origin,
            vary.values.len()
        )));
    }
    Ok(vary.change(0))
}

//! `strand bench --contact`: the bundled cases with an environment (contact against CAD
//! meshes), each solved at its own discretisation: iterations, contacts and the median
//! cold solve time, with the issue-10 target for the cooler hoses (≤ 15 iterations).

use std::path::{Path, PathBuf};

use strand_case::Case;

/// The bundled contact cases, relative to the `cases/` folder, with what each exercises.
pub const CONTACT_CASES: [(&str, &str); 3] = [
    (
        "cooler_hose_contact.ron",
        "three hoses and a T in an engine bay; hose 3 on a bracket",
    ),
    (
        "cable_over_box.ron",
        "a cable against a closed box, around two vertical edges",
    ),
    (
        "hose_in_groove.ron",
        "a heavy hose hanging into a 90° V-groove, on both flanks",
    ),
];

/// Newton iterations the cooler-hose contact case may take (issue 10).
pub const COOLER_TARGET_ITERATIONS: usize = 15;

/// One row of the contact benchmark.
#[derive(Clone, Debug)]
pub struct ContactRow {
    /// The case file.
    pub case: PathBuf,
    /// What the case exercises.
    pub what: &'static str,
    /// Scalar unknowns.
    pub unknowns: usize,
    /// Newton iterations (all levels).
    pub iterations: usize,
    /// Constraint rows carrying load at the solution (contacts, joint limits).
    pub contacts: usize,
    /// Final residual, N.
    pub residual_n: f64,
    /// Whether the solve converged.
    pub converged: bool,
    /// Median wall time of a cold solve (contact set-up, symbolic analysis, Newton), ms.
    pub cold_ms: f64,
}

/// Solves every case of [`CONTACT_CASES`] found in `cases_dir`, `repeats` times each.
pub fn run_contact(
    cases_dir: &Path,
    repeats: usize,
) -> Result<Vec<ContactRow>, Box<dyn std::error::Error>> {
    let mut rows = Vec::new();
    for (file, what) in CONTACT_CASES {
        let path = cases_dir.join(file);
        let built = Case::from_path(&path)?.build(None)?;
        let mut times = Vec::with_capacity(repeats);
        let mut last = None;
        for _ in 0..repeats.max(1) {
            let (solution, cold_ms, ()) = super::cold_solve(&built, |_| Ok(()))?;
            times.push(cold_ms);
            let contacts = solution
                .constraints
                .iter()
                .filter(|(_, force)| *force > 0.0)
                .count();
            last = Some((solution.report, contacts));
        }
        let (report, contacts) = last.expect("at least one repeat");
        rows.push(ContactRow {
            case: path,
            what,
            unknowns: report.unknowns,
            iterations: report.iterations,
            contacts,
            residual_n: report.residual.combined_n,
            converged: report.converged,
            cold_ms: super::median(times),
        });
    }
    Ok(rows)
}

/// The table, then the cooler-hose target marked met or NOT MET.
pub fn format_contact_table(rows: &[ContactRow]) -> String {
    let mut out = String::from(
        "case                      unknowns  iterations  active rows  residual [N]  converged  cold solve [ms]  what\n",
    );
    for row in rows {
        let name = row
            .case
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        out.push_str(&format!(
            "{name:<24}  {:>8}  {:>10}  {:>11}  {:>12.2e}  {:>9}  {:>15.2}  {}\n",
            row.unknowns,
            row.iterations,
            row.contacts,
            row.residual_n,
            if row.converged { "yes" } else { "NO" },
            row.cold_ms,
            row.what,
        ));
    }
    if let Some(cooler) = rows.iter().find(|r| r.case.ends_with(CONTACT_CASES[0].0)) {
        out.push_str(&format!(
            "cooler_hose_contact: {} iterations [target: <= {COOLER_TARGET_ITERATIONS}: {}]\n",
            cooler.iterations,
            if cooler.iterations <= COOLER_TARGET_ITERATIONS {
                "met"
            } else {
                "NOT MET"
            }
        ));
    }
    out
}

//! Variants on the command line: the warm-started solve of one variant (`strand solve
//! CASE --variant NAME`) and `strand study` ([`strand_study::study`]), printed as a
//! table of convergence and of the peaks per rod per variant.

use std::io::Write;
use std::path::Path;

use strand_case::BuiltCase;
use strand_report::{ArcOrigin, ResultDoc, StudyPeak};
use strand_solve::Solution;
use strand_study::study::{StudyEvent, StudySpec, run_study};

use crate::Exit;
use crate::commands::Failure;
use crate::progress::Progress;
use crate::summary::{number, significant};

/// The warning that a variant starts cold because the case did not converge.
fn cold_start_warning(
    err: &mut dyn Write,
    origin: &str,
    name: &str,
    residual_n: f64,
    iterations: usize,
) {
    let _ = writeln!(
        err,
        "warning: {origin}: the case itself did not converge (residual {} N after {iterations} iterations); \
         variant '{name}' starts from its own initial guess instead of a warm start",
        number(residual_n),
    );
}

/// Solves variant `name` warm-started from the base solution if that converged,
/// otherwise cold (with a warning on `err`), with the progress line. Returns the
/// solution and whether it was warm-started.
pub(crate) fn solve_variant(
    base: &BuiltCase,
    base_solution: &Solution,
    built: &BuiltCase,
    name: &str,
    err: &mut dyn Write,
) -> Result<(Solution, bool), Failure> {
    if !base_solution.report.converged {
        cold_start_warning(
            err,
            &base.origin,
            name,
            base_solution.report.residual.combined_n,
            base_solution.report.iterations,
        );
    }
    let _progress = Progress::start(&built.origin);
    Ok(strand_study::solve::solve_variant(
        base,
        base_solution,
        built,
    )?)
}

/// `strand study CASE [--variants a,b,…] [--out DIR] [--segments N]`.
pub(crate) fn run(
    path: &Path,
    names: &[String],
    dir: Option<&Path>,
    segments: Option<usize>,
    export_unit: Option<strand_report::ExportUnit>,
    out: &mut dyn Write,
    err: &mut dyn Write,
) -> Result<Exit, Failure> {
    let spec = StudySpec {
        case: path.to_path_buf(),
        variants: names.to_vec(),
        out: dir.map(Path::to_path_buf),
        segments,
        export_unit,
    };
    let mut progress = None;
    let study = run_study(&spec, &mut |event| match event {
        StudyEvent::Solving { origin } => progress = Some(Progress::start(origin)),
        StudyEvent::Solved => progress = None,
        StudyEvent::ColdStart {
            origin,
            variant,
            base_residual_n,
            base_iterations,
        } => cold_start_warning(err, origin, variant, base_residual_n, base_iterations),
    })?;
    drop(progress);
    let unit = study.length_unit;
    let _ = write!(
        out,
        "{}",
        table(
            &study.case_name,
            &study.origin,
            &study.names,
            &study.docs,
            &study.peaks,
            &study.origins,
            unit.symbol(),
            unit.metres()
        )
    );
    let _ = writeln!(
        out,
        "written     {}, {}, {}",
        study.svg.display(),
        study.csv.display(),
        study
            .names
            .iter()
            .map(|n| format!("{}", study.dir.join(n).join("result.json").display()))
            .collect::<Vec<_>>()
            .join(", ")
    );
    let failed: Vec<&str> = study
        .names
        .iter()
        .zip(&study.docs)
        .filter(|(_, d)| !d.converged)
        .map(|(n, _)| n.as_str())
        .collect();
    if failed.is_empty() {
        Ok(Exit::Success)
    } else {
        let _ = writeln!(
            err,
            "warning: {}: not converged: {}; results written with \"converged\": false",
            study.origin,
            failed.join(", ")
        );
        Ok(Exit::NotConverged)
    }
}

/// Left-aligned columns separated by two spaces.
fn columns(rows: &[Vec<String>]) -> String {
    let widths: Vec<usize> = (0..rows[0].len())
        .map(|c| rows.iter().map(|r| r[c].chars().count()).max().unwrap_or(0))
        .collect();
    let mut out = String::new();
    for row in rows {
        let mut line = String::from("  ");
        for (c, cell) in row.iter().enumerate() {
            line.push_str(cell);
            if c + 1 < row.len() {
                let pad = widths[c] - cell.chars().count() + 2;
                line.push_str(&" ".repeat(pad));
            }
        }
        out.push_str(line.trim_end());
        out.push('\n');
    }
    out
}

fn percent(change: Option<f64>, first: bool) -> String {
    match change {
        _ if first => "-".to_string(),
        Some(p) => format!("{}{} %", if p >= 0.0 { "+" } else { "" }, significant(p, 3)),
        None => "n/a".to_string(),
    }
}

/// The terminal summary of a study: convergence per variant, then the peaks per rod
/// per variant with the change against the first variant.
fn table(
    case_name: &str,
    origin: &str,
    names: &[String],
    docs: &[ResultDoc],
    peaks: &[StudyPeak],
    origins: &[ArcOrigin],
    unit: &str,
    metres_per_unit: f64,
) -> String {
    let mut s = format!(
        "study       {} ({}): {} variant(s), reference {}\n",
        case_name,
        origin,
        names.len(),
        names[0]
    );
    let mut rows = vec![vec![
        "variant".to_string(),
        "start".to_string(),
        "converged".to_string(),
        "iterations".to_string(),
        "residual [N]".to_string(),
        "stable".to_string(),
    ]];
    for (name, doc) in names.iter().zip(docs) {
        rows.push(vec![
            name.clone(),
            match doc.base_iterations {
                Some(b) => format!("warm (base: {b} iterations)"),
                None => "cold".to_string(),
            },
            if doc.converged { "yes" } else { "NO" }.to_string(),
            doc.iterations.to_string(),
            number(doc.residual_n),
            if doc.stable { "yes" } else { "no" }.to_string(),
        ]);
    }
    s.push_str(&columns(&rows));
    let at_junction = docs
        .first()
        .is_some_and(|d| d.reactions.iter().any(|r| r.kind == "port"));
    let from = if at_junction {
        "from the junction for a rod with one end at a junction port, else from its start"
    } else if origins.contains(&ArcOrigin::End) {
        "from the rod's start, or its end where the plot marks it"
    } else {
        "from the rod's start"
    };
    s.push_str(&format!(
        "peaks       (change against {}; s {from})\n",
        names[0]
    ));
    let mut rows = vec![vec![
        "rod".to_string(),
        "variant".to_string(),
        "peak |f| [N]".to_string(),
        "change".to_string(),
        format!("at s [{unit}]"),
        "peak |m| [N·m]".to_string(),
        "change".to_string(),
        format!("at s [{unit}]"),
    ]];
    let mut rods: Vec<&str> = Vec::new();
    for p in peaks {
        if !rods.contains(&p.rod.as_str()) {
            rods.push(&p.rod);
        }
    }
    for rod in rods {
        for p in peaks.iter().filter(|p| p.rod == rod) {
            let first = p.variant == names[0];
            rows.push(vec![
                p.rod.clone(),
                p.variant.clone(),
                number(p.peak_force_n),
                percent(p.force_change_pct, first),
                number(p.peak_force_s_m / metres_per_unit),
                number(p.peak_moment_nm),
                percent(p.moment_change_pct, first),
                number(p.peak_moment_s_m / metres_per_unit),
            ]);
        }
    }
    s.push_str(&columns(&rows));
    s
}

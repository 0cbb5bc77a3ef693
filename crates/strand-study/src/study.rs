//! `strand study`: named variants of a case solved (each warm-started from the case's
//! own solution, [`crate::solve::solve_variant`]) and compared — their results in
//! `DIR/<variant>/`, the peaks of the internal forces and moments per rod per variant
//! in `DIR/study.csv` and the force and moment curves in `DIR/study.svg`.
//!
//! ```
//! use strand_study::study::{StudySpec, run_study};
//! let dir = tempfile::tempdir()?;
//! let spec = StudySpec {
//!     variants: vec!["base".into(), "plus50".into()],
//!     segments: Some(10),
//!     out: Some(dir.path().to_path_buf()),
//!     ..StudySpec::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../cases/study_demo.ron"))
//! };
//! let study = run_study(&spec, &mut |_event| {})?;
//! assert_eq!(study.names, ["base", "plus50"]);
//! assert!(study.docs.iter().all(|d| d.converged));
//! // The 50 mm longer hose, clamped at the same points, is warm-started from the base.
//! assert!(study.docs[1].warm_start);
//! assert!(dir.path().join("plus50/result.json").exists() && study.csv.exists());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::path::{Path, PathBuf};
use std::time::Instant;

use strand_case::{BASE_VARIANT, BuiltCase, Case, LengthUnit};
use strand_report::{
    ArcOrigin, ResultDoc, StudyPeak, StudyRun, Timing, arc_origin, study_csv, study_peaks,
    study_svg, write_atomic,
};

use crate::error::{Result, StudyError};
use crate::solve::{result_doc, solve_cold, solve_variant, write_result};

/// What to study: the options of `strand study`.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StudySpec {
    /// The case file.
    pub case: PathBuf,
    /// The variants to compare, the first the reference (`base`: the case itself);
    /// empty: `base` and every variant of the case, in file order.
    pub variants: Vec<String>,
    /// Output directory (default: `out/<case>-study`).
    pub out: Option<PathBuf>,
    /// Segments of every rod (default: the case's).
    pub segments: Option<usize>,
    /// Length unit of every variant's exported geometry (default: the case's).
    pub export_unit: Option<strand_report::ExportUnit>,
}

impl StudySpec {
    /// A study of every variant of `case` with the default options.
    pub fn new(case: impl Into<PathBuf>) -> Self {
        Self {
            case: case.into(),
            variants: Vec::new(),
            out: None,
            segments: None,
            export_unit: None,
        }
    }
}

/// What a study is doing, for a front end's progress display and warnings.
#[derive(Clone, Debug, PartialEq)]
pub enum StudyEvent<'a> {
    /// A solve of `origin` starts (the case, or a variant).
    Solving {
        /// The case or variant being solved.
        origin: &'a str,
    },
    /// The solve started last is done.
    Solved,
    /// The case itself did not converge: `variant` starts from its own initial guess
    /// instead of a warm start.
    ColdStart {
        /// The case file, as messages name it.
        origin: &'a str,
        /// The variant.
        variant: &'a str,
        /// The residual the case stopped at, N.
        base_residual_n: f64,
        /// The Newton iterations the case took.
        base_iterations: usize,
    },
}

/// A finished study.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct StudyResult {
    /// Case name (the file stem).
    pub case_name: String,
    /// The case file, as messages name it.
    pub origin: String,
    /// The variants, the first the reference.
    pub names: Vec<String>,
    /// The result of each variant (as in `DIR/<variant>/result.json`).
    pub docs: Vec<ResultDoc>,
    /// The peaks of |f| and |m| per rod per variant, with the changes against the
    /// reference.
    pub peaks: Vec<StudyPeak>,
    /// Where each rod's arc length is measured from in the peaks and plots.
    pub origins: Vec<ArcOrigin>,
    /// The case's length unit.
    pub length_unit: LengthUnit,
    /// The output directory.
    pub dir: PathBuf,
    /// `DIR/study.svg`.
    pub svg: PathBuf,
    /// `DIR/study.csv`.
    pub csv: PathBuf,
}

/// The variants of `spec` (or `base` and every variant of `case`), checked: none
/// empty, none twice.
fn variant_names(case: &Case, names: &[String]) -> Result<Vec<String>> {
    let names: Vec<String> = if names.is_empty() {
        std::iter::once(BASE_VARIANT)
            .chain(case.variant_names())
            .map(str::to_string)
            .collect()
    } else {
        names.to_vec()
    };
    for (i, name) in names.iter().enumerate() {
        if name.is_empty() {
            return Err(StudyError::Input(
                "--variants: empty variant name (write e.g. --variants base,longer)".into(),
            ));
        }
        if names[..i].contains(name) {
            return Err(StudyError::Input(format!(
                "--variants: '{name}' is listed twice (list every variant once)"
            )));
        }
    }
    Ok(names)
}

/// Runs the study of `spec`: builds every variant first (bad input stops the study
/// before anything is written), solves the case and each variant, writes their
/// results, `study.csv` and `study.svg`. `events` hears of each solve. A variant that
/// does not converge is in the result with `converged: false`, not an error.
pub fn run_study(spec: &StudySpec, events: &mut dyn FnMut(StudyEvent)) -> Result<StudyResult> {
    let started = Instant::now();
    let case = Case::from_path(&spec.case)?;
    crate::limits::check_case(&case)?;
    let read = started.elapsed().as_secs_f64();
    let names = variant_names(&case, &spec.variants)?;
    let base = case.build(spec.segments)?;
    let variants: Vec<Option<BuiltCase>> = names
        .iter()
        .map(|name| {
            if name == BASE_VARIANT {
                Ok(None)
            } else {
                case.build_variant(name, spec.segments).map(Some)
            }
        })
        .collect::<Result<_, _>>()?;
    let build = started.elapsed().as_secs_f64() - read;
    let dir: PathBuf = spec
        .out
        .clone()
        .unwrap_or_else(|| Path::new("out").join(format!("{}-study", case.name)));
    let not_written = |e: strand_report::ReportError| {
        StudyError::Io(format!("{}: results not written: {e}", case.origin))
    };

    events(StudyEvent::Solving {
        origin: &base.origin,
    });
    let base_solution = solve_cold(&base);
    events(StudyEvent::Solved);
    let base_solution = base_solution?;
    let mut docs: Vec<ResultDoc> = Vec::with_capacity(names.len());
    for (name, variant) in names.iter().zip(&variants) {
        let (built, solution, warm) = match variant {
            None => (&base, base_solution.clone(), false),
            Some(built) => {
                if !base_solution.report.converged {
                    events(StudyEvent::ColdStart {
                        origin: &base.origin,
                        variant: name,
                        base_residual_n: base_solution.report.residual.combined_n,
                        base_iterations: base_solution.report.iterations,
                    });
                }
                events(StudyEvent::Solving {
                    origin: &built.origin,
                });
                let solved = solve_variant(&base, &base_solution, built);
                events(StudyEvent::Solved);
                let (solution, warm) = solved?;
                (built, solution, warm)
            }
        };
        let solve_s = solution.report.solve_seconds;
        let timing = Timing {
            read,
            build,
            solve: solve_s,
            post: 0.0,
            total: read + build + solve_s,
        };
        let doc = result_doc(
            built,
            &solution,
            timing,
            Some(name),
            warm.then_some(base_solution.report.iterations),
        )?;
        write_result(&dir.join(name), &doc, built, spec.export_unit.as_ref())?;
        docs.push(doc);
    }

    let runs: Vec<StudyRun> = names
        .iter()
        .zip(&docs)
        .map(|(variant, doc)| StudyRun { variant, doc })
        .collect();
    let origins: Vec<ArcOrigin> = (0..base.model.system().rods.len())
        .map(|r| arc_origin(&base.model, r))
        .collect();
    let peaks = study_peaks(&runs, &origins);
    let unit = base.length_unit;
    let title = format!("{}: variants {}", case.name, names.join(", "));
    let svg = study_svg(&title, &runs, &origins, unit.symbol(), unit.metres());
    let (svg_path, csv_path) = (dir.join("study.svg"), dir.join("study.csv"));
    write_atomic(&csv_path, study_csv(&peaks).as_bytes()).map_err(not_written)?;
    write_atomic(&svg_path, svg.as_bytes()).map_err(not_written)?;
    Ok(StudyResult {
        case_name: case.name.clone(),
        origin: case.origin.clone(),
        names,
        docs,
        peaks,
        origins,
        length_unit: unit,
        dir,
        svg: svg_path,
        csv: csv_path,
    })
}

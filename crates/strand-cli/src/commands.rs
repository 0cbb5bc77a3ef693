//! The subcommands `solve`, `check` and `bench` (`study` is in [`crate::study`], the
//! convergence map of `bench --grid` in [`crate::bench::grid`]).

use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

use strand_case::{BuiltCase, Case, CaseError};
use strand_report::{ExportUnit, Timing};
use strand_solve::Solution;
use strand_study::{ErrorKind, StudyError};

use crate::Exit;
use crate::args::{Command, ExportUnitArg};
use crate::summary::summary;

/// A failure with the exit status it maps to.
#[derive(Debug)]
pub(crate) struct Failure {
    pub exit: Exit,
    pub message: String,
}

impl From<CaseError> for Failure {
    fn from(e: CaseError) -> Self {
        Failure {
            exit: Exit::InvalidInput,
            message: e.to_string(),
        }
    }
}

impl From<ErrorKind> for Exit {
    fn from(kind: ErrorKind) -> Self {
        match kind {
            ErrorKind::Input => Exit::InvalidInput,
            ErrorKind::Io => Exit::Failure,
            ErrorKind::NotConverged => Exit::NotConverged,
        }
    }
}

impl From<StudyError> for Failure {
    fn from(e: StudyError) -> Self {
        Failure {
            exit: e.kind().into(),
            message: e.to_string(),
        }
    }
}

/// Solves `built` cold ([`strand_study::solve::solve_cold`]) with the progress line.
pub(crate) fn solve_cold(built: &BuiltCase) -> Result<Solution, Failure> {
    let _progress = crate::progress::Progress::start(&built.origin);
    Ok(strand_study::solve::solve_cold(built)?)
}

/// An `--out` that names an existing file, not a directory: an input error before any
/// work (a solve of minutes would otherwise end in "cannot write").
fn check_out_dir(dir: &Path) -> Result<(), Failure> {
    match dir {
        dir if dir.exists() && !dir.is_dir() => Err(Failure {
            exit: Exit::InvalidInput,
            message: format!(
                "--out {}: is a file, not a directory; name a directory (it is created if \
                 missing)",
                dir.display()
            ),
        }),
        _ => Ok(()),
    }
}

pub(crate) fn execute(
    command: &Command,
    out: &mut dyn Write,
    err: &mut dyn Write,
) -> Result<Exit, Failure> {
    if let Some(dir) = command.out_dir() {
        check_out_dir(dir)?;
    }
    match command {
        Command::Solve {
            case,
            out: dir,
            segments,
            variant,
            motion: None,
            export_unit: unit,
        } => solve_case(
            case,
            dir.as_deref(),
            segments.map(|n| n as usize),
            variant.as_deref(),
            unit.map(ExportUnitArg::unit),
            out,
            err,
        ),
        Command::Solve {
            case,
            out: dir,
            segments,
            motion: Some(pose),
            export_unit: unit,
            ..
        } => crate::motion::solve_pose(
            case,
            pose,
            dir.as_deref(),
            segments.map(|n| n as usize),
            unit.map(ExportUnitArg::unit),
            out,
            err,
        ),
        Command::Motion {
            case,
            motion,
            range,
            out: dir,
            segments,
            predictor,
        } => crate::motion::run(
            case,
            motion,
            range,
            dir.as_deref(),
            segments.map(|n| n as usize),
            (*predictor).into(),
            out,
            err,
        ),
        Command::Sensitivity {
            case,
            params,
            out: dir,
            export_unit: unit,
        } => crate::sensitivity::run(case, params, dir, unit.map(ExportUnitArg::unit), out),
        Command::Optimize {
            case,
            vary,
            minimize,
            subject_to,
            out: dir,
            export_unit: unit,
        } => crate::optimize::run(
            &crate::optimize::Options {
                case,
                vary,
                minimize,
                subject_to,
                dir,
                export_unit: unit.map(ExportUnitArg::unit),
            },
            out,
        ),
        Command::Study {
            case,
            variants,
            out: dir,
            segments,
            export_unit: unit,
        } => crate::study::run(
            case,
            variants,
            dir.as_deref(),
            segments.map(|n| n as usize),
            unit.map(ExportUnitArg::unit),
            out,
            err,
        ),
        Command::Batch {
            case,
            vary,
            out: dir,
            jobs,
            force_jobs,
            yes,
            keep,
            shard,
            segments,
            retry_failed,
            export_unit: unit,
            motion,
        } => crate::batch::run(
            strand_study::batch::BatchSpec {
                case: case.clone(),
                vary: vary.clone(),
                out: dir.clone(),
                jobs: *jobs,
                force_jobs: *force_jobs,
                yes: *yes,
                keep: (*keep).into(),
                shard: shard.clone(),
                segments: segments.map(|n| n as usize),
                retry_failed: *retry_failed,
                export_unit: unit.map(ExportUnitArg::unit),
                motion: motion.clone(),
            },
            out,
            err,
        ),
        Command::Merge { dirs, out: dir } => crate::batch::merge(dirs, dir.as_deref(), out, err),
        Command::Report {
            dirs,
            out: file,
            labels,
            title,
        } => crate::report::run(dirs, file, labels, title.as_deref(), out),
        Command::Check { case, segments } => check_case(case, segments.map(|n| n as usize), out),
        Command::Bench {
            grid: true, cases, ..
        } => Ok(bench_grid(*cases, out)),
        Command::Bench {
            sensitivity: true,
            case,
            repeats,
            ..
        } => {
            use crate::bench::sensitivity::{format as format_bench, run as run_bench};
            let bench = run_bench(case, *repeats).map_err(|e| Failure {
                exit: Exit::InvalidInput,
                message: format!("{}: {e}", case.display()),
            })?;
            let _ = write!(
                out,
                "{}: sensitivities, median of {repeats} runs\n{}",
                case.display(),
                format_bench(&bench)
            );
            Ok(Exit::Success)
        }
        Command::Bench {
            motion: true,
            repeats,
            ..
        } => crate::bench::motion::run_and_print(Path::new("cases"), *repeats, out),
        Command::Bench {
            mesh: Some(mesh),
            mesh_scale,
            repeats,
            ..
        } => crate::bench::mesh::run_and_print(mesh, *mesh_scale, *repeats, out),
        Command::Bench {
            contact: true,
            repeats,
            ..
        } => {
            use crate::bench::contact::{format_contact_table, run_contact};
            let rows = run_contact(Path::new("cases"), *repeats).map_err(|e| Failure {
                exit: Exit::InvalidInput,
                message: format!("{e}\n  hint: run `strand bench --contact` from the repository root (it reads cases/)"),
            })?;
            let _ = write!(
                out,
                "contact cases, median of {repeats} solves each\n{}",
                format_contact_table(&rows)
            );
            Ok(if rows.iter().all(|r| r.converged) {
                Exit::Success
            } else {
                Exit::NotConverged
            })
        }
        Command::Bench {
            case,
            segments,
            repeats,
            ..
        } => {
            if segments.contains(&0) {
                return Err(Failure {
                    exit: Exit::InvalidInput,
                    message: "--segments: every entry must be ≥ 1".into(),
                });
            }
            let rows = crate::bench::run(case, segments, *repeats).map_err(|e| Failure {
                exit: Exit::InvalidInput,
                message: e.to_string(),
            })?;
            let _ = write!(
                out,
                "{}: bench, median of {} solves each\n{}",
                case.display(),
                repeats,
                crate::bench::format_table(&rows)
            );
            Ok(if rows.iter().all(|r| r.converged) {
                Exit::Success
            } else {
                Exit::NotConverged
            })
        }
    }
}

/// `strand bench --grid`: the convergence map, one line per case as it is solved, then
/// the summary.
fn bench_grid(cases: usize, out: &mut dyn Write) -> Exit {
    use crate::bench::grid::{GridSummary, format_grid_row, grid_header, run_grid};
    let _ = write!(
        out,
        "convergence map: {cases} cases, default solver settings\n{}",
        grid_header()
    );
    let _ = out.flush();
    let rows = run_grid(cases, |row| {
        let _ = write!(out, "{}", format_grid_row(row));
        let _ = out.flush();
    });
    let summary = GridSummary::of(&rows);
    let _ = write!(out, "\n{summary}");
    if summary.converged == summary.cases {
        Exit::Success
    } else {
        Exit::NotConverged
    }
}

fn load(path: &Path, segments: Option<usize>) -> Result<(BuiltCase, Timing), Failure> {
    let started = Instant::now();
    let case = Case::from_path(path)?;
    strand_study::limits::check_case(&case)?;
    let read = started.elapsed().as_secs_f64();
    let built = case.build(segments)?;
    let total = started.elapsed().as_secs_f64();
    Ok((
        built,
        Timing {
            read,
            build: total - read,
            total,
            ..Timing::default()
        },
    ))
}

fn check_case(path: &Path, segments: Option<usize>, out: &mut dyn Write) -> Result<Exit, Failure> {
    let case = Case::from_path(path)?;
    strand_study::limits::check_case(&case)?;
    let built = case.build(segments)?;
    // Every hose must start clear of the environment and of each other, as `solve`
    // requires.
    strand_study::solve::check_start(&built)?;
    // Every variant must build and start clear too.
    let variants = case.variant_names();
    for name in &variants {
        let variant = case.build_variant(name, segments)?;
        variant
            .check_start()
            .map_err(|e| StudyError::solver(&format!("{} (variant '{name}')", built.origin), e))?;
    }
    let system = built.model.system();
    let segments: usize = system.rods.iter().map(|r| r.rod.segments()).sum();
    let variants = if variants.is_empty() {
        String::new()
    } else {
        format!("; variants: {}", variants.join(", "))
    };
    let _ = writeln!(
        out,
        "ok: {} is valid ({} rod(s), {segments} segments, {} unknowns{variants})",
        built.origin,
        system.rods.len(),
        built.model.dofs().len()
    );
    if let Some(start) = built.start.describe() {
        let _ = writeln!(out, "start       {start}");
    }
    let _ = write!(out, "{}", crate::summary::projection_lines(&built));
    let diagnostics: Vec<_> = built
        .environment
        .iter()
        .map(|m| {
            (
                m.name().to_string(),
                strand_report::MeshDiagnosticsResult::of(m),
            )
        })
        .collect();
    let mut text = String::new();
    crate::summary::environment_lines(&mut text, &diagnostics, built.length_unit);
    let _ = write!(out, "{text}");
    Ok(Exit::Success)
}

fn solve_case(
    path: &Path,
    dir: Option<&Path>,
    segments: Option<usize>,
    variant: Option<&str>,
    export_unit: Option<ExportUnit>,
    out: &mut dyn Write,
    err: &mut dyn Write,
) -> Result<Exit, Failure> {
    let started = Instant::now();
    let (built, solution, mut timing, base_iterations) = match variant {
        None => {
            let (built, timing) = load(path, segments)?;
            let solution = solve_cold(&built)?;
            (built, solution, timing, None)
        }
        Some(name) => {
            let case = Case::from_path(path)?;
            strand_study::limits::check_case(&case)?;
            let read = started.elapsed().as_secs_f64();
            let base = case.build(segments)?;
            let built = case.build_variant(name, segments)?;
            let build = started.elapsed().as_secs_f64() - read;
            let base_solution = solve_cold(&base)?;
            let (solution, warm) =
                crate::study::solve_variant(&base, &base_solution, &built, name, err)?;
            let timing = Timing {
                read,
                build,
                ..Timing::default()
            };
            (
                built,
                solution,
                timing,
                warm.then_some(base_solution.report.iterations),
            )
        }
    };
    timing.solve = solution.report.solve_seconds;
    timing.total = started.elapsed().as_secs_f64();
    let solved = Solved {
        built: &built,
        solution: &solution,
        timing,
        variant,
        base_iterations,
        export_unit,
    };
    write_solved(&solved, dir, out, err)
}

/// A solved case (or variant, or pose: `variant` names it) to write and summarise.
pub(crate) struct Solved<'a> {
    pub built: &'a BuiltCase,
    pub solution: &'a strand_solve::Solution,
    pub timing: Timing,
    pub variant: Option<&'a str>,
    pub base_iterations: Option<usize>,
    /// `--export-unit`, if given (default: the case's length unit).
    pub export_unit: Option<ExportUnit>,
}

/// Writes the results of a solve to `dir` [default out/<case>/<variant>] and prints
/// its summary and findings; the exit status says whether it converged.
pub(crate) fn write_solved(
    solved: &Solved,
    dir: Option<&Path>,
    out: &mut dyn Write,
    err: &mut dyn Write,
) -> Result<Exit, Failure> {
    let Solved {
        built,
        solution,
        timing,
        variant,
        base_iterations,
        ref export_unit,
    } = *solved;
    let doc = strand_study::solve::result_doc(built, solution, timing, variant, base_iterations)?;
    let dir: PathBuf = dir.map(Path::to_path_buf).unwrap_or_else(|| {
        let dir = Path::new("out").join(&built.name);
        match variant {
            Some(name) => dir.join(name),
            None => dir,
        }
    });
    let written = strand_study::solve::write_result(&dir, &doc, built, export_unit.as_ref())?;
    let _ = write!(out, "{}", summary(built, &doc, &written));
    let unit = built.length_unit;
    let _ = write!(
        out,
        "{}",
        strand_report::findings_text(&doc, &doc.findings, unit.metres(), unit.symbol())
    );
    if !doc.findings.is_empty() {
        let _ = writeln!(
            err,
            "warning: {}: {} limit violation(s), listed above and in result.json \"findings\"",
            built.origin,
            doc.findings.len()
        );
    }
    for stretched in strand_study::solve::stretched_rods(&built.origin, &doc) {
        let _ = writeln!(err, "warning: {stretched}");
    }
    match strand_study::solve::not_converged(&built.origin, variant, &doc) {
        None => Ok(Exit::Success),
        Some(message) => {
            let _ = writeln!(
                err,
                "warning: {message}; results written with \"converged\": false"
            );
            Ok(Exit::NotConverged)
        }
    }
}

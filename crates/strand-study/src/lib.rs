//! # strand-study
//!
//! Strand as a library beyond a single solve: cases solved cold or warm-started,
//! variants, studies that compare them, batches over a grid of varied parameters
//! (parallel, warm-started along a continuation tree, resumable, shardable, merged,
//! summarised), sensitivities and design optimisation with exact gradients — the engine of the `strand` command line, which is
//! a thin front end over this crate (argument parsing, progress bar, printing, exit
//! codes).
//!
//! Every error is a [`StudyError`] whose message is the one `strand` prints after
//! `error: `, and whose [`StudyError::kind`] gives the exit status it maps to. Nothing
//! here prints: long runs report progress through a callback. Lengths are in metres
//! and forces in newtons inside results (`ResultDoc` keys carry their units); case
//! files and `--vary` values are in the case's length unit unless a unit is written.
//!
//! Load and build a case, solve it (the solution says whether it converged, with its
//! residual in N):
//!
//! ```
//! use strand_case::Case;
//! let case = Case::from_path(concat!(env!("CARGO_MANIFEST_DIR"), "/../../cases/elastica_fig2.ron"))?;
//! strand_study::limits::check_case(&case)?;
//! let built = case.build(Some(8))?; // 8 segments instead of the case's 19
//! let solution = strand_study::solve::solve_cold(&built)?;
//! assert!(solution.report.converged);
//! assert!(solution.report.residual.combined_n <= solution.report.tolerance_n);
//! # Ok::<(), strand_study::StudyError>(())
//! ```
//!
//! Apply a variant (here an unnamed one: the rod 50 mm longer) and solve it
//! warm-started from the case's solution; read the results from its result document:
//!
//! ```
//! use strand_case::Case;
//! use strand_case::schema::{Amount, Change, VariantChange};
//! use strand_report::Timing;
//! use strand_study::solve::{result_doc, solve_cold, solve_variant};
//! let case = Case::from_path(concat!(env!("CARGO_MANIFEST_DIR"), "/../../cases/study_demo.ron"))?;
//! let base = case.build(Some(10))?;
//! let longer = case.build_with_changes(
//!     "plus50",
//!     &[VariantChange { item: "rods.hose.length".into(), change: Change::Add(Amount::Number(50.0)) }],
//!     Some(10),
//! )?;
//! let base_solution = solve_cold(&base)?;
//! let (solution, warm) = solve_variant(&base, &base_solution, &longer)?;
//! assert!(warm && solution.report.converged);
//! let doc = result_doc(&longer, &solution, Timing::default(), Some("plus50"), Some(base_solution.report.iterations))?;
//! // Sectional forces per vertex, N; the hose is 0.45 m long.
//! let hose = &doc.rods[0];
//! assert!((hose.s_m.last().unwrap() - 0.45).abs() < 1e-12);
//! assert_eq!(hose.force_n.len(), 11);
//! # Ok::<(), strand_study::StudyError>(())
//! ```
//!
//! A small batch into a temporary folder and its results: see [`batch`]; a study of
//! named variants: see [`study`]; the best design within bounds: see [`optimize`].

pub mod batch;
pub mod change;
pub mod error;
pub mod findings;
pub mod format;
pub mod limits;
pub mod motion;
pub mod optimize;
pub mod sensitivity;
pub mod solve;
pub mod study;

pub use error::{ErrorKind, Result, StudyError};

/// The public results, specs and errors are plain owned values that cross threads
/// (a Python wrapper releases the GIL around them): checked at compile time.
const _: () = {
    const fn send<T: Send>() {}
    send::<batch::Batch>();
    send::<batch::OpenBatch>();
    send::<batch::BatchSpec>();
    send::<batch::BatchReport>();
    send::<batch::BatchResults>();
    send::<batch::MergeReport>();
    send::<study::StudySpec>();
    send::<study::StudyResult>();
    send::<StudyError>();
};

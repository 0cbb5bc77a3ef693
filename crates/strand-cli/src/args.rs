//! Command-line arguments (clap derive).

use std::path::PathBuf;

use clap::{Parser, Subcommand};

/// Static equilibria of cables and hoses as discrete Cosserat rods.
#[derive(Debug, Parser)]
#[command(name = "strand", version)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// `strand batch --keep`: which files a solved variant keeps.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum Keep {
    /// `state.json` and a `result.json` thinned to what `summary.csv` reads.
    Summary,
    /// `result.json` and `state.json` (the default).
    #[default]
    Results,
    /// Every file: also one CSV per rod, `rods.vtp`, `tubes.obj` and `tubes.stl`.
    All,
}

impl From<Keep> for strand_study::batch::Keep {
    fn from(keep: Keep) -> Self {
        match keep {
            Keep::Summary => Self::Summary,
            Keep::Results => Self::Results,
            Keep::All => Self::All,
        }
    }
}

/// `--export-unit`: the length unit of the exported geometry (`rods.vtp`, `tubes.obj`,
/// `tubes.stl`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum ExportUnitArg {
    /// Millimetres.
    Mm,
    /// Metres.
    M,
}

impl ExportUnitArg {
    /// The unit of the exported geometry.
    pub fn unit(self) -> strand_report::ExportUnit {
        match self {
            Self::Mm => strand_report::ExportUnit::new(1e-3, "mm"),
            Self::M => strand_report::ExportUnit::metre(),
        }
    }
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Solve a case and write result.json and one CSV per rod.
    Solve {
        /// The case file (RON).
        case: PathBuf,
        /// Output directory [default: out/<case name>].
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
        /// Override the number of segments of every rod.
        #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=crate::limits::MAX_SEGMENTS as i64))]
        segments: Option<u32>,
        /// Solve this variant of the case (defined under `variants`), warm-started from
        /// the solution of the case itself [default output: out/<case name>/<variant>].
        #[arg(long, value_name = "NAME")]
        variant: Option<String>,
        /// Solve the case with the parts of a motion moved to a pose, cold:
        /// `--motion engine_roll=4deg` [default output: out/<case name>/<NAME=VALUE>].
        #[arg(long, value_name = "NAME=VALUE", conflicts_with = "variant")]
        motion: Option<String>,
        /// Length unit of rods.vtp, tubes.obj and tubes.stl [default: the case's
        /// `length_unit`, the unit its environment meshes are usually drawn in].
        #[arg(long, value_enum, value_name = "UNIT")]
        export_unit: Option<ExportUnitArg>,
    },
    /// Follow a motion of the case's parts (defined under `motions`) from the case's
    /// pose in both directions, warm-started: DIR/motion.csv, DIR/events.csv,
    /// DIR/motion.svg, DIR/envelope.obj and DIR/steps/<k>/ (see README, "Motions").
    Motion {
        /// The case file (RON).
        case: PathBuf,
        /// The motion to drive.
        #[arg(long, value_name = "NAME")]
        motion: String,
        /// Parameter values FROM..TO:STEP in the motion's unit, e.g. -8deg..8deg:0.5deg.
        #[arg(long, value_name = "FROM..TO:STEP", allow_hyphen_values = true)]
        range: String,
        /// Output directory [default: out/<case name>-<motion>].
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
        /// Override the number of segments of every rod.
        #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=crate::limits::MAX_SEGMENTS as i64))]
        segments: Option<u32>,
        /// Where each step starts: the exact tangent of the path combined with the
        /// previous pose (second order), the secant of the last two poses, or the last
        /// pose.
        #[arg(long, value_enum, default_value_t = PredictorArg::Secant)]
        predictor: PredictorArg,
    },
    /// Solve a case and differentiate every output (reactions, peak |f| and |m|,
    /// bend radii, clearances, junction poses, contact forces) with respect to design
    /// parameters: DIR/sensitivity.json and DIR/sensitivity.csv.
    Sensitivity {
        /// The case file (RON).
        case: PathBuf,
        /// A parameter, named as in `batch --vary` without values: hose2.length,
        /// oil_cooler.position.z, oil_cooler.direction.x (a turn about x, deg),
        /// tee.ports.hose2.direction.z, clips.grommet.at, tee.mass,
        /// hose_small.youngs_modulus (Pa), sections.paper.ei (N·m²), gravity.z,
        /// hose1.end.force.x.
        #[arg(long = "param", value_name = "NAME", required = true)]
        params: Vec<String>,
        /// Output directory.
        #[arg(long, value_name = "DIR")]
        out: PathBuf,
        /// Length unit of the base solve's rods.vtp, tubes.obj and tubes.stl
        /// [default: the case's `length_unit`].
        #[arg(long, value_enum, value_name = "UNIT")]
        export_unit: Option<ExportUnitArg>,
    },
    /// Find the best design within bounds with exact gradients (trust-region SQP):
    /// DIR/optimum.json, DIR/history.csv, DIR/history.svg and DIR/<case>_optimum.ron.
    Optimize {
        /// The case file (RON).
        case: PathBuf,
        /// A design variable with bounds, named as in `batch --vary`:
        /// hose2.length=150mm..300mm (values) or oil_cooler.position.z=-20mm..+20mm
        /// (offsets from the case).
        #[arg(long = "vary", value_name = "NAME=LO..HI", required = true)]
        vary: Vec<String>,
        /// What to minimise: peak_force (the largest peak |f| of all rods),
        /// peak_force:<rod>, peak_moment (the largest peak |m|), peak_moment:<rod>,
        /// max_reaction, energy, or an output name of
        /// sensitivity.json.
        #[arg(long, value_name = "OBJECTIVE", default_value = "peak_force")]
        minimize: String,
        /// A constraint: "clearance>=10mm", "clearance:<rod>>=10mm",
        /// "bend_radius>=min" (each section's min_bend_radius), "bend_radius>=60mm",
        /// or an output: "oil_cooler.force_N.z<=20N".
        #[arg(long = "subject-to", value_name = "CONSTRAINT")]
        subject_to: Vec<String>,
        /// Output directory.
        #[arg(long, value_name = "DIR")]
        out: PathBuf,
        /// Length unit of the optimum's rods.vtp, tubes.obj and tubes.stl
        /// [default: the case's `length_unit`].
        #[arg(long, value_enum, value_name = "UNIT")]
        export_unit: Option<ExportUnitArg>,
    },
    /// Solve variants of a case and compare them: DIR/study.svg (|f| and |m| against
    /// arc length), DIR/study.csv (peaks per rod per variant) and DIR/<variant>/result.json.
    Study {
        /// The case file (RON).
        case: PathBuf,
        /// Comma-separated variants, `base` for the case itself; the first is the
        /// reference [default: base and every variant of the case].
        #[arg(long, value_delimiter = ',', value_name = "NAMES")]
        variants: Vec<String>,
        /// Output directory [default: out/<case name>-study].
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
        /// Override the number of segments of every rod.
        #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=crate::limits::MAX_SEGMENTS as i64))]
        segments: Option<u32>,
        /// Length unit of rods.vtp, tubes.obj and tubes.stl [default: the case's
        /// `length_unit`, the unit its environment meshes are usually drawn in].
        #[arg(long, value_enum, value_name = "UNIT")]
        export_unit: Option<ExportUnitArg>,
    },
    /// Solve every combination of varied parameters in parallel, warm-started along
    /// each parameter; resumable; DIR/summary.csv, DIR/summary.svg and
    /// DIR/variants/<id>/ (see README, "Batches").
    Batch {
        /// The case file (RON).
        case: PathBuf,
        /// A varied parameter, ITEM=A..B:STEP or ITEM=A,B,C; a sign makes the values
        /// offsets from the case (hose2.length=+0mm..+100mm:10mm), none sets them
        /// (tee.mass=0.5kg,1kg); a direction turns by offsets in deg or rad
        /// (oil_cooler.direction.y=-10deg..+10deg:5deg), a stiffness takes N, N·m² or
        /// Pa (hose_small.youngs_modulus=4MPa,6MPa). Repeat for a grid.
        #[arg(long, value_name = "ITEM=VALUES", required = true)]
        vary: Vec<String>,
        /// Output directory (re-running with the same options resumes it).
        #[arg(long, value_name = "DIR")]
        out: PathBuf,
        /// Worker threads [default: the available cores; more are capped at them
        /// unless --force-jobs; at most 1024].
        #[arg(long, value_name = "N")]
        jobs: Option<usize>,
        /// Use the --jobs given even above the available cores.
        #[arg(long)]
        force_jobs: bool,
        /// Start a batch estimated above 10 GB or 100 000 variants.
        #[arg(long)]
        yes: bool,
        /// Files kept per solved variant: `results` (result.json, state.json), `all`
        /// (also rod CSVs, rods.vtp, tubes.obj, tubes.stl: three times the files, about
        /// half the batch's time) or `summary` (state.json and a result.json thinned to
        /// the summary's peaks).
        #[arg(long, value_enum, default_value_t = Keep::Results)]
        keep: Keep,
        /// Run only the I-th of N deterministic shares of the variants (1-based);
        /// combine the shards with `strand merge`.
        #[arg(long, value_name = "I/N")]
        shard: Option<String>,
        /// Override the number of segments of every rod.
        #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=crate::limits::MAX_SEGMENTS as i64))]
        segments: Option<u32>,
        /// Solve variants recorded as failed (failed.json) again instead of skipping them.
        #[arg(long)]
        retry_failed: bool,
        /// Length unit of each variant's rods.vtp, tubes.obj and tubes.stl (with
        /// `--keep all`) [default: the case's `length_unit`]; applies to the variants
        /// solved in this run, like --keep.
        #[arg(long, value_enum, value_name = "UNIT")]
        export_unit: Option<ExportUnitArg>,
        /// Solve every variant with the parts of a motion moved to a pose, as
        /// `strand solve --motion` does: `--motion engine_roll=4deg`.
        #[arg(long, value_name = "NAME=VALUE")]
        motion: Option<String>,
    },
    /// Combine the directories of a sharded batch and write summary.csv and summary.svg.
    Merge {
        /// Batch output directories (shards of one batch).
        #[arg(required = true)]
        dirs: Vec<PathBuf>,
        /// Where to combine them [default: the first DIR].
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
    },
    /// Validate a case without solving it.
    Check {
        /// The case file (RON).
        case: PathBuf,
        /// Override the number of segments of every rod.
        #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=crate::limits::MAX_SEGMENTS as i64))]
        segments: Option<u32>,
    },
    /// Write an HTML design-review report comparing results (one self-contained file:
    /// summary, sectional quantities along each hose, side and top views, tables).
    Report {
        /// Result directories, each with a result.json from `strand solve` or
        /// `strand study`; the first is the reference.
        #[arg(required = true, value_name = "RESULT_DIR")]
        dirs: Vec<PathBuf>,
        /// The HTML file to write.
        #[arg(long, value_name = "FILE", default_value = "report.html")]
        out: PathBuf,
        /// Comma-separated labels of the results, in order [default: each result's
        /// variant, or its directory's name].
        #[arg(long, value_delimiter = ',', value_name = "NAMES")]
        labels: Vec<String>,
        /// Title of the report [default: "Design review: <case>"].
        #[arg(long)]
        title: Option<String>,
    },
    /// Benchmark: solve time, iterations and residual at several discretisations
    /// (medians of repeated solves; the paper's IPOPT times for comparison), or with
    /// --grid the convergence map of issue 9.
    #[command(after_help = "\
With --grid (no CASE, --segments or --repeats), the first N cases of the seeded
convergence map (single rods: clamp/pin/free/port ends, EI 10 to 1e-6 N m^2, EA/EI
up to 1e12, 10 to 1000 edges, spans up to 0.999 L, gravity, dead loads, routes,
clips) are solved once each with the default solver settings. One line per case:
label, Newton iterations (all, fine, coarse, continuation), residual [N], stable,
cold solve time [ms]; then the converged count, total/median/max iterations, median
and total time, and the issue-9 targets (all converge, median iterations <= 20, max
<= 100) marked met or NOT MET. Exit code 3 if a case does not converge.")]
    Bench {
        /// The case file (RON).
        #[arg(default_value = "cases/elastica_fig3.ron")]
        case: PathBuf,
        /// Comma-separated numbers of segments per rod.
        #[arg(long, value_delimiter = ',', default_value = "19,99,999", value_parser = clap::builder::RangedU64ValueParser::<usize>::new().range(1..=crate::limits::MAX_SEGMENTS as u64))]
        segments: Vec<usize>,
        /// Repeated solves per discretisation (the median is reported).
        #[arg(long, default_value_t = 20, value_parser = clap::builder::RangedU64ValueParser::<usize>::new().range(1..=10_000))]
        repeats: usize,
        /// Run the convergence map of issue 9 instead of CASE: iterations and time
        /// per case, and totals/medians against the targets (see below).
        #[arg(long, conflicts_with_all = ["case", "segments", "repeats"])]
        grid: bool,
        /// Run the bundled contact cases (cases/cooler_hose_contact.ron,
        /// cable_over_box.ron, hose_in_groove.ron; from the current folder) instead of
        /// CASE, each at its own discretisation: iterations, active rows, median time.
        #[arg(long, conflicts_with_all = ["case", "segments", "grid"])]
        contact: bool,
        /// Time the sensitivities of every output with respect to up to ten
        /// parameters of CASE (lengths, masses, connector positions, gravity) against
        /// its solve and its Newton iterations.
        #[arg(long, conflicts_with_all = ["segments", "grid", "contact", "motion"])]
        sensitivity: bool,
        /// Run the engine-roll motion (cases/cooler_hose_engine_roll.ron, -8° to 8° in
        /// 0.5° steps, from the current folder) with each predictor instead of CASE:
        /// poses, Newton iterations per pose, and the time of the path following
        /// (builds, solves, tangents; wall and CPU).
        #[arg(long, conflicts_with_all = ["case", "segments", "grid", "contact"])]
        motion: bool,
        /// Time the load of an environment mesh file (OBJ or STL) instead of CASE:
        /// cold (read, parse, topology, BVH) and through a fresh mesh cache, medians
        /// of --repeats loads, against the issue-11 targets per 1M triangles.
        #[arg(long, value_name = "FILE", conflicts_with_all = ["case", "segments", "grid", "contact", "motion", "sensitivity"])]
        mesh: Option<PathBuf>,
        /// File units to metres for --mesh (0.001: a file in mm).
        #[arg(long, value_name = "S", requires = "mesh", default_value_t = 0.001)]
        mesh_scale: f64,
        /// Number of convergence-map cases to run (with --grid).
        #[arg(long, value_name = "N", requires = "grid", default_value_t = crate::bench::grid::DEFAULT_CASES, value_parser = clap::builder::RangedU64ValueParser::<usize>::new().range(1..=100_000))]
        cases: usize,
    },
}

impl Command {
    /// The output directory the command writes into, if it names one (`report` writes
    /// a file, `check` and `bench` nothing).
    pub(crate) fn out_dir(&self) -> Option<&std::path::Path> {
        match self {
            Command::Solve { out, .. }
            | Command::Motion { out, .. }
            | Command::Study { out, .. }
            | Command::Merge { out, .. } => out.as_deref(),
            Command::Sensitivity { out, .. }
            | Command::Optimize { out, .. }
            | Command::Batch { out, .. } => Some(out),
            _ => None,
        }
    }
}

/// Where each step of `strand motion` starts ([`strand_case::motion::Predictor`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum PredictorArg {
    /// The exact tangent (implicit function theorem) combined with the previous pose.
    Tangent,
    /// The secant of the last two poses.
    Secant,
    /// The last pose.
    Last,
}

impl From<PredictorArg> for strand_case::motion::Predictor {
    fn from(p: PredictorArg) -> Self {
        match p {
            PredictorArg::Tangent => Self::Tangent,
            PredictorArg::Secant => Self::Secant,
            PredictorArg::Last => Self::Last,
        }
    }
}

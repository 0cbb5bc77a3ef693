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
        #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=10_000_000))]
        segments: Option<u32>,
        /// Solve this variant of the case (defined under `variants`), warm-started from
        /// the solution of the case itself [default output: out/<case name>/<variant>].
        #[arg(long, value_name = "NAME")]
        variant: Option<String>,
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
        #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=10_000_000))]
        segments: Option<u32>,
    },
    /// Validate a case without solving it.
    Check {
        /// The case file (RON).
        case: PathBuf,
        /// Override the number of segments of every rod.
        #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=10_000_000))]
        segments: Option<u32>,
    },
    /// Benchmark: solve time, iterations and residual at several discretisations
    /// (medians of repeated solves; the paper's IPOPT times for comparison).
    Bench {
        /// The case file (RON).
        #[arg(default_value = "cases/elastica_fig3.ron")]
        case: PathBuf,
        /// Comma-separated numbers of segments per rod.
        #[arg(long, value_delimiter = ',', default_value = "19,99,999")]
        segments: Vec<usize>,
        /// Repeated solves per discretisation (the median is reported).
        #[arg(long, default_value_t = 20)]
        repeats: usize,
    },
}

//! # strand-report
//!
//! Result writers. [`collect`] turns a solved [`strand_system::Model`] into a
//! [`ResultDoc`] (convergence, timing, per-vertex sectional quantities of every rod,
//! support reactions; SI units, every key suffixed with its unit); [`write_results`]
//! writes it as `DIR/result.json` plus one `DIR/<rod>.csv` per rod ([`rod_csv`],
//! [`CSV_HEADER`]), atomically: nothing half-written remains on error.
//!
//! `result.json` keys: `case`, `converged`, `termination`, `residual_N`,
//! `force_residual_N`, `moment_residual_Nm`, `tolerance_N`, `iterations`,
//! `shifted_iterations`, `stable`, `energy_J`, `unknowns`, `timing_s` {`read`, `build`,
//! `solve`, `post`, `total`}, `rods` [{`name`, `length_m`, `segments`, per-vertex arrays
//! `s_m`, `position_m`, `force_N`, `moment_Nm`, `tangential_force_N`, `shear_force_N`,
//! `bending_moment_Nm`, `torsion_Nm`, `total_moment_Nm`, `hamiltonian_N`,
//! `curvature_1pm`, per-edge `edge_force_N`}], `reactions` [{`name`, `kind`, `rod`,
//! `end`, `position_m`, `force_N`, `moment_Nm`}].

mod csv;
mod result;
mod write;

#[cfg(test)]
mod tests;

pub use csv::{CSV_HEADER, push_number, rod_csv};
pub use result::{ReactionResult, ResultDoc, RodResult, Timing, collect};
pub use write::{ReportError, is_safe_name, write_atomic, write_results};

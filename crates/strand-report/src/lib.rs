//! # strand-report
//!
//! Result writers. [`collect`] turns a solved [`strand_system::Model`] into a
//! [`ResultDoc`] (convergence, timing, per-vertex sectional quantities of every rod,
//! support reactions; SI units, every key suffixed with its unit); [`write_results`]
//! writes it as `DIR/result.json` plus one `DIR/<rod>.csv` per rod ([`rod_csv`],
//! [`CSV_HEADER`]), atomically: nothing half-written remains on error.
//!
//! `result.json` keys: `case`, `variant` (when a variant was solved), `warm_start`,
//! `base_iterations` (when warm-started), `converged`, `termination`, `residual_N`,
//! `force_residual_N`, `moment_residual_Nm`, `tolerance_N`, `iterations`,
//! `shifted_iterations`, `stable`, `energy_J`, `unknowns`, `timing_s` {`read`, `build`,
//! `solve`, `post`, `total`}, `rods` [{`name`, `length_m`, `segments`, per-vertex arrays
//! `s_m`, `position_m`, `force_N`, `moment_Nm`, `tangential_force_N`, `shear_force_N`,
//! `bending_moment_Nm`, `torsion_Nm`, `total_moment_Nm`, `hamiltonian_N`,
//! `curvature_1pm`, per-edge `edge_force_N`}], `reactions` [{`name`, `kind`, `rod`,
//! `end`, `position_m`, `force_N`, `moment_Nm`}], `bodies` [{`name`, `fixed`,
//! `position_m`, `orientation_quaternion_wxyz`, `rotation_matrix`, `mass_kg`}],
//! `clips` [{`name`, `rod`, `vertex`, `s_m`, `position_m`, `joint`, `axis_world`,
//! `value` (rad or m; `null` for fixed and spherical joints), `rotation_wxyz`
//! (spherical), `limits`, `at_limit`, `force_N`, `moment_Nm`}].
//!
//! Variant studies: [`study_peaks`] and [`study_csv`] tabulate the peak internal force
//! and moment of every rod in every variant with the change against the first variant;
//! [`study_svg`] plots `|f|` and `|m|` against arc length (from the rod's
//! [`arc_origin`]) in two stacked panels, as self-contained SVG.

mod clips;
mod csv;
mod result;
mod study;
mod svg;
mod write;

#[cfg(test)]
mod tests;

pub use clips::{AT_LIMIT_TOLERANCE, ClipResult, collect_clips};
pub use csv::{CSV_HEADER, push_number, rod_csv};
pub use result::{
    BodyResult, ReactionResult, ResultDoc, RodResult, Timing, collect, name_connectors,
};
pub use study::{
    ArcOrigin, STUDY_CSV_HEADER, StudyPeak, StudyRun, arc_origin, magnitude, study_csv, study_peaks,
};
pub use svg::study_svg;
pub use write::{ReportError, is_safe_name, write_atomic, write_results};

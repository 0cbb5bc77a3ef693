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
//!
//! Plots: every SVG figure (study, batch summary, motion, the report's plots,
//! projections and 3D view) is drawn with the one module [`plot`] (figure, axes,
//! ticks, series, legend, palette, escaping).
//!
//! Exports: [`rods_vtp`] (VTK XML PolyData of the centrelines with the sectional
//! quantities as point data, `DIR/rods.vtp`) and [`tubes_obj`] (tube surface meshes,
//! `DIR/tubes.obj`), both written by [`write_results`]; CAD out ([`write_results_in`]):
//! both in the case's length unit ([`ExportUnit`]) plus the tubes as binary STL
//! ([`tubes_stl`], `DIR/tubes.stl`).
//!
//! Design review: [`report_html`] renders one self-contained HTML page (inline SVG,
//! CSS and one small inline script; no network) comparing several results: findings
//! first, a summary, a rotatable 3D view (hoses as tubes coloured by `|f|`, `|m|` or
//! bend radius, environment outlines, contacts), sectional quantities along the arc
//! length with the contacts marked, side, top and front projections coloured by `|f|`
//! with the environment outlines and contacts, and tables of peaks, reactions,
//! contacts, clearances, bend radii and differences against the first result.
//! [`check_result`] rejects a `result.json` whose arrays do not fit.
//!
//! Environment and limits: [`collect_outlines`] puts the outline of every mesh near
//! the hoses (rims and edges sharper than [`FEATURE_ANGLE_RAD`], clipped to the hoses'
//! box grown by [`OUTLINE_MARGIN_M`]) into `environment[*].segments_m`; [`find`] lists
//! the `findings` (bend radius below `min_bend_radius_m`, clearance below
//! `min_clearance_m`), [`findings_text`] prints them.

mod cad;
mod clips;
mod contacts;
mod csv;
mod digits;
mod environment;
mod findings;
mod fittings;
pub mod motion;
mod number;
mod optimum;
mod optimum_plot;
mod outline;
pub mod plot;
mod provenance;
mod report;
mod result;
mod sensitivity;
mod study;
mod study_plot;
mod surface;
mod tube;
mod vtk;
mod write;

#[cfg(test)]
mod export_tests;
#[cfg(test)]
mod tests;

pub use cad::{ExportUnit, tube_triangles, tubes_stl, tubes_stl_of};
pub use clips::{AT_LIMIT_TOLERANCE, ClipResult, collect_clips};
pub use contacts::{
    CLEARANCE_SEARCH_M, ContactOutputs, LeastClearance, clearance_search_m, collect_clearances,
    collect_contact_outputs, collect_contacts, least_clearances, pressing_contacts,
};
pub use csv::{CSV_HEADER, rod_csv};
pub use digits::significant;
pub use environment::{MeshDiagnosticsResult, collect_environment};
pub use findings::{
    Finding, FindingKind, FindingValue, bend_radii, find, findings_text, limits_stated,
    number as finding_number,
};
pub use fittings::{
    CLIP_RADIUS_FACTOR, CLIP_WIDTH_FACTOR, CONNECTOR_LENGTH_FACTOR, CONNECTOR_OVERLAP_FACTOR,
    CONNECTOR_RADIUS_FACTOR, Fitting, FittingKind, FittingPiece, fittings,
};
pub use number::{push_integer, push_number};
pub use optimum::{
    OptimumConstraint, OptimumDoc, OptimumIterate, OptimumObjective, OptimumParameter,
};
pub use optimum_plot::optimum_svg;
pub use outline::{
    Aabb, FEATURE_ANGLE_RAD, MAX_OUTLINE_SEGMENTS, OUTLINE_MARGIN_M, collect_outlines,
    mesh_outline, region_around,
};
pub use plot::{
    DASH_PATTERNS, LINE_COLOURS, MIN_DEUTERANOPIA_DELTA_E, axis_label, axis_ticks, dash_pattern,
    line_colour,
};
pub use provenance::{Provenance, fnv1a64, mixed_cases, utc};
pub use report::{
    MotionAxis, ReportInputError, ReportRun, ReportStudies, check_result, motion_report_html,
    report_html, report_html_with_studies,
};
pub use result::{
    BodyResult, ClearanceResult, ContactResult, EnvironmentOutline, ReactionResult, ResultDoc,
    RodResult, Timing, collect, name_connectors,
};
pub use sensitivity::{
    ARG_TIE, OutputValue, SensitivityDoc, SensitivityOutput, SensitivityParameter, design_outputs,
    sensitivity_doc, sensitivity_doc_from, ties,
};
pub use study::{
    ArcOrigin, STUDY_CSV_HEADER, StudyPeak, StudyRun, arc_origin, magnitude, study_csv, study_peaks,
};
pub use study_plot::study_svg;
pub use surface::{MAX_SURFACE_TRIANGLES, mesh_surface};
pub use tube::{
    BALL_BANDS, DEFAULT_RADIUS_FRACTION, MAX_MITRE, TUBE_SIDES, TubeMesh, ball_mesh,
    rod_tube_meshes, tube_mesh, tube_radius, tube_rings, tubes_obj, tubes_obj_in, tubes_obj_of,
};
pub use vtk::{VTK_POINT_ARRAYS, VtkPointArray, rods_vtp, rods_vtp_in};
pub use write::{
    ReportError, is_safe_name, write_atomic, write_result_files, write_results, write_results_in,
};

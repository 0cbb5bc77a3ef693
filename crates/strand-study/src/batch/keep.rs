//! `--keep summary|results|all`: which files a solved variant keeps, so that huge
//! sweeps fit on disk ([`super::Keep`]).
//!
//! - `results` (default): `result.json` and `state.json` (no CSV, VTK, OBJ or STL
//!   files: two files a variant, where creating the files, not writing their bytes, is
//!   most of the cost);
//! - `all`: also one CSV per rod, `rods.vtp`, `tubes.obj`, `tubes.stl` (geometry in the
//!   case's length unit);
//! - `summary`: `state.json` (resume needs it) and a **thin** `result.json` that holds
//!   only what `summary.csv` reads: per rod the one force, moment and curvature vector
//!   where the peak |f|, |m| and the tightest bend are, the reactions and the smallest
//!   clearance. Every summary number is computed from the thin file exactly as from
//!   the full one (bit for bit); `strand report` needs `all` or `results`.

use strand_report::{ExportUnit, ResultDoc, magnitude};

use super::Keep;

/// The entry of `values` with the largest `key` (none for an empty list).
fn largest<T: Clone>(values: &[T], key: impl Fn(&T) -> f64) -> Vec<T> {
    let mut best: Option<(&T, f64)> = None;
    for v in values {
        let k = key(v);
        if best.is_none_or(|(_, b)| k > b) {
            best = Some((v, k));
        }
    }
    best.map(|(v, _)| vec![v.clone()]).unwrap_or_default()
}

/// The thin result of `--keep summary` (see the module docs), made from the full `doc`
/// in place (its long lists emptied, not copied). Thinning a thin result changes
/// nothing.
pub(crate) fn thin(mut doc: ResultDoc) -> ResultDoc {
    for rod in &mut doc.rods {
        rod.force_n = largest(&rod.force_n, magnitude);
        rod.moment_nm = largest(&rod.moment_nm, magnitude);
        rod.curvature_1pm = largest(&rod.curvature_1pm, |k| k[0].hypot(k[1]));
        rod.s_m.clear();
        rod.position_m.clear();
        rod.tangential_force_n.clear();
        rod.shear_force_n.clear();
        rod.bending_moment_nm.clear();
        rod.torsion_nm.clear();
        rod.total_moment_nm.clear();
        rod.hamiltonian_n.clear();
        rod.edge_force_n.clear();
        rod.section_frames_wxyz.clear();
    }
    doc.clearance = largest(&doc.clearance, |c| -c.distance_m);
    doc.contacts.clear();
    doc.environment.clear();
    doc
}

/// The `result.json` document a variant keeps under `keep`.
pub(crate) fn kept_doc(doc: ResultDoc, keep: Keep) -> ResultDoc {
    match keep {
        Keep::Summary => thin(doc),
        Keep::Results | Keep::All => doc,
    }
}

/// Bytes of the files a variant with result `doc` (the full one) and a `state.json`
/// of `state_bytes` writes under `keep`, its geometry in `unit`.
pub(crate) fn variant_bytes(
    doc: &ResultDoc,
    state_bytes: usize,
    keep: Keep,
    unit: &ExportUnit,
) -> u64 {
    let json = |d: &ResultDoc| serde_json::to_vec_pretty(d).map_or(0, |v| v.len());
    let files = match keep {
        Keep::Summary => json(&thin(doc.clone())),
        Keep::Results => json(doc),
        Keep::All => {
            json(doc)
                + doc
                    .rods
                    .iter()
                    .map(|r| strand_report::rod_csv(r).len())
                    .sum::<usize>()
                + strand_report::rods_vtp_in(doc, unit).len()
                + strand_report::tubes_obj_in(doc, unit).len()
                + strand_report::tubes_stl(doc, unit).len()
        }
    };
    (files + state_bytes) as u64
}

//! The report of a motion (`strand report DIR` on a `strand motion` folder): the worst
//! pose of each quantity, with the parameter value where it occurs; the 3D view then
//! animates the poses ([`super::view3d`]).

use std::fmt::Write;

use super::ReportRun;
use super::format::{Cell, push_table};
use crate::motion::{WorstKind, worst_poses};
use crate::plot::escape;

/// The motion whose poses a report's results are, one value per result in order.
#[derive(Clone, Copy, Debug)]
pub struct MotionAxis<'a> {
    /// The motion's name (`engine_roll`).
    pub name: &'a str,
    /// Its parameter's unit (`deg`, `mm`).
    pub unit: &'a str,
    /// The parameter value of each result, in the results' order.
    pub values: &'a [f64],
}

/// The pose labels of `axis` (`-8 deg`), one per result.
pub(crate) fn pose_labels(axis: &MotionAxis) -> Vec<String> {
    axis.values
        .iter()
        .map(|v| format!("{} = {} {}", axis.name, super::sig(*v), axis.unit))
        .collect()
}

/// Appends the table of the worst poses.
pub(crate) fn push_worst_poses(html: &mut String, runs: &[ReportRun], axis: &MotionAxis) {
    let poses: Vec<(f64, &crate::ResultDoc)> = axis
        .values
        .iter()
        .zip(runs)
        .map(|(v, r)| (*v, r.doc))
        .collect();
    let _ = writeln!(
        html,
        "<p class=\"note\">{} pose(s) of motion '{}' ({} to {} {}); per hose the largest peak |f| and |m| and the smallest bend radius, per obstacle the smallest clearance of any hose, with the pose where each occurs. The 3D view below plays the motion.</p>",
        runs.len(),
        escape(axis.name),
        super::sig(axis.values.iter().copied().fold(f64::INFINITY, f64::min)),
        super::sig(
            axis.values
                .iter()
                .copied()
                .fold(f64::NEG_INFINITY, f64::max)
        ),
        escape(axis.unit)
    );
    let rows: Vec<_> = worst_poses(&poses)
        .into_iter()
        .map(|w| {
            let (value, unit) = match w.kind {
                WorstKind::PeakForce => (w.value, "N"),
                WorstKind::PeakMoment => (w.value, "N·m"),
                WorstKind::MinBendRadius | WorstKind::MinClearance => (w.value * 1e3, "mm"),
            };
            let label = format!("{} [{unit}]", w.kind.label());
            (
                vec![("item", w.item.clone())],
                vec![
                    Cell::text(label),
                    Cell::text(w.item),
                    Cell::Num(value),
                    Cell::Num(w.at),
                ],
            )
        })
        .collect();
    let at = format!("at {} [{}]", axis.name, axis.unit);
    push_table(
        html,
        "worst-poses",
        &["quantity", "hose / obstacle", "worst", &at],
        &rows,
    );
}

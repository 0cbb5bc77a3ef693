//! The worst pose of each quantity over a motion: per hose the largest peak `|f|` and
//! `|m|` and the smallest bend radius, per obstacle the smallest clearance of any
//! hose, each with the parameter value where it occurs.

use super::table::{clearance_to, min_bend_radius, peak, union};
use crate::ResultDoc;

/// What a [`Worst`] measures.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WorstKind {
    /// The largest internal force magnitude along the hose, N.
    PeakForce,
    /// The largest internal moment magnitude along the hose, N·m.
    PeakMoment,
    /// The smallest bend radius of the hose, m.
    MinBendRadius,
    /// The smallest clearance of any hose to the obstacle, m.
    MinClearance,
}

impl WorstKind {
    /// A label for tables: `peak |f|`, `peak |m|`, `min bend radius`, `min clearance`.
    pub fn label(self) -> &'static str {
        match self {
            Self::PeakForce => "peak |f|",
            Self::PeakMoment => "peak |m|",
            Self::MinBendRadius => "min bend radius",
            Self::MinClearance => "min clearance",
        }
    }
}

/// The worst pose of one quantity.
#[derive(Clone, Debug, PartialEq)]
pub struct Worst {
    /// What is measured.
    pub kind: WorstKind,
    /// The hose (or, for a clearance, the obstacle: a mesh or another hose).
    pub item: String,
    /// The worst value (N, N·m or m, see [`WorstKind`]).
    pub value: f64,
    /// The parameter value of the pose where it occurs (the first such pose), in the
    /// motion's unit.
    pub at: f64,
}

/// The worst pose of each quantity over `poses` (parameter value, result), in order:
/// per hose peak `|f|`, peak `|m|`, min bend radius; then per obstacle the min
/// clearance (obstacles in order of first appearance; a pose where nothing came
/// within the clearance search does not count).
///
/// ```
/// use strand_report::motion::{WorstKind, worst_poses};
/// assert!(worst_poses(&[]).is_empty());
/// assert_eq!(WorstKind::PeakForce.label(), "peak |f|");
/// ```
pub fn worst_poses(poses: &[(f64, &ResultDoc)]) -> Vec<Worst> {
    let mut out = Vec::new();
    let docs = || poses.iter().map(|(_, d)| *d);
    let rods = union(docs(), |d| d.rods.iter().map(|r| r.name.as_str()).collect());
    let extreme = |kind, item: &str, values: Vec<(f64, f64)>, largest: bool| {
        values
            .into_iter()
            .filter(|(_, v)| !v.is_nan())
            .reduce(|a, b| {
                let better = if largest { b.1 > a.1 } else { b.1 < a.1 };
                if better { b } else { a }
            })
            .map(|(at, value)| Worst {
                kind,
                item: item.to_string(),
                value,
                at,
            })
    };
    for rod in rods {
        let each = |f: &dyn Fn(&crate::RodResult) -> f64| -> Vec<(f64, f64)> {
            poses
                .iter()
                .filter_map(|(at, d)| d.rods.iter().find(|r| r.name == rod).map(|r| (*at, f(r))))
                .collect()
        };
        out.extend(extreme(
            WorstKind::PeakForce,
            rod,
            each(&|r| peak(&r.force_n)),
            true,
        ));
        out.extend(extreme(
            WorstKind::PeakMoment,
            rod,
            each(&|r| peak(&r.moment_nm)),
            true,
        ));
        out.extend(extreme(
            WorstKind::MinBendRadius,
            rod,
            each(&|r| min_bend_radius(&r.curvature_1pm)),
            false,
        ));
    }
    let obstacles = union(docs(), |d| {
        d.clearance.iter().map(|c| c.with.as_str()).collect()
    });
    for with in obstacles {
        let values = poses
            .iter()
            .filter_map(|(at, d)| clearance_to(d, with).map(|c| (*at, c)))
            .collect();
        out.extend(extreme(WorstKind::MinClearance, with, values, false));
    }
    out
}

//! Tables of the supports' reactions, contacts, clearances and bend radii.

use super::format::{Cell, push_table};
use super::{ReportRun, arc_at, report_origin};
use crate::result::RodResult;
use crate::study::{ArcOrigin, magnitude};

fn keys(result: &str, rod: &str) -> Vec<(&'static str, String)> {
    vec![("result", result.to_string()), ("rod", rod.to_string())]
}

/// Reactions at connectors and junction ports, the junction bodies, and the clips.
pub(crate) fn push_reactions(html: &mut String, runs: &[ReportRun]) {
    let mut rows = Vec::new();
    for run in runs {
        for r in run.doc.reactions.iter().filter(|r| r.kind != "clip") {
            rows.push((
                keys(run.label, &r.rod),
                vec![
                    Cell::text(run.label),
                    Cell::text(&r.name),
                    Cell::text(&r.kind),
                    Cell::text(&r.rod),
                    Cell::text(&r.end),
                    Cell::Num(r.force_n[0]),
                    Cell::Num(r.force_n[1]),
                    Cell::Num(r.force_n[2]),
                    Cell::Num(magnitude(&r.force_n)),
                    Cell::Num(magnitude(&r.moment_nm)),
                ],
            ));
        }
    }
    html.push_str("<h3>Connectors and junction ports</h3>\n");
    if rows.is_empty() {
        html.push_str("<p class=\"note\">No connector or port reactions.</p>\n");
    } else {
        push_table(
            html,
            "reactions",
            &[
                "result",
                "support",
                "kind",
                "hose",
                "end",
                "Fx [N]",
                "Fy [N]",
                "Fz [N]",
                "|F| [N]",
                "|M| [N·m]",
            ],
            &rows,
        );
        html.push_str("<p class=\"note\">Force and moment exerted by the support on the hose end (moment about the end vertex).</p>\n");
    }

    let bodies: Vec<_> = runs
        .iter()
        .flat_map(|run| run.doc.bodies.iter().map(move |b| (run, b)))
        .map(|(run, b)| {
            (
                keys(run.label, ""),
                vec![
                    Cell::text(run.label),
                    Cell::text(&b.name),
                    Cell::text(if b.fixed { "mounted" } else { "free" }),
                    Cell::Num(1e3 * b.position_m[0]),
                    Cell::Num(1e3 * b.position_m[1]),
                    Cell::Num(1e3 * b.position_m[2]),
                    Cell::Num(b.mass_kg),
                ],
            )
        })
        .collect();
    if !bodies.is_empty() {
        html.push_str("<h3>Junctions</h3>\n");
        push_table(
            html,
            "junctions",
            &[
                "result",
                "junction",
                "support",
                "x [mm]",
                "y [mm]",
                "z [mm]",
                "mass [kg]",
            ],
            &bodies,
        );
    }

    let clips: Vec<_> = runs
        .iter()
        .flat_map(|run| run.doc.clips.iter().map(move |c| (run, c)))
        .map(|(run, c)| {
            let value = match (c.value, c.joint.as_str()) {
                (Some(v), "prismatic") => Cell::text(format!("{} mm", super::format::sig(1e3 * v))),
                (Some(v), _) => Cell::text(format!("{} rad", super::format::sig(v))),
                (None, _) => Cell::None,
            };
            (
                keys(run.label, &c.rod),
                vec![
                    Cell::text(run.label),
                    Cell::text(&c.name),
                    Cell::text(&c.rod),
                    Cell::Num(1e3 * c.s_m),
                    Cell::text(&c.joint),
                    value,
                    Cell::Check(!c.at_limit, "free", "at limit"),
                    Cell::Num(magnitude(&c.force_n)),
                    Cell::Num(magnitude(&c.moment_nm)),
                ],
            )
        })
        .collect();
    if !clips.is_empty() {
        html.push_str("<h3>Clips</h3>\n");
        push_table(
            html,
            "clips",
            &[
                "result",
                "clip",
                "hose",
                "s [mm]",
                "joint",
                "joint value",
                "limit",
                "|F| [N]",
                "|M| [N·m]",
            ],
            &clips,
        );
    }
}

/// Contact forces and clearances, or "no contact".
pub(crate) fn push_contacts(html: &mut String, runs: &[ReportRun]) {
    let contacts: Vec<_> = runs
        .iter()
        .flat_map(|run| run.doc.contacts.iter().map(move |c| (run, c)))
        .map(|(run, c)| {
            (
                keys(run.label, &c.rod),
                vec![
                    Cell::text(run.label),
                    Cell::text(&c.rod),
                    Cell::text(&c.with),
                    Cell::Num(1e3 * c.s_m),
                    Cell::Num(c.force_n),
                    Cell::Num(1e3 * c.point_m[0]),
                    Cell::Num(1e3 * c.point_m[1]),
                    Cell::Num(1e3 * c.point_m[2]),
                ],
            )
        })
        .collect();
    html.push_str("<h3>Contacts</h3>\n");
    if contacts.is_empty() {
        html.push_str("<p class=\"note\" id=\"no-contact\">No contact in any result.</p>\n");
    } else {
        push_table(
            html,
            "contacts",
            &[
                "result",
                "hose",
                "with",
                "s [mm]",
                "force [N]",
                "x [mm]",
                "y [mm]",
                "z [mm]",
            ],
            &contacts,
        );
    }
    let clearance: Vec<_> = runs
        .iter()
        .flat_map(|run| run.doc.clearance.iter().map(move |c| (run, c)))
        .map(|(run, c)| {
            (
                keys(run.label, &c.rod),
                vec![
                    Cell::text(run.label),
                    Cell::text(&c.rod),
                    Cell::text(&c.with),
                    Cell::Num(1e3 * c.distance_m),
                    Cell::Num(1e3 * c.s_m),
                ],
            )
        })
        .collect();
    html.push_str("<h3>Clearances</h3>\n");
    if clearance.is_empty() {
        html.push_str("<p class=\"note\" id=\"no-clearance\">No clearance data: no environment within the search margin in any result.</p>\n");
    } else {
        push_table(
            html,
            "clearance",
            &["result", "hose", "with", "clearance [mm]", "s [mm]"],
            &clearance,
        );
    }
}

/// The smallest bend radius `1/|K_b|` of `rod` (`K_b`: the first two curvature
/// components), m, and its vertex; `None` if the rod is straight everywhere.
pub(crate) fn min_bend_radius(rod: &RodResult) -> Option<(f64, usize)> {
    let mut best: Option<(f64, usize)> = None;
    for (j, k) in rod.curvature_1pm.iter().enumerate() {
        let bending = k[0].hypot(k[1]);
        if bending > 0.0 || bending.is_nan() {
            let radius = 1.0 / bending;
            if best.is_none_or(|(b, _)| radius < b || radius.is_nan()) {
                best = Some((radius, j));
            }
        }
    }
    best
}

/// Per run and hose: the smallest bend radius, where, and the check against the
/// allowed minimum when one is given.
pub(crate) fn push_bend_radius(html: &mut String, runs: &[ReportRun]) {
    let mut rows = Vec::new();
    for run in runs {
        for rod in &run.doc.rods {
            let origin = runs
                .first()
                .map_or(ArcOrigin::Start, |r| report_origin(r.doc, &rod.name));
            let least = min_bend_radius(rod);
            let check = match (least, rod.min_bend_radius_m) {
                (_, None) => Cell::None,
                (None, Some(_)) => Cell::Check(true, "ok", ""),
                (Some((r, _)), Some(allowed)) => Cell::Check(r >= allowed, "ok", "VIOLATED"),
            };
            rows.push((
                keys(run.label, &rod.name),
                vec![
                    Cell::text(run.label),
                    Cell::text(&rod.name),
                    least.map_or(Cell::text("straight"), |(r, _)| Cell::Num(1e3 * r)),
                    Cell::opt(least.map(|(_, j)| 1e3 * arc_at(rod, origin, j))),
                    Cell::opt(rod.min_bend_radius_m.map(|r| 1e3 * r)),
                    check,
                ],
            ));
        }
    }
    push_table(
        html,
        "bend-radius",
        &[
            "result",
            "hose",
            "smallest bend radius [mm]",
            "at s [mm]",
            "allowed minimum [mm]",
            "check",
        ],
        &rows,
    );
    html.push_str("<p class=\"note\">Bend radius 1/|K_b| from the bending part of the material curvature at the vertices; – where the case gives no allowed minimum.</p>\n");
}

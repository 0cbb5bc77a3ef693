//! The short human-readable summary printed after a solve.

use std::fmt::Write;
use std::path::PathBuf;

use strand_case::{BuiltCase, LengthUnit};
use strand_report::ResultDoc;

pub use strand_study::format::{number, significant};

/// A vector `(x, y, z)` scaled by `scale`; components whose magnitude is at most
/// `noise` (in the vector's own unit, e.g. the solver tolerance for forces) or below
/// 1e-10 of the largest print as 0, to hide round-off.
pub fn vector(v: &[f64; 3], scale: f64, noise: f64) -> String {
    let largest = v.iter().fold(0.0f64, |m, c| m.max(c.abs()));
    let clean = |c: f64| {
        if c.abs() <= noise || c.abs() < 1e-10 * largest {
            0.0
        } else {
            c * scale
        }
    };
    format!(
        "({}, {}, {})",
        number(clean(v[0])),
        number(clean(v[1])),
        number(clean(v[2]))
    )
}

/// Rotation angle (rad, in [0, π]) and unit axis of a quaternion `[w, x, y, z]`
/// (axis `(0, 0, 1)` for no rotation).
fn rotation(q: &[f64; 4]) -> (f64, [f64; 3]) {
    let sign = if q[0] < 0.0 { -1.0 } else { 1.0 };
    let v = [sign * q[1], sign * q[2], sign * q[3]];
    let s = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    if s == 0.0 {
        return (0.0, [0.0, 0.0, 1.0]);
    }
    (2.0 * s.atan2(sign * q[0]), [v[0] / s, v[1] / s, v[2] / s])
}

fn yes(flag: bool) -> &'static str {
    if flag { "yes" } else { "no" }
}

/// One line per clip placed by `at_point`: how far the point was from the nominal
/// centreline it was projected onto, in the case's length unit.
pub(crate) fn projection_lines(built: &BuiltCase) -> String {
    let unit = built.length_unit;
    let mut s = String::new();
    for (clip, distance) in &built.clip_projections {
        let _ = writeln!(
            s,
            "clip        '{clip}': at_point is {} {unit} from the nominal centreline (projected onto it)",
            number(distance / unit.metres())
        );
    }
    for moved in &built.moved_bodies {
        let at = moved.to / unit.metres();
        let _ = writeln!(
            s,
            "junction    '{}': its `position` holds a hose's end inside or against a part; \
             the start puts it {} {unit} away, at ({}, {}, {}) {unit} (give a `position` clear of the parts to choose)",
            moved.name,
            number((moved.to - moved.from).norm() / unit.metres()),
            number(at.x),
            number(at.y),
            number(at.z),
        );
    }
    s
}

/// The summary of a solved case.
pub fn summary(built: &BuiltCase, doc: &ResultDoc, written: &[PathBuf]) -> String {
    let unit: LengthUnit = built.length_unit;
    let mut s = String::new();
    let _ = writeln!(s, "case        {} ({})", doc.case, built.origin);
    s += &projection_lines(built);
    if let Some(start) = built.start.describe()
        && doc.variant.is_none()
    {
        let _ = writeln!(s, "start       {start}");
    }
    if let Some(variant) = &doc.variant {
        let start = match doc.base_iterations {
            Some(n) if doc.warm_start => {
                format!("warm start from the case's solution, which took {n} iterations")
            }
            _ => "cold start".to_string(),
        };
        let _ = writeln!(s, "variant     {variant} ({start})");
    }
    let segments: usize = doc.rods.iter().map(|r| r.segments).sum();
    let _ = writeln!(
        s,
        "unknowns    {} ({} rod(s), {segments} segments)",
        doc.unknowns,
        doc.rods.len()
    );
    let stopped = if doc.converged {
        String::new()
    } else {
        format!(", stopped: {}", doc.termination)
    };
    // A converged residual above the tolerance is one at this model's round-off floor
    // (the solver accepts a stall within 4 × the floor): say so, or the line reads as a
    // contradiction.
    let tolerance = if doc.converged && doc.residual_n > doc.tolerance_n {
        format!(
            "above the tolerance {} N but at this model's round-off floor {} N",
            number(doc.tolerance_n),
            number(doc.residual_floor_n)
        )
    } else {
        format!("tolerance {} N", number(doc.tolerance_n))
    };
    let _ = writeln!(
        s,
        "converged   {} (residual {} N, {tolerance}, {} iterations{stopped})",
        yes(doc.converged),
        number(doc.residual_n),
        doc.iterations,
    );
    // Where the iterations went, when not all in one direct solve: the final solve,
    // the coarse level, the continuation (load or stiffness steps, a release retry),
    // leaving unstable states, and attempts that a later one replaced.
    let mut parts = Vec::new();
    if doc.coarse_iterations > 0 {
        parts.push(format!("{} coarse", doc.coarse_iterations));
    }
    if doc.continuation_steps > 0 {
        // A converged release retry is the final solve itself: a step without
        // iterations of its own.
        parts.push(match doc.continuation_iterations {
            0 => format!("after {} continuation step(s)", doc.continuation_steps),
            n => format!("{n} in {} continuation step(s)", doc.continuation_steps),
        });
    }
    if doc.escape_iterations > 0 {
        parts.push(format!(
            "{} leaving an unstable state",
            doc.escape_iterations
        ));
    }
    let accounted = doc.fine_iterations
        + doc.coarse_iterations
        + doc.continuation_iterations
        + doc.escape_iterations;
    let replaced = doc.iterations.saturating_sub(accounted);
    if replaced > 0 {
        parts.push(format!("{replaced} in attempts that did not converge"));
    }
    if !parts.is_empty() {
        parts.insert(0, format!("{} final", doc.fine_iterations));
        let _ = writeln!(s, "iterations  {} ({})", doc.iterations, parts.join(", "));
    }
    let mut curvature = format!(
        "{} negative, {} neutral direction(s)",
        doc.negative_directions, doc.neutral_directions
    );
    if doc.gauge_freedoms > 0 {
        curvature += &format!(
            "; {} free turn(s) of a round rod about its axis held",
            doc.gauge_freedoms
        );
    }
    let _ = writeln!(s, "stable      {} ({curvature})", yes(doc.stable));
    let _ = writeln!(s, "energy      {} J", number(doc.energy_j));
    let _ = writeln!(
        s,
        "solve time  {} ms (total {} ms)",
        significant(doc.timing_s.solve * 1e3, 3),
        significant(doc.timing_s.total * 1e3, 3)
    );
    if !doc.bodies.is_empty() {
        let _ = writeln!(
            s,
            "bodies      (pose of the body frame; rotation from the world frame)"
        );
        let width = doc.bodies.iter().map(|b| b.name.len()).max().unwrap_or(0);
        for b in &doc.bodies {
            let (angle, axis) = rotation(&b.orientation_quaternion_wxyz);
            let _ = writeln!(
                s,
                "  {:width$}  {}  {} kg  at {} {unit}  rotated {}° about {}",
                b.name,
                if b.fixed { "fixed" } else { "free " },
                number(b.mass_kg),
                vector(&b.position_m, 1.0 / unit.metres(), 1e-12),
                significant(angle.to_degrees(), 4),
                vector(&axis, 1.0, 1e-12),
            );
        }
    }
    if doc.reactions.is_empty() {
        let _ = writeln!(s, "reactions   none");
    } else {
        let _ = writeln!(s, "reactions   (on the rod; moment about the end vertex)");
        let width = doc
            .reactions
            .iter()
            .map(|r| r.name.len())
            .max()
            .unwrap_or(0);
        // Reaction components below the convergence tolerance are numerically zero.
        let longest_m = doc.rods.iter().map(|r| r.length_m).fold(0.0, f64::max);
        let (force_noise, moment_noise) = (doc.tolerance_n, doc.tolerance_n * longest_m);
        let grouped = !doc.reactions.iter().all(|r| r.kind == "connector");
        for (kind, heading) in [
            ("connector", "connectors (fixed in space)"),
            (
                "port",
                "junction ports (on the rod; the junction feels the opposite)",
            ),
        ] {
            let group: Vec<_> = doc.reactions.iter().filter(|r| r.kind == kind).collect();
            if grouped && !group.is_empty() {
                let _ = writeln!(s, "  {heading}");
            }
            for r in group {
                let _ = writeln!(
                    s,
                    "  {}{:width$}  at {} {unit}  force {} N  moment {} N·m",
                    if grouped { "  " } else { "" },
                    r.name,
                    vector(&r.position_m, 1.0 / unit.metres(), 1e-12),
                    vector(&r.force_n, 1.0, force_noise),
                    vector(&r.moment_nm, 1.0, moment_noise),
                );
            }
        }
    }
    clip_lines(&mut s, doc, unit);
    contact_lines(&mut s, built, doc, unit);
    let diagnostics: Vec<_> = doc
        .environment
        .iter()
        .filter_map(|e| e.diagnostics.clone().map(|d| (e.name.clone(), d)))
        .collect();
    environment_lines(&mut s, &diagnostics, unit);
    let files: Vec<String> = written.iter().map(|p| p.display().to_string()).collect();
    let _ = writeln!(s, "written     {}", files.join(", "));
    s
}

/// One line per clip: where it holds its rod, its joint value, its reaction.
fn clip_lines(s: &mut String, doc: &ResultDoc, unit: LengthUnit) {
    if doc.clips.is_empty() {
        return;
    }
    let _ = writeln!(
        s,
        "clips       (joint value; force and moment on the rod about the clipped vertex)"
    );
    let width = doc.clips.iter().map(|c| c.name.len()).max().unwrap_or(0);
    let longest_m = doc.rods.iter().map(|r| r.length_m).fold(0.0, f64::max);
    let (force_noise, moment_noise) = (doc.tolerance_n, doc.tolerance_n * longest_m);
    for c in &doc.clips {
        let state = match (c.joint.as_str(), c.value, c.rotation_wxyz) {
            ("revolute", Some(v), _) => format!("revolute {}°", significant(v.to_degrees(), 4)),
            ("prismatic", Some(v), _) => format!("prismatic {} {unit}", number(v / unit.metres())),
            ("spherical", _, Some(q)) => {
                let (angle, axis) = rotation(&q);
                format!(
                    "spherical {}° about {}",
                    significant(angle.to_degrees(), 4),
                    vector(&axis, 1.0, 1e-12)
                )
            }
            (joint, ..) => joint.to_string(),
        };
        let limit = if c.at_limit { " (at limit)" } else { "" };
        let _ = writeln!(
            s,
            "  {:width$}  {} at s = {} {unit}  {state}{limit}  force {} N  moment {} N·m",
            c.name,
            c.rod,
            number(c.s_m / unit.metres()),
            vector(&c.force_n, 1.0, force_noise),
            vector(&c.moment_nm, 1.0, moment_noise),
        );
    }
}

/// Contacts listed one per line on the terminal, at most (the largest forces; every
/// one is in `result.json`).
const MAX_CONTACT_LINES: usize = 12;

/// Per rod in contact: how many contacts, where along it and their total force.
fn contact_counts(s: &mut String, doc: &ResultDoc, unit: LengthUnit) {
    let u = unit.symbol();
    // One pass over the contacts (a harness has hundreds of rods), printed by rod.
    let mut per_rod: std::collections::HashMap<&str, (usize, f64, f64, f64)> =
        std::collections::HashMap::new();
    for c in &doc.contacts {
        let (n, from, to, total) =
            per_rod
                .entry(c.rod.as_str())
                .or_insert((0, f64::INFINITY, f64::NEG_INFINITY, 0.0));
        *n += 1;
        *from = from.min(c.s_m);
        *to = to.max(c.s_m);
        *total += c.force_n;
    }
    for rod in &doc.rods {
        if let Some(&(count, from, to, total)) = per_rod.get(rod.name.as_str()) {
            let _ = writeln!(
                s,
                "  {}: {count} contacts from s = {} to {} {u}, forces summing to {} N (all in result.json)",
                rod.name,
                number(from / unit.metres()),
                number(to / unit.metres()),
                number(total),
            );
        }
    }
}

/// Active contacts and the smallest clearance of every rod (cases with an environment).
fn contact_lines(s: &mut String, built: &BuiltCase, doc: &ResultDoc, unit: LengthUnit) {
    if built.environment.is_empty() {
        return;
    }
    let u = unit.symbol();
    let contacts = &doc.contacts;
    if contacts.is_empty() {
        let _ = writeln!(s, "contacts    none");
    } else {
        // A fine cable lying along a surface touches at thousands of points: the
        // terminal shows the largest forces and a line per rod, result.json has all.
        let shown: Vec<&strand_report::ContactResult> = if contacts.len() <= MAX_CONTACT_LINES {
            contacts.iter().collect()
        } else {
            // The largest forces, listed in the order of the rest (by rod, along it).
            let mut largest: Vec<usize> = (0..contacts.len()).collect();
            largest.sort_by(|&a, &b| contacts[b].force_n.total_cmp(&contacts[a].force_n));
            largest.truncate(MAX_CONTACT_LINES);
            largest.sort_unstable();
            largest.iter().map(|&k| &contacts[k]).collect()
        };
        let _ = writeln!(
            s,
            "contacts    {}(force on the rod along the normal, from the obstacle)",
            if shown.len() < contacts.len() {
                format!("{}, the {} largest ", contacts.len(), shown.len())
            } else {
                String::new()
            }
        );
        for c in shown {
            let _ = writeln!(
                s,
                "  {} at s = {} {u} on {}  at {} {u}  {} N along {}",
                c.rod,
                number(c.s_m / unit.metres()),
                c.with,
                vector(&c.point_m, 1.0 / unit.metres(), 1e-12),
                number(c.force_n),
                vector(&c.normal, 1.0, 1e-12),
            );
        }
        if contacts.len() > MAX_CONTACT_LINES {
            contact_counts(s, doc, unit);
        }
    }
    let _ = writeln!(
        s,
        "clearance   (smallest surface distance per rod, other rods included)"
    );
    for rod in &doc.rods {
        let nearest = doc
            .clearance
            .iter()
            .filter(|c| c.rod == rod.name && c.with != rod.name)
            .min_by(|a, b| a.distance_m.total_cmp(&b.distance_m));
        match nearest {
            Some(c) => {
                let _ = writeln!(
                    s,
                    "  {}  {} {u} to {} at s = {} {u}",
                    rod.name,
                    number(c.distance_m / unit.metres()),
                    c.with,
                    number(c.s_m / unit.metres())
                );
            }
            None => {
                let _ = writeln!(
                    s,
                    "  {}  nothing within {} {u}",
                    rod.name,
                    number(strand_report::CLEARANCE_SEARCH_M / unit.metres())
                );
            }
        }
    }
}

/// The environment meshes' diagnostics: one line of counts and one of the bounding
/// box (in the case's unit: a part in m read as mm is 1000 times too small) per mesh.
pub(crate) fn environment_lines(
    s: &mut String,
    meshes: &[(String, strand_report::MeshDiagnosticsResult)],
    unit: LengthUnit,
) {
    if meshes.is_empty() {
        return;
    }
    let u = unit.symbol();
    let _ = writeln!(
        s,
        "environment (meshes as loaded; duplicate vertices welded for the edge checks)"
    );
    for (name, d) in meshes {
        let shape = if d.closed {
            "closed (has an inside)".to_string()
        } else {
            format!(
                "open ({} boundary edges{}): no inside",
                d.boundary_edges,
                if d.misoriented_edges > 0 {
                    format!(", {} misoriented edges", d.misoriented_edges)
                } else {
                    String::new()
                }
            )
        };
        let _ = writeln!(
            s,
            "  {name}  {} triangles ({} degenerate skipped, {} slivers), {} vertices ({} duplicates), \
             {} non-manifold edges, {shape}",
            d.triangles,
            d.degenerate_skipped,
            d.slivers,
            d.vertices,
            d.duplicate_vertices,
            d.non_manifold_edges,
        );
        if !matches!(d.cache.as_str(), "" | "off") {
            let _ = writeln!(s, "  {name}  {}", d.cache_detail);
        }
        let scale = 1.0 / unit.metres();
        let _ = writeln!(
            s,
            "  {name}  box {} .. {} {u}, size {} x {} x {} {u}",
            vector(&d.bounding_box_min_m, scale, 0.0),
            vector(&d.bounding_box_max_m, scale, 0.0),
            number(d.size_m[0] * scale),
            number(d.size_m[1] * scale),
            number(d.size_m[2] * scale),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_short_and_readable() {
        assert_eq!(number(0.0), "0");
        assert_eq!(number(2.0), "2");
        assert_eq!(number(-0.6192912), "-0.619291");
        assert_eq!(number(980.612971), "980.613");
        assert_eq!(number(3.2e-12), "3.2e-12");
        assert_eq!(number(1e-9), "1e-9");
        assert_eq!(number(-1.234567e7), "-1.23457e7");
        assert_eq!(number(-1e-7 * 0.0), "0");
        assert_eq!(significant(0.694311, 3), "0.694");
        assert_eq!(vector(&[1.0, 1e-16, -2.0], 1000.0, 0.0), "(1000, 0, -2000)");
        assert_eq!(vector(&[3e-12, 1e-11, 0.0], 1.0, 1e-9), "(0, 0, 0)");
    }
}

//! Placing the parts that ride on a motion: checking every `moves_with` of a case
//! file, and the file with the parts of one motion moved to a parameter value.

use nalgebra::{Isometry3, Point3, Vector3};

use super::MotionPose;
use crate::centreline::read_centreline;
use crate::error::{CaseError, Reporter};
use crate::schema::{CaseFile, EndDef, OrientationDef, Vec3};
use crate::units::LengthUnit;

/// Every motion of `file`, validated, in file order.
pub(crate) fn motions(
    report: &Reporter,
    unit: LengthUnit,
    file: &CaseFile,
) -> Result<Vec<MotionPose>, CaseError> {
    file.motions
        .iter()
        .map(|(name, def)| MotionPose::compile(report, unit, name, def))
        .collect()
}

fn defined(file: &CaseFile) -> String {
    if file.motions.is_empty() {
        "the case defines no motions".to_string()
    } else {
        let names: Vec<&str> = file.motions.iter().map(|(n, _)| n.as_str()).collect();
        format!("defined: {}", names.join(", "))
    }
}

/// Checks that every `moves_with` names a motion of the file and sits on a part that
/// can move (a fixed junction, a clip base in the world).
pub(crate) fn check_parts(report: &Reporter, file: &CaseFile) -> Result<(), CaseError> {
    let check = |item: String, name: &Option<String>| -> Result<(), CaseError> {
        match name {
            Some(n) if !file.motions.iter().any(|(m, _)| m == n) => Err(report.invalid(
                format!("{item}.moves_with"),
                format!("no motion named '{n}' ({})", defined(file)),
                "name a motion defined under `motions`, or remove `moves_with`",
            )),
            _ => Ok(()),
        }
    };
    for (name, c) in &file.connectors {
        check(format!("connectors '{name}'"), &c.moves_with)?;
    }
    for (name, j) in &file.junctions {
        let item = format!("junctions '{name}'");
        check(item.clone(), &j.moves_with)?;
        if j.moves_with.is_some() && !j.fixed {
            return Err(report.invalid(
                format!("{item}.moves_with"),
                "only a mounted junction (`fixed: true`) can ride on a motion; a free one finds its own pose",
                "add `fixed: true` or remove `moves_with`",
            ));
        }
    }
    for (name, c) in &file.clips {
        let item = format!("clips '{name}'");
        check(item.clone(), &c.moves_with)?;
        if c.moves_with.is_some() && (c.on.is_some() || c.base.is_none()) {
            return Err(report.invalid(
                format!("{item}.moves_with"),
                "only a clip with its own `base` in the world can ride on a motion (one `on` a junction or clip moves with that)",
                "give the clip a `base` and no `on`, or move the part it is on",
            ));
        }
    }
    for e in &file.environment {
        check(format!("environment '{}'", e.name), &e.moves_with)?;
    }
    Ok(())
}

fn point(map: &Isometry3<f64>, v: &Vec3) -> Vec3 {
    (map * Point3::from(*v)).coords.into()
}

fn vector(map: &Isometry3<f64>, v: &Vec3) -> Vec3 {
    (map.rotation * Vector3::from(*v)).into()
}

/// Environment meshes by name with the rigid map (world, m) that moves them.
pub(crate) type MovedMeshes = Vec<(String, Isometry3<f64>)>;

/// `file` with every part riding on `motion` carried by `map` (case's length unit of
/// `unit`), except the environment meshes: those are returned by name with the map in
/// metres, to be placed without rebuilding them. A route read from a file
/// (`route_file`) on a rod held by a moving part becomes an inline `route`, so that
/// its end can move with the part.
pub(crate) fn moved(
    report: &Reporter,
    unit: LengthUnit,
    file: &CaseFile,
    motion: &str,
    map: &Isometry3<f64>,
) -> Result<(CaseFile, MovedMeshes), CaseError> {
    let rides = |m: &Option<String>| m.as_deref() == Some(motion);
    let mut file = file.clone();
    // A route (initial guess) starts and ends where its rod is held: its end points
    // move with the parts holding them.
    let held_by_moving = |end: &EndDef| match end {
        EndDef::Connector(c) | EndDef::ConnectorPin(c) => file
            .connectors
            .iter()
            .any(|(n, d)| n == c && rides(&d.moves_with)),
        EndDef::Port(j, _) | EndDef::PortPin(j, _) => file
            .junctions
            .iter()
            .any(|(n, d)| n == j && rides(&d.moves_with)),
        _ => false,
    };
    let moves: Vec<[bool; 2]> = file
        .rods
        .iter()
        .map(|r| [held_by_moving(&r.start), held_by_moving(&r.end)])
        .collect();
    for (i, (rod, [start, end])) in file.rods.iter_mut().zip(moves).enumerate() {
        if let (true, None, Some(def)) = (start || end, &rod.route, &rod.route_file) {
            let item = format!("rods[{i}] '{}'.route_file", rod.name);
            let points = read_centreline(report, &item, def)?;
            rod.route = Some(points.iter().map(|p| (p / unit.metres()).into()).collect());
            rod.route_file = None;
        }
        if let Some(route) = rod.route.as_mut().filter(|r| !r.is_empty()) {
            if start {
                route[0] = point(map, &route[0]);
            }
            if end {
                let last = route.len() - 1;
                route[last] = point(map, &route[last]);
            }
        }
    }
    for (_, c) in &mut file.connectors {
        if rides(&c.moves_with) {
            c.position = point(map, &c.position);
            c.direction = vector(map, &c.direction);
            c.normal = vector(map, &c.normal);
        }
    }
    for (_, j) in &mut file.junctions {
        if rides(&j.moves_with) {
            j.position = point(map, &j.position);
            let o = j.orientation.take().unwrap_or(OrientationDef {
                direction: [0.0, 0.0, 1.0],
                normal: [1.0, 0.0, 0.0],
            });
            j.orientation = Some(OrientationDef {
                direction: vector(map, &o.direction),
                normal: vector(map, &o.normal),
            });
        }
    }
    for (_, c) in &mut file.clips {
        if let (true, Some(base)) = (rides(&c.moves_with), c.base.as_mut()) {
            base.position = point(map, &base.position);
            base.direction = vector(map, &base.direction);
            base.normal = vector(map, &base.normal);
        }
    }
    let metres = Isometry3::from_parts(
        (map.translation.vector * unit.metres()).into(),
        map.rotation,
    );
    let meshes = file
        .environment
        .iter()
        .filter(|e| rides(&e.moves_with))
        .map(|e| (e.name.clone(), metres))
        .collect();
    Ok((file, meshes))
}

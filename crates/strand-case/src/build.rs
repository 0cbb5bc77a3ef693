//! A parsed case file → a validated [`Model`] with its initial state and settings.

use std::sync::Arc;

use nalgebra::{Isometry3, Vector3};
use strand_contact::ObstacleMesh;
use strand_rod::{NominalRod, RodState, Section};
use strand_solve::SolverSettings;
use strand_system::{Model, RodSpec, System, SystemState, initial_state};

use crate::attach::{Attachments, build_attachments, check_reach};
use crate::centreline::read_centreline;
use crate::clips::{clip_specs, clips_on_rod, place_clips, project_clip_points, resolve_clips};
use crate::ends::build_end;
use crate::environment::{EnvironmentCache, load_environment};
use crate::error::{CaseError, Reporter};
use crate::nominal::{
    build_reference, initial_guess, nominal_end, nominal_shape, stated_length, use_guesses,
};
use crate::schema::{CaseFile, EndDef, RodDef};
use crate::sections::{build_sections, min_bend_radii, names};
use crate::start::Start;
use crate::units::LengthUnit;

/// Largest allowed distance between a route's first/last point and the held end it
/// should start/end at, as a fraction of the rod length (the point is then snapped).
pub const ROUTE_END_TOLERANCE: f64 = 0.01;

/// A case ready to solve: SI units throughout.
#[derive(Clone, Debug)]
pub struct BuiltCase {
    /// Case name (the file stem), used for the default output directory.
    pub name: String,
    /// The file as named by the user.
    pub origin: String,
    /// Length unit the file was written in (for messages; the model is in m).
    pub length_unit: LengthUnit,
    /// The validated model (rods, supports, loads in SI units).
    pub model: Model,
    /// Initial configuration (route hint or the system's default guess).
    pub initial: SystemState,
    /// Solver settings from the file (defaults where not given).
    pub settings: SolverSettings,
    /// Per rod, the names of the connectors holding its start and end (`None` for an
    /// end held otherwise): the names of their reactions in the results.
    pub connector_names: Vec<[Option<String>; 2]>,
    /// Per rod, the smallest allowed bend radius of its section in m (`None` where
    /// the section states no `min_bend_radius`).
    pub min_bend_radius: Vec<Option<f64>>,
    /// Per rod, its required clearance to the environment and the other rods in m
    /// (`None` where the rod states no `min_clearance`).
    pub min_clearance: Vec<Option<f64>>,
    /// The named connectors with an allowed load (`max_force`, `max_moment`).
    pub connector_limits: Vec<crate::limits::ConnectorLimit>,
    /// Per rod, the name of its section and, for a `Tube` section, its inner radius
    /// in m (`None` for an `Explicit` section): the report's input table.
    pub sections: Vec<(String, Option<f64>)>,
    /// Environment meshes (OBJ files in world coordinates, m, with their BVH), in
    /// file order; shared with the case's other builds (variants, batches).
    pub environment: Vec<Arc<ObstacleMesh>>,
    /// Which default guess `initial` is: hanging, or (when that passes through an
    /// obstacle) bowed sideways or arched up.
    pub start: Start,
    /// Free junctions the start moved away from their given `position` (a hose's end
    /// at a port was inside or against a part there), in body order.
    pub moved_bodies: Vec<crate::placement::BodyMove>,
    /// Clips placed by `at_point`: their names and the distance (m) from the given point
    /// to the nominal centreline it was projected onto, in file order.
    pub clip_projections: Vec<(String, f64)>,
    /// When no start clears: a rod (its index) and a hint more precise than "give a
    /// route" for its start error (how long the way around the parts is).
    pub(crate) start_hint: Option<(usize, strand_solve::StartHint)>,
}

/// What a build takes beyond the case file: the meshes a motion moves, and the state a
/// warm-started solve will begin from.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct BuildExtras<'a> {
    /// Environment meshes (by name) moved rigidly by the map (world, m): placed
    /// ([`strand_contact::ObstacleMesh::placed`]), not rebuilt.
    pub moved_meshes: &'a [(String, Isometry3<f64>)],
    /// The state a warm-started solve begins from: it becomes `initial`, and no
    /// default guess is computed or checked against the environment (the guess is
    /// only computed where an end's dead moment is measured from it).
    pub warm: Option<&'a SystemState>,
    /// The rod vertex of every clip (in clip order) to keep where the clips stay in
    /// order (a base build's: see [`crate::clips::place_clips`]).
    pub clip_vertices: Option<&'a [usize]>,
    /// A model of the same case whose symbolic phase the build reuses where the
    /// structure is the same ([`Model::try_new_like`]).
    pub like: Option<&'a Model>,
}

/// Builds the model; `segments` overrides every rod's number of segments. Environment
/// meshes come from `environment` when already built there.
pub(crate) fn build(
    name: &str,
    origin: &str,
    file: &CaseFile,
    segments: Option<usize>,
    environment: &EnvironmentCache,
    extras: BuildExtras<'_>,
) -> Result<BuiltCase, CaseError> {
    let report = Reporter { origin };
    let unit = LengthUnit::parse(&file.units.length).ok_or_else(|| {
        report.invalid(
            "units.length",
            format!("unknown length unit \"{}\"", file.units.length),
            format!("use {}", LengthUnit::ACCEPTED),
        )
    })?;
    let sections = build_sections(&report, unit, &file.sections)?;
    let min_bend_radius = min_bend_radii(&report, unit, file)?;
    let min_clearance = crate::limits::min_clearances(&report, unit, file)?;
    let connector_limits = crate::limits::connector_limits(&report, file)?;
    crate::motion::check(&report, unit, file)?;
    let attachments = build_attachments(&report, unit, file)?;
    let mut clips = resolve_clips(&report, unit, file)?;
    if file.rods.is_empty() {
        return Err(report.invalid("rods", "the case has no rods", "add at least one rod"));
    }
    let mut rods = Vec::with_capacity(file.rods.len());
    let mut guesses = Vec::with_capacity(file.rods.len());
    let mut projections = Vec::new();
    for (i, def) in file.rods.iter().enumerate() {
        let item = format!("rods[{i}] '{}'", def.name);
        check_name(&report, i, &def.name)?;
        if let Some(first) = file.rods[..i].iter().position(|r| r.name == def.name) {
            return Err(report.invalid(
                &item,
                format!("duplicate rod name (also used by rods[{first}])"),
                "give every rod a unique name",
            ));
        }
        if let (Some(nominal), Some((_, section))) = (
            &def.nominal,
            sections.iter().find(|(n, _)| *n == def.section),
        ) && clips_on_rod(&clips, i).iter().any(|s| s.is_nan())
        {
            let shape = nominal_shape(&report, &format!("{item}.nominal"), unit, nominal)?;
            let radius = section.outer_radius;
            projections.extend(project_clip_points(
                &report, unit, i, &shape, radius, &mut clips,
            )?);
        }
        let stations = clips_on_rod(&clips, i);
        let (rod, guess, nominal) = build_rod(
            &report,
            &item,
            unit,
            &sections,
            &attachments,
            def,
            segments,
            &stations,
        )?;
        let rod = place_clips(
            &report,
            &item,
            unit,
            i,
            def,
            rod,
            nominal.as_ref(),
            &mut clips,
            extras.clip_vertices,
        )?;
        rods.push(rod);
        guesses.push(guess);
    }
    attachments.check_usage(&report, file)?;
    let gravity = report.finite3("gravity", &file.gravity, " m/s²")?;
    file.solver
        .validate()
        .map_err(|source| CaseError::Settings {
            origin: origin.to_string(),
            source,
        })?;

    let clips = clip_specs(clips, &attachments.bodies);
    let mut system = System {
        rods,
        bodies: attachments.bodies,
        clips,
        gravity,
    };
    let system_error = |source| CaseError::System {
        origin: origin.to_string(),
        source,
    };
    system.validate().map_err(system_error)?;
    check_reach(&report, unit, &system)?;
    // Dead end moments are measured from the rod's nominal (initial) end frame.
    let dead_moment = system
        .rods
        .iter()
        .any(|r| r.start.load.moment != Vector3::zeros() || r.end.load.moment != Vector3::zeros());
    let nominal_of = |system: &mut System| {
        let mut nominal = initial_state(system);
        use_guesses(&mut nominal, &guesses);
        for (spec, state) in system.rods.iter_mut().zip(&nominal.rods) {
            spec.start.load.moment_reference = state.frames[0];
            spec.end.load.moment_reference = state.frames[state.frames.len() - 1];
        }
        nominal
    };
    // The initial guess does not depend on the loads' moment references: it is the
    // nominal state (computing it again doubled the build time).
    let initial = match extras.warm {
        Some(warm) => {
            if dead_moment {
                nominal_of(&mut system);
            }
            warm.clone()
        }
        None => nominal_of(&mut system),
    };
    let model = match extras.like {
        Some(like) => Model::try_new_like(system, like),
        None => Model::try_new(system),
    }
    .map_err(system_error)?;
    let environment = load_environment(&report, unit, file, environment, extras.moved_meshes)?;
    let mut built = BuiltCase {
        name: name.to_string(),
        origin: origin.to_string(),
        length_unit: unit,
        model,
        initial,
        settings: file.solver.clone(),
        connector_names: file.rods.iter().map(connector_names).collect(),
        min_bend_radius,
        min_clearance,
        connector_limits,
        sections: file
            .rods
            .iter()
            .map(|rod| {
                let def = file.sections.iter().find(|(n, _)| *n == rod.section);
                let inner = match def.map(|(_, d)| d) {
                    Some(crate::schema::SectionDef::Tube { inner_radius, .. }) => {
                        Some(inner_radius * unit.metres())
                    }
                    _ => None,
                };
                (rod.section.clone(), inner)
            })
            .collect(),
        environment,
        start: Start::Hanging,
        moved_bodies: Vec::new(),
        clip_projections: projections,
        start_hint: None,
    };
    built.start = if extras.warm.is_some() {
        Start::Given
    } else {
        built.clear_start(&guesses)
    };
    Ok(built)
}

/// The connectors holding the start and end of a rod, by name.
fn connector_names(def: &RodDef) -> [Option<String>; 2] {
    [&def.start, &def.end].map(|end| match end {
        EndDef::Connector(name) | EndDef::ConnectorPin(name) => Some(name.clone()),
        _ => None,
    })
}

fn check_name(report: &Reporter, index: usize, name: &str) -> Result<(), CaseError> {
    let allowed = |c: char| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.');
    if name.is_empty() || name.starts_with('.') || !name.chars().all(allowed) {
        return Err(report.invalid(
            format!("rods[{index}].name"),
            format!("invalid rod name '{name}': the name is also the CSV file name"),
            "use letters, digits, '_', '-' and '.' only (not starting with '.')",
        ));
    }
    Ok(())
}

fn build_rod(
    report: &Reporter,
    item: &str,
    unit: LengthUnit,
    sections: &[(String, Section)],
    attachments: &Attachments,
    def: &RodDef,
    segments_override: Option<usize>,
    clip_stations: &[f64],
) -> Result<(RodSpec, Option<RodState>, Option<NominalRod>), CaseError> {
    let section = sections
        .iter()
        .find(|(n, _)| *n == def.section)
        .map(|(_, s)| *s)
        .ok_or_else(|| {
            report.invalid(
                item,
                format!(
                    "section '{}' is not defined (defined: {})",
                    def.section,
                    names(sections)
                ),
                "add the section under `sections` or correct the name",
            )
        })?;
    let length = stated_length(report, item, unit, def)?;
    let segments = segments_override.unwrap_or(def.segments);
    if segments == 0 {
        let hint = if segments_override.is_some() {
            "pass --segments 1 or more"
        } else {
            "use 1 or more segments"
        };
        return Err(report.invalid(
            format!("{item}.segments"),
            "a rod needs at least 1 segment (got 0)",
            hint,
        ));
    }
    let (rod, nominal) = build_reference(
        report,
        item,
        unit,
        section,
        def,
        length,
        segments,
        clip_stations,
    )?;
    let length = rod.length();
    let at_nominal_end = |at_end| nominal_end(nominal.as_ref(), at_end);
    let (start_item, end_item) = (format!("{item}.start"), format!("{item}.end"));
    let start = match attachments.end(report, &start_item, &def.start, false)? {
        Some(end) => end,
        None => build_end(report, &start_item, unit, &def.start, at_nominal_end(false))?,
    };
    let mut end = match attachments.end(report, &end_item, &def.end, true)? {
        Some(end) => end,
        None => build_end(report, &end_item, unit, &def.end, at_nominal_end(true))?,
    };
    if def.twist_turns != 0 {
        if let Some(label) = [("start", &start), ("end", &end)]
            .iter()
            .find(|(_, e)| !e.has_frame())
            .map(|(label, _)| *label)
        {
            return Err(report.invalid(
                format!("{item}.twist_turns"),
                format!(
                    "{} extra twist turn(s) need both ends clamped, but the {label} does not hold the section's rotation",
                    def.twist_turns
                ),
                "clamp both ends (Clamp, NominalClamp, Connector or Port) or remove `twist_turns`",
            ));
        }
        end.twist_turns = def.twist_turns;
    }
    let file_route = match (&def.route, &def.route_file) {
        (Some(_), Some(_)) => {
            return Err(report.invalid(
                format!("{item}.route_file"),
                "both `route` and `route_file` are given",
                "give the route either inline (`route`) or from a file (`route_file`)",
            ));
        }
        (None, Some(file)) => Some(
            read_centreline(report, &format!("{item}.route_file"), file)?
                .iter()
                .map(|p| (p / unit.metres()).into())
                .collect::<Vec<[f64; 3]>>(),
        ),
        _ => None,
    };
    let route = match def.route.as_ref().or(file_route.as_ref()) {
        None => None,
        Some(points) => Some(build_route(
            report,
            &format!("{item}.route"),
            unit,
            points,
            attachments.initial_position(&start),
            attachments.initial_position(&end),
            length,
        )?),
    };
    // Without a route, a moulded rod starts from its nominal shape.
    let guess = nominal
        .as_ref()
        .filter(|_| route.is_none())
        .map(|n| initial_guess(n, &start, &end));
    let spec = RodSpec {
        name: def.name.clone(),
        rod,
        start,
        end,
        route,
    };
    Ok((spec, guess, nominal))
}

/// Converts a route to m and snaps its first/last point onto held ends.
fn build_route(
    report: &Reporter,
    item: &str,
    unit: LengthUnit,
    points: &[[f64; 3]],
    start: Option<Vector3<f64>>,
    end: Option<Vector3<f64>>,
    length_m: f64,
) -> Result<Vec<Vector3<f64>>, CaseError> {
    if points.len() < 2 {
        return Err(report.invalid(
            item,
            format!("a route needs at least 2 points (got {})", points.len()),
            "add points or remove the route",
        ));
    }
    let u = format!(" {unit}");
    let mut route = points
        .iter()
        .enumerate()
        .map(|(k, p)| {
            report
                .finite3(&format!("{item}[{k}]"), p, &u)
                .map(|v| v * unit.metres())
        })
        .collect::<Result<Vec<_>, _>>()?;
    let polyline_m: f64 = route.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
    if polyline_m <= 1e-9 * length_m {
        return Err(report.invalid(
            item,
            "the route has zero length (all points coincide)",
            "give distinct points along the rod's path or remove the route",
        ));
    }
    let last = route.len() - 1;
    for (k, held, label) in [(0, start, "start"), (last, end, "end")] {
        if let Some(held) = held {
            let gap = (route[k] - held).norm();
            if gap > ROUTE_END_TOLERANCE * length_m {
                return Err(report.invalid(
                    format!("{item}[{k}]"),
                    format!("the route's {label} point is {:.6} {unit} away from the held {label} position", gap / unit.metres()),
                    format!("make the route {} at the {label} support's position", if k == 0 { "start" } else { "end" }),
                ));
            }
            route[k] = held;
        }
    }
    Ok(route)
}

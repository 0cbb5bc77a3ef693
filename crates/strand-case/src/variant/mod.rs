//! Named variants of a case: small changes of the base file (a longer hose, a moved
//! clamp, another gravity), applied to the parsed file before it is validated and
//! built, so a variant is checked exactly like a case.
//!
//! ```ron
//! variants: {
//!     "hose2_plus50": [(item: "rods.hose2.length", change: Add(50))],
//!     "moved": [
//!         (item: "rods.hose2.end.position", change: Add((0, 20, 0))),
//!         (item: "rods.hose2.segments", change: Set(40)),
//!     ],
//!     "moon": [(item: "gravity", change: Set((0, 0, -1.62)))],
//! }
//! ```

mod item;
pub(crate) mod section;
mod turn;

pub use item::{
    ItemError, ItemQuantity, RodEnd, SectionStiffness, ShortFormError, VariantItem, expand_short,
};

use crate::error::{CaseError, Reporter};
use crate::schema::{Amount, CaseFile, Change, EndDef, VariantChange, Vec3};

/// The items a variant can change, for messages.
pub const VARIANT_ITEMS: &str = "rods.<rod>.length (Add/Set a number), \
rods.<rod>.segments (Set a whole number), \
rods.<rod>.start.position, rods.<rod>.end.position (Add/Set a vector; held ends only), \
rods.<rod>.start.force, rods.<rod>.end.force (Add/Set a vector in N), \
junctions.<junction>.mass (Add/Set a number in kg), \
junctions.<junction>.ports.<port>.position (Add/Set a vector, body frame), \
junctions.<junction>.ports.<port>.direction (Add a rotation vector in deg about the body axes), \
connectors.<connector>.position (Add/Set a vector), \
connectors.<connector>.direction (Add a rotation vector in deg about the world axes), \
clips.<clip>.at (Add/Set a number; clips placed by `at`), \
clips.<clip>.base.position (Add/Set a vector; clips with a `base`), \
clips.<clip>.base.direction (Add a rotation vector in deg about the base's parent axes), \
environment.<mesh>.position (Add/Set a vector), \
sections.<section>.ea, .ga (N), .ei, .gj (N·m²) of an Explicit section, \
sections.<section>.youngs_modulus (Pa) of a Tube (Add/Set a number), \
gravity (Add/Set a vector in m/s²)";

/// The name `strand study` uses for the unchanged case; no variant may take it.
pub const BASE_VARIANT: &str = "base";

/// Largest number of segments a variant may set (as the command line's `--segments`).
const MAX_SEGMENTS: f64 = 10_000_000.0;

/// Whether `name` can name a variant: it is also a directory name (`strand study`).
fn is_valid_name(name: &str) -> bool {
    !name.is_empty()
        && !name.starts_with('.')
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.'))
}

/// Checks a variant's name.
pub(crate) fn check_name(report: &Reporter, name: &str) -> Result<(), CaseError> {
    let item = format!("variants '{name}'");
    if name == BASE_VARIANT {
        return Err(report.invalid(
            item,
            "the variant name 'base' is reserved for the unchanged case",
            "rename the variant",
        ));
    }
    if !is_valid_name(name) {
        return Err(report.invalid(
            item,
            "invalid variant name: the name is also a directory name",
            "use letters, digits, '_', '-' and '.' only (not starting with '.')",
        ));
    }
    Ok(())
}

/// The changes of variant `name`, or an error listing the defined variants.
pub(crate) fn find<'f>(
    report: &Reporter,
    file: &'f CaseFile,
    name: &str,
) -> Result<&'f [VariantChange], CaseError> {
    match file.variants.iter().find(|(n, _)| n == name) {
        Some((_, changes)) => Ok(changes),
        None => {
            let defined: Vec<&str> = file.variants.iter().map(|(n, _)| n.as_str()).collect();
            let (message, hint) = if defined.is_empty() {
                (
                    format!("no variant named '{name}': the case defines no variants"),
                    "add it under `variants: { \"name\": [(item: ..., change: ...)] }` (see cases/README.md)"
                        .to_string(),
                )
            } else {
                (
                    format!(
                        "no variant named '{name}' (defined: {})",
                        defined.join(", ")
                    ),
                    format!(
                        "use one of the defined variants{} or add it under `variants`",
                        if name == BASE_VARIANT {
                            " ('base' means the case itself only in `strand study`)"
                        } else {
                            ""
                        }
                    ),
                )
            };
            Err(report.invalid("variants", message, hint))
        }
    }
}

fn number(
    report: &Reporter,
    at: &str,
    item: &str,
    amount: Amount,
    unit: &str,
) -> Result<f64, CaseError> {
    match amount {
        Amount::Number(x) => Ok(x),
        Amount::Vector(_) => Err(report.invalid(
            at,
            format!("{item} takes a number{unit}, not a vector"),
            format!("write e.g. `(item: \"{item}\", change: Add(50))`"),
        )),
    }
}

fn vector(
    report: &Reporter,
    at: &str,
    item: &str,
    amount: Amount,
    unit: &str,
) -> Result<Vec3, CaseError> {
    match amount {
        Amount::Vector(v) => Ok(v),
        Amount::Number(_) => Err(report.invalid(
            at,
            format!("{item} takes a vector (x, y, z){unit}, not a number"),
            format!("write e.g. `(item: \"{item}\", change: Add((0, 0, 10)))`"),
        )),
    }
}

fn changed(base: f64, change: &Change, x: f64) -> f64 {
    match change {
        Change::Add(_) => base + x,
        Change::Set(_) => x,
    }
}

fn changed3(base: &Vec3, change: &Change, v: &Vec3) -> Vec3 {
    match change {
        Change::Add(_) => [base[0] + v[0], base[1] + v[1], base[2] + v[2]],
        Change::Set(_) => *v,
    }
}

/// The file with variant `name` applied (not yet validated: the caller builds it).
pub(crate) fn apply(report: &Reporter, file: &CaseFile, name: &str) -> Result<CaseFile, CaseError> {
    let changes = find(report, file, name)?;
    check_name(report, name)?;
    apply_changes(report, file, name, changes)
}

/// The file with `changes` applied; `name` labels them in messages
/// (`variants '<name>'[k] "<item>"`).
pub(crate) fn apply_changes(
    report: &Reporter,
    file: &CaseFile,
    name: &str,
    changes: &[VariantChange],
) -> Result<CaseFile, CaseError> {
    let unit = format!(" (in {})", file.units.length);
    let mut out = file.clone();
    for (k, VariantChange { item, change }) in changes.iter().enumerate() {
        let at = format!("variants '{name}'[{k}] \"{item}\"");
        let amount = match change {
            Change::Add(a) | Change::Set(a) => *a,
        };
        let target =
            VariantItem::parse(file, item).map_err(|e| report.invalid(&at, e.message, e.hint))?;
        match target {
            VariantItem::Gravity => {
                let v = vector(report, &at, item, amount, " in m/s²")?;
                out.gravity = changed3(&out.gravity, change, &v);
            }
            VariantItem::RodLength(r) => {
                let x = number(report, &at, item, amount, &unit)?;
                let Some(length) = out.rods[r].length else {
                    return Err(report.invalid(
                        &at,
                        format!(
                            "rod '{}' has no `length`: its length is that of its nominal shape",
                            out.rods[r].name
                        ),
                        "change the rod's nominal points instead (a moulded rod's length is fixed)",
                    ));
                };
                out.rods[r].length = Some(changed(length, change, x));
            }
            VariantItem::RodSegments(r) => {
                let x = number(report, &at, item, amount, "")?;
                if matches!(change, Change::Add(_)) {
                    return Err(report.invalid(
                        &at,
                        "the number of segments can only be Set",
                        format!("write `(item: \"{item}\", change: Set(40))`"),
                    ));
                }
                if !(x.fract() == 0.0 && (1.0..=MAX_SEGMENTS).contains(&x)) {
                    return Err(report.invalid(
                        &at,
                        format!("the number of segments must be a whole number from 1 to 10000000 (got {x})"),
                        "set a whole number of segments, e.g. Set(40)",
                    ));
                }
                out.rods[r].segments = x as usize;
            }
            VariantItem::EndPosition { rod: r, end: side } => {
                let v = vector(report, &at, item, amount, &unit)?;
                let rod = &mut out.rods[r];
                let end = match side {
                    RodEnd::Start => &mut rod.start,
                    RodEnd::End => &mut rod.end,
                };
                let position = match end {
                    EndDef::Clamp { position, .. } | EndDef::Pin { position, .. } => position,
                    EndDef::NominalClamp { .. } => {
                        return Err(report.invalid(
                            &at,
                            format!(
                                "the {} of rod '{}' is NominalClamp(): it is held where the nominal shape ends",
                                side.label(),
                                rod.name
                            ),
                            "change the nominal points, or use a Clamp end with its own position",
                        ));
                    }
                    EndDef::Free { .. } => {
                        return Err(report.invalid(
                            &at,
                            format!(
                                "the {} of rod '{}' is Free(): it has no position to change",
                                side.label(),
                                rod.name
                            ),
                            "change the position of a Clamp or Pin end only",
                        ));
                    }
                    EndDef::Connector(c) | EndDef::ConnectorPin(c) => {
                        return Err(report.invalid(
                            &at,
                            format!(
                                "the {} of rod '{}' is held by connector '{c}'",
                                side.label(),
                                rod.name
                            ),
                            format!("move the connector instead: \"connectors.{c}.position\""),
                        ));
                    }
                    EndDef::Port(j, _) | EndDef::PortPin(j, _) => {
                        return Err(report.invalid(
                            &at,
                            format!(
                                "the {} of rod '{}' is held by a port of junction '{j}', which places it",
                                side.label(),
                                rod.name
                            ),
                            "change the position of a Clamp or Pin end only",
                        ));
                    }
                };
                let old = *position;
                let new = changed3(&old, change, &v);
                *position = new;
                // The route is only the initial guess: move its point at this end along.
                if let Some(route) = rod.route.as_mut().filter(|r| !r.is_empty()) {
                    let point = match side {
                        RodEnd::Start => &mut route[0],
                        RodEnd::End => route.last_mut().expect("non-empty"),
                    };
                    for i in 0..3 {
                        point[i] += new[i] - old[i];
                    }
                }
            }
            VariantItem::EndForce { rod: r, end: side } => {
                let v = vector(report, &at, item, amount, " in N")?;
                let end = match side {
                    RodEnd::Start => &mut out.rods[r].start,
                    RodEnd::End => &mut out.rods[r].end,
                };
                let force = match end {
                    EndDef::Clamp { force, .. }
                    | EndDef::Pin { force, .. }
                    | EndDef::Free { force, .. }
                    | EndDef::NominalClamp { force, .. } => force,
                    EndDef::Connector(_)
                    | EndDef::ConnectorPin(_)
                    | EndDef::Port(..)
                    | EndDef::PortPin(..) => {
                        return Err(report.invalid(
                            &at,
                            format!(
                                "the {} of rod '{}' is held by a connector or port, which takes no dead loads",
                                side.label(),
                                out.rods[r].name
                            ),
                            "change the force of a Clamp, Pin, NominalClamp or Free end only",
                        ));
                    }
                };
                *force = changed3(force, change, &v);
            }
            VariantItem::JunctionMass(j) => {
                let x = number(report, &at, item, amount, " in kg")?;
                let mass = &mut out.junctions[j].1.mass;
                *mass = changed(*mass, change, x);
            }
            VariantItem::ClipAt(c) => {
                let x = number(report, &at, item, amount, &unit)?;
                let (name, clip) = &mut out.clips[c];
                let Some(station) = clip.at.as_mut() else {
                    return Err(report.invalid(
                        &at,
                        format!("clip '{name}' is placed by `at_point`, not by `at`"),
                        "change a clip placed by its arc length `at`",
                    ));
                };
                *station = changed(*station, change, x);
            }
            VariantItem::ClipBasePosition(c) => {
                let v = vector(report, &at, item, amount, &unit)?;
                let (name, clip) = &mut out.clips[c];
                let Some(base) = clip.base.as_mut() else {
                    return Err(report.invalid(
                        &at,
                        format!("clip '{name}' has no `base` of its own"),
                        "change the base position of a clip with a `base`",
                    ));
                };
                base.position = changed3(&base.position, change, &v);
            }
            VariantItem::ConnectorDirection(c) => {
                let turn = turn::rotation(report, &at, item, change)?;
                let connector = &mut out.connectors[c].1;
                turn::frame(&turn, &mut connector.direction, &mut connector.normal);
            }
            VariantItem::PortPosition { junction, port } => {
                let v = vector(report, &at, item, amount, &unit)?;
                let port = &mut out.junctions[junction].1.ports[port].1;
                port.position = changed3(&port.position, change, &v);
            }
            VariantItem::PortDirection { junction, port } => {
                let turn = turn::rotation(report, &at, item, change)?;
                let port = &mut out.junctions[junction].1.ports[port].1;
                turn::frame(&turn, &mut port.direction, &mut port.normal);
            }
            VariantItem::ClipBaseDirection(c) => {
                let turn = turn::rotation(report, &at, item, change)?;
                let (name, clip) = &mut out.clips[c];
                let Some(base) = clip.base.as_mut() else {
                    return Err(report.invalid(
                        &at,
                        format!("clip '{name}' has no `base` of its own"),
                        "turn the base of a clip with a `base`",
                    ));
                };
                turn::frame(&turn, &mut base.direction, &mut base.normal);
            }
            VariantItem::Section { section, stiffness } => {
                let x = number(
                    report,
                    &at,
                    item,
                    amount,
                    &format!(" in {}", stiffness.unit()),
                )?;
                section::change(&mut out.sections[section].1, stiffness, |v| {
                    changed(v, change, x)
                });
            }
            VariantItem::EnvironmentPosition(e) => {
                let v = vector(report, &at, item, amount, &unit)?;
                let mesh = &mut out.environment[e];
                mesh.position = changed3(&mesh.position, change, &v);
            }
            VariantItem::ConnectorPosition(c) => {
                let v = vector(report, &at, item, amount, &unit)?;
                let (name, connector) = &mut out.connectors[c];
                let old = connector.position;
                let new = changed3(&old, change, &v);
                connector.position = new;
                // Routes are only initial guesses: move their points at this connector.
                for rod in &mut out.rods {
                    for (held, first) in [(&rod.start, true), (&rod.end, false)] {
                        let at_connector = matches!(held, EndDef::Connector(n) | EndDef::ConnectorPin(n) if n == name);
                        if let Some(route) =
                            rod.route.as_mut().filter(|r| at_connector && !r.is_empty())
                        {
                            let point = if first {
                                &mut route[0]
                            } else {
                                route.last_mut().expect("non-empty")
                            };
                            for i in 0..3 {
                                point[i] += new[i] - old[i];
                            }
                        }
                    }
                }
            }
        }
    }
    Ok(out)
}

/// Marks an error found while building variant `name` as the variant's.
pub(crate) fn in_variant(error: CaseError, name: &str) -> CaseError {
    error.within(
        &format!("variant '{name}'"),
        "correct the variant's changes (under `variants` in the case, or the values of `--vary`)",
        |item| item.starts_with("variants"),
    )
}

/// Marks an error found while building a design at a point (a sensitivity's
/// difference step, an optimisation's trial) as that point's: `point` names the
/// parameters' changes there.
pub(crate) fn in_design(error: CaseError, point: &str) -> CaseError {
    error.within(
        &format!("the design at {point}"),
        "the parameters there make the case invalid: keep them within what it allows (for `strand optimize`, narrow the bounds of `--vary`)",
        |item| item.starts_with("variants"),
    )
}

#[cfg(test)]
mod tests {
    use nalgebra::Vector3;

    use crate::schema::{Amount, Change};
    use crate::{Case, CaseError};

    const ORIGIN: &str = "cases/two.ron";

    /// Two rods (one with a '.' in its name and a route), three variants.
    const CASE: &str = r#"(
    units: (length: "mm"),
    sections: {
        "paper": Explicit(ea: 30e3, ga: 10e3, ei: 1, gj: 1, mass_per_length: 0.1),
    },
    rods: [
        (
            name: "hose1", section: "paper", length: 1000, segments: 10,
            start: Clamp(position: (0, 0, 0), tangent: (1, 0, 0), normal: (0, 1, 0)),
            end: Free(force: (2, 1, 0)),
        ),
        (
            name: "hose.2", section: "paper", length: 400, segments: 8,
            start: Pin(position: (0, 0, 0)),
            end: Clamp(position: (380, 0, 0), tangent: (1, 0, 0), normal: (0, 1, 0)),
            route: [(0, 0, 0), (190, 0, -100), (380, 0, 0)],
        ),
    ],
    gravity: (0, 0, -9.81),
    variants: {
        "plus50": [(item: "rods.hose.2.length", change: Add(50))],
        "moved": [
            (item: "rods.hose.2.end.position", change: Add((0, 20, -10))),
            (item: "rods.hose.2.start.position", change: Set((1, 2, 3))),
            (item: "rods.hose.2.segments", change: Set(12)),
            (item: "rods.hose1.end.force", change: Add((1, 0, 0))),
        ],
        "moon": [(item: "gravity", change: Set((0, 0, -1.62)))],
        "longer": [(item: "rods.hose1.length", change: Set(1200.5))],
    },
)"#;

    #[test]
    fn clip_stations_clip_bases_and_mesh_positions_are_variant_items() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../cases");
        let add = |item: &str, amount: Amount| crate::schema::VariantChange {
            item: item.into(),
            change: Change::Add(amount),
        };
        let report = crate::error::Reporter { origin: "test" };
        let harness = Case::from_path(dir.join("harness_clips.ron")).unwrap();
        let changed = super::apply_changes(
            &report,
            &harness.file,
            "t",
            &[
                add("clips.grommet.at", Amount::Number(5.0)),
                add(
                    "clips.grommet.base.position",
                    Amount::Vector([0.0, 0.0, 2.0]),
                ),
            ],
        )
        .unwrap();
        let (old, new) = (&harness.file.clips[0].1, &changed.clips[0].1);
        assert_eq!(new.at.unwrap(), old.at.unwrap() + 5.0);
        let (old_base, new_base) = (old.base.as_ref().unwrap(), new.base.as_ref().unwrap());
        assert_eq!(new_base.position[2], old_base.position[2] + 2.0);
        // The changed case still builds (the clip moves along the trunk).
        harness
            .build_with_changes("t", &[add("clips.grommet.at", Amount::Number(5.0))], None)
            .unwrap();
        let contact = Case::from_path(dir.join("cooler_hose_contact.ron")).unwrap();
        let moved = super::apply_changes(
            &report,
            &contact.file,
            "t",
            &[add(
                "environment.brackets.position",
                Amount::Vector([0.0, 0.0, -3.0]),
            )],
        )
        .unwrap();
        let at = |f: &crate::CaseFile| {
            f.environment
                .iter()
                .find(|e| e.name == "brackets")
                .unwrap()
                .position[2]
        };
        assert_eq!(at(&moved), at(&contact.file) - 3.0);
        let unknown = super::apply_changes(
            &report,
            &contact.file,
            "t",
            &[add(
                "environment.nowhere.position",
                Amount::Vector([0.0; 3]),
            )],
        )
        .unwrap_err()
        .to_string();
        assert!(unknown.contains("meshes: radiator"), "{unknown}");
    }

    #[test]
    fn directions_turn_frames_and_stiffnesses_change_their_section() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../cases");
        let add = |item: &str, amount: Amount| crate::schema::VariantChange {
            item: item.into(),
            change: Change::Add(amount),
        };
        let report = crate::error::Reporter { origin: "test" };
        let cooler = Case::from_path(dir.join("cooler_hose.ron")).unwrap();
        let changed = super::apply_changes(
            &report,
            &cooler.file,
            "t",
            &[
                // A quarter turn about z: (1, 1, -1) → (-1, 1, -1), the normal z stays.
                add(
                    "connectors.oil_cooler.direction",
                    Amount::Vector([0.0, 0.0, 90.0]),
                ),
                // Port hose2 of the T, (0, -1, 0) turned by 90° about the body's x.
                add(
                    "junctions.tee.ports.hose2.direction",
                    Amount::Vector([90.0, 0.0, 0.0]),
                ),
                add(
                    "junctions.tee.ports.hose3.position",
                    Amount::Vector([0.0, 5.0, 0.0]),
                ),
                add("sections.hose_small.youngs_modulus", Amount::Number(1e6)),
            ],
        )
        .unwrap();
        let near = |a: [f64; 3], b: [f64; 3]| (0..3).all(|i| (a[i] - b[i]).abs() < 1e-12);
        let cooler_out = &changed.connectors[1].1;
        assert!(
            near(cooler_out.direction, [-1.0, 1.0, -1.0]),
            "{cooler_out:?}"
        );
        assert!(near(cooler_out.normal, [0.0, 0.0, 1.0]), "{cooler_out:?}");
        let tee = &changed.junctions[0].1;
        assert!(near(tee.ports[1].1.direction, [0.0, 0.0, -1.0]), "{tee:?}");
        assert!(near(tee.ports[1].1.normal, [0.0, -1.0, 0.0]), "{tee:?}");
        assert!(near(tee.ports[2].1.position, [35.0, 5.0, 0.0]), "{tee:?}");
        let crate::schema::SectionDef::Tube { youngs_modulus, .. } = changed.sections[1].1 else {
            panic!("a tube");
        };
        assert_eq!(youngs_modulus, 6e6);
        // The changed case builds, the smaller hose 20 % stiffer in bending.
        let built = cooler
            .build_with_changes(
                "t",
                &[add(
                    "sections.hose_small.youngs_modulus",
                    Amount::Number(1e6),
                )],
                None,
            )
            .unwrap();
        let base = cooler.build(None).unwrap();
        let bending =
            |b: &crate::BuiltCase| b.model.system().rods[1].rod.section().curvature_stiffness();
        assert!((bending(&built)[0] / bending(&base)[0] - 1.2).abs() < 1e-12);
        // A clip base turns with its joint axes; an Explicit section's fields change.
        let harness = Case::from_path(dir.join("harness_clips.ron")).unwrap();
        let turned = super::apply_changes(
            &report,
            &harness.file,
            "t",
            &[add(
                "clips.bracket.base.direction",
                Amount::Vector([0.0, 0.0, 90.0]),
            )],
        )
        .unwrap();
        let base = turned.clips[1].1.base.as_ref().unwrap();
        assert!(near(base.direction, [0.0, 1.0, 0.0]) && near(base.normal, [0.0, 0.0, 1.0]));
        let elastica = Case::from_path(dir.join("elastica_fig2.ron")).unwrap();
        let stiffer = super::apply_changes(
            &report,
            &elastica.file,
            "t",
            &[crate::schema::VariantChange {
                item: "sections.paper.ei".into(),
                change: Change::Set(Amount::Number(2.5)),
            }],
        )
        .unwrap();
        assert!(
            matches!(stiffer.sections[0].1, crate::schema::SectionDef::Explicit { ei, .. } if ei == 2.5)
        );
    }

    #[test]
    fn bad_directions_and_stiffnesses_name_the_item_and_the_fix() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../cases");
        let cooler = Case::from_path(dir.join("cooler_hose.ron")).unwrap();
        let harness = Case::from_path(dir.join("harness_clips.ron")).unwrap();
        let report = crate::error::Reporter { origin: "test" };
        for (case, item, change, needles) in [
            (
                &cooler,
                "connectors.oil_cooler.direction",
                Change::Set(Amount::Vector([1.0, 0.0, 0.0])),
                &["can only be turned", "Add((0, 0, 15))"][..],
            ),
            (
                &cooler,
                "connectors.oil_cooler.direction",
                Change::Add(Amount::Number(5.0)),
                &["takes a rotation vector (x, y, z) in degrees, not a number"][..],
            ),
            (
                &cooler,
                "sections.hose_small.ei",
                Change::Add(Amount::Number(1.0)),
                &[
                    "it is a Tube",
                    "sections.hose_small.youngs_modulus",
                    "Explicit",
                ][..],
            ),
            (
                &cooler,
                "sections.hose_tiny.youngs_modulus",
                Change::Add(Amount::Number(1.0)),
                &[
                    "no section named 'hose_tiny'",
                    "sections: hose_large, hose_small",
                ][..],
            ),
            (
                &cooler,
                "sections.hose_small.youngs_modulus",
                Change::Add(Amount::Vector([1.0, 0.0, 0.0])),
                &["takes a number in Pa, not a vector"][..],
            ),
            (
                &cooler,
                "junctions.tee.ports.hose9.direction",
                Change::Add(Amount::Vector([0.0, 0.0, 1.0])),
                &["no port named 'hose9'", "ports: hose1, hose2, hose3"][..],
            ),
            (
                &cooler,
                "junctions.tee.ports.hose2.normal",
                Change::Add(Amount::Vector([0.0, 0.0, 1.0])),
                &[
                    "'normal' is not a field of port 'hose2'",
                    "`position`, `direction`",
                ][..],
            ),
            (
                &cooler,
                "connectors.oil_cooler.normal",
                Change::Add(Amount::Vector([0.0, 0.0, 1.0])),
                &["only `position`, `direction`"][..],
            ),
            (
                &harness,
                "clips.bracket.base.direction",
                Change::Set(Amount::Vector([0.0, 0.0, 1.0])),
                &["can only be turned"][..],
            ),
        ] {
            let e = super::apply_changes(
                &report,
                &case.file,
                "t",
                &[crate::schema::VariantChange {
                    item: item.into(),
                    change,
                }],
            )
            .unwrap_err()
            .to_string();
            assert!(e.contains(&format!("\"{item}\"")), "{item}: {e}");
            assert!(e.contains("hint: "), "{item}: {e}");
            for needle in needles {
                assert!(e.contains(needle), "{item}: {e} lacks {needle}");
            }
        }
        // A stiffness set to zero is the section's own error, within the variant.
        let e = cooler
            .build_with_changes(
                "soft",
                &[crate::schema::VariantChange {
                    item: "sections.hose_small.youngs_modulus".into(),
                    change: Change::Set(Amount::Number(0.0)),
                }],
                None,
            )
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("variant 'soft'") && e.contains("youngs_modulus"),
            "{e}"
        );
    }

    fn case(text: &str) -> Case {
        Case::from_str(text, ORIGIN).unwrap()
    }

    fn variant_err(text: &str, name: &str) -> String {
        match case(text).build_variant(name, None) {
            Ok(_) => panic!("expected an error for variant {name}"),
            Err(e) => {
                let m = e.to_string();
                assert!(m.starts_with(ORIGIN), "message must name the file: {m}");
                assert!(m.contains("hint: "), "message must carry a hint: {m}");
                assert!(matches!(e, CaseError::Invalid { .. }), "{m}");
                m
            }
        }
    }

    /// `CASE` with the variants replaced by `variants` (RON map body).
    fn with_variants(variants: &str) -> String {
        let start = CASE.find("    variants: {").unwrap();
        format!("{}    variants: {{ {variants} }},\n)", &CASE[..start])
    }

    #[test]
    fn variants_parse_in_file_order_with_numbers_and_vectors() {
        let c = case(CASE);
        assert_eq!(c.variant_names(), ["plus50", "moved", "moon", "longer"]);
        let (_, changes) = &c.file.variants[1];
        assert_eq!(
            changes[0].change,
            Change::Add(Amount::Vector([0.0, 20.0, -10.0]))
        );
        assert_eq!(changes[2].change, Change::Set(Amount::Number(12.0)));
        // No variants at all is the default.
        let plain = with_variants("").replace("    variants: {  },\n", "");
        assert!(case(&plain).variant_names().is_empty());
        // The file round-trips through RON.
        let text = ron::ser::to_string(&c.file).unwrap();
        assert_eq!(Case::from_str(&text, ORIGIN).unwrap().file, c.file);
    }

    #[test]
    fn length_and_gravity_changes_apply_in_si_units() {
        let c = case(CASE);
        let base = c.build(None).unwrap();
        let plus = c.build_variant("plus50", None).unwrap();
        let (b, p) = (&base.model.system().rods[1], &plus.model.system().rods[1]);
        assert!((p.rod.length() - b.rod.length() - 0.05).abs() < 1e-15);
        assert_eq!(p.rod.segments(), 8);
        assert_eq!(base.model.system().rods[0], plus.model.system().rods[0]);
        let longer = c.build_variant("longer", None).unwrap();
        assert!((longer.model.system().rods[0].rod.length() - 1.2005).abs() < 1e-15);
        let moon = c.build_variant("moon", Some(3)).unwrap();
        assert_eq!(moon.model.system().gravity, Vector3::new(0.0, 0.0, -1.62));
        assert!(
            moon.model
                .system()
                .rods
                .iter()
                .all(|r| r.rod.segments() == 3)
        );
    }

    #[test]
    fn end_changes_move_supports_routes_and_loads() {
        let built = case(CASE).build_variant("moved", None).unwrap();
        let rods = &built.model.system().rods;
        let hose2 = &rods[1];
        let end = hose2.end.support.position().unwrap();
        assert!((end - Vector3::new(0.38, 0.02, -0.01)).norm() < 1e-15);
        let start = hose2.start.support.position().unwrap();
        assert!((start - Vector3::new(0.001, 0.002, 0.003)).norm() < 1e-15);
        assert_eq!(hose2.rod.segments(), 12);
        let route = hose2.route.as_ref().unwrap();
        assert!((route[0] - start).norm() < 1e-15);
        assert!((route[2] - end).norm() < 1e-15);
        assert!((route[1] - Vector3::new(0.19, 0.0, -0.1)).norm() < 1e-15);
        assert_eq!(rods[0].end.load.force, Vector3::new(3.0, 1.0, 0.0));
    }

    #[test]
    fn unknown_variant_lists_the_defined_ones() {
        let m = variant_err(CASE, "plus60");
        assert!(
            m.contains("no variant named 'plus60' (defined: plus50, moved, moon, longer)"),
            "{m}"
        );
        let none = with_variants("");
        let m = variant_err(&none, "plus50");
        assert!(m.contains("defines no variants"), "{m}");
        let m = variant_err(CASE, "base");
        assert!(
            m.contains("'base' means the case itself only in `strand study`"),
            "{m}"
        );
        let m = variant_err(&with_variants("\"base\": []"), "base");
        assert!(m.contains("reserved"), "{m}");
    }

    #[test]
    fn unknown_items_name_the_variant_and_list_valid_items() {
        for (item, needle) in [
            (
                "rods.hose.2.colour",
                "'colour' is not a field of rod 'hose.2'",
            ),
            ("rods.hose3.length", "there is no rod named 'hose3'"),
            ("rods.hose3.end.position", "there is no rod named 'hose3'"),
            (
                "gravityy",
                "unknown item: an item is `gravity` or starts with `rods.<rod name>.`",
            ),
            ("rods.hose1", "there is no rod named 'hose1'"),
        ] {
            let text = with_variants(&format!(
                "\"bad\": [(item: \"gravity\", change: Add((0, 0, 0))), (item: \"{item}\", change: Add(1))]"
            ));
            let m = variant_err(&text, "bad");
            assert!(
                m.contains(&format!("variants 'bad'[1] \"{item}\": ")),
                "{item}: {m}"
            );
            assert!(m.contains(needle), "{item}: {m}");
            assert!(
                m.contains("hint: valid items: rods.<rod>.length")
                    && m.contains("rods: hose1, hose.2"),
                "{item}: {m}"
            );
        }
    }

    #[test]
    fn changes_must_fit_their_item() {
        for (change, needle) in [
            (
                "(item: \"rods.hose1.length\", change: Add((1, 2, 3)))",
                "takes a number (in mm), not a vector",
            ),
            (
                "(item: \"gravity\", change: Set(9.81))",
                "takes a vector (x, y, z) in m/s², not a number",
            ),
            (
                "(item: \"rods.hose1.segments\", change: Add(2))",
                "can only be Set",
            ),
            (
                "(item: \"rods.hose1.segments\", change: Set(2.5))",
                "whole number",
            ),
            (
                "(item: \"rods.hose1.segments\", change: Set(0))",
                "whole number",
            ),
            (
                "(item: \"rods.hose1.end.position\", change: Add((1, 0, 0)))",
                "is Free(): it has no position",
            ),
        ] {
            let m = variant_err(&with_variants(&format!("\"bad\": [{change}]")), "bad");
            assert!(m.contains("variants 'bad'[0]"), "{change}: {m}");
            assert!(m.contains(needle), "{change}: {m}");
        }
    }

    #[test]
    fn invalid_results_of_a_variant_name_it() {
        let m = variant_err(
            &with_variants("\"short\": [(item: \"rods.hose1.length\", change: Add(-1000))]"),
            "short",
        );
        assert!(
            m.contains("variant 'short': rods[0] 'hose1'.length: must be a finite number > 0"),
            "{m}"
        );
        let m = variant_err(
            &with_variants(
                "\"far\": [(item: \"rods.hose.2.end.position\", change: Set((900, 0, 0)))]",
            ),
            "far",
        );
        assert!(m.contains("variant 'far': ") && m.contains("apart"), "{m}");
    }

    #[test]
    fn malformed_variants_are_syntax_errors() {
        for (variants, needle) in [
            (
                "\"a\": [(item: \"gravity\", change: Add((0, 0)))]",
                "3 components",
            ),
            ("\"a\": [(item: \"gravity\", change: Scale(2))]", "Scale"),
            (
                "\"a\": [(item: \"gravity\", change: Add(\"x\"))]",
                "a number (e.g. 50) or a vector",
            ),
            ("\"a\": [], \"a\": []", "variant 'a' is defined twice"),
            ("\"a\": [(item: \"gravity\")]", "change"),
        ] {
            match Case::from_str(&with_variants(variants), ORIGIN) {
                Err(CaseError::Syntax { message, .. }) => {
                    assert!(message.contains(needle), "{variants}: {message}")
                }
                other => panic!("{variants}: expected a syntax error, got {other:?}"),
            }
        }
        let m = variant_err(&with_variants("\"a/b\": []"), "a/b");
        assert!(m.contains("invalid variant name"), "{m}");
    }
}

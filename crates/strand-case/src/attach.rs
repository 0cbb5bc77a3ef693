//! Connectors and junctions of a case file, and the rod ends that refer to them.
//!
//! A **connector** is a fixed nozzle in space: `position`, the nozzle axis `direction`
//! (pointing out of the connector into the hose) and `normal` (the section's `a1`). A
//! rod that *starts* at a connector leaves it along `direction`; a rod that *ends* at
//! one arrives against it, so its frame there has `a3 = −direction` (the connector's
//! frame turned by π about `a1`, as at a body port).
//!
//! A **junction** is a rigid body ([`BodySpec`]) with named ports; a port's
//! `direction` likewise points out of the body into the hose.
//!
//! Rod ends `Connector("c")`, `ConnectorPin("c")`, `Port("j", "p")` and
//! `PortPin("j", "p")` become [`Support::Clamped`], [`Support::Pinned`] and
//! [`Support::Port`]. Unknown names are errors listing the defined ones; a junction
//! without rods, a port or connector holding two rod ends, and hoses that cannot reach
//! from their connectors to a free junction are errors naming the item.

use nalgebra::{UnitQuaternion, Vector3};
use strand_system::{BodyHandle, BodySpec, End, EndLoad, Port, Pose, Support, System};

use crate::ends::frame_from_tangent_normal;
use crate::error::{CaseError, Reporter};
use crate::schema::{CaseFile, EndDef};
use crate::units::LengthUnit;

/// A connector in SI units.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Connector {
    /// Name in the case file (also the name of its reaction).
    pub name: String,
    /// Position, m.
    pub position: Vector3<f64>,
    /// Frame with `a3` along the nozzle axis (out of the connector) and `a1` along the
    /// normal.
    pub frame: UnitQuaternion<f64>,
}

/// The connectors and junctions (as bodies, in file order) of a case.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Attachments {
    /// Connectors in file order.
    pub connectors: Vec<Connector>,
    /// Junctions in file order.
    pub bodies: Vec<BodySpec>,
}

/// Whether `name` can name a connector, junction or port: it appears in reaction names
/// (`tee.hose1`) and variant items (`junctions.tee.mass`), so no `.`.
fn is_valid_name(name: &str) -> bool {
    !name.is_empty()
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-'))
}

fn check_name(report: &Reporter, item: &str, name: &str) -> Result<(), CaseError> {
    if is_valid_name(name) {
        Ok(())
    } else {
        Err(report.invalid(
            item,
            format!("invalid name '{name}'"),
            "use letters, digits, '_' and '-' only (no '.': it separates junction and port in reaction names)",
        ))
    }
}

fn list<'a>(names: impl Iterator<Item = &'a str>) -> String {
    let names: Vec<&str> = names.collect();
    if names.is_empty() {
        "none".to_string()
    } else {
        names.join(", ")
    }
}

/// A frame from a direction and a normal, with an error naming `item`.
fn frame(
    report: &Reporter,
    item: &str,
    direction: &[f64; 3],
    normal: &[f64; 3],
) -> Result<UnitQuaternion<f64>, CaseError> {
    let d = report.finite3(&format!("{item}.direction"), direction, "")?;
    let n = report.finite3(&format!("{item}.normal"), normal, "")?;
    frame_from_tangent_normal(&d, &n).map_err(|e| {
        report.invalid(
            item,
            e.to_string().replace("tangent", "direction"),
            "direction is the nozzle axis, pointing out of the part into the hose; normal is any \
             direction across it (e.g. direction (1, 0, 0), normal (0, 0, 1))",
        )
    })
}

/// The rotation by π about `a1`: turns a connector's or port's frame (`a3` out of the
/// part) into the frame of a rod *ending* there (`a3` into the part).
fn arriving() -> UnitQuaternion<f64> {
    UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI)
}

/// Converts and checks the file's connectors and junctions.
pub(crate) fn build_attachments(
    report: &Reporter,
    unit: LengthUnit,
    file: &CaseFile,
) -> Result<Attachments, CaseError> {
    let u = format!(" {unit}");
    let mut connectors = Vec::with_capacity(file.connectors.len());
    for (name, def) in &file.connectors {
        let item = format!("connectors '{name}'");
        check_name(report, &item, name)?;
        let position =
            report.finite3(&format!("{item}.position"), &def.position, &u)? * unit.metres();
        let frame = frame(report, &item, &def.direction, &def.normal)?;
        connectors.push(Connector {
            name: name.clone(),
            position,
            frame,
        });
    }
    let mut bodies = Vec::with_capacity(file.junctions.len());
    for (name, def) in &file.junctions {
        let item = format!("junctions '{name}'");
        check_name(report, &item, name)?;
        let mass = report.non_negative(&format!("{item}.mass"), def.mass, " kg")?;
        let center_of_mass =
            report.finite3(&format!("{item}.center_of_mass"), &def.center_of_mass, &u)?
                * unit.metres();
        let position =
            report.finite3(&format!("{item}.position"), &def.position, &u)? * unit.metres();
        let orientation = match &def.orientation {
            None => UnitQuaternion::identity(),
            Some(o) => frame(
                report,
                &format!("{item}.orientation"),
                &o.direction,
                &o.normal,
            )?,
        };
        let carries_clip = file
            .clips
            .iter()
            .any(|(_, c)| c.on.as_deref() == Some(name));
        if def.ports.is_empty() && !carries_clip {
            return Err(report.invalid(
                &item,
                "the junction has no ports and no clip is mounted on it",
                "add ports: { \"name\": (position: ..., direction: ..., normal: ...) }, \
                 or mount a clip on it with `on`",
            ));
        }
        let mut ports = Vec::with_capacity(def.ports.len());
        for (port_name, port) in &def.ports {
            let port_item = format!("{item}.ports '{port_name}'");
            check_name(report, &port_item, port_name)?;
            let position = report.finite3(&format!("{port_item}.position"), &port.position, &u)?
                * unit.metres();
            let frame = frame(report, &port_item, &port.direction, &port.normal)?;
            ports.push(Port {
                name: port_name.clone(),
                position,
                frame,
            });
        }
        bodies.push(BodySpec {
            name: name.clone(),
            mass,
            center_of_mass,
            pose: Pose {
                position,
                orientation,
            },
            fixed: def.fixed,
            ports,
        });
    }
    Ok(Attachments { connectors, bodies })
}

impl Attachments {
    /// The end `def` of a rod if it refers to a connector or a junction port, `None`
    /// for the other forms (built by [`crate::ends::build_end`]). `item` is e.g.
    /// `rods[0] 'hose'.start`.
    pub(crate) fn end(
        &self,
        report: &Reporter,
        item: &str,
        def: &EndDef,
        at_end: bool,
    ) -> Result<Option<End>, CaseError> {
        let support = match def {
            EndDef::Connector(name) | EndDef::ConnectorPin(name) => {
                let connector = self.connector(report, item, name)?;
                if matches!(def, EndDef::ConnectorPin(_)) {
                    Support::Pinned {
                        position: connector.position,
                    }
                } else {
                    let frame = if at_end {
                        connector.frame * arriving()
                    } else {
                        connector.frame
                    };
                    Support::Clamped {
                        position: connector.position,
                        frame,
                    }
                }
            }
            EndDef::Port(junction, port) | EndDef::PortPin(junction, port) => {
                let (body, port) = self.port(report, item, junction, port)?;
                Support::Port {
                    body: BodyHandle(body),
                    port,
                    clamped: matches!(def, EndDef::Port(..)),
                }
            }
            _ => return Ok(None),
        };
        Ok(Some(End {
            support,
            load: EndLoad::default(),
            twist_turns: 0,
        }))
    }

    fn connector(
        &self,
        report: &Reporter,
        item: &str,
        name: &str,
    ) -> Result<&Connector, CaseError> {
        self.connectors
            .iter()
            .find(|c| c.name == name)
            .ok_or_else(|| {
                report.invalid(
                    item,
                    format!(
                        "connector '{name}' is not defined (defined: {})",
                        list(self.connectors.iter().map(|c| c.name.as_str()))
                    ),
                    "add it under `connectors: { \"name\": (position: ..., direction: ..., normal: ...) }` \
                     or correct the name",
                )
            })
    }

    fn port(
        &self,
        report: &Reporter,
        item: &str,
        junction: &str,
        port: &str,
    ) -> Result<(usize, usize), CaseError> {
        let Some(body) = self.bodies.iter().position(|b| b.name == junction) else {
            return Err(report.invalid(
                item,
                format!(
                    "junction '{junction}' is not defined (defined: {})",
                    list(self.bodies.iter().map(|b| b.name.as_str()))
                ),
                "add it under `junctions` or correct the name",
            ));
        };
        let ports = &self.bodies[body].ports;
        match ports.iter().position(|p| p.name == port) {
            Some(p) => Ok((body, p)),
            None => Err(report.invalid(
                item,
                format!(
                    "junction '{junction}' has no port '{port}' (its ports: {})",
                    list(ports.iter().map(|p| p.name.as_str()))
                ),
                format!("add the port under `junctions.{junction}.ports` or correct the name"),
            )),
        }
    }

    /// Where a held end is in the initial configuration (a port at its junction's
    /// initial pose), m; `None` for a free end.
    pub(crate) fn initial_position(&self, end: &End) -> Option<Vector3<f64>> {
        match end.support {
            Support::Port { body, port, .. } => {
                let body = &self.bodies[body.0];
                Some(body.pose.transform_point(&body.ports[port].position))
            }
            support => support.position(),
        }
    }

    /// Every junction holds at least one rod end, and every connector and port at most
    /// one (names are already resolved).
    pub(crate) fn check_usage(&self, report: &Reporter, file: &CaseFile) -> Result<(), CaseError> {
        let mut users: Vec<(String, String)> = Vec::new();
        for (i, rod) in file.rods.iter().enumerate() {
            for (label, def) in [("start", &rod.start), ("end", &rod.end)] {
                let (key, what) = match def {
                    EndDef::Connector(c) | EndDef::ConnectorPin(c) => {
                        (format!("connector {c}"), format!("connector '{c}'"))
                    }
                    EndDef::Port(j, p) | EndDef::PortPin(j, p) => (
                        format!("port {j}.{p}"),
                        format!("port '{p}' of junction '{j}'"),
                    ),
                    _ => continue,
                };
                let here = format!("rods[{i}] '{}'.{label}", rod.name);
                if let Some((_, first)) = users.iter().find(|(k, _)| *k == key) {
                    return Err(report.invalid(
                        &here,
                        format!("{what} already holds {first}: it can hold one rod end"),
                        "give each rod end its own connector or port",
                    ));
                }
                users.push((key, here));
            }
        }
        for body in &self.bodies {
            let prefix = format!("port {}.", body.name);
            let carries_clip = file
                .clips
                .iter()
                .any(|(_, c)| c.on.as_deref() == Some(body.name.as_str()));
            if !carries_clip && !users.iter().any(|(k, _)| k.starts_with(&prefix)) {
                return Err(report.invalid(
                    format!("junctions '{}'", body.name),
                    "no rod end is attached to this junction and no clip is mounted on it",
                    format!(
                        "attach a rod end with Port(\"{}\", \"<port>\") or remove the junction",
                        body.name
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// Largest axial strain a hose may need to reach (as in [`System::validate`]).
const REACH: f64 = 1.1;

/// Two hoses that hang a free junction between supports fixed in space must reach
/// across: the distance between their fixed ends may not exceed 110 % of their
/// lengths plus the distance between their ports.
pub(crate) fn check_reach(
    report: &Reporter,
    unit: LengthUnit,
    system: &System,
) -> Result<(), CaseError> {
    let poses = system.body_poses();
    for (b, body) in system.bodies.iter().enumerate() {
        if body.fixed {
            continue;
        }
        // (rod, fixed far end, port position in the body frame, rod length)
        let mut legs = Vec::new();
        for spec in &system.rods {
            for (end, other, other_at_end) in [
                (&spec.start, &spec.end, true),
                (&spec.end, &spec.start, false),
            ] {
                let Support::Port {
                    body: held, port, ..
                } = end.support
                else {
                    continue;
                };
                if held.0 != b {
                    continue;
                }
                let fixed_far = match other.support {
                    Support::Port { body, .. } if !system.bodies[body.0].fixed => None,
                    _ => system.end_placement(other, other_at_end, &poses).0,
                };
                if let Some(far) = fixed_far {
                    legs.push((
                        &spec.name,
                        far,
                        body.ports[port].position,
                        spec.rod.length(),
                    ));
                }
            }
        }
        for (i, a) in legs.iter().enumerate() {
            for c in &legs[i + 1..] {
                let distance = (a.1 - c.1).norm();
                let reach = REACH * (a.3 + c.3) + (a.2 - c.2).norm();
                if distance > reach {
                    let mm = |x: f64| format!("{:.1} {unit}", x / unit.metres());
                    return Err(report.invalid(
                        format!("rods '{}' and '{}'", a.0, c.0),
                        format!(
                            "these hoses ({} and {} long) hang junction '{}' between supports {} apart, \
                             farther than they can reach ({} with the junction)",
                            mm(a.3),
                            mm(c.3),
                            body.name,
                            mm(distance),
                            mm(reach)
                        ),
                        "lengthen the hoses or move their connectors closer together",
                    ));
                }
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use nalgebra::Vector3;
    use strand_system::{BodyHandle, Support};

    use crate::schema::{Amount, Change};
    use crate::{Case, CaseError};

    const ORIGIN: &str = "cases/tee.ron";

    /// Two hoses from connectors to a free-hanging T, a third pinned at a port.
    const TEE: &str = r#"(
    units: (length: "mm"),
    sections: {
        "rubber": Tube(youngs_modulus: 5e6, poisson_ratio: 0.5, density: 1100,
                       inner_radius: 9.4, outer_radius: 12.9),
    },
    connectors: {
        "left": (position: (-300, 0, 0), direction: (1, 0, 0), normal: (0, 0, 1)),
        "right": (position: (300, 0, 20), direction: (-1, 0, 0), normal: (0, 0, 1)),
        "top": (position: (0, 250, 60), direction: (0, -1, 0), normal: (0, 0, 1)),
    },
    junctions: {
        "tee": (
            mass: 1.0,
            center_of_mass: (0, 0, -10),
            position: (0, 0, -50),
            ports: {
                "west": (position: (-30, 0, 0), direction: (-1, 0, 0), normal: (0, 0, 1)),
                "east": (position: (30, 0, 0), direction: (1, 0, 0), normal: (0, 0, 1)),
                "north": (position: (0, 30, 0), direction: (0, 1, 0), normal: (0, 0, 1)),
            },
        ),
    },
    rods: [
        (name: "west", section: "rubber", length: 400, segments: 20,
         start: Connector("left"), end: Port("tee", "west")),
        (name: "east", section: "rubber", length: 380, segments: 20,
         start: Port("tee", "east"), end: Connector("right")),
        (name: "north", section: "rubber", length: 300, segments: 15,
         start: PortPin("tee", "north"), end: ConnectorPin("top")),
    ],
    gravity: (0, 0, -9.81),
    variants: {
        "heavy": [(item: "junctions.tee.mass", change: Add(0.5))],
        "moved": [(item: "connectors.right.position", change: Set((310, 0, 0)))],
    },
)"#;

    fn with(from: &str, to: &str) -> String {
        assert!(TEE.contains(from), "test bug: {from:?} not in TEE");
        TEE.replacen(from, to, 1)
    }

    /// The message of the error that building `text` gives; it must name the file.
    fn message(text: &str) -> String {
        let error = match Case::from_str(text, ORIGIN).and_then(|c| c.build(None)) {
            Ok(_) => panic!("expected an error for:\n{text}"),
            Err(e) => e,
        };
        let m = error.to_string();
        assert!(m.starts_with(ORIGIN), "message must name the file: {m}");
        m
    }

    #[test]
    fn connectors_and_ports_become_supports() {
        let case = Case::from_str(TEE, ORIGIN).unwrap();
        let built = case.build(None).unwrap();
        let system = built.model.system();
        assert_eq!(system.bodies.len(), 1);
        let tee = &system.bodies[0];
        assert_eq!(
            (tee.name.as_str(), tee.mass, tee.fixed),
            ("tee", 1.0, false)
        );
        assert!((tee.center_of_mass - Vector3::new(0.0, 0.0, -0.01)).norm() < 1e-15);
        assert!((tee.pose.position - Vector3::new(0.0, 0.0, -0.05)).norm() < 1e-15);
        let names: Vec<&str> = tee.ports.iter().map(|p| p.name.as_str()).collect();
        assert_eq!(names, ["west", "east", "north"]);
        assert!((tee.ports[2].frame * Vector3::z() - Vector3::y()).norm() < 1e-15);
        let [west, east, north] = &system.rods[..] else {
            panic!("three rods")
        };
        // A rod leaving a connector runs along its direction ...
        let Support::Clamped { position, frame } = west.start.support else {
            panic!("{:?}", west.start.support)
        };
        assert!((position - Vector3::new(-0.3, 0.0, 0.0)).norm() < 1e-15);
        assert!((frame * Vector3::z() - Vector3::x()).norm() < 1e-15);
        assert!((frame * Vector3::x() - Vector3::z()).norm() < 1e-15);
        // ... and a rod arriving at one runs against it, with the same a1.
        let Support::Clamped { frame, .. } = east.end.support else {
            panic!("{:?}", east.end.support)
        };
        assert!((frame * Vector3::z() - Vector3::x()).norm() < 1e-15);
        assert!((frame * Vector3::x() - Vector3::z()).norm() < 1e-15);
        assert_eq!(
            west.end.support,
            Support::Port {
                body: BodyHandle(0),
                port: 0,
                clamped: true
            }
        );
        assert_eq!(
            north.start.support,
            Support::Port {
                body: BodyHandle(0),
                port: 2,
                clamped: false
            }
        );
        assert_eq!(
            north.end.support,
            Support::Pinned {
                position: Vector3::new(0.0, 0.25, 0.06)
            }
        );
        let named = |s: &str| Some(s.to_string());
        assert_eq!(
            built.connector_names,
            vec![
                [named("left"), None],
                [None, named("right")],
                [None, named("top")]
            ]
        );
        assert_eq!(built.initial.bodies[0], tee.pose);
        // The new parts round-trip through RON.
        let text = ron::ser::to_string(&case.file).unwrap();
        assert_eq!(Case::from_str(&text, ORIGIN).unwrap().file, case.file);
    }

    #[test]
    fn unknown_names_list_the_defined_ones() {
        let m = message(&with("Connector(\"left\")", "Connector(\"lft\")"));
        assert!(
            m.contains(
                "rods[0] 'west'.start: connector 'lft' is not defined (defined: left, right, top)"
            ),
            "{m}"
        );
        let m = message(&with("ConnectorPin(\"top\")", "ConnectorPin(\"up\")"));
        assert!(
            m.contains("rods[2] 'north'.end: connector 'up' is not defined"),
            "{m}"
        );
        let m = message(&with("Port(\"tee\", \"west\")", "Port(\"y\", \"west\")"));
        assert!(
            m.contains("rods[0] 'west'.end: junction 'y' is not defined (defined: tee)"),
            "{m}"
        );
        let m = message(&with(
            "PortPin(\"tee\", \"north\")",
            "PortPin(\"tee\", \"south\")",
        ));
        assert!(
            m.contains(
                "rods[2] 'north'.start: junction 'tee' has no port 'south' (its ports: west, east, north)"
            ),
            "{m}"
        );
        assert!(
            m.contains("hint: add the port under `junctions.tee.ports`"),
            "{m}"
        );
    }

    #[test]
    fn a_junction_needs_a_rod_and_a_port_or_connector_holds_one() {
        let text = with(
            "    },\n    rods: [",
            "        \"spare\": (mass: 0.2, position: (0, 0, 0), ports: {\"a\": (position: (0, 0, 0), direction: (1, 0, 0), normal: (0, 0, 1))}),\n    },\n    rods: [",
        );
        let m = message(&text);
        assert!(
            m.contains("junctions 'spare': no rod end is attached to this junction"),
            "{m}"
        );
        let m = message(&with(
            "end: Connector(\"right\")",
            "end: Connector(\"left\")",
        ));
        assert!(
            m.contains("rods[1] 'east'.end: connector 'left' already holds rods[0] 'west'.start"),
            "{m}"
        );
        let m = message(&with("Port(\"tee\", \"east\")", "Port(\"tee\", \"west\")"));
        assert!(
            m.contains("rods[1] 'east'.start: port 'west' of junction 'tee' already holds rods[0] 'west'.end"),
            "{m}"
        );
    }

    #[test]
    fn bad_directions_masses_and_names_are_rejected() {
        for (from, to, needle) in [
            (
                "direction: (1, 0, 0), normal: (0, 0, 1)),\n        \"right\"",
                "direction: (0, 0, 0), normal: (0, 0, 1)),\n        \"right\"",
                "connectors 'left': the direction must be a non-zero direction",
            ),
            (
                "(position: (300, 0, 20), direction: (-1, 0, 0), normal: (0, 0, 1))",
                "(position: (300, 0, 20), direction: (-1, 0, 0), normal: (2, 0, 0))",
                "connectors 'right': the normal must not be zero or parallel to the direction",
            ),
            (
                "\"north\": (position: (0, 30, 0), direction: (0, 1, 0), normal: (0, 0, 1))",
                "\"north\": (position: (0, 30, 0), direction: (0, 1, 0), normal: (0, -3, 0))",
                "junctions 'tee'.ports 'north': the normal must not be zero or parallel",
            ),
            (
                "mass: 1.0",
                "mass: -1",
                "junctions 'tee'.mass: must be a finite number ≥ 0",
            ),
            (
                "position: (0, 0, -50),",
                "position: (0, 0, -50), orientation: (direction: (0, 0, 1), normal: (0, 0, -1)),",
                "junctions 'tee'.orientation: the normal must not be zero or parallel",
            ),
            (
                "\"left\": (",
                "\"le.ft\": (",
                "connectors 'le.ft': invalid name 'le.ft'",
            ),
        ] {
            let m = message(&with(from, to));
            assert!(m.contains(needle), "{to}: {m}");
            assert!(m.contains("hint: "), "{m}");
        }
    }

    #[test]
    fn hoses_too_short_for_their_attachments_are_rejected() {
        // Between a connector and a mounted junction: the system's own check.
        let fixed = with("mass: 1.0,", "mass: 1.0, fixed: true,")
            .replace("(position: (-300, 0, 0)", "(position: (-900, 0, 0)");
        match Case::from_str(&fixed, ORIGIN).and_then(|c| c.build(None)) {
            Err(e @ CaseError::System { .. }) => {
                let m = e.to_string();
                assert!(m.starts_with(ORIGIN), "{m}");
                assert!(
                    m.contains("rod 'west' is 0.400000 m long but its ends are held"),
                    "{m}"
                );
            }
            other => panic!("expected a system error, got {other:?}"),
        }
        // Two hoses hanging a free junction between connectors 1.6 m apart.
        let m = message(&with("(position: (-300, 0, 0)", "(position: (-1300, 0, 0)"));
        assert!(
            m.contains("rods 'west' and 'east': these hoses (400.0 mm and 380.0 mm long) hang junction 'tee' between supports 1600.1 mm apart, farther than they can reach (918.0 mm"),
            "{m}"
        );
        assert!(m.contains("hint: lengthen the hoses"), "{m}");
    }

    #[test]
    fn variants_change_junction_masses_and_connector_positions() {
        let case = Case::from_str(TEE, ORIGIN).unwrap();
        let heavy = case.build_variant("heavy", None).unwrap();
        assert_eq!(heavy.model.system().bodies[0].mass, 1.5);
        let moved = case.build_variant("moved", None).unwrap();
        let Support::Clamped { position, .. } = moved.model.system().rods[1].end.support else {
            panic!("clamped")
        };
        assert!((position - Vector3::new(0.31, 0.0, 0.0)).norm() < 1e-15);
        assert_eq!(
            case.file.variants[1].1[0].change,
            Change::Set(Amount::Vector([310.0, 0.0, 0.0]))
        );
        for (item, change, needle) in [
            (
                "junctions.tea.mass",
                "Add(1)",
                "there is no junction named 'tea'",
            ),
            (
                "junctions.tee.position",
                "Add((1, 0, 0))",
                "'position' is not a field of junction 'tee'",
            ),
            ("connectors.right.position", "Add(1)", "takes a vector"),
            (
                "connectors.back.position",
                "Add((1, 0, 0))",
                "there is no connector named 'back'",
            ),
            (
                "rods.west.start.position",
                "Add((1, 0, 0))",
                "held by connector 'left'",
            ),
            (
                "rods.west.end.force",
                "Add((1, 0, 0))",
                "takes no dead loads",
            ),
        ] {
            let text = with(
                "\"heavy\": [(item: \"junctions.tee.mass\", change: Add(0.5))]",
                &format!("\"bad\": [(item: \"{item}\", change: {change})]"),
            );
            let case = Case::from_str(&text, ORIGIN).unwrap();
            let m = case.build_variant("bad", None).unwrap_err().to_string();
            assert!(m.contains(&format!("variants 'bad'[0] \"{item}\"")), "{m}");
            assert!(m.contains(needle), "{item}: {m}");
        }
        // A heavier junction that breaks nothing; a negative mass names the variant.
        let text = with("Add(0.5)", "Add(-2)");
        let m = Case::from_str(&text, ORIGIN)
            .unwrap()
            .build_variant("heavy", None)
            .unwrap_err()
            .to_string();
        assert!(
            m.contains("variant 'heavy': junctions 'tee'.mass: must be a finite number ≥ 0"),
            "{m}"
        );
    }
}

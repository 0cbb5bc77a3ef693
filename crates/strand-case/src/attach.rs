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
        let center_of_mass = report
            .finite3(&format!("{item}.center_of_mass"), &def.center_of_mass, &u)?
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
        if def.ports.is_empty() {
            return Err(report.invalid(
                &item,
                "the junction has no ports",
                "add ports: { \"name\": (position: ..., direction: ..., normal: ...) }",
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
            if !users.iter().any(|(k, _)| k.starts_with(&prefix)) {
                return Err(report.invalid(
                    format!("junctions '{}'", body.name),
                    "no rod end is attached to this junction",
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
pub(crate) fn check_reach(report: &Reporter, unit: LengthUnit, system: &System) -> Result<(), CaseError> {
    let poses = system.body_poses();
    for (b, body) in system.bodies.iter().enumerate() {
        if body.fixed {
            continue;
        }
        // (rod, fixed far end, port position in the body frame, rod length)
        let mut legs = Vec::new();
        for spec in &system.rods {
            for (end, other, other_at_end) in
                [(&spec.start, &spec.end, true), (&spec.end, &spec.start, false)]
            {
                let Support::Port { body: held, port, .. } = end.support else {
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
                    legs.push((&spec.name, far, body.ports[port].position, spec.rod.length()));
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

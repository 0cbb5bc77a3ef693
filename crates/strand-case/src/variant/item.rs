//! The variant-item grammar: what a change of a variant (or a batch's `--vary`, or a
//! sensitivity's `--param`) addresses, resolved against a case file into a typed
//! [`VariantItem`].
//!
//! Full form: `gravity`, `rods.<rod>.length`, `rods.<rod>.segments`,
//! `rods.<rod>.{start,end}.{position,force}`, `junctions.<junction>.mass`,
//! `junctions.<junction>.ports.<port>.{position,direction}`,
//! `connectors.<connector>.{position,direction}`, `clips.<clip>.at`,
//! `clips.<clip>.base.{position,direction}`, `environment.<mesh>.position`,
//! `sections.<section>.{ea,ga,ei,gj,youngs_modulus}` (see [`VARIANT_ITEMS`]). A
//! `direction` item turns a frame by a rotation vector in degrees (Add only). Short
//! form ([`expand_short`]): the same without the `rods.`, `junctions.`, `connectors.`,
//! `clips.`, `environment.` or `sections.` prefix (`hose2.length`, `tee.mass`,
//! `oil_cooler.direction`, `hose_small.youngs_modulus`).
//!
//! ```
//! use strand_case::{Case, ItemQuantity, RodEnd, VariantItem};
//! let case = Case::from_path(concat!(env!("CARGO_MANIFEST_DIR"), "/../../cases/cooler_hose.ron"))?;
//! let item = VariantItem::parse(&case.file, "rods.hose2.length").unwrap();
//! assert_eq!(item, VariantItem::RodLength(1));
//! assert_eq!(item.quantity(), ItemQuantity::Length);
//! // The case's own value, in m: hose 2 is 190 mm long.
//! assert!((item.case_value(&case.file).unwrap() - 0.19).abs() < 1e-12);
//! let end = VariantItem::parse(&case.file, "rods.hose1.end.force").unwrap();
//! assert_eq!(end, VariantItem::EndForce { rod: 0, end: RodEnd::End });
//! assert!(end.is_vector());
//! assert_eq!(strand_case::expand_short(&case.file, "tee.mass").unwrap(), "junctions.tee.mass");
//! # Ok::<(), strand_case::CaseError>(())
//! ```

use crate::schema::CaseFile;
use crate::units::LengthUnit;

use super::VARIANT_ITEMS;

/// One end of a rod.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum RodEnd {
    /// The rod's start (arc length 0).
    Start,
    /// The rod's end.
    End,
}

impl RodEnd {
    /// `start` or `end`, as written in items.
    pub fn label(self) -> &'static str {
        match self {
            RodEnd::Start => "start",
            RodEnd::End => "end",
        }
    }
}

/// What kind of number an item takes (the unit its changes are written in).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ItemQuantity {
    /// A length or position, in the case's length unit.
    Length,
    /// A mass, kg.
    Mass,
    /// A force, N.
    Force,
    /// An acceleration (gravity), m/s².
    Acceleration,
    /// A whole number (segments).
    Count,
    /// A turn of a frame, degrees (a rotation vector: about the world axes for a
    /// connector, about the junction's body axes for a port, about the parent frame's
    /// axes for a clip base).
    Angle,
    /// A bending or torsional stiffness (`ei`, `gj`), N·m².
    BendingStiffness,
    /// Young's modulus of a tube section, Pa.
    Modulus,
}

/// A stiffness of a section that a variant can change, as the case file names it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SectionStiffness {
    /// `ea` of an `Explicit` section: axial stiffness, N.
    Ea,
    /// `ga` of an `Explicit` section: shear stiffness, N.
    Ga,
    /// `ei` of an `Explicit` section: bending stiffness, N·m².
    Ei,
    /// `gj` of an `Explicit` section: torsional stiffness, N·m².
    Gj,
    /// `youngs_modulus` of a `Tube` section, Pa (scales all four stiffnesses).
    YoungsModulus,
}

impl SectionStiffness {
    /// Every stiffness, in the order of [`SectionStiffness::field`] names.
    pub const ALL: [SectionStiffness; 5] = [
        SectionStiffness::Ea,
        SectionStiffness::Ga,
        SectionStiffness::Ei,
        SectionStiffness::Gj,
        SectionStiffness::YoungsModulus,
    ];

    /// The field's name in the case file (`ei`, `youngs_modulus`).
    pub fn field(self) -> &'static str {
        match self {
            SectionStiffness::Ea => "ea",
            SectionStiffness::Ga => "ga",
            SectionStiffness::Ei => "ei",
            SectionStiffness::Gj => "gj",
            SectionStiffness::YoungsModulus => "youngs_modulus",
        }
    }

    /// Whether the field belongs to a `Tube` section (else to an `Explicit` one).
    pub fn of_tube(self) -> bool {
        self == SectionStiffness::YoungsModulus
    }

    /// The field's unit: `N`, `N·m²` or `Pa`.
    pub fn unit(self) -> &'static str {
        match self.quantity() {
            ItemQuantity::Force => "N",
            ItemQuantity::BendingStiffness => "N·m²",
            _ => "Pa",
        }
    }

    /// The kind of number the field is.
    pub fn quantity(self) -> ItemQuantity {
        match self {
            SectionStiffness::Ea | SectionStiffness::Ga => ItemQuantity::Force,
            SectionStiffness::Ei | SectionStiffness::Gj => ItemQuantity::BendingStiffness,
            SectionStiffness::YoungsModulus => ItemQuantity::Modulus,
        }
    }
}

/// A variant item resolved against a case file: the thing a change addresses, by its
/// index in the file's lists (rods, junctions, connectors, clips, environment meshes
/// in file order).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum VariantItem {
    /// `gravity` (a vector, m/s²).
    Gravity,
    /// `rods.<rod>.length` (a number, case length unit).
    RodLength(usize),
    /// `rods.<rod>.segments` (a whole number, Set only).
    RodSegments(usize),
    /// `rods.<rod>.<end>.position` (a vector, case length unit; held ends only).
    EndPosition {
        /// The rod's index.
        rod: usize,
        /// Which end.
        end: RodEnd,
    },
    /// `rods.<rod>.<end>.force` (a vector, N).
    EndForce {
        /// The rod's index.
        rod: usize,
        /// Which end.
        end: RodEnd,
    },
    /// `junctions.<junction>.mass` (a number, kg).
    JunctionMass(usize),
    /// `connectors.<connector>.position` (a vector, case length unit).
    ConnectorPosition(usize),
    /// `connectors.<connector>.direction` (a rotation vector in degrees about the
    /// world x, y, z axes, Add only): turns the nozzle's frame (its `direction` and
    /// `normal`) about its position.
    ConnectorDirection(usize),
    /// `junctions.<junction>.ports.<port>.position` (a vector in the junction's body
    /// frame, case length unit).
    PortPosition {
        /// The junction's index.
        junction: usize,
        /// The port's index within the junction.
        port: usize,
    },
    /// `junctions.<junction>.ports.<port>.direction` (a rotation vector in degrees
    /// about the junction's body axes, Add only): turns the port's frame.
    PortDirection {
        /// The junction's index.
        junction: usize,
        /// The port's index within the junction.
        port: usize,
    },
    /// `clips.<clip>.at` (a number, case length unit; clips placed by `at`).
    ClipAt(usize),
    /// `clips.<clip>.base.position` (a vector, case length unit; clips with a `base`).
    ClipBasePosition(usize),
    /// `clips.<clip>.base.direction` (a rotation vector in degrees about the axes of
    /// the frame the base is written in, Add only; clips with a `base`): turns the
    /// clip's base frame, and its joint axes with it.
    ClipBaseDirection(usize),
    /// `sections.<section>.<ea|ga|ei|gj|youngs_modulus>` (a number in N, N·m² or
    /// Pa): a stiffness of a section, for every rod of that section.
    Section {
        /// The section's index.
        section: usize,
        /// Which stiffness.
        stiffness: SectionStiffness,
    },
    /// `environment.<mesh>.position` (a vector, case length unit).
    EnvironmentPosition(usize),
}

/// An item that names nothing a variant can change: the message and the fix.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{message} (hint: {hint})")]
pub struct ItemError {
    /// What is wrong.
    pub message: String,
    /// How to fix it.
    pub hint: String,
}

fn item_error(message: impl Into<String>, hint: impl Into<String>) -> ItemError {
    ItemError {
        message: message.into(),
        hint: hint.into(),
    }
}

/// A short-form item ([`expand_short`]) that names no entry, or more than one.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum ShortFormError {
    /// No rod, junction, connector, clip or mesh has the item's first name.
    #[error("'{0}' names no rod, junction or connector of the case")]
    Unknown(String),
    /// Several entries of different kinds share the name: the full forms.
    #[error("'{item}' is ambiguous: {}", full.join(" or "))]
    Ambiguous {
        /// The item as written.
        item: String,
        /// The full forms it could mean.
        full: Vec<String>,
    },
}

/// The rod fields a variant can change, as written after `rods.<rod>.`.
const ROD_FIELDS: [&str; 6] = [
    "length",
    "segments",
    "start.position",
    "end.position",
    "start.force",
    "end.force",
];

/// The prefixes of full-form items.
const PREFIXES: [&str; 6] = [
    "rods.",
    "junctions.",
    "connectors.",
    "clips.",
    "environment.",
    "sections.",
];

/// `names` joined by `, `, or `none`.
fn listed(names: &[&str]) -> String {
    if names.is_empty() {
        "none".to_string()
    } else {
        names.join(", ")
    }
}

/// The rod names of `file`, for messages.
pub(crate) fn rod_names(file: &CaseFile) -> String {
    listed(
        &file
            .rods
            .iter()
            .map(|r| r.name.as_str())
            .collect::<Vec<_>>(),
    )
}

/// The full form of a short-form `item` (`hose2.length` → `rods.hose2.length`,
/// `tee.mass` → `junctions.tee.mass`); a full-form item (or `gravity`) is returned as
/// it is. The first name must be that of exactly one rod, junction, connector, clip or
/// environment mesh, or of a section when the rest is one of its stiffnesses
/// (`hose_small.youngs_modulus`).
pub fn expand_short(file: &CaseFile, item: &str) -> Result<String, ShortFormError> {
    if item == "gravity" || PREFIXES.iter().any(|p| item.starts_with(p)) {
        return Ok(item.to_string());
    }
    let prefixed = |names: Vec<&str>, prefix: &str| {
        names
            .iter()
            .any(|n| {
                item.len() > n.len() && item.starts_with(n) && item.as_bytes()[n.len()] == b'.'
            })
            .then(|| format!("{prefix}{item}"))
    };
    let found: Vec<String> = [
        prefixed(file.rods.iter().map(|r| r.name.as_str()).collect(), "rods."),
        prefixed(
            file.junctions.iter().map(|(n, _)| n.as_str()).collect(),
            "junctions.",
        ),
        prefixed(
            file.connectors.iter().map(|(n, _)| n.as_str()).collect(),
            "connectors.",
        ),
        prefixed(
            file.clips.iter().map(|(n, _)| n.as_str()).collect(),
            "clips.",
        ),
        prefixed(
            file.environment.iter().map(|e| e.name.as_str()).collect(),
            "environment.",
        ),
        // A section shares its name with a rod more often than not (`trunk`): only
        // its stiffness fields make a short form a section's.
        prefixed(
            file.sections
                .iter()
                .map(|(n, _)| n.as_str())
                .filter(|n| {
                    SectionStiffness::ALL.iter().any(|f| {
                        item.len() == n.len() + 1 + f.field().len() && item.ends_with(f.field())
                    })
                })
                .collect(),
            "sections.",
        ),
    ]
    .into_iter()
    .flatten()
    .collect();
    match <[String; 1]>::try_from(found) {
        Ok([one]) => Ok(one),
        Err(found) if found.is_empty() => Err(ShortFormError::Unknown(item.to_string())),
        Err(found) => Err(ShortFormError::Ambiguous {
            item: item.to_string(),
            full: found,
        }),
    }
}

impl VariantItem {
    /// Resolves a full-form `item` against `file`; the error says what is wrong and
    /// lists the valid items and names.
    pub fn parse(file: &CaseFile, item: &str) -> Result<Self, ItemError> {
        let unknown = |message: String| {
            item_error(
                message,
                format!("valid items: {VARIANT_ITEMS}; rods: {}", rod_names(file)),
            )
        };
        if item == "gravity" {
            return Ok(Self::Gravity);
        }
        if let Some(rest) = item.strip_prefix("junctions.") {
            return junction_item(file, item, rest);
        }
        if let Some(rest) = item.strip_prefix("connectors.") {
            return named(
                item,
                rest,
                "connector",
                &file.connectors,
                &["position", "direction"],
            )
            .map(|(index, field)| match field {
                "direction" => Self::ConnectorDirection(index),
                _ => Self::ConnectorPosition(index),
            });
        }
        if let Some(rest) = item.strip_prefix("sections.") {
            return section_item(file, rest);
        }
        if let Some(rest) = item.strip_prefix("clips.") {
            let (field, target): (&str, fn(usize) -> Self) = if rest.ends_with(".base.position") {
                ("base.position", Self::ClipBasePosition)
            } else if rest.ends_with(".base.direction") {
                ("base.direction", Self::ClipBaseDirection)
            } else {
                ("at", Self::ClipAt)
            };
            let name = rest
                .strip_suffix(field)
                .and_then(|n| n.strip_suffix('.'))
                .unwrap_or(rest);
            let defined: Vec<&str> = file.clips.iter().map(|(n, _)| n.as_str()).collect();
            return match file.clips.iter().position(|(n, _)| n == name) {
                Some(index) => Ok(target(index)),
                None => Err(item_error(
                    format!("there is no clip named '{name}' with a field `{field}`"),
                    format!(
                        "write clips.<clip>.at, clips.<clip>.base.position or clips.<clip>.base.direction; clips: {}",
                        listed(&defined)
                    ),
                )),
            };
        }
        if let Some(rest) = item.strip_prefix("environment.") {
            let name = rest.strip_suffix(".position").unwrap_or(rest);
            let defined: Vec<&str> = file.environment.iter().map(|e| e.name.as_str()).collect();
            return match file.environment.iter().position(|e| e.name == name) {
                Some(index) if rest.ends_with(".position") => Ok(Self::EnvironmentPosition(index)),
                _ => Err(item_error(
                    format!("'{rest}' is not the position of an environment mesh"),
                    format!(
                        "write environment.<mesh>.position; meshes: {}",
                        listed(&defined)
                    ),
                )),
            };
        }
        let Some(rest) = item.strip_prefix("rods.") else {
            return Err(unknown(
                "unknown item: an item is `gravity` or starts with `rods.<rod name>.`, \
                 `junctions.<junction name>.`, `connectors.<connector name>.`, \
                 `clips.<clip name>.`, `sections.<section name>.` or `environment.<mesh name>.`"
                    .to_string(),
            ));
        };
        // Rod names may contain '.': take the longest name that prefixes the rest.
        let rod = file
            .rods
            .iter()
            .enumerate()
            .filter(|(_, r)| {
                rest.len() > r.name.len()
                    && rest.starts_with(r.name.as_str())
                    && rest.as_bytes()[r.name.len()] == b'.'
            })
            .max_by_key(|(_, r)| r.name.len());
        let Some((rod, def)) = rod else {
            let guess = ROD_FIELDS
                .iter()
                .find_map(|f| rest.strip_suffix(f).and_then(|r| r.strip_suffix('.')))
                .unwrap_or_else(|| rest.split('.').next().unwrap_or(rest));
            return Err(unknown(format!("there is no rod named '{guess}'")));
        };
        let field = &rest[def.name.len() + 1..];
        Ok(match field {
            "length" => Self::RodLength(rod),
            "segments" => Self::RodSegments(rod),
            "start.position" => Self::EndPosition {
                rod,
                end: RodEnd::Start,
            },
            "end.position" => Self::EndPosition {
                rod,
                end: RodEnd::End,
            },
            "start.force" => Self::EndForce {
                rod,
                end: RodEnd::Start,
            },
            "end.force" => Self::EndForce {
                rod,
                end: RodEnd::End,
            },
            _ => {
                return Err(unknown(format!(
                    "'{field}' is not a field of rod '{}' that a variant can change",
                    def.name
                )));
            }
        })
    }

    /// The kind of number the item takes.
    pub fn quantity(self) -> ItemQuantity {
        match self {
            Self::Gravity => ItemQuantity::Acceleration,
            Self::RodSegments(_) => ItemQuantity::Count,
            Self::EndForce { .. } => ItemQuantity::Force,
            Self::JunctionMass(_) => ItemQuantity::Mass,
            Self::ConnectorDirection(_)
            | Self::PortDirection { .. }
            | Self::ClipBaseDirection(_) => ItemQuantity::Angle,
            Self::Section { stiffness, .. } => stiffness.quantity(),
            Self::PortPosition { .. }
            | Self::RodLength(_)
            | Self::EndPosition { .. }
            | Self::ConnectorPosition(_)
            | Self::ClipAt(_)
            | Self::ClipBasePosition(_)
            | Self::EnvironmentPosition(_) => ItemQuantity::Length,
        }
    }

    /// Whether the item is a vector (x, y, z) rather than a number.
    pub fn is_vector(self) -> bool {
        !matches!(
            self,
            Self::RodLength(_)
                | Self::RodSegments(_)
                | Self::JunctionMass(_)
                | Self::ClipAt(_)
                | Self::Section { .. }
        )
    }

    /// The case's own value of a rod's length (m), a rod's segments (a count), a
    /// junction's mass (kg) or a section's stiffness (N, N·m², Pa); `None` for other
    /// items and for a rod without a `length` (its nominal shape gives it).
    pub fn case_value(self, file: &CaseFile) -> Option<f64> {
        let metres = || LengthUnit::parse(&file.units.length).map(|u| u.metres());
        match self {
            Self::RodLength(r) => Some(file.rods.get(r)?.length? * metres()?),
            Self::RodSegments(r) => Some(file.rods.get(r)?.segments as f64),
            Self::JunctionMass(j) => Some(file.junctions.get(j)?.1.mass),
            Self::Section { section, stiffness } => {
                crate::variant::section::stiffness_of(&file.sections.get(section)?.1, stiffness)
            }
            _ => None,
        }
    }

    /// The case's own value of component `component` (0, 1, 2 for x, y, z) of gravity
    /// (m/s²) or of a connector's position (m); `None` for other items.
    pub fn case_component(self, file: &CaseFile, component: usize) -> Option<f64> {
        match self {
            Self::Gravity => file.gravity.get(component).copied(),
            Self::ConnectorPosition(c) => {
                let metres = LengthUnit::parse(&file.units.length)?.metres();
                Some(file.connectors.get(c)?.1.position.get(component)? * metres)
            }
            _ => None,
        }
    }
}

/// Resolves `<name>.<field>` (the item without its `junctions.`/`connectors.` prefix)
/// against the named entries of one kind; `fields` are the changeable fields. Returns
/// the entry's index and the field.
fn named<'f, T>(
    item: &str,
    rest: &str,
    kind: &str,
    entries: &[(String, T)],
    fields: &[&'f str],
) -> Result<(usize, &'f str), ItemError> {
    let defined: Vec<&str> = entries.iter().map(|(n, _)| n.as_str()).collect();
    let hint = format!(
        "valid items: {VARIANT_ITEMS}; {kind}s: {}",
        listed(&defined)
    );
    let (name, wanted) = rest.split_once('.').unwrap_or((rest, ""));
    let Some(index) = entries.iter().position(|(n, _)| n == name) else {
        return Err(item_error(
            format!("there is no {kind} named '{name}'"),
            hint,
        ));
    };
    match fields.iter().find(|f| **f == wanted) {
        Some(field) => Ok((index, field)),
        None => Err(item_error(
            format!(
                "'{wanted}' is not a field of {kind} '{name}' that a variant can change (only {})",
                fields
                    .iter()
                    .map(|f| format!("`{f}`"))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
            format!(
                "write e.g. \"{}\"",
                item.strip_suffix(wanted)
                    .map_or_else(|| item.to_string(), |p| format!("{p}{}", fields[0]))
            ),
        )),
    }
}

/// Resolves `junctions.<junction>.mass` or `junctions.<junction>.ports.<port>.
/// {position,direction}` (`rest`: the item without `junctions.`).
fn junction_item(file: &CaseFile, item: &str, rest: &str) -> Result<VariantItem, ItemError> {
    let Some((name, tail)) = rest.split_once(".ports.") else {
        return named(item, rest, "junction", &file.junctions, &["mass"])
            .map(|(index, _)| VariantItem::JunctionMass(index));
    };
    let (junction, _) = named(
        item,
        &format!("{name}.mass"),
        "junction",
        &file.junctions,
        &["mass"],
    )?;
    let ports = &file.junctions[junction].1.ports;
    let (port, field) = named(item, tail, "port", ports, &["position", "direction"])?;
    Ok(match field {
        "direction" => VariantItem::PortDirection { junction, port },
        _ => VariantItem::PortPosition { junction, port },
    })
}

/// Resolves `sections.<section>.<stiffness>` (`rest`: the item without `sections.`):
/// `ea`, `ga`, `ei`, `gj` of an `Explicit` section, `youngs_modulus` of a `Tube`.
fn section_item(file: &CaseFile, rest: &str) -> Result<VariantItem, ItemError> {
    let defined: Vec<&str> = file.sections.iter().map(|(n, _)| n.as_str()).collect();
    // Section names may contain '.': the field is the last part.
    let (name, field) = rest.rsplit_once('.').unwrap_or((rest, ""));
    let Some(section) = file.sections.iter().position(|(n, _)| n == name) else {
        return Err(item_error(
            format!("there is no section named '{name}'"),
            format!(
                "write sections.<section>.<ea|ga|ei|gj|youngs_modulus>; sections: {}",
                listed(&defined)
            ),
        ));
    };
    let tube = matches!(
        file.sections[section].1,
        crate::schema::SectionDef::Tube { .. }
    );
    let fields: Vec<&str> = SectionStiffness::ALL
        .iter()
        .filter(|f| f.of_tube() == tube)
        .map(|f| f.field())
        .collect();
    match SectionStiffness::ALL
        .iter()
        .find(|f| f.field() == field && f.of_tube() == tube)
    {
        Some(&stiffness) => Ok(VariantItem::Section { section, stiffness }),
        None if tube => Err(item_error(
            format!(
                "'{field}' is not a stiffness of section '{name}': it is a Tube, whose stiffnesses follow from `youngs_modulus` (Pa), `poisson_ratio` and its radii"
            ),
            format!(
                "write sections.{name}.youngs_modulus, or write the section as Explicit(ea, ga, ei, gj, ...) to change one stiffness alone"
            ),
        )),
        None => Err(item_error(
            format!("'{field}' is not a stiffness of the Explicit section '{name}'"),
            format!("write sections.{name}.<{}>", fields.join("|")),
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cooler() -> CaseFile {
        let path =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../cases/cooler_hose.ron");
        crate::Case::from_path(path).unwrap().file
    }

    #[test]
    fn every_item_kind_resolves_to_its_entry() {
        let file = cooler();
        let rod = |name: &str| file.rods.iter().position(|r| r.name == name).unwrap();
        for (text, want) in [
            ("gravity", VariantItem::Gravity),
            ("rods.hose2.length", VariantItem::RodLength(rod("hose2"))),
            (
                "rods.hose3.segments",
                VariantItem::RodSegments(rod("hose3")),
            ),
            (
                "rods.hose1.start.position",
                VariantItem::EndPosition {
                    rod: rod("hose1"),
                    end: RodEnd::Start,
                },
            ),
            ("junctions.tee.mass", VariantItem::JunctionMass(0)),
        ] {
            assert_eq!(VariantItem::parse(&file, text), Ok(want), "{text}");
        }
        let connector = &file.connectors[0].0;
        assert_eq!(
            VariantItem::parse(&file, &format!("connectors.{connector}.position")),
            Ok(VariantItem::ConnectorPosition(0))
        );
        // Wrong fields and names say which, with the valid items.
        let e = VariantItem::parse(&file, "junctions.tee.colour").unwrap_err();
        assert!(
            e.message
                .contains("'colour' is not a field of junction 'tee'"),
            "{e}"
        );
        let e = VariantItem::parse(&file, "rods.hose9.length").unwrap_err();
        assert_eq!(e.message, "there is no rod named 'hose9'");
        assert!(e.hint.contains("rods: hose1, hose2, hose3"), "{e}");
    }

    #[test]
    fn quantities_vectors_and_case_values_follow_the_item() {
        let file = cooler();
        let length = VariantItem::parse(&file, "rods.hose2.length").unwrap();
        assert_eq!(length.quantity(), ItemQuantity::Length);
        assert!(!length.is_vector());
        // 190 mm in the file.
        assert!((length.case_value(&file).unwrap() - 0.190).abs() < 1e-15);
        let mass = VariantItem::parse(&file, "junctions.tee.mass").unwrap();
        assert_eq!(mass.case_value(&file), Some(file.junctions[0].1.mass));
        assert_eq!(VariantItem::Gravity.quantity(), ItemQuantity::Acceleration);
        assert!(VariantItem::Gravity.is_vector());
        assert_eq!(VariantItem::Gravity.case_value(&file), None);
    }

    #[test]
    fn short_forms_expand_to_exactly_one_entry() {
        let file = cooler();
        assert_eq!(
            expand_short(&file, "hose2.length").unwrap(),
            "rods.hose2.length"
        );
        assert_eq!(
            expand_short(&file, "rods.x.length").unwrap(),
            "rods.x.length"
        );
        assert_eq!(expand_short(&file, "gravity").unwrap(), "gravity");
        assert_eq!(
            expand_short(&file, "hose9.length"),
            Err(ShortFormError::Unknown("hose9.length".into()))
        );
        // A rod and a junction of the same name: both full forms are named.
        let mut twice = file.clone();
        twice.junctions[0].0 = "hose2".into();
        let e = expand_short(&twice, "hose2.mass").unwrap_err();
        assert_eq!(
            e.to_string(),
            "'hose2.mass' is ambiguous: rods.hose2.mass or junctions.hose2.mass"
        );
    }
}

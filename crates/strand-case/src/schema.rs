//! The RON schema of a case file, exactly as written (before unit conversion).
//!
//! Every struct and enum denies unknown fields, so a misspelt field is an error with
//! its line and column instead of being silently ignored.
//!
//! # Units
//!
//! - **lengths** — rod `length`, every `position` (also of connectors, junctions and
//!   ports), a junction's `center_of_mass`, `route` and `nominal` points,
//!   `outer_radius`, `inner_radius` — are in the case's length unit,
//!   `units: (length: "mm")` or `units: (length: "m")`;
//! - a junction's `mass` in kg;
//! - forces in N, moments in N·m;
//! - axial and shear stiffnesses `ea`, `ga` in N; bending and torsional stiffnesses
//!   `ei`, `gj` in N·m²;
//! - Young's modulus in Pa, density in kg/m³, mass per length in kg/m;
//! - gravity in m/s² (never scaled by the length unit);
//! - directions (`tangent`, `normal`, `direction`) are dimensionless and need not be
//!   unit vectors; a connector's or port's `direction` points out of the part into the
//!   hose.

use serde::de::{Deserializer, MapAccess, Visitor};
use serde::{Deserialize, Serialize};
use strand_solve::SolverSettings;

pub use crate::clips::{ClipDef, ClipFrameDef, JointDef};
pub use crate::environment::{AxisAngleDef, EnvironmentDef};

/// A 3-vector as written in a case file: `(x, y, z)`.
pub type Vec3 = [f64; 3];

/// The whole case file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CaseFile {
    /// Units of the file: `(length: "mm")` or `(length: "m")`.
    pub units: Units,
    /// Named cross sections: `{ "name": Explicit(...), "other": Tube(...) }`, in file order.
    #[serde(
        deserialize_with = "ordered_map",
        serialize_with = "serialize_ordered_map"
    )]
    pub sections: Vec<(String, SectionDef)>,
    /// The rods (at least one).
    pub rods: Vec<RodDef>,
    /// Gravitational acceleration in m/s², e.g. `(0, 0, -9.81)`; `(0, 0, 0)` for none.
    pub gravity: Vec3,
    /// Newton solver settings; every field is optional (defaults of [`SolverSettings`]).
    #[serde(default)]
    pub solver: SolverSettings,
    /// Named variants of the case, in file order (optional):
    /// `{ "hose2_plus50": [(item: "rods.hose2.length", change: Add(50))] }`.
    #[serde(
        default,
        deserialize_with = "ordered_variants",
        serialize_with = "serialize_ordered_map",
        skip_serializing_if = "Vec::is_empty"
    )]
    pub variants: Vec<(String, Vec<VariantChange>)>,
    /// Named connectors, in file order (optional): fixed nozzles in space that hold
    /// rod ends, `{ "radiator_outlet": (position: (0, 0, 0), direction: (1, 0, 0),
    /// normal: (0, 0, 1)) }`. A rod end refers to one as `Connector("radiator_outlet")`.
    #[serde(
        default,
        deserialize_with = "ordered_connectors",
        serialize_with = "serialize_ordered_map",
        skip_serializing_if = "Vec::is_empty"
    )]
    pub connectors: Vec<(String, ConnectorDef)>,
    /// Named junctions (rigid bodies with ports, e.g. a T-piece), in file order
    /// (optional). A rod end refers to a port as `Port("tee", "hose1")`.
    #[serde(
        default,
        deserialize_with = "ordered_junctions",
        serialize_with = "serialize_ordered_map",
        skip_serializing_if = "Vec::is_empty"
    )]
    pub junctions: Vec<(String, JunctionDef)>,
    /// Named clips, in file order (optional): joints fixed in space that hold a rod at
    /// an interior point, `{ "c1": (rod: "hose", at: 250, base: (...), joint: Fixed) }`
    /// (see [`ClipDef`]).
    #[serde(
        default,
        deserialize_with = "ordered_clips",
        serialize_with = "serialize_ordered_map",
        skip_serializing_if = "Vec::is_empty"
    )]
    pub clips: Vec<(String, ClipDef)>,
    /// Environment meshes (OBJ files), in file order (optional):
    /// `[(name: "engine", obj: "../assets/engine_bay/engine.obj", unit: "mm",
    /// scale: 1.0, position: (0, 0, 0), rotation: (axis: (0, 0, 1), angle_deg: 0))]`
    /// (see [`EnvironmentDef`]; paths relative to the case file).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub environment: Vec<EnvironmentDef>,
    /// Named motions of groups of parts, in file order (optional): `{ "engine_roll":
    /// (unit: "deg", moves: [Rotate(axis: (1, 0, 0), point: (0, 0, -80))]) }` (see
    /// [`crate::motion`]). Parts ride on one with `moves_with: "engine_roll"`.
    #[serde(
        default,
        deserialize_with = "ordered_motions",
        serialize_with = "serialize_ordered_map",
        skip_serializing_if = "Vec::is_empty"
    )]
    pub motions: Vec<(String, crate::motion::MotionDef)>,
}

impl CaseFile {
    /// The file with every relative path (environment meshes, route and nominal-shape
    /// files) made relative to `folder` instead (joined to it): for writing the case
    /// somewhere else, e.g. the optimal design of `strand optimize`, so that it still
    /// finds its files. `folder` is the folder of the original case file.
    pub fn rebased(&self, folder: &std::path::Path) -> CaseFile {
        let rebase = |path: &mut String| {
            if std::path::Path::new(path.as_str()).is_relative() {
                *path = folder.join(path.as_str()).display().to_string();
            }
        };
        let mut out = self.clone();
        for mesh in &mut out.environment {
            rebase(&mut mesh.obj);
        }
        for rod in &mut out.rods {
            if let Some(route) = &mut rod.route_file {
                rebase(&mut route.file);
            }
            if let Some(file) = rod.nominal.as_mut().and_then(|n| n.file.as_mut()) {
                rebase(file);
            }
        }
        out
    }
}

/// The units of a case file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Units {
    /// Length unit of every length, position and radius in the file: `"mm"` or `"m"`.
    pub length: String,
}

/// A cross section.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum SectionDef {
    /// Explicit effective stiffnesses (isotropic in bending and shear).
    Explicit {
        /// Axial stiffness `EA` in N.
        ea: f64,
        /// Shear stiffness `GA` in N.
        ga: f64,
        /// Bending stiffness `EI` in N·m².
        ei: f64,
        /// Torsional stiffness `GJ` in N·m².
        gj: f64,
        /// Mass per length in kg/m (0 for a weightless rod).
        mass_per_length: f64,
        /// Outer radius in the case's length unit (for contact and drawing; optional).
        #[serde(default)]
        outer_radius: Option<f64>,
        /// Smallest allowed bend radius of the centreline in the case's length unit
        /// (optional; `strand batch` reports the solved minimum against it).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        min_bend_radius: Option<f64>,
    },
    /// A circular tube of an isotropic material (`inner_radius: 0` for a solid rod).
    Tube {
        /// Young's modulus `E` in Pa.
        youngs_modulus: f64,
        /// Poisson's ratio `ν`, in (−1, 0.5].
        poisson_ratio: f64,
        /// Density in kg/m³.
        density: f64,
        /// Inner radius in the case's length unit.
        inner_radius: f64,
        /// Outer radius in the case's length unit.
        outer_radius: f64,
        /// Smallest allowed bend radius of the centreline in the case's length unit
        /// (optional; `strand batch` reports the solved minimum against it).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        min_bend_radius: Option<f64>,
    },
}

/// A rod.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RodDef {
    /// Unique name; also the name of the rod's CSV file, so only letters, digits,
    /// `_`, `-` and `.` are allowed.
    pub name: String,
    /// Name of a section in `sections`.
    pub section: String,
    /// Stress-free length in the case's length unit. Required, except for a rod with
    /// a `nominal` shape, whose length is the nominal centreline's: given there, it
    /// is a check and must agree with it within 1 %.
    #[serde(default)]
    pub length: Option<f64>,
    /// Number of segments (edges), at least 1.
    pub segments: usize,
    /// The end at `s = 0`.
    pub start: EndDef,
    /// The end at `s = length`.
    pub end: EndDef,
    /// Optional initial-guess polyline (e.g. the CAD route) in the case's length unit;
    /// it must start and end at the held end positions.
    #[serde(default)]
    pub route: Option<Vec<Vec3>>,
    /// The initial-guess polyline from a CSV or OBJ file instead of `route`:
    /// `(file: "routes.obj", object: "hose1", unit: "mm")` (see [`crate::centreline`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub route_file: Option<crate::centreline::CentrelineFileDef>,
    /// Optional nominal (stress-free, moulded) shape: the rod is pre-deformed, its
    /// reference strains and curvatures are those of this centreline.
    #[serde(default)]
    pub nominal: Option<NominalDef>,
    /// Whole turns of twist (360° each, right-handed about the rod's tangent) the rod
    /// is installed with beyond the shortest twist between its end frames (default 0).
    /// The end frames fix the twist only modulo one turn: a hose wound by 190° has the
    /// same end frames as one wound by −170°; `twist_turns: 1` with end normals 190°
    /// apart (the shortest twist −170°) selects +190°, `twist_turns: 2` with equal end
    /// normals two full turns. Both ends must be clamped (`Clamp`, `NominalClamp`,
    /// `Connector`, `Port`).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub twist_turns: i32,
    /// Required clearance in the case's length unit (optional): the smallest allowed
    /// surface-to-surface distance between this rod and every environment mesh and
    /// every other rod; `solve` and `report` list each closer approach as a finding.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min_clearance: Option<f64>,
}

fn is_zero(turns: &i32) -> bool {
    *turns == 0
}

/// The nominal shape of a pre-deformed (moulded) rod, e.g. its CAD centreline:
/// `(points: [(0, 0, 0), (100, 0, 0), ...])`, optionally with one frame per point,
/// `frames: [(tangent: (1, 0, 0), normal: (0, 0, 1)), ...]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NominalDef {
    /// Points along the centreline in the case's length unit, from the rod's start to
    /// its end (at least 2; consecutive points distinct). A smooth curve is laid
    /// through them (exact on straight runs and circular bends). Leave out when the
    /// points come from `file`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub points: Vec<Vec3>,
    /// The centreline from a file instead of `points`: a CSV of points whose header
    /// names the unit (`x_mm,y_mm,z_mm`), or an OBJ polyline (with `object` and `unit`);
    /// see [`crate::centreline`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub file: Option<String>,
    /// For an OBJ `file`: the object whose `l` elements are the centreline.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub object: Option<String>,
    /// For an OBJ `file`: the unit of its coordinates (`"mm"` or `"m"`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub unit: Option<String>,
    /// Optional section frames at the points, one per point: they fix the tangents and
    /// the twist of the nominal shape. Without them the section is not twisted along
    /// the centreline (parallel transport).
    #[serde(default)]
    pub frames: Option<Vec<FrameDef>>,
}

/// A section frame as in a clamp: `a3` along `tangent` (towards the rod's end), `a1`
/// along `normal` orthogonalised against it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FrameDef {
    /// Tangent direction (any non-zero length).
    pub tangent: Vec3,
    /// Direction of the first director `a1` (not parallel to `tangent`).
    pub normal: Vec3,
}

/// How a rod end is held, with optional dead loads (world frame, default zero).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum EndDef {
    /// Position and frame prescribed: the rod leaves along `tangent` (pointing from the
    /// start of the rod towards its end, at both ends) with its first director `a1`
    /// along `normal` (orthogonalised against `tangent`).
    Clamp {
        /// Position in the case's length unit.
        position: Vec3,
        /// Tangent direction (any non-zero length).
        tangent: Vec3,
        /// Direction of the first director `a1` (must not be parallel to `tangent`).
        normal: Vec3,
        /// Dead force on the end vertex in N (carried directly by the clamp).
        #[serde(default)]
        force: Vec3,
        /// Dead moment on the end edge in N·m.
        #[serde(default)]
        moment: Vec3,
    },
    /// Position prescribed, frame free (a ball joint).
    Pin {
        /// Position in the case's length unit.
        position: Vec3,
        /// Dead force on the end vertex in N (carried directly by the pin).
        #[serde(default)]
        force: Vec3,
        /// Dead moment on the end edge in N·m.
        #[serde(default)]
        moment: Vec3,
    },
    /// Clamped where the rod's `nominal` shape ends, with its nominal end frame: the
    /// moulded rod mounted as designed (only for a rod with a `nominal` shape).
    NominalClamp {
        /// Dead force on the end vertex in N (carried directly by the clamp).
        #[serde(default)]
        force: Vec3,
        /// Dead moment on the end edge in N·m.
        #[serde(default)]
        moment: Vec3,
    },
    /// Clamped at the named connector (see `connectors`): the rod leaves the
    /// connector along its `direction` at a rod's start and enters it against its
    /// `direction` at a rod's end; `a1` is the connector's `normal`.
    Connector(String),
    /// Pinned (ball joint) at the named connector's position; the frame is free.
    ConnectorPin(String),
    /// Clamped at port `port` of junction `junction`: `Port("tee", "hose1")`.
    Port(String, String),
    /// Held at port `port` of junction `junction` by a ball joint (frame free):
    /// `PortPin("tee", "hose1")`.
    PortPin(String, String),
    /// Nothing holds the end; write `Free()` or e.g. `Free(force: (2, 1, 0))`.
    Free {
        /// Dead force on the end vertex in N.
        #[serde(default)]
        force: Vec3,
        /// Dead moment on the end edge in N·m (measured from the rod's initial end frame).
        #[serde(default)]
        moment: Vec3,
    },
}

/// Deserialises a RON map into its entries in file order. Duplicate keys are an error
/// (a map type would silently keep only the last one).
fn ordered_map<'de, D, T>(deserializer: D) -> Result<Vec<(String, T)>, D::Error>
where
    D: Deserializer<'de>,
    T: Deserialize<'de>,
{
    ordered_entries(
        deserializer,
        "section",
        "a map of named sections, e.g. { \"steel\": Explicit(...) }",
    )
}

/// [`ordered_map`] for `variants`.
fn ordered_variants<'de, D>(deserializer: D) -> Result<Vec<(String, Vec<VariantChange>)>, D::Error>
where
    D: Deserializer<'de>,
{
    ordered_entries(
        deserializer,
        "variant",
        "a map of named variants, e.g. { \"longer\": [(item: \"rods.hose.length\", change: Add(50))] }",
    )
}

/// [`ordered_map`] for `connectors`.
fn ordered_connectors<'de, D>(deserializer: D) -> Result<Vec<(String, ConnectorDef)>, D::Error>
where
    D: Deserializer<'de>,
{
    ordered_entries(
        deserializer,
        "connector",
        "a map of named connectors, e.g. { \"outlet\": (position: (0, 0, 0), direction: (1, 0, 0), normal: (0, 0, 1)) }",
    )
}

/// [`ordered_map`] for `junctions`.
fn ordered_junctions<'de, D>(deserializer: D) -> Result<Vec<(String, JunctionDef)>, D::Error>
where
    D: Deserializer<'de>,
{
    ordered_entries(
        deserializer,
        "junction",
        "a map of named junctions, e.g. { \"tee\": (mass: 1, position: (0, 0, 0), ports: { ... }) }",
    )
}

/// [`ordered_map`] for `motions`.
fn ordered_motions<'de, D>(
    deserializer: D,
) -> Result<Vec<(String, crate::motion::MotionDef)>, D::Error>
where
    D: Deserializer<'de>,
{
    ordered_entries(
        deserializer,
        "motion",
        "a map of named motions, e.g. { \"engine_roll\": (unit: \"deg\", moves: [Rotate(axis: (1, 0, 0), point: (0, 0, 0))]) }",
    )
}

/// [`ordered_map`] for `clips`.
fn ordered_clips<'de, D>(deserializer: D) -> Result<Vec<(String, ClipDef)>, D::Error>
where
    D: Deserializer<'de>,
{
    ordered_entries(
        deserializer,
        "clip",
        "a map of named clips, e.g. { \"c1\": (rod: \"hose\", at: 250, base: (...), joint: Fixed) }",
    )
}

/// [`ordered_map`] for the ports of a junction.
fn ordered_ports<'de, D>(deserializer: D) -> Result<Vec<(String, PortDef)>, D::Error>
where
    D: Deserializer<'de>,
{
    ordered_entries(
        deserializer,
        "port",
        "a map of named ports, e.g. { \"hose1\": (position: (-35, 0, 0), direction: (-1, 0, 0), normal: (0, 0, 1)) }",
    )
}

fn ordered_entries<'de, D, T>(
    deserializer: D,
    what: &'static str,
    expecting: &'static str,
) -> Result<Vec<(String, T)>, D::Error>
where
    D: Deserializer<'de>,
    T: Deserialize<'de>,
{
    struct Entries<T> {
        what: &'static str,
        expecting: &'static str,
        marker: std::marker::PhantomData<T>,
    }
    impl<'de, T: Deserialize<'de>> Visitor<'de> for Entries<T> {
        type Value = Vec<(String, T)>;
        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            f.write_str(self.expecting)
        }
        fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Self::Value, A::Error> {
            let mut entries: Vec<(String, T)> = Vec::new();
            while let Some((name, value)) = map.next_entry::<String, T>()? {
                if entries.iter().any(|(n, _)| *n == name) {
                    let what = self.what;
                    return Err(serde::de::Error::custom(format!(
                        "{what} '{name}' is defined twice: {what} names must be unique"
                    )));
                }
                entries.push((name, value));
            }
            Ok(entries)
        }
    }
    deserializer.deserialize_map(Entries {
        what,
        expecting,
        marker: std::marker::PhantomData,
    })
}

fn serialize_ordered_map<S, T>(entries: &[(String, T)], serializer: S) -> Result<S::Ok, S::Error>
where
    S: serde::Serializer,
    T: Serialize,
{
    use serde::ser::SerializeMap;
    let mut map = serializer.serialize_map(Some(entries.len()))?;
    for (name, value) in entries {
        map.serialize_entry(name, value)?;
    }
    map.end()
}

/// One change of a variant: `(item: "rods.hose2.length", change: Add(50))`.
///
/// Items (rods addressed by name; lengths and positions in the case's length unit):
///
/// | item | value | changes |
/// |------|-------|---------|
/// | `rods.<rod>.length` | number | `Add`, `Set` |
/// | `rods.<rod>.segments` | whole number ≥ 1 | `Set` |
/// | `rods.<rod>.start.position`, `rods.<rod>.end.position` | vector (held ends only) | `Add`, `Set` |
/// | `rods.<rod>.start.force`, `rods.<rod>.end.force` | vector, N | `Add`, `Set` |
/// | `gravity` | vector, m/s² | `Add`, `Set` |
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VariantChange {
    /// What to change, e.g. `"rods.hose2.length"` or `"gravity"`.
    pub item: String,
    /// How to change it.
    pub change: Change,
}

/// How a variant changes an item.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Change {
    /// Add to the base value: `Add(50)` or `Add((0, 0, 10))`.
    Add(Amount),
    /// Replace the base value: `Set(450)` or `Set((0, 0, -9.81))`.
    Set(Amount),
}

/// The value of a [`Change`]: a number (`50`) or a vector (`(0, 0, 10)`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Amount {
    /// A number.
    Number(f64),
    /// A 3-vector.
    Vector(Vec3),
}

impl Serialize for Amount {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        match self {
            Amount::Number(x) => serializer.serialize_f64(*x),
            Amount::Vector(v) => v.serialize(serializer),
        }
    }
}

impl<'de> Deserialize<'de> for Amount {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct AmountVisitor;
        impl<'de> Visitor<'de> for AmountVisitor {
            type Value = Amount;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a number (e.g. 50) or a vector (e.g. (0, 0, 10))")
            }
            fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<Amount, E> {
                Ok(Amount::Number(v))
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<Amount, E> {
                Ok(Amount::Number(v as f64))
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<Amount, E> {
                Ok(Amount::Number(v as f64))
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> Result<Amount, A::Error> {
                let mut v = [0.0; 3];
                for (i, x) in v.iter_mut().enumerate() {
                    *x = seq
                        .next_element()?
                        .ok_or_else(|| serde::de::Error::invalid_length(i, &"3 components"))?;
                }
                if seq.next_element::<f64>()?.is_some() {
                    return Err(serde::de::Error::invalid_length(4, &"3 components"));
                }
                Ok(Amount::Vector(v))
            }
        }
        deserializer.deserialize_any(AmountVisitor)
    }
}

/// A connector: a fixed nozzle in space that holds a rod end,
/// `(position: (x, y, z), direction: (dx, dy, dz), normal: (nx, ny, nz))`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ConnectorDef {
    /// Where the rod end is held, in the case's length unit.
    pub position: Vec3,
    /// The nozzle axis, pointing out of the connector into the hose (any non-zero
    /// length).
    pub direction: Vec3,
    /// Direction of the section's first director `a1` (not parallel to `direction`).
    pub normal: Vec3,
    /// Largest allowed force the connector may take from the hose, N (a design
    /// limit, checked after the solve: `findings`); none when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_force: Option<f64>,
    /// Largest allowed moment the connector may take from the hose, N·m (a design
    /// limit, checked after the solve: `findings`); none when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_moment: Option<f64>,
    /// The motion this part rides on (optional; see [`crate::motion`]): the part is
    /// where it is written at the motion's parameter 0 and moves rigidly with the
    /// motion, `moves_with: "engine_roll"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub moves_with: Option<String>,
}

/// A port of a junction, in the junction's body frame:
/// `(position: (x, y, z), direction: (dx, dy, dz), normal: (nx, ny, nz))`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PortDef {
    /// Where the rod end is held, body frame, in the case's length unit.
    pub position: Vec3,
    /// The port axis, pointing out of the junction into the hose (body frame).
    pub direction: Vec3,
    /// Direction of the section's first director `a1` (body frame; not parallel to
    /// `direction`).
    pub normal: Vec3,
}

/// The orientation of a junction: its body frame's z axis along `direction` and its
/// x axis along `normal` (orthogonalised against `direction`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OrientationDef {
    /// Direction of the body's z axis (world frame).
    pub direction: Vec3,
    /// Direction of the body's x axis (world frame; not parallel to `direction`).
    pub normal: Vec3,
}

/// A junction: a rigid body (T- or Y-piece, branch) whose ports hold rod ends.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JunctionDef {
    /// Mass in kg (≥ 0).
    pub mass: f64,
    /// Centre of mass in the body frame, in the case's length unit (default: the
    /// body's origin).
    #[serde(default)]
    pub center_of_mass: Vec3,
    /// Position of the body's origin, in the case's length unit: where a mounted
    /// (`fixed: true`) junction is, and the initial guess of a free-hanging one.
    pub position: Vec3,
    /// Orientation of the body frame (default: aligned with the world frame): the
    /// actual one if `fixed`, the initial guess otherwise.
    #[serde(default)]
    pub orientation: Option<OrientationDef>,
    /// Whether the junction is mounted (pose prescribed) instead of free-hanging
    /// (default `false`: its pose is an unknown).
    #[serde(default)]
    pub fixed: bool,
    /// Named ports, in file order: `{ "hose1": (position: ..., direction: ..., normal: ...) }`.
    #[serde(
        default,
        deserialize_with = "ordered_ports",
        serialize_with = "serialize_ordered_map"
    )]
    pub ports: Vec<(String, PortDef)>,
    /// The motion this junction rides on (only a `fixed` one) (optional; see [`crate::motion`]): the part is
    /// where it is written at the motion's parameter 0 and moves rigidly with the
    /// motion, `moves_with: "engine_roll"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub moves_with: Option<String>,
}

//! The RON schema of a case file, exactly as written (before unit conversion).
//!
//! Every struct and enum denies unknown fields, so a misspelt field is an error with
//! its line and column instead of being silently ignored.
//!
//! # Units
//!
//! - **lengths** — rod `length`, every `position`, `route` point, `outer_radius`,
//!   `inner_radius` — are in the case's length unit, `units: (length: "mm")` or
//!   `units: (length: "m")`;
//! - forces in N, moments in N·m;
//! - axial and shear stiffnesses `ea`, `ga` in N; bending and torsional stiffnesses
//!   `ei`, `gj` in N·m²;
//! - Young's modulus in Pa, density in kg/m³, mass per length in kg/m;
//! - gravity in m/s² (never scaled by the length unit);
//! - directions (`tangent`, `normal`) are dimensionless and need not be unit vectors.

use serde::de::{Deserializer, MapAccess, Visitor};
use serde::{Deserialize, Serialize};
use strand_solve::SolverSettings;

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
    /// Stress-free length in the case's length unit.
    pub length: f64,
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
    struct Entries<T>(std::marker::PhantomData<T>);
    impl<'de, T: Deserialize<'de>> Visitor<'de> for Entries<T> {
        type Value = Vec<(String, T)>;
        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            f.write_str("a map of named sections, e.g. { \"steel\": Explicit(...) }")
        }
        fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Self::Value, A::Error> {
            let mut entries: Vec<(String, T)> = Vec::new();
            while let Some((name, value)) = map.next_entry::<String, T>()? {
                if entries.iter().any(|(n, _)| *n == name) {
                    return Err(serde::de::Error::custom(format!(
                        "section '{name}' is defined twice: section names must be unique"
                    )));
                }
                entries.push((name, value));
            }
            Ok(entries)
        }
    }
    deserializer.deserialize_map(Entries(std::marker::PhantomData))
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

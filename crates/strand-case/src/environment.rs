//! Environment meshes of a case: OBJ or STL files placed in the world, loaded once and
//! shared.
//!
//! ```ron
//! environment: [
//!     (name: "engine", obj: "../assets/engine_bay/engine.obj", unit: "mm", scale: 1.0,
//!      position: (0, 0, 0), rotation: (axis: (0, 0, 1), angle_deg: 0)),
//! ],
//! ```
//!
//! `obj` (or its aliases `stl`, `mesh`) names a Wavefront OBJ or a binary or ASCII STL
//! file; the format is told from the content
//! ([`strand_contact::mesh::stl::detect_format`]), and STL corners are welded by
//! position (see [`strand_contact::STL_WELD_RELATIVE_TOLERANCE`]).
//!
//! A file coordinate `x` becomes the world point `R (unit · scale · x) + position`
//! (`position` in the case's length unit, `R` the rotation by `angle_deg` about
//! `axis`). Paths are relative to the case file's folder. Built meshes (with their
//! BVH) are cached in the [`crate::Case`], keyed by resolved path, name and
//! transform, so variants and batch runs of a case share them; large mesh files also go
//! through the on-disk cache ([`strand_contact::mesh_cache`], settings from the
//! environment: `STRAND_CACHE_DIR`, `STRAND_MESH_CACHE=off`), so the next process
//! reads the built mesh instead of parsing the file and building its BVH.

use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, PoisonError};

use nalgebra::{Isometry3, Translation3, Unit, UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};
use strand_contact::{MeshCacheSettings, ObstacleMesh};

use crate::build::BuiltCase;
use crate::error::{CaseError, Reporter};
use crate::schema::{CaseFile, Vec3};
use crate::units::LengthUnit;

/// One environment mesh: `(name: "engine", obj: "engine.obj", unit: "mm", scale: 1.0,
/// position: (0, 0, 0), rotation: (axis: (0, 0, 1), angle_deg: 0))`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EnvironmentDef {
    /// Unique name (used in messages and results).
    pub name: String,
    /// Path of the mesh file (Wavefront OBJ, binary or ASCII STL, told apart by
    /// content), relative to the case file's folder (or absolute). Also accepted as
    /// `stl:` or `mesh:`.
    #[serde(alias = "stl", alias = "mesh")]
    pub obj: String,
    /// Length unit of the coordinates in the mesh file: `"mm"` or `"m"` (independent of
    /// the case's unit).
    pub unit: String,
    /// Extra scale factor applied to the file's coordinates (default 1).
    #[serde(default = "unit_scale")]
    pub scale: f64,
    /// Where the file's origin is placed, in the case's length unit (default origin).
    #[serde(default)]
    pub position: Vec3,
    /// Rotation of the file's axes (default none), applied about the file's origin
    /// before the translation.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rotation: Option<AxisAngleDef>,
    /// The motion this mesh rides on (optional; see [`crate::motion`]): the part is
    /// where it is written at the motion's parameter 0 and moves rigidly with the
    /// motion, `moves_with: "engine_roll"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub moves_with: Option<String>,
}

fn unit_scale() -> f64 {
    1.0
}

/// A rotation by `angle_deg` degrees about `axis` (right-hand rule):
/// `(axis: (0, 0, 1), angle_deg: 90)`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AxisAngleDef {
    /// Rotation axis (any non-zero length).
    pub axis: Vec3,
    /// Rotation angle in degrees.
    pub angle_deg: f64,
}

/// Cache of built environment meshes, shared by clones of a [`crate::Case`] (and so by
/// its variants and batch runs, also across threads), in front of the on-disk mesh
/// cache of [`EnvironmentCache::disk`].
#[derive(Clone)]
pub struct EnvironmentCache {
    entries: Arc<Mutex<Vec<CacheEntry>>>,
    /// The on-disk mesh cache used for meshes not built yet (default:
    /// [`MeshCacheSettings::from_env`]).
    pub disk: MeshCacheSettings,
}

impl Default for EnvironmentCache {
    fn default() -> Self {
        Self {
            entries: Arc::default(),
            disk: MeshCacheSettings::from_env(),
        }
    }
}

/// A built mesh with what it was built from.
type CacheEntry = (MeshKey, Arc<ObstacleMesh>);

/// What makes two environment entries the same mesh.
#[derive(Clone, Debug, PartialEq)]
struct MeshKey {
    path: PathBuf,
    name: String,
    scale_to_metres: u64,
    pose: [u64; 7],
}

impl EnvironmentCache {
    /// Number of meshes held.
    pub fn len(&self) -> usize {
        self.lock().len()
    }

    /// Whether no mesh is held.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, Vec<CacheEntry>> {
        self.entries.lock().unwrap_or_else(PoisonError::into_inner)
    }
}

/// Caches compare equal: a cache never changes what a case means.
impl PartialEq for EnvironmentCache {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl std::fmt::Debug for EnvironmentCache {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "EnvironmentCache({} meshes)", self.len())
    }
}

impl BuiltCase {
    /// Warnings about the environment meshes for the user, from their
    /// [`strand_contact::MeshDiagnostics`]: degenerate triangles skipped, slivers,
    /// duplicate vertices, non-manifold or inconsistently wound edges, e.g.
    /// `environment 'engine': 12 degenerate (zero-area) triangle(s) skipped`.
    pub fn environment_warnings(&self) -> Vec<String> {
        self.environment
            .iter()
            .flat_map(|m| {
                m.diagnostics()
                    .warnings()
                    .into_iter()
                    .map(move |w| format!("environment '{}': {w}", m.name()))
            })
            .collect()
    }
}

/// Validates the case's `environment` entries and loads their meshes (from `cache`
/// when already built), in file order. The meshes named in `moved` are then moved
/// rigidly by their map (world, m) without being rebuilt ([`ObstacleMesh::placed`]):
/// a part riding on a motion is one cached mesh at every pose.
pub(crate) fn load_environment(
    report: &Reporter,
    unit: LengthUnit,
    file: &CaseFile,
    cache: &EnvironmentCache,
    moved: &[(String, Isometry3<f64>)],
) -> Result<Vec<Arc<ObstacleMesh>>, CaseError> {
    let mut meshes = load_placed(report, unit, file, cache)?;
    for mesh in &mut meshes {
        if let Some((_, map)) = moved.iter().find(|(name, _)| name == mesh.name()) {
            *mesh = Arc::new(mesh.placed(map));
        }
    }
    Ok(meshes)
}

/// The meshes where the file places them (from `cache` when already built).
fn load_placed(
    report: &Reporter,
    unit: LengthUnit,
    file: &CaseFile,
    cache: &EnvironmentCache,
) -> Result<Vec<Arc<ObstacleMesh>>, CaseError> {
    let folder = Path::new(report.origin)
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_default();
    let mut meshes = Vec::with_capacity(file.environment.len());
    for (i, def) in file.environment.iter().enumerate() {
        let item = format!("environment[{i}] '{}'", def.name);
        if def.name.trim().is_empty() {
            return Err(report.invalid(
                format!("environment[{i}].name"),
                "the name is empty",
                "give every environment mesh a name",
            ));
        }
        if let Some(first) = file.environment[..i]
            .iter()
            .position(|e| e.name == def.name)
        {
            return Err(report.invalid(
                &item,
                format!("duplicate environment name (also used by environment[{first}])"),
                "give every environment mesh a unique name",
            ));
        }
        let file_unit = LengthUnit::parse(&def.unit).ok_or_else(|| {
            report.invalid(
                format!("{item}.unit"),
                format!("unknown length unit \"{}\"", def.unit),
                format!(
                    "use {} (the unit of the mesh file's coordinates)",
                    LengthUnit::ACCEPTED
                ),
            )
        })?;
        let scale = report.positive(&format!("{item}.scale"), def.scale, "")?;
        let position = report.finite3(
            &format!("{item}.position"),
            &def.position,
            &format!(" {unit}"),
        )?;
        let rotation = rotation(report, &item, def.rotation.as_ref())?;
        let pose = Isometry3::from_parts(Translation3::from(position * unit.metres()), rotation);
        let scale_to_metres = file_unit.metres() * scale;
        let path = folder.join(&def.obj);
        let key = MeshKey {
            path: path.canonicalize().unwrap_or_else(|_| path.clone()),
            name: def.name.clone(),
            scale_to_metres: scale_to_metres.to_bits(),
            pose: pose_bits(&pose),
        };
        let mut entries = cache.lock();
        if let Some((_, mesh)) = entries.iter().find(|(k, _)| *k == key) {
            meshes.push(Arc::clone(mesh));
            continue;
        }
        let mesh = ObstacleMesh::load_cached(&path, scale_to_metres, &pose, &cache.disk)
            .map_err(|e| {
                let text = e.to_string();
                let (message, hint) = text.split_once("\n  hint: ").unwrap_or((&text, ""));
                report.invalid(format!("environment[{i}].obj"), message, hint)
            })?
            .with_name(def.name.clone());
        let mesh = Arc::new(mesh);
        entries.push((key, Arc::clone(&mesh)));
        meshes.push(mesh);
    }
    Ok(meshes)
}

/// The rotation of an entry (identity when not given).
fn rotation(
    report: &Reporter,
    item: &str,
    def: Option<&AxisAngleDef>,
) -> Result<UnitQuaternion<f64>, CaseError> {
    let Some(def) = def else {
        return Ok(UnitQuaternion::identity());
    };
    let item = format!("{item}.rotation");
    let axis = report.finite3(&format!("{item}.axis"), &def.axis, "")?;
    let angle = report.finite(&format!("{item}.angle_deg"), def.angle_deg, "°")?;
    let axis = Unit::try_new(axis, 0.0).ok_or_else(|| {
        report.invalid(
            format!("{item}.axis"),
            "the rotation axis is zero",
            "give a non-zero axis, e.g. (0, 0, 1)",
        )
    })?;
    Ok(UnitQuaternion::from_axis_angle(&axis, angle.to_radians()))
}

/// The exact bits of a pose, for cache keys.
fn pose_bits(pose: &Isometry3<f64>) -> [u64; 7] {
    let t: Vector3<f64> = pose.translation.vector;
    let q = pose.rotation.coords;
    [t.x, t.y, t.z, q.x, q.y, q.z, q.w].map(f64::to_bits)
}

#[cfg(test)]
#[path = "environment_tests.rs"]
mod tests;

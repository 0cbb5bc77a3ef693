//! Loading an environment mesh from a Wavefront OBJ file: the plain subset read in
//! parallel ([`super::plain_obj`]), everything else by tobj, with the same result.

use std::io::Cursor;
use std::path::Path;

use nalgebra::{Isometry3, Point3};

use rayon::prelude::*;

use super::from_triangles::build;
use super::plain_obj::{ObjTriangles, read_plain_obj};
use super::{MeshError, ObstacleMesh};

impl ObstacleMesh {
    /// Loads an OBJ file: all objects and groups in the file are merged into one mesh,
    /// polygons are triangulated, points, lines, normals, texture coordinates and
    /// materials are ignored. Every file coordinate is multiplied by
    /// `scale_to_metres` (e.g. `0.001` for a file in mm) and then placed by `pose`
    /// (m, rad): `x_world = pose · (scale_to_metres · x_file)`.
    ///
    /// The mesh is named after the file stem. Degenerate triangles are skipped and
    /// counted. Errors name the path: missing or unreadable file, malformed OBJ, no
    /// triangles, a NaN or infinite vertex (with its OBJ number and line).
    pub fn load_obj(
        path: impl AsRef<Path>,
        scale_to_metres: f64,
        pose: &Isometry3<f64>,
    ) -> Result<Self, MeshError> {
        let path = path.as_ref();
        check_placement(&path.display().to_string(), scale_to_metres, pose)?;
        let bytes = std::fs::read(path).map_err(|source| MeshError::Read {
            path: path.to_path_buf(),
            source,
        })?;
        obj_mesh(path, &bytes, scale_to_metres, pose)
    }
}

/// The mesh of the OBJ file `path` whose content is `bytes` (see
/// [`ObstacleMesh::load_obj`]).
pub(crate) fn obj_mesh(
    path: &Path,
    bytes: &[u8],
    scale_to_metres: f64,
    pose: &Isometry3<f64>,
) -> Result<ObstacleMesh, MeshError> {
    let label = path.display().to_string();
    check_placement(&label, scale_to_metres, pose)?;
    let parsed = match read_plain_obj(bytes) {
        Some(parsed) => parsed,
        None => tobj_triangles(path, bytes)?,
    };
    if let Some(&file) = parsed
        .positions
        .iter()
        .find(|p| !p.iter().all(|x| x.is_finite()))
    {
        return Err(non_finite_vertex(&label, bytes, Point3::from(file)));
    }
    // Placed where they are (the file's positions are not needed afterwards).
    let mut vertices = parsed.positions;
    vertices.par_iter_mut().for_each(|vertex| {
        let world = pose * Point3::from(Point3::from(*vertex).coords * scale_to_metres);
        *vertex = [world.x, world.y, world.z];
    });
    build(name_of(path), vertices, parsed.triangles).map_err(|e| e.of_file(&label))
}

/// The vertices and triangles of an OBJ file as tobj reads it: every model's
/// positions, the models merged in file order.
pub(crate) fn tobj_triangles(path: &Path, bytes: &[u8]) -> Result<ObjTriangles, MeshError> {
    let options = load_options();
    let no_materials = |_: &Path| -> tobj::MTLLoadResult { Ok((Vec::new(), Default::default())) };
    let (models, _materials) = tobj::load_obj_buf(&mut Cursor::new(bytes), &options, no_materials)
        .map_err(|e| MeshError::Parse {
            path: path.to_path_buf(),
            message: e.to_string(),
        })?;
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    for model in &models {
        let mesh = &model.mesh;
        let offset = u32::try_from(positions.len()).map_err(|_| MeshError::Parse {
            path: path.to_path_buf(),
            message: "more than 2^32 vertices".to_string(),
        })?;
        positions.extend(mesh.positions.chunks_exact(3).map(|p| [p[0], p[1], p[2]]));
        triangles.extend(
            mesh.indices
                .chunks_exact(3)
                .map(|t| [t[0] + offset, t[1] + offset, t[2] + offset]),
        );
    }
    Ok(ObjTriangles {
        positions,
        triangles,
    })
}

/// The placement of a mesh file, `label`: a finite positive scale to metres and a
/// finite pose, else [`MeshError::InvalidScale`] / [`MeshError::InvalidPose`].
pub(crate) fn check_placement(
    label: &str,
    scale_to_metres: f64,
    pose: &Isometry3<f64>,
) -> Result<(), MeshError> {
    if !(scale_to_metres.is_finite() && scale_to_metres > 0.0) {
        return Err(MeshError::InvalidScale {
            mesh: label.to_string(),
            scale: scale_to_metres,
        });
    }
    let mut pose_values = pose
        .translation
        .vector
        .iter()
        .chain(pose.rotation.coords.iter());
    if !pose_values.all(|x| x.is_finite()) {
        return Err(MeshError::InvalidPose {
            mesh: label.to_string(),
        });
    }
    Ok(())
}

/// Triangulated faces only, positions indexed separately from normals and texture
/// coordinates. Set field by field: the struct has more fields when tobj features
/// are enabled elsewhere in the build.
#[allow(clippy::field_reassign_with_default)]
fn load_options() -> tobj::LoadOptions {
    let mut options = tobj::LoadOptions::default();
    options.triangulate = true;
    options.single_index = false;
    options.ignore_points = true;
    options.ignore_lines = true;
    options
}

/// The mesh name for a file: its stem.
pub(crate) fn name_of(path: &Path) -> String {
    path.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| path.display().to_string())
}

/// The error for a non-finite vertex, locating its `v` line in the file.
fn non_finite_vertex(label: &str, bytes: &[u8], found: Point3<f64>) -> MeshError {
    let text = String::from_utf8_lossy(bytes);
    let mut vertex = 0;
    for (line_index, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        if words.next() != Some("v") {
            continue;
        }
        vertex += 1;
        let values: Vec<f64> = words.take(3).filter_map(|w| w.parse().ok()).collect();
        if values.len() == 3 && !values.iter().all(|x| x.is_finite()) {
            return MeshError::NonFiniteVertex {
                mesh: label.to_string(),
                vertex,
                at: format!(" (line {})", line_index + 1),
                x: values[0],
                y: values[1],
                z: values[2],
            };
        }
    }
    MeshError::NonFiniteVertex {
        mesh: label.to_string(),
        vertex: 0,
        at: String::new(),
        x: found.x,
        y: found.y,
        z: found.z,
    }
}

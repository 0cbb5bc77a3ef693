//! Why an environment mesh could not be built.

use std::path::PathBuf;

/// Why an environment mesh could not be read or built. Every message names the mesh
/// (its file path, or the name given to [`super::ObstacleMesh::try_from_triangles`])
/// and says how to fix the problem.
#[derive(Debug, thiserror::Error)]
pub enum MeshError {
    /// The mesh file (OBJ or STL) could not be read (missing, no permission, …).
    #[error("{}: cannot read the mesh file: {source}\n  hint: check the path (relative paths are resolved against the case file's folder) and that the file is readable", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// The I/O error.
        #[source]
        source: std::io::Error,
    },
    /// The OBJ file is malformed.
    #[error("{}: not a valid OBJ file ({message})\n  hint: export the mesh again as Wavefront OBJ (vertices `v x y z`, faces `f i j k`)", path.display())]
    Parse {
        /// The file.
        path: PathBuf,
        /// What the OBJ parser reported.
        message: String,
    },
    /// A vertex has a NaN or infinite coordinate.
    #[error(
        "{mesh}: vertex {vertex}{at} has a non-finite coordinate ({x}, {y}, {z})\n  hint: repair or re-export the mesh"
    )]
    NonFiniteVertex {
        /// The mesh's file path or name.
        mesh: String,
        /// 1-based vertex number (the OBJ numbering for a file).
        vertex: usize,
        /// Where in the file (`" (line 12)"`), or empty.
        at: String,
        /// The coordinates as read.
        x: f64,
        /// The coordinates as read.
        y: f64,
        /// The coordinates as read.
        z: f64,
    },
    /// A vertex lies farther from the origin than any part of a machine
    /// ([`MAX_COORDINATE_M`]): a wrong unit or scale, or a damaged file (the
    /// squares of such coordinates overflow, and every triangle would look degenerate).
    #[error(
        "{mesh}: vertex {vertex} lies at ({x:e}, {y:e}, {z:e}) m, beyond the {limit:e} m from the origin a part may lie\n  hint: check the mesh's `unit` and `scale`, or repair the file"
    )]
    VertexTooFar {
        /// The mesh's file path or name.
        mesh: String,
        /// 1-based vertex number.
        vertex: usize,
        /// The coordinates in the world, m.
        x: f64,
        /// The coordinates in the world, m.
        y: f64,
        /// The coordinates in the world, m.
        z: f64,
        /// [`MAX_COORDINATE_M`].
        limit: f64,
    },
    /// A triangle refers to a vertex that does not exist.
    #[error(
        "{mesh}: triangle {triangle} refers to vertex index {index}, but there are only {count} vertices\n  hint: triangle indices are 0-based and must be < the number of vertices"
    )]
    IndexOutOfRange {
        /// The mesh's name.
        mesh: String,
        /// 0-based triangle number.
        triangle: usize,
        /// The offending 0-based vertex index.
        index: u32,
        /// Number of vertices.
        count: usize,
    },
    /// No triangle of positive area is left.
    #[error(
        "{mesh}: the mesh has no triangles{detail}\n  hint: check that the file holds faces (`f` lines), not only points or lines"
    )]
    NoTriangles {
        /// The mesh's file path or name.
        mesh: String,
        /// Extra detail, e.g. `" (all 12 are degenerate)"`.
        detail: String,
    },
    /// The scale to metres is not a finite positive number.
    #[error(
        "{mesh}: invalid scale to metres {scale}\n  hint: give a finite scale > 0 (e.g. 0.001 for a file in mm)"
    )]
    InvalidScale {
        /// The mesh's file path or name.
        mesh: String,
        /// The scale given.
        scale: f64,
    },
    /// The pose has a non-finite translation or rotation.
    #[error("{mesh}: the pose is not finite\n  hint: give a finite position and rotation")]
    InvalidPose {
        /// The mesh's file path or name.
        mesh: String,
    },
    /// The STL file is broken: truncated, inconsistent with its header, malformed
    /// ASCII, or with non-finite coordinates.
    #[error("{}: {problem}\n  hint: {hint}", path.display())]
    Stl {
        /// The file.
        path: PathBuf,
        /// What is wrong (with the triangle or line where it applies).
        problem: String,
        /// How to fix it.
        hint: String,
    },
}

/// The farthest a mesh vertex may lie from the origin, m (a million kilometres: far
/// beyond any machine, far below where squared lengths overflow).
pub const MAX_COORDINATE_M: f64 = 1e9;

impl MeshError {
    /// The error of building the mesh of file `label` (its path): the errors that name
    /// the mesh name the file instead of the mesh (its file stem).
    pub(crate) fn of_file(self, label: &str) -> Self {
        match self {
            MeshError::NoTriangles { detail, .. } => MeshError::NoTriangles {
                mesh: label.to_string(),
                detail,
            },
            MeshError::VertexTooFar {
                vertex,
                x,
                y,
                z,
                limit,
                ..
            } => MeshError::VertexTooFar {
                mesh: label.to_string(),
                vertex,
                x,
                y,
                z,
                limit,
            },
            other => other,
        }
    }
}

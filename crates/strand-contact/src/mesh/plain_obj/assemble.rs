//! The pieces of a plain OBJ file joined into the vertices and triangles tobj gives.

use rayon::prelude::*;

use super::ObjTriangles;
use super::chunk::Chunk;

/// Joins the parsed pieces of a file (in file order). `None` when a reference is one
/// the plain path does not accept (tobj decides those).
pub(super) fn assemble(chunks: Vec<Chunk>) -> Option<ObjTriangles> {
    let total_texcoords: i64 = chunks.iter().map(|c| c.texcoords).sum();
    let total_normals: i64 = chunks.iter().map(|c| c.normals).sum();
    let (mut vertices_before, mut texcoords_before, mut normals_before) = (0i64, 0i64, 0i64);
    let mut vertex_offsets = Vec::with_capacity(chunks.len());
    let mut corner_count = 0usize;
    let mut model_starts = Vec::new();
    for chunk in &chunks {
        // tobj checks texture and normal references only when the file has any.
        let texcoords_fine =
            total_texcoords == 0 || chunk.texcoords_needed_before <= texcoords_before;
        let normals_fine = total_normals == 0 || chunk.normals_needed_before <= normals_before;
        if chunk.vertices_needed_before > vertices_before || !texcoords_fine || !normals_fine {
            return None;
        }
        vertex_offsets.push(vertices_before);
        model_starts.extend(chunk.model_starts.iter().map(|t| corner_count / 3 + t));
        vertices_before += chunk.positions.len() as i64;
        texcoords_before += chunk.texcoords;
        normals_before += chunk.normals;
        corner_count += chunk.corners.len();
    }
    u32::try_from(vertices_before).ok()?;

    // Every corner as a vertex index of the file (pieces in parallel).
    let mut corners = vec![0u32; corner_count];
    let mut pieces: Vec<&mut [u32]> = Vec::with_capacity(chunks.len());
    let mut rest = corners.as_mut_slice();
    for chunk in &chunks {
        let (piece, tail) = rest.split_at_mut(chunk.corners.len());
        pieces.push(piece);
        rest = tail;
    }
    pieces
        .into_par_iter()
        .zip(chunks.par_iter().zip(vertex_offsets.par_iter()))
        .for_each(|(piece, (chunk, &offset))| {
            piece.copy_from_slice(&chunk.corners);
            for &(slot, from_start) in &chunk.relative {
                piece[slot] = (offset + from_start) as u32;
            }
        });
    let mut positions = Vec::with_capacity(vertices_before as usize);
    for chunk in chunks {
        positions.extend_from_slice(&chunk.positions);
    }
    Some(renumber(&positions, &corners, &model_starts))
}

/// tobj's vertex order: the triangles split into models at `model_starts` (where the
/// model so far has triangles), and each model's vertices in the order its triangles
/// first use them (a vertex used by two models appears twice, unused ones not at all).
fn renumber(positions: &[[f64; 3]], corners: &[u32], model_starts: &[usize]) -> ObjTriangles {
    let triangle_count = corners.len() / 3;
    let mut ends: Vec<usize> = model_starts
        .iter()
        .copied()
        .filter(|&t| t > 0 && t < triangle_count)
        .collect();
    ends.dedup();
    ends.push(triangle_count);
    let mut vertices = Vec::with_capacity(positions.len());
    let mut triangles = Vec::with_capacity(triangle_count);
    let mut new_index = vec![u32::MAX; positions.len()];
    let mut start = 0;
    for end in ends {
        let model = &corners[3 * start..3 * end];
        for corner in model.chunks_exact(3) {
            let triangle: [u32; 3] = std::array::from_fn(|k| {
                let old = corner[k] as usize;
                if new_index[old] == u32::MAX {
                    new_index[old] = vertices.len() as u32;
                    vertices.push(positions[old]);
                }
                new_index[old]
            });
            triangles.push(triangle);
        }
        // The next model numbers its vertices afresh.
        for &old in model {
            new_index[old as usize] = u32::MAX;
        }
        start = end;
    }
    ObjTriangles {
        positions: vertices,
        triangles,
    }
}

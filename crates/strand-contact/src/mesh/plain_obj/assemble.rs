//! The pieces of a plain OBJ file joined into the vertices and triangles tobj gives.

use rayon::prelude::*;

use super::ObjTriangles;
use super::chunk::Chunk;

/// Joins the parsed pieces of a file (in file order). `None` when a reference is one
/// the plain path does not accept (tobj decides those).
pub(super) fn assemble(mut chunks: Vec<Chunk>) -> Option<ObjTriangles> {
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

    // Every corner as a vertex index of the file, in place (pieces in parallel).
    chunks
        .par_iter_mut()
        .zip(vertex_offsets.par_iter())
        .for_each(|(chunk, &offset)| {
            for &(slot, from_start) in &chunk.relative {
                chunk.corners[slot] = (offset + from_start) as u32;
            }
        });
    let corners: Vec<&[u32]> = chunks.iter().map(|c| c.corners.as_slice()).collect();
    let positions: Vec<&[[f64; 3]]> = chunks.iter().map(|c| c.positions.as_slice()).collect();
    Some(renumber(
        &positions,
        &vertex_offsets,
        &corners,
        corner_count,
        &model_starts,
    ))
}

/// tobj's vertex order: the triangles split into models at `model_starts` (where the
/// model so far has triangles), and each model's vertices in the order its triangles
/// first use them (a vertex used by two models appears twice, unused ones not at all).
/// The file's positions and corners are given piece by piece (`positions[k]` starting
/// at vertex `vertex_offsets[k]`), `corner_count` corners in all.
fn renumber(
    positions: &[&[[f64; 3]]],
    vertex_offsets: &[i64],
    corners: &[&[u32]],
    corner_count: usize,
    model_starts: &[usize],
) -> ObjTriangles {
    let triangle_count = corner_count / 3;
    let mut ends: Vec<usize> = model_starts
        .iter()
        .copied()
        .filter(|&t| t > 0 && t < triangle_count)
        .collect();
    ends.dedup();
    ends.push(triangle_count);
    let vertex_count = positions.iter().map(|p| p.len()).sum();
    let position = |old: usize| {
        let piece = vertex_offsets.partition_point(|&offset| offset as usize <= old) - 1;
        positions[piece][old - vertex_offsets[piece] as usize]
    };
    let mut vertices = Vec::with_capacity(vertex_count);
    let mut triangles = Vec::with_capacity(triangle_count);
    let mut new_index = vec![u32::MAX; vertex_count];
    // With several models, the file index of each vertex of the current one.
    let several = ends.len() > 1;
    let mut model_vertices: Vec<u32> = Vec::new();
    // The triangles in file order, piece by piece; `ends[model]` ends the current
    // model.
    let mut model = 0;
    for piece in corners {
        for corner in piece.chunks_exact(3) {
            if triangles.len() == ends[model] {
                // The next model numbers its vertices afresh.
                for old in model_vertices.drain(..) {
                    new_index[old as usize] = u32::MAX;
                }
                model += 1;
            }
            let mut triangle = [0u32; 3];
            for (new, &old) in triangle.iter_mut().zip(corner) {
                let old = old as usize;
                if new_index[old] == u32::MAX {
                    new_index[old] = vertices.len() as u32;
                    vertices.push(position(old));
                    if several {
                        model_vertices.push(old as u32);
                    }
                }
                *new = new_index[old];
            }
            triangles.push(triangle);
        }
    }
    ObjTriangles {
        positions: vertices,
        triangles,
    }
}

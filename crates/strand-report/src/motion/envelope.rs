//! The swept envelope of each hose over a motion (`DIR/envelope.obj`): the union of
//! the hose's tubes over every pose and between neighbouring poses, as a closed
//! triangle mesh usable as a keep-out zone in CAD.
//!
//! Construction: a voxel grid of pitch `h` (a third of the hose radius by default);
//! a voxel is in the envelope when its centre lies within `r + h·√3/2` of the hose's
//! centreline at some pose or at one of the poses linearly interpolated between
//! neighbouring ones, so every voxel the tube touches is in it (the envelope contains
//! every tube). Voxel configurations that would make the boundary non-manifold (two
//! voxels meeting only along an edge or at a corner) are filled, which only enlarges
//! the envelope. The mesh is the boundary of the voxel set: closed, consistently
//! oriented (normals outwards), every edge shared by exactly two triangles.
//!
//! Work: per pose and segment, the voxels within the segment's box grown by the
//! radius; the grid covers the hoses' bounding box only.

use std::collections::HashMap;
use std::fmt::Write;

use nalgebra::Vector3;

use crate::ResultDoc;

/// Centreline samples between neighbouring poses (besides the poses themselves).
const BETWEEN: usize = 3;

/// The envelope of one hose: a voxel set and its boundary mesh.
#[derive(Clone, Debug)]
pub struct Envelope {
    /// The hose's name.
    pub rod: String,
    /// Voxel pitch, m.
    pub pitch_m: f64,
    /// Vertices of the boundary mesh, m.
    pub vertices: Vec<[f64; 3]>,
    /// Triangles of the boundary mesh (indices into `vertices`, counter-clockwise seen
    /// from outside).
    pub triangles: Vec<[usize; 3]>,
}

/// A dense voxel grid over a box.
struct Grid {
    origin: Vector3<f64>,
    pitch: f64,
    dims: [usize; 3],
    cells: Vec<bool>,
}

impl Grid {
    fn index(&self, i: [usize; 3]) -> usize {
        (i[2] * self.dims[1] + i[1]) * self.dims[0] + i[0]
    }

    fn get(&self, i: [i64; 3]) -> bool {
        if (0..3).any(|a| i[a] < 0 || i[a] >= self.dims[a] as i64) {
            return false;
        }
        self.cells[self.index([i[0] as usize, i[1] as usize, i[2] as usize])]
    }

    fn set(&mut self, i: [i64; 3]) {
        let k = self.index([i[0] as usize, i[1] as usize, i[2] as usize]);
        self.cells[k] = true;
    }

    fn centre(&self, i: [i64; 3]) -> Vector3<f64> {
        self.origin
            + Vector3::new(i[0] as f64 + 0.5, i[1] as f64 + 0.5, i[2] as f64 + 0.5) * self.pitch
    }

    /// Marks every voxel whose centre is within `reach` of segment `a b`.
    fn capsule(&mut self, a: &Vector3<f64>, b: &Vector3<f64>, reach: f64) {
        let lo = a.inf(b).add_scalar(-reach) - self.origin;
        let hi = a.sup(b).add_scalar(reach) - self.origin;
        let (pitch, dims) = (self.pitch, self.dims);
        let range = move |axis: usize| {
            let from = ((lo[axis] / pitch).floor() as i64).max(0);
            let to = ((hi[axis] / pitch).ceil() as i64).min(dims[axis] as i64 - 1);
            from..=to
        };
        let ab = b - a;
        let len2 = ab.norm_squared();
        for z in range(2) {
            for y in range(1) {
                for x in range(0) {
                    let p = self.centre([x, y, z]);
                    let t = if len2 > 0.0 {
                        ((p - a).dot(&ab) / len2).clamp(0.0, 1.0)
                    } else {
                        0.0
                    };
                    if (p - (a + ab * t)).norm() <= reach {
                        self.set([x, y, z]);
                    }
                }
            }
        }
    }

    /// Fills voxels until the boundary is a manifold: in every 2×2×2 block, the
    /// filled and the empty voxels are each connected through shared faces within
    /// the block (else the whole block is filled).
    fn make_manifold(&mut self) {
        loop {
            let mut changed = false;
            for z in -1..self.dims[2] as i64 {
                for y in -1..self.dims[1] as i64 {
                    for x in -1..self.dims[0] as i64 {
                        let cell = |k: usize| {
                            [
                                x + (k & 1) as i64,
                                y + ((k >> 1) & 1) as i64,
                                z + ((k >> 2) & 1) as i64,
                            ]
                        };
                        let mask: u8 = (0..8)
                            .filter(|&k| self.get(cell(k)))
                            .fold(0, |m, k| m | (1 << k));
                        if mask == 0 || mask == 0xff {
                            continue;
                        }
                        if !(face_connected(mask) && face_connected(!mask)) {
                            for k in 0..8 {
                                let c = cell(k);
                                if (0..3).all(|a| c[a] >= 0 && c[a] < self.dims[a] as i64) {
                                    self.set(c);
                                }
                            }
                            changed = true;
                        }
                    }
                }
            }
            if !changed {
                return;
            }
        }
    }
}

/// Whether the voxels of a 2×2×2 block in `mask` (bit `x + 2y + 4z`) are connected
/// through shared faces.
fn face_connected(mask: u8) -> bool {
    let Some(first) = (0..8).find(|k| mask & (1 << k) != 0) else {
        return true;
    };
    let mut seen = 1u8 << first;
    let mut stack = vec![first];
    while let Some(k) = stack.pop() {
        for bit in [1, 2, 4] {
            let n = k ^ bit;
            if mask & (1 << n) != 0 && seen & (1 << n) == 0 {
                seen |= 1 << n;
                stack.push(n);
            }
        }
    }
    seen == mask
}

/// The envelope of rod `rod` over the poses `docs` (in order of the parameter), with
/// tube radius `radius_m` and voxel pitch `pitch_m`; `None` if no pose has the rod.
pub fn envelope_of(
    docs: &[&ResultDoc],
    rod: &str,
    radius_m: f64,
    pitch_m: f64,
) -> Option<Envelope> {
    let lines: Vec<Vec<Vector3<f64>>> = docs
        .iter()
        .filter_map(|d| d.rods.iter().find(|r| r.name == rod))
        .map(|r| r.position_m.iter().map(|p| Vector3::from(*p)).collect())
        .collect();
    let first = lines.first()?;
    let reach = radius_m + pitch_m * 3f64.sqrt() / 2.0;
    let (mut lo, mut hi) = (first[0], first[0]);
    for p in lines.iter().flatten() {
        lo = lo.inf(p);
        hi = hi.sup(p);
    }
    let margin = reach + 2.0 * pitch_m;
    let origin = lo.add_scalar(-margin);
    let dims =
        [0, 1, 2].map(|a| (((hi[a] - lo[a] + 2.0 * margin) / pitch_m).ceil() as usize).max(1));
    let mut grid = Grid {
        origin,
        pitch: pitch_m,
        dims,
        cells: vec![false; dims[0] * dims[1] * dims[2]],
    };
    let mut sweep = |line: &[Vector3<f64>]| {
        for w in line.windows(2) {
            grid.capsule(&w[0], &w[1], reach);
        }
    };
    for (k, line) in lines.iter().enumerate() {
        sweep(line);
        if let Some(next) = lines.get(k + 1).filter(|n| n.len() == line.len()) {
            for j in 1..=BETWEEN {
                let t = j as f64 / (BETWEEN + 1) as f64;
                let mid: Vec<Vector3<f64>> = line
                    .iter()
                    .zip(next)
                    .map(|(a, b)| a + (b - a) * t)
                    .collect();
                sweep(&mid);
            }
        }
    }
    grid.make_manifold();
    let (vertices, triangles) = boundary(&grid);
    Some(Envelope {
        rod: rod.to_string(),
        pitch_m,
        vertices,
        triangles,
    })
}

/// The boundary faces of the voxel set, two triangles per face, corners shared.
fn boundary(grid: &Grid) -> (Vec<[f64; 3]>, Vec<[usize; 3]>) {
    let mut index: HashMap<[i64; 3], usize> = HashMap::new();
    let mut vertices = Vec::new();
    let mut triangles = Vec::new();
    let mut corner = |c: [i64; 3], vertices: &mut Vec<[f64; 3]>| -> usize {
        *index.entry(c).or_insert_with(|| {
            let p = grid.origin + Vector3::new(c[0] as f64, c[1] as f64, c[2] as f64) * grid.pitch;
            vertices.push([p.x, p.y, p.z]);
            vertices.len() - 1
        })
    };
    for z in 0..grid.dims[2] as i64 {
        for y in 0..grid.dims[1] as i64 {
            for x in 0..grid.dims[0] as i64 {
                if !grid.get([x, y, z]) {
                    continue;
                }
                for axis in 0..3 {
                    for side in [-1i64, 1] {
                        let mut n = [x, y, z];
                        n[axis] += side;
                        if grid.get(n) {
                            continue;
                        }
                        // The face's corners, counter-clockwise seen from outside.
                        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
                        let mut base = [x, y, z];
                        if side > 0 {
                            base[axis] += 1;
                        }
                        let at = |du: i64, dv: i64| {
                            let mut c = base;
                            c[u] += du;
                            c[v] += dv;
                            c
                        };
                        let mut quad = [at(0, 0), at(1, 0), at(1, 1), at(0, 1)];
                        if side < 0 {
                            quad.reverse();
                        }
                        let q = quad.map(|c| corner(c, &mut vertices));
                        triangles.push([q[0], q[1], q[2]]);
                        triangles.push([q[0], q[2], q[3]]);
                    }
                }
            }
        }
    }
    (vertices, triangles)
}

/// The envelope of every rod over the poses `docs` as one OBJ (one object per hose),
/// coordinates in the unit of `metres` m per unit named `unit` (the case's), with the
/// voxel pitch of each hose a third of its tube radius (`radius_m` per rod name).
pub fn envelope_obj(
    docs: &[&ResultDoc],
    radius_m: &[(String, f64)],
    metres: f64,
    unit: &str,
) -> (String, Vec<Envelope>) {
    let mut obj = format!(
        "# strand motion envelope: the space each hose sweeps over the motion, closed mesh, {unit}\n"
    );
    let mut envelopes = Vec::new();
    let mut offset = 0;
    for (rod, radius) in radius_m {
        let Some(env) = envelope_of(docs, rod, *radius, radius / 3.0) else {
            continue;
        };
        let _ = writeln!(obj, "o {rod}_envelope");
        for v in &env.vertices {
            let _ = writeln!(
                obj,
                "v {} {} {}",
                v[0] / metres,
                v[1] / metres,
                v[2] / metres
            );
        }
        for t in &env.triangles {
            let _ = writeln!(
                obj,
                "f {} {} {}",
                t[0] + offset + 1,
                t[1] + offset + 1,
                t[2] + offset + 1
            );
        }
        offset += env.vertices.len();
        envelopes.push(env);
    }
    (obj, envelopes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn face_connectivity_of_blocks() {
        assert!(face_connected(0b0000_0011)); // two along x
        assert!(!face_connected(0b0000_1001)); // diagonal in the z = 0 plane
        assert!(!face_connected(0b1000_0001)); // opposite corners
        assert!(face_connected(0b0000_0000));
    }

    #[test]
    fn boundary_is_closed_and_oriented() {
        let mut grid = Grid {
            origin: Vector3::zeros(),
            pitch: 1.0,
            dims: [4, 4, 4],
            cells: vec![false; 64],
        };
        grid.set([1, 1, 1]);
        grid.set([2, 2, 1]);
        grid.make_manifold();
        let (v, t) = boundary(&grid);
        let mut edges: HashMap<(usize, usize), i32> = HashMap::new();
        for tri in &t {
            for k in 0..3 {
                *edges.entry((tri[k], tri[(k + 1) % 3])).or_default() += 1;
            }
        }
        // Every directed edge once, and its reverse once.
        assert!(
            edges
                .iter()
                .all(|(&(a, b), &n)| n == 1 && edges.get(&(b, a)) == Some(&1))
        );
        // Outward normals: the signed volume is the filled volume.
        let volume: f64 = t
            .iter()
            .map(|tri| {
                let [a, b, c] = tri.map(|i| Vector3::from(v[i]));
                a.dot(&b.cross(&c)) / 6.0
            })
            .sum();
        let filled = grid.cells.iter().filter(|c| **c).count() as f64;
        assert!((volume - filled).abs() < 1e-9, "{volume} vs {filled}");
        assert!(filled >= 4.0, "the diagonal pair is joined");
    }
}

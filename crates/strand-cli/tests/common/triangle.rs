//! The point of a triangle closest to a point, written for the tests that check the
//! solver's contact geometry by brute force (independent of parry): Ericson's
//! Voronoi-region method on plain `[f64; 3]` vectors.

/// A point or vector, m or mm as the caller's data.
pub type V = [f64; 3];

/// `a − b`.
pub fn sub(a: V, b: V) -> V {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// `a · b`.
pub fn dot(a: V, b: V) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// `a + t d`.
pub fn along(a: V, d: V, t: f64) -> V {
    [a[0] + t * d[0], a[1] + t * d[1], a[2] + t * d[2]]
}

/// The point of triangle `abc` closest to `p` (Ericson, Real-Time Collision
/// Detection, 5.1.5).
pub fn closest_on_triangle(p: V, a: V, b: V, c: V) -> V {
    let (ab, ac, ap) = (sub(b, a), sub(c, a), sub(p, a));
    let (d1, d2) = (dot(ab, ap), dot(ac, ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = sub(p, b);
    let (d3, d4) = (dot(ab, bp), dot(ac, bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return along(a, ab, d1 / (d1 - d3));
    }
    let cp = sub(p, c);
    let (d5, d6) = (dot(ab, cp), dot(ac, cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return along(a, ac, d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        return along(b, sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = 1.0 / (va + vb + vc);
    let (v, w) = (vb * denom, vc * denom);
    along(along(a, ab, v), ac, w)
}

/// Every triangle of an OBJ file (global 1-based indices; polygons fanned from their
/// first corner), in the file's units.
pub fn obj_triangles(path: &std::path::Path) -> Vec<[V; 3]> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut vertices = Vec::new();
    let mut out = Vec::new();
    for line in text.lines() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => {
                let v: Vec<f64> = words.map(|t| t.parse().unwrap()).collect();
                vertices.push([v[0], v[1], v[2]]);
            }
            Some("f") => {
                let i: Vec<usize> = words
                    .map(|t| t.split('/').next().unwrap().parse::<usize>().unwrap() - 1)
                    .collect();
                for k in 1..i.len() - 1 {
                    out.push([vertices[i[0]], vertices[i[k]], vertices[i[k + 1]]]);
                }
            }
            _ => {}
        }
    }
    out
}

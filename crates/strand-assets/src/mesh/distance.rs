//! Exact point–triangle distance and the brute-force point–mesh distance.

use nalgebra::Point3;

use super::TriangleMesh;

/// The point of triangle `(a, b, c)` closest to `p` (Ericson, *Real-Time Collision
/// Detection*, 5.1.5: Voronoi regions of vertices, edges and face). Degenerate
/// triangles are handled (the result lies on the segment or point they reduce to).
pub fn closest_point_on_triangle(
    p: &Point3<f64>,
    a: &Point3<f64>,
    b: &Point3<f64>,
    c: &Point3<f64>,
) -> Point3<f64> {
    let ab = b - a;
    let ac = c - a;
    let ap = p - a;
    let d1 = ab.dot(&ap);
    let d2 = ac.dot(&ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return *a;
    }
    let bp = p - b;
    let d3 = ab.dot(&bp);
    let d4 = ac.dot(&bp);
    if d3 >= 0.0 && d4 <= d3 {
        return *b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return a + ab * v;
    }
    let cp = p - c;
    let d5 = ab.dot(&cp);
    let d6 = ac.dot(&cp);
    if d6 >= 0.0 && d5 <= d6 {
        return *c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return a + ac * w;
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return b + (c - b) * w;
    }
    let denom = va + vb + vc;
    if denom.abs() <= f64::MIN_POSITIVE {
        // Degenerate (collinear) triangle that slipped through: best of its edges.
        return [(a, b), (b, c), (c, a)]
            .into_iter()
            .map(|(s, e)| closest_on_segment(p, s, e))
            .min_by(|x, y| (x - p).norm_squared().total_cmp(&(y - p).norm_squared()))
            .unwrap_or(*a);
    }
    let v = vb / denom;
    let w = vc / denom;
    a + ab * v + ac * w
}

fn closest_on_segment(p: &Point3<f64>, s: &Point3<f64>, e: &Point3<f64>) -> Point3<f64> {
    let d = e - s;
    let len2 = d.norm_squared();
    if len2 == 0.0 {
        return *s;
    }
    s + d * ((p - s).dot(&d) / len2).clamp(0.0, 1.0)
}

impl TriangleMesh {
    /// Distance from `p` to the nearest point of any triangle, by checking every
    /// triangle (brute force: meant for checks and small meshes). Unsigned: a point
    /// inside a closed mesh gets its distance to the surface. `None` for an empty mesh.
    pub fn distance_to_point(&self, p: &Point3<f64>) -> Option<f64> {
        (0..self.triangles.len())
            .map(|t| {
                let [a, b, c] = self.triangle_points(t);
                (closest_point_on_triangle(p, &a, &b, &c) - p).norm()
            })
            .min_by(f64::total_cmp)
    }

    /// Whether `p` is inside this closed, outward-oriented mesh (generalised winding
    /// number above ½). Meaningless for open meshes.
    pub fn contains_point(&self, p: &Point3<f64>) -> bool {
        let mut solid_angle = 0.0;
        for t in 0..self.triangles.len() {
            let [a, b, c] = self.triangle_points(t);
            let (a, b, c) = (a - p, b - p, c - p);
            let (la, lb, lc) = (a.norm(), b.norm(), c.norm());
            let numerator = a.dot(&b.cross(&c));
            let denominator = la * lb * lc + a.dot(&b) * lc + b.dot(&c) * la + c.dot(&a) * lb;
            solid_angle += 2.0 * numerator.atan2(denominator);
        }
        solid_angle / (4.0 * std::f64::consts::PI) > 0.5
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::Point3;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    use super::closest_point_on_triangle;

    /// Distance to the triangle by dense barycentric sampling (an upper bound that
    /// converges to the true distance).
    fn sampled_distance(p: &Point3<f64>, a: &Point3<f64>, b: &Point3<f64>, c: &Point3<f64>) -> f64 {
        let n = 300;
        let mut best = f64::INFINITY;
        for i in 0..=n {
            for j in 0..=(n - i) {
                let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
                let q = a + (b - a) * u + (c - a) * v;
                best = best.min((q - p).norm());
            }
        }
        best
    }

    #[test]
    fn closest_point_matches_dense_sampling_in_every_voronoi_region() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let mut random_point = |s: f64| {
            Point3::new(
                rng.random_range(-s..s),
                rng.random_range(-s..s),
                rng.random_range(-s..s),
            )
        };
        for _ in 0..60 {
            let (a, b, c) = (random_point(1.0), random_point(1.0), random_point(1.0));
            let p = random_point(2.0);
            let q = closest_point_on_triangle(&p, &a, &b, &c);
            let exact = (q - p).norm();
            let sampled = sampled_distance(&p, &a, &b, &c);
            // Sampling can only be farther; its error is below the grid spacing (~1/300 of an edge).
            assert!(
                exact <= sampled + 1e-12,
                "exact {exact} > sampled {sampled}"
            );
            assert!(sampled - exact < 0.02, "exact {exact} vs sampled {sampled}");
        }
    }

    #[test]
    fn degenerate_triangles_reduce_to_segments() {
        let a = Point3::new(0.0, 0.0, 0.0);
        let b = Point3::new(1.0, 0.0, 0.0);
        let p = Point3::new(0.5, 2.0, 0.0);
        let q = closest_point_on_triangle(&p, &a, &b, &b);
        assert!((q - Point3::new(0.5, 0.0, 0.0)).norm() < 1e-12);
    }
}

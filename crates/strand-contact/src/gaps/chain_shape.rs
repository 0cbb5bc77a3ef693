//! The shape of every run of consecutive edges in an [`EdgeTree`](super::edge_tree):
//! a bounding sphere and a cone holding the edges' directions, per tree node.
//!
//! With them a query tells, for a whole run at once, that the distance from a given
//! segment grows (or shrinks) strictly along the run, so that no edge inside it can be
//! a local minimum of the distance (see `rod_rod_minima`).

use nalgebra::{Point3, Vector3};

/// Sphere and direction cone of a run of edges of one rod.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Shape {
    /// Centre of a sphere holding every point of the run's edges, m.
    pub(crate) centre: Point3<f64>,
    /// Its radius, m.
    pub(crate) radius: f64,
    /// Unit axis of the cone of the edges' directions (in the order of the edges).
    pub(crate) axis: Vector3<f64>,
    /// Half-angle of that cone, rad (∞: no cone below a right angle holds them).
    pub(crate) spread: f64,
    /// Length of the run's shortest edge, m.
    pub(crate) shortest: f64,
    /// The rod of the run's edges; `None` for a run over two rods or with no edges.
    pub(crate) rod: Option<usize>,
}

impl Shape {
    const EMPTY: Shape = Shape {
        centre: Point3::new(0.0, 0.0, 0.0),
        radius: -1.0,
        axis: Vector3::new(0.0, 0.0, 0.0),
        spread: f64::INFINITY,
        shortest: f64::INFINITY,
        rod: None,
    };

    /// The shape of edge `[a, b]` of rod `rod`.
    pub(crate) fn of_edge(rod: usize, a: &Point3<f64>, b: &Point3<f64>) -> Self {
        let direction = b - a;
        let length = direction.norm();
        let (axis, spread) = match direction.try_normalize(0.0) {
            Some(axis) => (axis, 0.0),
            None => (Vector3::zeros(), f64::INFINITY),
        };
        Self {
            centre: nalgebra::center(a, b),
            radius: 0.5 * length,
            axis,
            spread,
            shortest: length,
            rod: Some(rod),
        }
    }

    /// The shape of two runs together (a conservative sphere and cone).
    fn merged(&self, other: &Shape) -> Shape {
        if self.radius < 0.0 {
            return *other;
        }
        if other.radius < 0.0 {
            return *self;
        }
        // The smallest sphere holding both spheres.
        let offset = other.centre - self.centre;
        let distance = offset.norm();
        let (centre, radius) = if distance + other.radius <= self.radius {
            (self.centre, self.radius)
        } else if distance + self.radius <= other.radius {
            (other.centre, other.radius)
        } else {
            let radius = 0.5 * (distance + self.radius + other.radius);
            let centre = self.centre + offset * ((radius - self.radius) / distance);
            (centre, radius)
        };
        let (axis, spread) = match (self.axis + other.axis).try_normalize(0.0) {
            Some(axis) if self.spread.is_finite() && other.spread.is_finite() => {
                let angle = |v: &Vector3<f64>| axis.dot(v).clamp(-1.0, 1.0).acos();
                let spread =
                    (angle(&self.axis) + self.spread).max(angle(&other.axis) + other.spread);
                if spread < std::f64::consts::FRAC_PI_2 {
                    (axis, spread)
                } else {
                    (axis, f64::INFINITY)
                }
            }
            _ => (Vector3::zeros(), f64::INFINITY),
        };
        Shape {
            centre,
            radius,
            axis,
            spread,
            shortest: self.shortest.min(other.shortest),
            rod: if self.rod == other.rod {
                self.rod
            } else {
                None
            },
        }
    }
}

/// The shapes of the nodes of a complete binary tree over a list of edges (node `k`
/// has children `2k` and `2k + 1`, leaves from `size`: the layout of `EdgeTree`).
pub(crate) struct ChainShapes {
    shapes: Vec<Shape>,
}

impl ChainShapes {
    /// The shapes over `leaves` (one per edge, in the tree's order), bottom-up.
    pub(crate) fn new(leaves: &[Shape]) -> Self {
        let size = leaves.len().next_power_of_two().max(1);
        let mut shapes = vec![Shape::EMPTY; 2 * size];
        shapes[size..size + leaves.len()].copy_from_slice(leaves);
        for k in (1..size).rev() {
            shapes[k] = shapes[2 * k].merged(&shapes[2 * k + 1]);
        }
        Self { shapes }
    }

    /// The shape of tree node `node`.
    pub(crate) fn node(&self, node: usize) -> &Shape {
        &self.shapes[node]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_node_holds_its_edges_points_and_directions() {
        // A helix of 37 edges, two rods (the second from edge 20).
        let points: Vec<Point3<f64>> = (0..=37)
            .map(|j| {
                let phi = 0.21 * j as f64;
                Point3::new(phi.cos(), phi.sin(), 0.1 * phi)
            })
            .collect();
        let leaves: Vec<Shape> = points
            .windows(2)
            .enumerate()
            .map(|(j, w)| Shape::of_edge(usize::from(j >= 20), &w[0], &w[1]))
            .collect();
        let shapes = ChainShapes::new(&leaves);
        let size = leaves.len().next_power_of_two();
        for node in 1..size {
            // The node's edges: leaves [first, first + count).
            let level = usize::BITS - 1 - node.leading_zeros();
            let count = size >> level;
            let first = (node - (1 << level)) * count;
            let edges = first..(first + count).min(leaves.len());
            let shape = shapes.node(node);
            if edges.is_empty() {
                continue;
            }
            let rods: Vec<usize> = edges.clone().map(|j| usize::from(j >= 20)).collect();
            let one_rod = rods.iter().all(|&r| r == rods[0]);
            assert_eq!(shape.rod, one_rod.then_some(rods[0]), "node {node}");
            for j in edges.clone() {
                for p in [points[j], points[j + 1]] {
                    assert!((p - shape.centre).norm() <= shape.radius * (1.0 + 1e-12));
                }
                if shape.spread.is_finite() {
                    let direction = (points[j + 1] - points[j]).normalize();
                    let angle = shape.axis.dot(&direction).clamp(-1.0, 1.0).acos();
                    // acos near 1 loses half the digits: 1e-8 rad.
                    assert!(angle <= shape.spread + 1e-7, "node {node} edge {j}");
                }
                assert!(shape.shortest <= (points[j + 1] - points[j]).norm());
            }
        }
        // Small runs of a gentle helix have a cone; the whole helix turns too far.
        assert!(shapes.node(size + 3).spread == 0.0);
        assert!(shapes.node((size + 4) / 2).spread.is_finite());
        assert!(shapes.node(1).spread.is_infinite());
    }
}

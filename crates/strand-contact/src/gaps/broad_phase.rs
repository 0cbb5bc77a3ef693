//! Broad phase: pairs of overlapping axis-aligned boxes by sweep and prune.

use nalgebra::Point3;

/// An axis-aligned bounding box, m.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Smallest corner.
    pub min: Point3<f64>,
    /// Largest corner.
    pub max: Point3<f64>,
}

impl Aabb {
    /// The box of segment `[a, b]` grown by `inflation` (m) on every side.
    pub fn of_segment(a: &Point3<f64>, b: &Point3<f64>, inflation: f64) -> Self {
        let grow = nalgebra::Vector3::repeat(inflation);
        Self {
            min: a.inf(b) - grow,
            max: a.sup(b) + grow,
        }
    }

    /// The box grown by `inflation` (m) on every side.
    pub fn grown(&self, inflation: f64) -> Self {
        let grow = nalgebra::Vector3::repeat(inflation);
        Self {
            min: self.min - grow,
            max: self.max + grow,
        }
    }

    /// Whether the two boxes overlap (touching counts).
    pub fn overlaps(&self, other: &Aabb) -> bool {
        (0..3).all(|k| self.min[k] <= other.max[k] && other.min[k] <= self.max[k])
    }
}

/// Every pair `(i, j)`, `i < j`, of overlapping boxes (touching counts), sorted.
///
/// Sweep and prune along the axis in which the box centres are most spread out:
/// `O(n log n + k)` for `k` pairs overlapping along that axis.
pub fn overlapping_pairs(boxes: &[Aabb]) -> Vec<(usize, usize)> {
    let axis = sweep_axis(boxes);
    let mut order: Vec<usize> = (0..boxes.len()).collect();
    order.sort_unstable_by(|&a, &b| boxes[a].min[axis].total_cmp(&boxes[b].min[axis]));
    let mut pairs = Vec::new();
    for (position, &i) in order.iter().enumerate() {
        let reach = boxes[i].max[axis];
        for &j in &order[position + 1..] {
            if boxes[j].min[axis] > reach {
                break;
            }
            if boxes[i].overlaps(&boxes[j]) {
                pairs.push((i.min(j), i.max(j)));
            }
        }
    }
    pairs.sort_unstable();
    pairs
}

/// The axis of largest variance of the box centres.
fn sweep_axis(boxes: &[Aabb]) -> usize {
    let n = boxes.len().max(1) as f64;
    let centre = |b: &Aabb, k: usize| 0.5 * (b.min[k] + b.max[k]);
    let variance = |k: usize| {
        let mean = boxes.iter().map(|b| centre(b, k)).sum::<f64>() / n;
        boxes
            .iter()
            .map(|b| (centre(b, k) - mean).powi(2))
            .sum::<f64>()
    };
    let spread = [variance(0), variance(1), variance(2)];
    (0..3)
        .max_by(|&a, &b| spread[a].total_cmp(&spread[b]))
        .unwrap_or(0)
}

//! Exact distance between a segment and an axis-aligned box: the BVH's lower bound.
//!
//! A box-to-box bound (the segment's bounding box against a node's) is loose for a
//! long diagonal segment hovering over a surface: every triangle under the segment's
//! bounding square would be tested. The exact distance keeps only the strip along
//! the segment.

use parry3d_f64::math::Vector as GlamVector;

/// Distance between the box `[min, max]` and the box `[segment_min, segment_max]` (a
/// cheap lower bound of the segment–box distance), m.
#[inline]
pub(crate) fn box_box_distance(
    min: GlamVector,
    max: GlamVector,
    segment_min: GlamVector,
    segment_max: GlamVector,
) -> f64 {
    (min - segment_max)
        .max(segment_min - max)
        .max(GlamVector::ZERO)
        .length()
}

/// Exact distance between segment `p + s d`, `s ∈ [0, 1]`, and the box `[min, max]`, m.
///
/// The squared distance is a convex piecewise quadratic in `s` whose pieces end where
/// a coordinate crosses a face plane of the box; the pieces are walked in order of
/// `s`, each minimised in closed form, and the walk stops at the first piece whose
/// minimiser lies before its end: by convexity the function does not decrease after
/// it. A point (`d = 0`) is one piece.
pub(crate) fn segment_box_distance(
    p: GlamVector,
    d: GlamVector,
    min: GlamVector,
    max: GlamVector,
) -> f64 {
    let mut breaks = [0.0_f64; 8];
    breaks[1] = 1.0;
    let mut count = 2;
    for k in 0..3 {
        if d[k] != 0.0 {
            for bound in [min[k], max[k]] {
                let s = (bound - p[k]) / d[k];
                if s > 0.0 && s < 1.0 {
                    breaks[count] = s;
                    count += 1;
                }
            }
        }
    }
    let breaks = &mut breaks[..count];
    // Insertion sort: at most eight values, most of them already in place.
    for i in 2..breaks.len() {
        let mut j = i;
        while breaks[j - 1] > breaks[j] {
            breaks.swap(j - 1, j);
            j -= 1;
        }
    }
    let mut best = f64::INFINITY;
    for piece in breaks.windows(2) {
        let (s0, s1) = (piece[0], piece[1]);
        let middle = 0.5 * (s0 + s1);
        // On this piece each axis is below, inside or above the box: its term is
        // (offset_k + s d_k)² or 0 (offset 0 and direction 0 inside).
        let (mut offset_dot, mut d_dot) = (0.0, 0.0);
        let mut offsets = [0.0; 3];
        let mut directions = [0.0; 3];
        for k in 0..3 {
            let x = p[k] + middle * d[k];
            let offset = if x < min[k] {
                p[k] - min[k]
            } else if x > max[k] {
                p[k] - max[k]
            } else {
                continue;
            };
            offsets[k] = offset;
            directions[k] = d[k];
            offset_dot += offset * d[k];
            d_dot += d[k] * d[k];
        }
        let unclamped = if d_dot > 0.0 { -offset_dot / d_dot } else { s0 };
        let s = unclamped.clamp(s0, s1);
        let squared: f64 = (0..3)
            .map(|k| (offsets[k] + s * directions[k]).powi(2))
            .sum();
        best = best.min(squared);
        if best == 0.0 || unclamped < s1 {
            break;
        }
    }
    best.sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point_box(x: GlamVector, min: GlamVector, max: GlamVector) -> f64 {
        (min - x).max(x - max).max(GlamVector::ZERO).length()
    }

    /// Against dense sampling of `s` (an upper bound within the sampling error) on
    /// pseudo-random segments and boxes.
    #[test]
    fn matches_dense_sampling() {
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        for case in 0..2000 {
            let min = GlamVector::new(next(), next(), next()) * 0.5;
            let max = min + GlamVector::new(next().abs(), next().abs(), next().abs()) * 0.5;
            let p = GlamVector::new(next(), next(), next()) * 1.5;
            let d = if case % 10 == 0 {
                GlamVector::new(next(), 0.0, 0.0)
            } else {
                GlamVector::new(next(), next(), next())
            };
            let exact = segment_box_distance(p, d, min, max);
            let samples = 20_000;
            let sampled = (0..=samples)
                .map(|i| point_box(p + d * (i as f64 / samples as f64), min, max))
                .fold(f64::INFINITY, f64::min);
            // The exact value is a lower bound and the sampling error is ≤ |d| / samples.
            assert!(exact <= sampled + 1e-14, "case {case}: {exact} > {sampled}");
            assert!(
                sampled - exact <= d.length() / samples as f64 + 1e-14,
                "case {case}"
            );
            let bound = box_box_distance(min, max, p.min(p + d), p.max(p + d));
            assert!(bound <= exact + 1e-14);
        }
    }
}

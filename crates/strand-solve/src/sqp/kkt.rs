//! The KKT system of one group's active rows, `[H Aᵀ; A 0] (δ, μ) = (0, r)`, in profile
//! (envelope) form and factorised as `L D Lᵀ` without forming `A H⁻¹ Aᵀ`.
//!
//! The group's unknowns keep their numbering along the rod (a narrow band), and each
//! row's multiplier is numbered right after the last unknown its gradient reaches, so
//! it only widens the band around its own support: the factorisation costs
//! `O((unknowns + rows) · width²)` for a profile `width` of a few blocks, instead of one
//! solve over all unknowns per row (`O(rows × unknowns)`) and a dense `rows × rows`
//! Schur matrix. No pivoting is needed: with `H` positive definite and rows independent
//! on every leading block, every unknown's pivot is positive and every multiplier's
//! negative (the inertia of a KKT matrix); a pivot of the wrong sign means the rows are
//! dependent, where the Schur complement would not be positive definite either.

use crate::constraints::Row;

/// Largest average profile width of the group's Hessian, in unknowns per row, for
/// which the KKT system is used (a rod numbered along its length has at most 12).
pub(super) const MAX_AVERAGE_WIDTH: usize = 24;

/// Estimated multiply–adds of one group's steps, to choose between the methods.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct PassCosts {
    /// One pass with the KKT system (factorisation and solve).
    pub kkt_pass: usize,
    /// One solve with the Hessian's factor over the group's unknowns.
    pub solve: usize,
}

/// What the KKT system of one group reads.
pub(super) struct KktInput<'a> {
    /// The factorised matrix `H`: upper CSC column pointers, row indices and values.
    pub col_ptr: &'a [usize],
    pub row_idx: &'a [usize],
    pub values: &'a [f64],
    /// All rows (indexed by the active list).
    pub rows: &'a [Row],
    /// The group's unknowns, in their order along the band.
    pub unknowns: &'a [usize],
    /// Per unknown: its position among its group's unknowns.
    pub local: &'a [usize],
}

/// The solution of one group's KKT system.
pub(super) struct KktSolution {
    /// The multipliers `λ = −μ` of the active rows, in their order.
    pub multipliers: Vec<f64>,
    /// The step correction `δ = H⁻¹ Aᵀ λ` on the group's unknowns, in their order.
    pub correction: Vec<f64>,
}

impl KktInput<'_> {
    /// The multiply–adds of one pass with the KKT system (its factorisation and solve,
    /// before the rows widen it) and of one solve with the group's Hessian factor, when
    /// the group's Hessian has a narrow profile along its numbering (average width at
    /// most [`MAX_AVERAGE_WIDTH`]); `None` otherwise. O(group's stored entries). The
    /// rows need no test: an active row widens only its own multiplier's profile row,
    /// by the span of its gradient (a contact reaches two vertices, a rod's
    /// self-contact or a contact between two rods further, at the cost of one solve
    /// over that span).
    pub(super) fn costs(&self) -> Option<PassCosts> {
        let (mut profile, mut squares) = (0, 0);
        for (p, &u) in self.unknowns.iter().enumerate() {
            let column = &self.row_idx[self.col_ptr[u]..self.col_ptr[u + 1]];
            let first = column.iter().map(|&r| self.local[r]).min().unwrap_or(p);
            let width = p + 1 - first.min(p);
            profile += width;
            squares += width * width;
        }
        (profile <= MAX_AVERAGE_WIDTH * self.unknowns.len().max(1)).then_some(PassCosts {
            kkt_pass: squares / 2 + 3 * profile,
            solve: 2 * profile,
        })
    }

    /// The last local unknown row `i` reaches (0 for no gradient: its multiplier's
    /// pivot is zero, and the solve fails as for dependent rows).
    fn last_unknown(&self, i: usize) -> usize {
        (self.rows[i].gradient.iter())
            .map(|&(k, _)| self.local[k])
            .max()
            .unwrap_or(0)
    }

    /// Solves the KKT system of the `active` rows (ascending) with the right-hand
    /// side `rhs` per active row (`−value − a·d_N`). Adds the multiply–adds of the
    /// factorisation and solve to `products`. `None` if a pivot has the wrong sign (the
    /// active rows are dependent on a leading block, or `H` is not positive definite).
    pub(super) fn solve(
        &self,
        active: &[usize],
        rhs: &[f64],
        products: &mut usize,
    ) -> Option<KktSolution> {
        let n = self.unknowns.len();
        let m = active.len();
        // The numbering: unknowns along the band, each row's multiplier right after the
        // last unknown it reaches.
        let mut order: Vec<(usize, usize)> =
            (0..m).map(|r| (self.last_unknown(active[r]), r)).collect();
        order.sort_unstable();
        let mut position = vec![0usize; n];
        let mut multiplier_position = vec![0usize; m];
        let mut next = order.iter().peekable();
        let mut count = 0;
        for (p, slot) in position.iter_mut().enumerate() {
            *slot = count;
            count += 1;
            while let Some(&&(last, r)) = next.peek() {
                if last != p {
                    break;
                }
                multiplier_position[r] = count;
                count += 1;
                next.next();
            }
        }
        if next.peek().is_some() {
            return None;
        }
        let size = n + m;
        // Per node: the first column of its profile row (unknowns couple to unknowns
        // of `H` before them, multipliers to their support).
        let mut first = vec![0usize; size];
        for (p, &u) in self.unknowns.iter().enumerate() {
            let column = &self.row_idx[self.col_ptr[u]..self.col_ptr[u + 1]];
            first[position[p]] = (column.iter())
                .map(|&r| position[self.local[r]])
                .fold(position[p], usize::min);
        }
        for (r, &i) in active.iter().enumerate() {
            first[multiplier_position[r]] = (self.rows[i].gradient.iter())
                .map(|&(k, _)| position[self.local[k]])
                .fold(multiplier_position[r], usize::min);
        }
        let mut start = Vec::with_capacity(size + 1);
        start.push(0);
        for (k, &f) in first.iter().enumerate() {
            start.push(start[k] + k - f + 1);
        }
        let mut l = vec![0.0; start[size]];
        for (p, &u) in self.unknowns.iter().enumerate() {
            let k = position[p];
            for at in self.col_ptr[u]..self.col_ptr[u + 1] {
                let c = position[self.local[self.row_idx[at]]];
                l[start[k] + c - first[k]] += self.values[at];
            }
        }
        for (r, &i) in active.iter().enumerate() {
            let k = multiplier_position[r];
            for &(u, a) in &self.rows[i].gradient {
                let c = position[self.local[u]];
                l[start[k] + c - first[k]] += a;
            }
        }
        let matrix = l.clone();
        let mut is_multiplier = vec![false; size];
        for &k in &multiplier_position {
            is_multiplier[k] = true;
        }
        let mut d = vec![0.0; size];
        for k in 0..size {
            let fk = first[k];
            let (done, rest) = l.split_at_mut(start[k]);
            let row = &mut rest[..k - fk + 1];
            // g_kj = K_kj − Σ_t g_kt L_jt (g_kt = L_kt d_t), then L_kj = g_kj / d_j.
            for j in fk..k {
                let fj = first[j];
                let t0 = fk.max(fj);
                let row_j = &done[start[j]..start[j + 1]];
                let (before, current) = row.split_at_mut(j - fk);
                let dot: f64 = (before[t0 - fk..].iter())
                    .zip(&row_j[t0 - fj..j - fj])
                    .map(|(a, b)| a * b)
                    .sum();
                current[0] -= dot;
                *products += j - t0;
            }
            let mut pivot = row[k - fk];
            for (j, g) in (fk..k).zip(row.iter_mut()) {
                let lkj = *g / d[j];
                pivot -= *g * lkj;
                *g = lkj;
            }
            *products += k - fk;
            // Unknowns' pivots are positive, multipliers' negative (NaN fails both).
            let sign = if is_multiplier[k] { -1.0 } else { 1.0 };
            if pivot.is_nan() || pivot * sign <= 0.0 {
                return None;
            }
            d[k] = pivot;
        }
        let profile = Profile {
            first: &first,
            start: &start,
            l: &l,
            d: &d,
        };
        let mut x = vec![0.0; size];
        for (r, &b) in rhs.iter().enumerate() {
            x[multiplier_position[r]] = b;
        }
        let b = x.clone();
        profile.substitute(&mut x);
        // One step of iterative refinement with the unfactorised system: the
        // multipliers (contact forces) to round-off of the residual, not of the
        // factorisation without pivoting.
        let mut residual = b;
        for k in 0..size {
            let row = &matrix[start[k]..start[k + 1]];
            for (j, &a) in (first[k]..=k).zip(row) {
                residual[k] -= a * x[j];
                if j != k {
                    residual[j] -= a * x[k];
                }
            }
        }
        profile.substitute(&mut residual);
        for (xk, dk) in x.iter_mut().zip(&residual) {
            *xk += dk;
        }
        *products += 6 * (start[size] - size);
        Some(KktSolution {
            multipliers: multiplier_position.iter().map(|&k| -x[k]).collect(),
            correction: position.iter().map(|&k| x[k]).collect(),
        })
    }
}

/// A factorised profile `L D Lᵀ` (unit lower `L` by rows, strictly below the diagonal;
/// the diagonal slot of each row is unused).
struct Profile<'a> {
    first: &'a [usize],
    start: &'a [usize],
    l: &'a [f64],
    d: &'a [f64],
}

impl Profile<'_> {
    /// Solves `L D Lᵀ x = b` in place: forward, diagonal and backward substitution.
    fn substitute(&self, x: &mut [f64]) {
        let size = self.d.len();
        for k in 0..size {
            let row = &self.l[self.start[k]..self.start[k + 1] - 1];
            let s: f64 = row
                .iter()
                .zip(&x[self.first[k]..k])
                .map(|(a, b)| a * b)
                .sum();
            x[k] -= s;
        }
        for (xk, dk) in x.iter_mut().zip(self.d) {
            *xk /= dk;
        }
        for k in (0..size).rev() {
            let row = &self.l[self.start[k]..self.start[k + 1] - 1];
            let xk = x[k];
            for (xj, a) in x[self.first[k]..k].iter_mut().zip(row) {
                *xj -= a * xk;
            }
        }
    }
}

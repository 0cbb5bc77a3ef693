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
//!
//! The factor is owned ([`KktFactor`]), so that later passes of the same step reuse it
//! for nearby active sets ([`super::kkt_updates`]).

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

/// Why the KKT system of a set of active rows could not be factorised.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum KktFailure {
    /// The multiplier pivot of this row (an index into all rows) had the wrong sign:
    /// the row depends on the active rows numbered before it (an edge's row on a
    /// flat face together with the rows of both its vertices).
    DependentRow(usize),
    /// An unknown's pivot was not positive: `H` is not positive definite on the group.
    NotDefinite,
}

/// The solution of one group's KKT system (refined once against the unfactorised one).
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
    ///
    /// The factorisation's cost is counted as [`Self::factor`] does it, row by row:
    /// row `k` takes a dot product with every earlier row `j` of its profile, over
    /// their common part only. A few long rows (a junction body numbered after its
    /// rods, whose row reaches back to every rod end it holds) therefore cost their
    /// length times the band's width, not their length squared: the estimate
    /// `Σ width² / 2` made the cooler hose at 8000 segments per hose look 2,600 times
    /// dearer than it is and kept its 164 contacts on the columns (a solve over 144,000
    /// unknowns per row and a step rebuild per pass: 9 s of a 15 s solve).
    pub(super) fn costs(&self) -> Option<PassCosts> {
        let first: Vec<usize> = (self.unknowns.iter().enumerate())
            .map(|(p, &u)| {
                let column = &self.row_idx[self.col_ptr[u]..self.col_ptr[u + 1]];
                column.iter().map(|&r| self.local[r]).fold(p, usize::min)
            })
            .collect();
        let (mut profile, mut factorisation) = (0, 0);
        for (k, &fk) in first.iter().enumerate() {
            profile += k + 1 - fk;
            factorisation += k - fk;
            for (j, &fj) in first.iter().enumerate().take(k).skip(fk) {
                factorisation += j - fk.max(fj);
            }
        }
        (profile <= MAX_AVERAGE_WIDTH * self.unknowns.len().max(1)).then_some(PassCosts {
            kkt_pass: factorisation + 3 * profile,
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

    /// Factorises the KKT system of the `active` rows (ascending) and solves it for the
    /// right-hand side `rhs` per active row (`−value − a·d_N`), without refinement.
    /// Adds the multiply–adds to `products`. Fails at the first pivot of the wrong
    /// sign: a multiplier's names its row, which depends on the active rows numbered
    /// before it; an unknown's means `H` is not positive definite.
    pub(super) fn factor(
        &self,
        active: &[usize],
        rhs: &[f64],
        products: &mut usize,
    ) -> Result<KktFactor, KktFailure> {
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
            return Err(KktFailure::NotDefinite);
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
        // Per node: the active row whose multiplier it is.
        let mut multiplier_of = vec![None; size];
        for (r, &k) in multiplier_position.iter().enumerate() {
            multiplier_of[k] = Some(active[r]);
        }
        let mut d = vec![0.0; size];
        let mut factorisation_products = 0;
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
                factorisation_products += j - t0;
            }
            let mut pivot = row[k - fk];
            for (j, g) in (fk..k).zip(row.iter_mut()) {
                let lkj = *g / d[j];
                pivot -= *g * lkj;
                *g = lkj;
            }
            factorisation_products += k - fk;
            // Unknowns' pivots are positive, multipliers' negative (NaN fails both).
            let sign = if multiplier_of[k].is_some() {
                -1.0
            } else {
                1.0
            };
            if pivot.is_nan() || pivot * sign <= 0.0 {
                *products += factorisation_products;
                return Err(
                    multiplier_of[k].map_or(KktFailure::NotDefinite, KktFailure::DependentRow)
                );
            }
            d[k] = pivot;
        }
        let substitution_products = 2 * (start[size] - size) + size;
        let mut factor = KktFactor {
            position,
            rows: active.to_vec(),
            rhs: rhs.to_vec(),
            multiplier_position,
            first,
            start,
            l,
            d,
            base_solution: Vec::new(),
            substitution_products,
            factorisation_products,
        };
        let mut x = vec![0.0; size];
        for (r, &b) in rhs.iter().enumerate() {
            x[factor.multiplier_position[r]] = b;
        }
        factor.substitute(&mut x);
        factor.base_solution = x;
        *products += factorisation_products + factor.substitution_products;
        Ok(factor)
    }

    /// The residual of the KKT system of the `active` rows at `(δ, μ)` (`δ` on the
    /// group's unknowns in their order, `μ` per active row):
    /// `(−(H δ + Aᵀ μ), rhs − A δ)`. Adds the multiply–adds to `products`.
    pub(super) fn residual(
        &self,
        active: &[usize],
        rhs: &[f64],
        delta: &[f64],
        mu: &[f64],
        products: &mut usize,
    ) -> (Vec<f64>, Vec<f64>) {
        let mut on_unknowns = vec![0.0; self.unknowns.len()];
        for (p, &u) in self.unknowns.iter().enumerate() {
            for at in self.col_ptr[u]..self.col_ptr[u + 1] {
                let (q, v) = (self.local[self.row_idx[at]], self.values[at]);
                on_unknowns[q] -= v * delta[p];
                if q != p {
                    on_unknowns[p] -= v * delta[q];
                }
            }
            *products += 2 * (self.col_ptr[u + 1] - self.col_ptr[u]);
        }
        let on_rows = (active.iter().zip(rhs).zip(mu))
            .map(|((&i, &b), &m)| {
                let gradient = &self.rows[i].gradient;
                *products += 2 * gradient.len();
                let mut reach = 0.0;
                for &(k, a) in gradient {
                    let p = self.local[k];
                    on_unknowns[p] -= a * m;
                    reach += a * delta[p];
                }
                b - reach
            })
            .collect();
        (on_unknowns, on_rows)
    }

    /// Solves the KKT system of the `active` rows (ascending) for `rhs` per active row,
    /// with a fresh factorisation and one step of iterative refinement (see
    /// [`Self::solve_updating`]).
    #[cfg(test)]
    pub(super) fn solve(
        &self,
        active: &[usize],
        rhs: &[f64],
        products: &mut usize,
    ) -> Option<KktSolution> {
        self.solve_updating(&mut None, active, rhs, products).ok()
    }
}

/// A factorised KKT system of one group's base rows, `[H Aᵀ; A 0] = L D Lᵀ` in profile
/// form (the unit lower `L` by rows, strictly below the diagonal; the diagonal slot of
/// each row is unused), owned so that later passes with other rows can reuse it
/// ([`super::kkt_updates`]).
pub(super) struct KktFactor {
    /// Per local unknown: its node in the numbering.
    pub position: Vec<usize>,
    /// The base rows, ascending.
    pub rows: Vec<usize>,
    /// Their right-hand sides.
    pub rhs: Vec<f64>,
    /// Per base row: its multiplier's node.
    pub multiplier_position: Vec<usize>,
    first: Vec<usize>,
    start: Vec<usize>,
    l: Vec<f64>,
    d: Vec<f64>,
    /// The solution for the base rows' right-hand sides (by node).
    pub base_solution: Vec<f64>,
    /// Multiply–adds of one substitution.
    pub substitution_products: usize,
    /// Multiply–adds of the factorisation.
    pub factorisation_products: usize,
}

impl KktFactor {
    /// Unknowns and multipliers (nodes).
    pub fn size(&self) -> usize {
        self.d.len()
    }

    /// Solves `L D Lᵀ x = b` in place: forward, diagonal and backward substitution.
    pub fn substitute(&self, x: &mut [f64]) {
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
        for (xk, dk) in x.iter_mut().zip(&self.d) {
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

//! One group's KKT system over a sequence of active sets, factorised once and updated
//! by a bordered system instead of factorised again for every pass.
//!
//! A primal–dual pass changes the active set by a row or two; the system of the new set
//! `S` is the base system `K0` (factorised for the base rows `B`) bordered by one column
//! per change: `[a_i; 0]` for a row `i ∈ S \ B` that joined, `e_j` (the multiplier's
//! unit vector) for a base row `j ∈ B \ S` that left — its multiplier is then held at
//! zero and its equation absorbed by the border's own unknown:
//!
//! ```text
//! [K0  C] [z]   [b  ]        G w = Cᵀ K0⁻¹ b − b_c,   z = K0⁻¹ b − K0⁻¹ C w,
//! [Cᵀ  0] [w] = [b_c]   ⟹   G = Cᵀ K0⁻¹ C  (changes × changes, dense).
//! ```
//!
//! A change costs one substitution with the base factor (`K0⁻¹ c`, kept while the change
//! stays) and a pass the small dense solve, instead of a factorisation of the whole band.
//! The inertia of `G` tells whether the new set's rows are independent, as the pivots'
//! signs of a fresh factorisation do (Haynsworth: `In(bordered) = In(K0) + In(−G)`, so
//! `G` has one positive eigenvalue per joined row and one negative per left row; its
//! `L E Lᵀ` with the joined rows first shows them as its pivots' signs). When it does
//! not, or a pivot is too small to trust, or the changes would cost more than a
//! factorisation, the set is factorised afresh as the new base: that factorisation's
//! pivots decide, as before there were updates. The solution is refined once against
//! the unfactorised system either way, and agrees with a fresh factorisation's to
//! round-off (`kkt_updates_tests.rs`, against a dense solve of every set).

use nalgebra::{DMatrix, DVector};

use super::kkt::{KktFactor, KktFailure, KktInput, KktSolution};

/// Most changes kept against one base factorisation (the dense solve grows as their
/// cube, the combination of the kept columns as their number × the band).
const MAX_CHANGES: usize = 32;

/// Smallest |pivot| of the scaled `G` (unit diagonal) for which the bordered solve is
/// used; below it the set is factorised afresh (its own pivots decide).
const MIN_PIVOT: f64 = 1e-10;

/// A change of the active set against the base rows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Change {
    /// The base row at this index of the base rows has left the set.
    Left(usize),
    /// This row has joined the set.
    Joined(usize),
}

/// The base factorisation and the kept changes (see the module documentation).
pub(super) struct KktUpdates {
    factor: KktFactor,
    /// The changes against the base rows, each with `K0⁻¹ c` (by node).
    changes: Vec<(Change, Vec<f64>)>,
    /// `G = Cᵀ K0⁻¹ C` over the changes, row by row.
    gram: Vec<Vec<f64>>,
}

/// `D P G Pᵀ D = L E Lᵀ` for one pass (see [`KktUpdates::bordered`]).
struct Bordered {
    /// `P`: the changes in the factor's order (joined rows first).
    order: Vec<usize>,
    /// `D`'s diagonal, in that order.
    scale: Vec<f64>,
    /// Unit lower triangular (below the diagonal).
    l: DMatrix<f64>,
    /// `E`.
    pivots: DVector<f64>,
}

impl Bordered {
    /// `G⁻¹ t`.
    fn solve(&self, t: &DVector<f64>) -> DVector<f64> {
        let k = self.order.len();
        let mut y: Vec<f64> = (0..k).map(|r| self.scale[r] * t[self.order[r]]).collect();
        for r in 0..k {
            y[r] -= (0..r).map(|c| self.l[(r, c)] * y[c]).sum::<f64>();
        }
        for (yr, e) in y.iter_mut().zip(self.pivots.iter()) {
            *yr /= e;
        }
        for r in (0..k).rev() {
            y[r] -= (r + 1..k).map(|c| self.l[(c, r)] * y[c]).sum::<f64>();
        }
        let mut w = DVector::zeros(k);
        for r in 0..k {
            w[self.order[r]] = self.scale[r] * y[r];
        }
        w
    }
}

impl KktInput<'_> {
    /// Solves the KKT system of the `active` rows (ascending) for the right-hand side
    /// `rhs` per active row, reusing the factorisation `kept` from an earlier pass of the
    /// same step when the changes since are few (a row keeps its right-hand side within
    /// a step), else factorising afresh into `kept`; one step of iterative refinement
    /// against the unfactorised system either way. Adds the multiply–adds to `products`.
    /// Fails as a fresh factorisation does ([`KktInput::factor`]): a row that depends on
    /// the rows before it, or `H` not positive definite.
    pub(super) fn solve_updating(
        &self,
        kept: &mut Option<KktUpdates>,
        active: &[usize],
        rhs: &[f64],
        products: &mut usize,
    ) -> Result<KktSolution, KktFailure> {
        if let Some(updates) = kept.as_mut()
            && updates.follow(self, active, rhs, products)
            && let Some(solution) = updates.solve(self, active, rhs, products)
        {
            return Ok(solution);
        }
        let fresh = KktUpdates {
            factor: self.factor(active, rhs, products)?,
            changes: Vec::new(),
            gram: Vec::new(),
        };
        // Without changes there is no border to reject: the fresh factor solves.
        let solution = fresh.solve(self, active, rhs, products);
        *kept = Some(fresh);
        solution.ok_or(KktFailure::NotDefinite)
    }
}

impl KktUpdates {
    /// The rows of the base factorisation, ascending.
    #[cfg(test)]
    pub(super) fn base_rows(&self) -> &[usize] {
        &self.factor.rows
    }

    /// The changes from the base rows to `active` (sorted: the base rows that left, by
    /// index, then the rows that joined), and per active row its base index (`None` if
    /// it joined).
    fn changes_to(&self, active: &[usize]) -> (Vec<Change>, Vec<Option<usize>>) {
        let base = &self.factor.rows;
        let mut changes = Vec::new();
        // Per active row: its base index, or `None` if it joined.
        let mut in_base = Vec::with_capacity(active.len());
        let (mut b, mut a) = (0, 0);
        while b < base.len() || a < active.len() {
            match (base.get(b), active.get(a)) {
                (Some(x), Some(y)) if x == y => {
                    in_base.push(Some(b));
                    (b, a) = (b + 1, a + 1);
                }
                (Some(x), Some(y)) if x > y => {
                    changes.push(Change::Joined(*y));
                    in_base.push(None);
                    a += 1;
                }
                (Some(_), _) => {
                    changes.push(Change::Left(b));
                    b += 1;
                }
                (None, Some(y)) => {
                    changes.push(Change::Joined(*y));
                    in_base.push(None);
                    a += 1;
                }
                (None, None) => unreachable!(),
            }
        }
        changes.sort_unstable();
        (changes, in_base)
    }

    /// Brings the kept changes to those of `active`: drops the ones gone, adds `K0⁻¹ c`
    /// and `G`'s entries for the new ones. `false` (nothing changed) when a factorisation
    /// would be cheaper or a kept row's right-hand side differs from the base's.
    fn follow(
        &mut self,
        input: &KktInput<'_>,
        active: &[usize],
        rhs: &[f64],
        products: &mut usize,
    ) -> bool {
        let (wanted, in_base) = self.changes_to(active);
        let same_rhs = (in_base.iter().zip(rhs))
            .all(|(b, r)| b.is_none_or(|b| self.factor.rhs[b].to_bits() == r.to_bits()));
        let new: Vec<Change> = (wanted.iter().copied())
            .filter(|c| self.changes.iter().all(|(k, _)| k != c))
            .collect();
        let factor = &self.factor;
        // This pass's work with the border (a substitution per new change, the kept
        // columns combined into the solution and its refinement) against a fresh
        // factorisation's (and its base solution's substitution).
        let bordered_work =
            new.len() * factor.substitution_products + 2 * wanted.len() * factor.size();
        let fresh_work = factor.factorisation_products + factor.substitution_products;
        if !same_rhs || wanted.len() > MAX_CHANGES || bordered_work > fresh_work {
            return false;
        }
        let keep: Vec<bool> = (self.changes.iter())
            .map(|(c, _)| wanted.binary_search(c).is_ok())
            .collect();
        retain_flagged(&mut self.changes, &keep);
        retain_flagged(&mut self.gram, &keep);
        for row in &mut self.gram {
            retain_flagged(row, &keep);
        }
        for change in new {
            let mut column = vec![0.0; factor.size()];
            match change {
                Change::Left(b) => column[factor.multiplier_position[b]] = 1.0,
                Change::Joined(i) => {
                    for &(u, a) in &input.rows[i].gradient {
                        column[factor.position[input.local[u]]] += a;
                    }
                }
            }
            factor.substitute(&mut column);
            *products += factor.substitution_products;
            let entries: Vec<f64> = (self.changes.iter())
                .map(|(c, _)| border_dot(input, factor, *c, &column))
                .collect();
            for (row, &g) in self.gram.iter_mut().zip(&entries) {
                row.push(g);
            }
            let mut own = entries;
            own.push(border_dot(input, factor, change, &column));
            self.gram.push(own);
            self.changes.push((change, column));
        }
        true
    }

    /// `G` scaled to a unit diagonal (`D G D`, `D = diag |G|^-½`: a joined row's entry
    /// is a compliance and a left row's a stiffness, so only the scaled matrix has
    /// meaningful pivots) and factorised as `L E Lᵀ`, the joined rows first, when its
    /// inertia is that of independent rows: one positive pivot per joined row and one
    /// negative per left row (congruence keeps the inertia, and with the joined rows'
    /// block positive definite the pivots' signs are it), each at least [`MIN_PIVOT`]
    /// in size. `None` otherwise.
    fn bordered(&self) -> Option<Bordered> {
        let k = self.changes.len();
        let mut order: Vec<usize> = (0..k).collect();
        order.sort_by_key(|&j| matches!(self.changes[j].0, Change::Left(_)));
        let scale: Vec<f64> = (order.iter())
            .map(|&j| 1.0 / self.gram[j][j].abs().sqrt())
            .collect();
        if scale.iter().any(|s| !s.is_finite()) {
            return None;
        }
        let mut l = DMatrix::from_fn(k, k, |r, c| {
            scale[r] * self.gram[order[r]][order[c]] * scale[c]
        });
        let mut pivots = DVector::zeros(k);
        for c in 0..k {
            let pivot = l[(c, c)]
                - (0..c)
                    .map(|t| l[(c, t)] * l[(c, t)] * pivots[t])
                    .sum::<f64>();
            let joined = matches!(self.changes[order[c]].0, Change::Joined(_));
            let sign = if joined { 1.0 } else { -1.0 };
            if pivot.is_nan() || pivot * sign < MIN_PIVOT {
                return None;
            }
            pivots[c] = pivot;
            for r in c + 1..k {
                let dot: f64 = (0..c).map(|t| l[(r, t)] * l[(c, t)] * pivots[t]).sum();
                l[(r, c)] = (l[(r, c)] - dot) / pivot;
            }
        }
        Some(Bordered {
            order,
            scale,
            l,
            pivots,
        })
    }

    /// Solves the bordered system for `z = K0⁻¹ b` (by node) and the right-hand sides
    /// `row_rhs` of the `active` rows (a joined row's enters through the border):
    /// `(δ, μ)`, `δ` on the group's unknowns and `μ` per active row.
    fn combine(
        &self,
        bordered: Option<&Bordered>,
        mut z: Vec<f64>,
        (active, in_base): (&[usize], &[Option<usize>]),
        row_rhs: &[f64],
        input: &KktInput<'_>,
        products: &mut usize,
    ) -> (Vec<f64>, Vec<f64>) {
        let factor = &self.factor;
        // Per change: its active index if it is a joined row.
        let joined_at: Vec<Option<usize>> = (self.changes.iter())
            .map(|(c, _)| match c {
                Change::Joined(i) => active.binary_search(i).ok(),
                Change::Left(_) => None,
            })
            .collect();
        let k = self.changes.len();
        let mut w = DVector::zeros(k);
        if let Some(bordered) = bordered {
            // Cᵀ z − b_c: a joined row's own right-hand side, zero for a left row.
            let t = DVector::from_fn(k, |j, _| {
                let given = joined_at[j].map_or(0.0, |a| row_rhs[a]);
                border_dot(input, factor, self.changes[j].0, &z) - given
            });
            w = bordered.solve(&t);
            for ((_, column), &wj) in self.changes.iter().zip(w.iter()) {
                for (zi, ci) in z.iter_mut().zip(column) {
                    *zi -= wj * ci;
                }
            }
            *products += k * (factor.size() + 2 * k);
        }
        let delta = factor.position.iter().map(|&n| z[n]).collect();
        let mut mu: Vec<f64> = (in_base.iter())
            .map(|b| b.map_or(0.0, |b| z[factor.multiplier_position[b]]))
            .collect();
        for (j, at) in joined_at.iter().enumerate() {
            if let Some(a) = at {
                mu[*a] = w[j];
            }
        }
        (delta, mu)
    }

    /// Solves the KKT system of `active` (its changes followed, see [`Self::follow`])
    /// for `rhs`, with one step of iterative refinement. `None` when `G`'s inertia or
    /// condition rules the bordered solve out (see [`Self::bordered`]).
    fn solve(
        &self,
        input: &KktInput<'_>,
        active: &[usize],
        rhs: &[f64],
        products: &mut usize,
    ) -> Option<KktSolution> {
        let bordered = if self.changes.is_empty() {
            None
        } else {
            Some(self.bordered()?)
        };
        let factor = &self.factor;
        let (_, in_base) = self.changes_to(active);
        let rows = (active, in_base.as_slice());
        let base = factor.base_solution.clone();
        let (mut delta, mut mu) = self.combine(bordered.as_ref(), base, rows, rhs, input, products);
        // One step of iterative refinement with the unfactorised system: the multipliers
        // (contact forces) to round-off of the residual, not of the factorisation
        // without pivoting or of the border.
        let (on_unknowns, on_rows) = input.residual(active, rhs, &delta, &mu, products);
        let mut z = vec![0.0; factor.size()];
        for (&n, &r) in factor.position.iter().zip(&on_unknowns) {
            z[n] = r;
        }
        for (b, &r) in in_base.iter().zip(&on_rows) {
            if let Some(b) = b {
                z[factor.multiplier_position[*b]] = r;
            }
        }
        factor.substitute(&mut z);
        *products += factor.substitution_products;
        let (d_delta, d_mu) = self.combine(bordered.as_ref(), z, rows, &on_rows, input, products);
        for (x, dx) in delta.iter_mut().zip(&d_delta) {
            *x += dx;
        }
        for (x, dx) in mu.iter_mut().zip(&d_mu) {
            *x += dx;
        }
        Some(KktSolution {
            multipliers: mu.iter().map(|m| -m).collect(),
            correction: delta,
        })
    }
}

/// `cᵀ x` for the border column of `change` (by node).
fn border_dot(input: &KktInput<'_>, factor: &KktFactor, change: Change, x: &[f64]) -> f64 {
    match change {
        Change::Left(b) => x[factor.multiplier_position[b]],
        Change::Joined(i) => (input.rows[i].gradient.iter())
            .map(|&(u, a)| a * x[factor.position[input.local[u]]])
            .sum(),
    }
}

/// Keeps the items of `items` whose flag in `keep` (one per item, in order) is set.
fn retain_flagged<T>(items: &mut Vec<T>, keep: &[bool]) {
    let mut flags = keep.iter();
    items.retain(|_| flags.next().copied().unwrap_or(false));
}

//! The bordered KKT solves ([`super::kkt_updates`]) against a dense solve of each active
//! set's KKT system (an independent reference), over sequences of sets that change by a
//! row or a few at a time, as the primal–dual passes change them; and dependent rows
//! refused as a fresh factorisation refuses them.

use nalgebra::DMatrix;

use super::kkt::{KktFailure, KktInput, KktSolution};
use super::kkt_tests::{Chain, chain};
use super::kkt_updates::KktUpdates;
use super::scaling_tests::{next, row};

/// The dense KKT system `[H Aᵀ; A 0] (δ, μ) = (0, rhs)` of `active`, solved by LU:
/// `(multipliers −μ, δ)`.
fn dense_kkt(rod: &Chain, active: &[usize], rhs: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let n = rod.dense.nrows();
    let m = active.len();
    let mut kkt = DMatrix::zeros(n + m, n + m);
    kkt.view_mut((0, 0), (n, n)).copy_from(&rod.dense);
    for (r, &i) in active.iter().enumerate() {
        for &(u, a) in &rod.rows[i].gradient {
            kkt[(n + r, u)] += a;
            kkt[(u, n + r)] += a;
        }
    }
    let mut b = nalgebra::DVector::zeros(n + m);
    for (r, &v) in rhs.iter().enumerate() {
        b[n + r] = v;
    }
    let x = kkt.lu().solve(&b).expect("the dense KKT system is regular");
    (
        (0..m).map(|r| -x[n + r]).collect(),
        (0..n).map(|u| x[u]).collect(),
    )
}

/// The KKT input of the whole chain as one group (`numbering`: `0..n`, which is both the
/// group's unknowns and each unknown's place among them).
fn whole_chain<'a>(rod: &'a Chain, numbering: &'a [usize]) -> KktInput<'a> {
    let (col_ptr, row_idx, values) = rod.cholesky.matrix();
    KktInput {
        col_ptr,
        row_idx,
        values,
        rows: &rod.rows,
        unknowns: numbering,
        local: numbering,
    }
}

fn assert_close(solution: &KktSolution, expected: &(Vec<f64>, Vec<f64>), what: &str) {
    for (got, want) in [
        (&solution.multipliers, &expected.0),
        (&solution.correction, &expected.1),
    ] {
        let size = want.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        for (a, b) in got.iter().zip(want) {
            assert!(
                (a - b).abs() <= 1e-10 * size,
                "{what}: {a} vs {b} (size {size})"
            );
        }
    }
}

#[test]
fn bordered_solves_over_changing_active_sets_are_the_dense_kkt_solutions() {
    let rod = chain(61, 3);
    let n = rod.dense.nrows();
    let numbering: Vec<usize> = (0..n).collect();
    let input = whole_chain(&rod, &numbering);
    // A fixed right-hand side per row (as within one exact step).
    let mut seed = 17;
    let row_rhs: Vec<f64> = rod.rows.iter().map(|_| next(&mut seed)).collect();
    let mut active: Vec<usize> = vec![2, 5, 9, 14, 20];
    let mut kept: Option<KktUpdates> = None;
    let (mut updating, mut fresh) = (0, 0);
    let (mut factorisations, mut base) = (0, None);
    for pass in 0..60 {
        let rhs: Vec<f64> = active.iter().map(|&i| row_rhs[i]).collect();
        let solution = input
            .solve_updating(&mut kept, &active, &rhs, &mut updating)
            .expect("independent rows");
        let now = kept.as_ref().map(|k| k.base_rows().to_vec());
        if now != base {
            factorisations += 1;
            base = now;
        }
        assert_close(
            &solution,
            &dense_kkt(&rod, &active, &rhs),
            &format!("pass {pass}"),
        );
        let again = input
            .solve(&active, &rhs, &mut fresh)
            .expect("independent rows");
        assert_close(
            &again,
            &dense_kkt(&rod, &active, &rhs),
            &format!("fresh {pass}"),
        );
        // One or two rows join or leave (every sixth pass five at once, as a batch).
        let changes = if pass % 6 == 5 { 5 } else { 1 + pass % 2 };
        for _ in 0..changes {
            let i = ((next(&mut seed) + 1.0) * 0.5 * rod.rows.len() as f64) as usize;
            let i = i.min(rod.rows.len() - 1);
            match active.binary_search(&i) {
                Ok(at) if active.len() > 1 => {
                    active.remove(at);
                }
                Ok(_) => {}
                Err(at) => active.insert(at, i),
            }
        }
    }
    // The passes reused factorisations (a batch of five changes costs more than one,
    // and is factorised afresh), and did less work than fresh ones.
    println!("{factorisations} factorisations in 60 passes; multiply–adds {updating} vs {fresh}");
    assert!(factorisations <= 20, "{factorisations} factorisations");
    assert!(
        updating < fresh,
        "updating {updating} vs fresh {fresh} multiply–adds"
    );
}

#[test]
fn a_joined_row_dependent_on_the_base_rows_is_refused_as_a_fresh_factorisation_refuses_it() {
    let mut rod = chain(21, 7);
    let n = rod.dense.nrows();
    // Row 10 repeats row 3's gradient: {3, 10} are dependent.
    let copy = rod.rows[3].gradient.clone();
    rod.rows.push(row(99, 0.1, copy));
    let dependent = rod.rows.len() - 1;
    let numbering: Vec<usize> = (0..n).collect();
    let input = whole_chain(&rod, &numbering);
    let mut kept = None;
    let mut products = 0;
    assert!(
        input
            .solve_updating(&mut kept, &[1, 3, 6], &[0.1, 0.2, 0.3], &mut products)
            .is_ok()
    );
    let active = [1, 3, 6, dependent];
    let rhs = [0.1, 0.2, 0.3, 0.4];
    assert!(input.solve(&active, &rhs, &mut products).is_none());
    // The row numbered later of the two is named (their supports end together).
    assert_eq!(
        input
            .solve_updating(&mut kept, &active, &rhs, &mut products)
            .err(),
        Some(KktFailure::DependentRow(dependent))
    );
    // And the set without row 3 is solved from the kept base again.
    let active = [1, 6, dependent];
    let rhs = [0.1, 0.3, 0.4];
    let solution = input
        .solve_updating(&mut kept, &active, &rhs, &mut products)
        .expect("independent rows");
    assert_close(&solution, &dense_kkt(&rod, &active, &rhs), "without row 3");
}

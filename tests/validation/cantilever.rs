//! A clamped cantilever under a small tip load against Euler–Bernoulli (with the shear
//! compliance of Timoshenko's beam, as the rod is shearable).

use nalgebra::Vector3;
use strand_system::End;
use strand_tests::reference::euler_bernoulli::cantilever_tip_load_timoshenko;

use crate::common::{clamped_rod, observed_orders, solve_converged};

#[test]
fn small_tip_load_matches_beam_theory() {
    // P L² / EI = 1e-4: geometric nonlinearity is O(1e-8) relative.
    let load = 1e-4;
    let beam = cantilever_tip_load_timoshenko(1.0, 1.0, 1e4, load);
    let mut errors = vec![];
    for n in [10, 20, 40, 80] {
        let (model, solution) = solve_converged(clamped_rod(
            n,
            End::free().with_force(Vector3::new(0.0, load, 0.0)),
        ));
        let tip = solution.state.rods[0].positions[n];
        let error = (tip.y - beam.tip_deflection).abs() / beam.tip_deflection;
        errors.push(error);
        let clamp = &model.reactions(&solution.state)[0];
        assert!((clamp.force.y + load).abs() < 1e-12);
        // The clamp moment balances the load's moment about the clamp exactly.
        assert!((clamp.moment.z + tip.x * load).abs() < 1e-12);
    }
    assert!(errors[3] < 1e-4, "errors {errors:?}");
    let orders = observed_orders(&errors);
    assert!(
        orders.iter().all(|p| *p > 1.8),
        "errors {errors:?} orders {orders:?}"
    );
}

//! Solving a built case: with contact against its environment when it has one.

use strand_solve::contact::Contact;
use strand_solve::{Solution, SolveError, SolverSettings, solve, solve_constrained};
use strand_system::SystemState;

use crate::BuiltCase;

impl BuiltCase {
    /// Contact of the case's rods with its environment meshes and with each other
    /// (pairs within twice the largest hose radius, at least 5 mm, enter the solve), or
    /// `None` for a case without an environment.
    pub fn contact(&self) -> Option<Contact> {
        (!self.environment.is_empty()).then(|| {
            Contact::new(
                self.environment.clone(),
                Contact::default_margin_m(&self.model),
            )
        })
    }

    /// Solves the case from `initial` with `settings`, with contact when it has an
    /// environment.
    pub fn solve_from(
        &self,
        initial: SystemState,
        settings: &SolverSettings,
    ) -> Result<Solution, SolveError> {
        match self.contact() {
            Some(contact) => solve_constrained(&self.model, &contact, initial, settings),
            None => solve(&self.model, initial, settings),
        }
    }
}

//! Solving a built case: with contact against its environment when it has one.

use strand_solve::contact::Contact;
use strand_solve::{
    Constraints, Solution, SolveError, SolverSettings, StartHint, solve, solve_constrained,
};
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
            Some(contact) => solve_constrained(&self.model, &contact, initial, settings)
                .map_err(|e| self.with_start_hint(e)),
            None => solve(&self.model, initial, settings),
        }
    }

    /// Checks the case's initial configuration as a solve does before its first step
    /// (with the supports enforced): `Err(SolveError::StartsInside)` naming where a hose
    /// starts inside an obstacle, inside a closed part, or overlapping itself or another
    /// hose. `strand check` and `strand solve` agree through this one check. A case
    /// without an environment has nothing to check.
    pub fn check_start(&self) -> Result<(), SolveError> {
        let Some(contact) = self.contact() else {
            return Ok(());
        };
        let mut start = self.initial.clone();
        self.model.enforce_supports(&mut start);
        contact
            .check_start(&self.model, &start)
            .map_err(|e| self.with_start_hint(SolveError::StartsInside(e)))
    }

    /// `error` with a start error's hint made precise where the build found it: when
    /// no start cleared and a rod is too short for the shortest way around the parts,
    /// how long that way is.
    fn with_start_hint(&self, mut error: SolveError) -> SolveError {
        if let (Some((rod, better)), SolveError::StartsInside(inside)) =
            (&self.start_hint, &mut error)
            && let Some((name, hint)) = inside.start_hint_mut()
            && *hint == StartHint::GiveRoute
            && self.model.system().rods[*rod].name == name
        {
            *hint = better.clone();
        }
        error
    }
}

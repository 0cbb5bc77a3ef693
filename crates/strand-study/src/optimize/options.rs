//! The problem as `strand optimize` states it: `--vary ITEM=LO..HI` (the variables,
//! [`crate::batch::bounds`]), `--minimize OBJECTIVE` ([`Objective::parse`]) and
//! `--subject-to CONSTRAINT` ([`Limit::parse`]).

use strand_case::{Case, DesignParameter};

use super::OptimizeError;
use super::problem::{Limit, Objective, Problem, Variable};
use crate::batch::bounds::parse_bounds;
use crate::sensitivity::parameter_scale;

impl Problem {
    /// The problem of `case` stated by the options `vary` (each `ITEM=LO..HI`),
    /// `minimize` and `subject_to`: the error names the option, its value and the fix.
    pub fn from_options(
        case: &Case,
        vary: &[String],
        minimize: &str,
        subject_to: &[String],
    ) -> Result<Self, OptimizeError> {
        let mut variables: Vec<Variable> = Vec::new();
        for text in vary {
            let b = parse_bounds(text, &case.file)
                .map_err(|e| OptimizeError::input("--vary", text, &e.message, &e.hint))?;
            let Some((scale, _)) = parameter_scale(b.target, case) else {
                return Err(OptimizeError::input(
                    "--vary",
                    text,
                    "not a continuous parameter",
                    "vary lengths, positions, directions, masses, forces, stiffnesses or gravity",
                ));
            };
            if variables
                .iter()
                .any(|v| v.parameter.item == b.item && v.parameter.component == b.component)
            {
                return Err(OptimizeError::input(
                    "--vary",
                    text,
                    "the variable is named twice",
                    "give each variable once",
                ));
            }
            variables.push(Variable {
                name: b.label,
                unit: b.unit,
                parameter: DesignParameter {
                    item: b.item,
                    component: b.component,
                    scale,
                },
                origin: b.origin,
                lower: b.lower,
                upper: b.upper,
            });
        }
        Ok(Problem {
            variables,
            objective: Objective::parse(minimize)?,
            limits: subject_to
                .iter()
                .map(|t| Limit::parse(t))
                .collect::<Result<_, _>>()?,
        })
    }
}

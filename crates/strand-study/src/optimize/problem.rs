//! What to optimise: the design variables with their bounds, the objective and the
//! output constraints, as the command line states them.

use strand_case::DesignParameter;

use super::OptimizeError;

/// One design variable: a parameter of the case with bounds.
#[derive(Clone, Debug, PartialEq)]
pub struct Variable {
    /// Its name as given (`hose2.length`), the key in `optimum.json`.
    pub name: String,
    /// The item's unit in the case (`mm`, `kg`, `N`, `m/s2`).
    pub unit: String,
    /// The parameter (item, component; its `scale` sets the difference steps).
    pub parameter: DesignParameter,
    /// The case's value in `unit`, if the case states one (values are then reported
    /// as `origin + offset`, else as offsets).
    pub origin: Option<f64>,
    /// Lowest offset from the case's value, in `unit`.
    pub lower: f64,
    /// Highest offset from the case's value, in `unit`.
    pub upper: f64,
}

impl Variable {
    /// The value at `offset` as reported: `origin + offset`, or the offset.
    pub fn value(&self, offset: f64) -> f64 {
        self.origin.unwrap_or(0.0) + offset
    }

    /// The bounds' width, in `unit`.
    pub fn width(&self) -> f64 {
        self.upper - self.lower
    }
}

/// The quantity to minimise (`--minimize`).
#[derive(Clone, Debug, PartialEq)]
pub enum Objective {
    /// `peak_force`: the largest peak |f| over all rods (a min–max).
    PeakForce,
    /// `peak_force:<rod>`: one rod's peak |f|.
    PeakForceOf(String),
    /// `peak_moment`: the largest peak |m| over all rods (a min–max).
    PeakMoment,
    /// `peak_moment:<rod>`: one rod's peak |m|.
    PeakMomentOf(String),
    /// `max_reaction`: the largest reaction force magnitude at a connector or clip (a
    /// min–max).
    MaxReaction,
    /// `energy`: the total potential energy, J.
    Energy,
    /// Any output name of `sensitivity.json` (`tee.position_m.z`, …).
    Output(String),
}

impl Objective {
    /// Parses `--minimize TEXT`.
    pub fn parse(text: &str) -> Result<Self, OptimizeError> {
        let text = text.trim();
        Ok(match text {
            "peak_force" => Objective::PeakForce,
            "peak_moment" => Objective::PeakMoment,
            "max_reaction" => Objective::MaxReaction,
            "energy" => Objective::Energy,
            _ => match text.split_once(':') {
                Some(("peak_force", rod)) if !rod.is_empty() => {
                    Objective::PeakForceOf(rod.to_string())
                }
                Some(("peak_moment", rod)) if !rod.is_empty() => {
                    Objective::PeakMomentOf(rod.to_string())
                }
                Some(_) => {
                    return Err(OptimizeError::input(
                        "--minimize",
                        text,
                        "is not an objective",
                        "write peak_force, peak_force:<rod>, peak_moment, peak_moment:<rod>, max_reaction, energy or an output name of sensitivity.json (e.g. hose2.min_bend_radius_m)",
                    ));
                }
                None if text.is_empty() || text.contains(char::is_whitespace) => {
                    return Err(OptimizeError::input(
                        "--minimize",
                        text,
                        "is not an objective",
                        "write peak_force, peak_force:<rod>, peak_moment, peak_moment:<rod>, max_reaction, energy or an output name",
                    ));
                }
                None => Objective::Output(text.to_string()),
            },
        })
    }

    /// The objective as written.
    pub fn name(&self) -> String {
        match self {
            Objective::PeakForce => "peak_force".into(),
            Objective::PeakForceOf(rod) => format!("peak_force:{rod}"),
            Objective::PeakMoment => "peak_moment".into(),
            Objective::PeakMomentOf(rod) => format!("peak_moment:{rod}"),
            Objective::MaxReaction => "max_reaction".into(),
            Objective::Energy => "energy".into(),
            Objective::Output(name) => name.clone(),
        }
    }

    /// The objective's unit.
    pub fn unit(&self) -> &'static str {
        match self {
            Objective::PeakForce | Objective::PeakForceOf(_) | Objective::MaxReaction => "N",
            Objective::PeakMoment | Objective::PeakMomentOf(_) => "N·m",
            Objective::Energy => "J",
            Objective::Output(name) => unit_of(name),
        }
    }
}

/// The SI unit of an output from its name (`_N`, `_Nm`, `_m`, `_J`, `_rad`; `1` else).
pub fn unit_of(name: &str) -> &'static str {
    let stem = name.split('.').find(|p| p.contains('_')).unwrap_or(name);
    for (suffix, unit) in [
        ("_Nm", "N·m"),
        ("_N", "N"),
        ("_m", "m"),
        ("_J", "J"),
        ("_rad", "rad"),
    ] {
        if stem.ends_with(suffix) {
            return unit;
        }
    }
    if name.ends_with(".joint_value") {
        return "rad or m";
    }
    "1"
}

/// What a constraint bounds.
#[derive(Clone, Debug, PartialEq)]
pub enum Bounded {
    /// `clearance`: every rod's clearance to every obstacle (and other rod).
    Clearance,
    /// `clearance:<rod>`: one rod's clearances.
    ClearanceOf(String),
    /// `bend_radius`: every rod's smallest bend radius.
    BendRadius,
    /// `bend_radius:<rod>`: one rod's.
    BendRadiusOf(String),
    /// Any output name of `sensitivity.json`.
    Output(String),
}

/// The bound of a constraint.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Bound {
    /// A value in SI units (m, N, N·m, J, rad).
    Value(f64),
    /// `min`: each rod's `min_bend_radius` from the case.
    CaseMinimum,
}

/// One `--subject-to` constraint: `NAME>=VALUE` or `NAME<=VALUE`.
#[derive(Clone, Debug, PartialEq)]
pub struct Limit {
    /// The constraint as written (`clearance>=10mm`).
    pub text: String,
    /// What it bounds.
    pub bounded: Bounded,
    /// `true` for `>=`, `false` for `<=`.
    pub at_least: bool,
    /// The bound.
    pub bound: Bound,
}

/// Units a bound may carry, with their size in SI.
const BOUND_UNITS: [(&str, f64, &str); 10] = [
    ("mm", 1e-3, "m"),
    ("cm", 1e-2, "m"),
    ("N·m", 1.0, "N·m"),
    ("Nm", 1.0, "N·m"),
    ("kN", 1e3, "N"),
    ("N", 1.0, "N"),
    ("J", 1.0, "J"),
    ("rad", 1.0, "rad"),
    ("deg", std::f64::consts::PI / 180.0, "rad"),
    ("m", 1.0, "m"),
];

impl Limit {
    /// Parses `--subject-to TEXT`.
    pub fn parse(text: &str) -> Result<Self, OptimizeError> {
        let bad =
            |message: &str, hint: &str| OptimizeError::input("--subject-to", text, message, hint);
        let (name, at_least, value) = if let Some((n, v)) = text.split_once(">=") {
            (n, true, v)
        } else if let Some((n, v)) = text.split_once("<=") {
            (n, false, v)
        } else {
            return Err(bad(
                "has no >= or <=",
                "write e.g. \"clearance>=10mm\", \"bend_radius>=min\" or \"oil_cooler.force_N.z<=20N\"",
            ));
        };
        let (name, value) = (name.trim(), value.trim());
        let bounded = match name {
            "clearance" => Bounded::Clearance,
            "bend_radius" => Bounded::BendRadius,
            _ => match name.split_once(':') {
                Some(("clearance", rod)) if !rod.is_empty() => Bounded::ClearanceOf(rod.into()),
                Some(("bend_radius", rod)) if !rod.is_empty() => Bounded::BendRadiusOf(rod.into()),
                Some(_) => {
                    return Err(bad(
                        "names no output",
                        "write clearance, clearance:<rod>, bend_radius, bend_radius:<rod> or an output name of sensitivity.json",
                    ));
                }
                None if name.is_empty() || name.contains(char::is_whitespace) => {
                    return Err(bad(
                        "names no output",
                        "write clearance, bend_radius or an output name before >= or <=",
                    ));
                }
                None => Bounded::Output(name.into()),
            },
        };
        let expected = match &bounded {
            Bounded::Output(n) => unit_of(n),
            _ => "m",
        };
        let bound = if value == "min" {
            if !matches!(bounded, Bounded::BendRadius | Bounded::BendRadiusOf(_)) || !at_least {
                return Err(bad(
                    "'min' is the case's min_bend_radius: only bend_radius>=min takes it",
                    "write a value with a unit, e.g. clearance>=10mm",
                ));
            }
            Bound::CaseMinimum
        } else {
            let (digits, size, unit) = BOUND_UNITS
                .iter()
                .find_map(|(u, size, si)| value.strip_suffix(u).map(|d| (d, *size, *si)))
                .unwrap_or((value, 1.0, expected));
            let number: f64 = digits.trim().parse().map_err(|_| {
                bad(
                    &format!("'{value}' is not a number with a unit"),
                    "write e.g. 10mm, 60mm, 20N, 1.5Nm",
                )
            })?;
            if !number.is_finite() {
                return Err(bad("the bound is not finite", "write a finite number"));
            }
            if unit != expected && expected != "1" && expected != "rad or m" {
                return Err(bad(
                    &format!("a bound in {unit} on an output in {expected}"),
                    &format!("give the bound in {expected} (or mm, cm for lengths)"),
                ));
            }
            Bound::Value(number * size)
        };
        Ok(Self {
            text: text.to_string(),
            bounded,
            at_least,
            bound,
        })
    }
}

/// The optimisation problem.
#[derive(Clone, Debug, PartialEq)]
pub struct Problem {
    /// The design variables.
    pub variables: Vec<Variable>,
    /// The objective.
    pub objective: Objective,
    /// The constraints.
    pub limits: Vec<Limit>,
}

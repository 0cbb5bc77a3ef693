//! Pre-deformed (moulded) rods in a case file: a rod's `nominal` shape → its stress-free
//! reference ([`Rod::try_from_nominal`]), its nominal end frames (for `NominalClamp`
//! ends) and its initial guess.
//!
//! Length rule: the nominal centreline defines the rod's stress-free length. The rod's
//! `length` may then be omitted; if it is given, it is a cross-check and must agree
//! with the nominal length within [`NOMINAL_LENGTH_TOLERANCE`] (1 %).

use nalgebra::{UnitQuaternion, Vector3};
use strand_rod::so3::frame_with_tangent;
use strand_rod::{NominalError, NominalRod, NominalShape, Rod, RodState, Section};
use strand_system::End;

use crate::centreline::{CentrelineFileDef, read_centreline};
use crate::ends::frame_from_tangent_normal;
use crate::error::{CaseError, Reporter};
use crate::schema::{NominalDef, RodDef};
use crate::units::LengthUnit;

/// Largest relative difference between a stated `length` and the length of the rod's
/// nominal shape.
pub const NOMINAL_LENGTH_TOLERANCE: f64 = 0.01;

/// The rod's stated `length` in m, if any (checked positive). A rod without a nominal
/// shape must state it.
pub(crate) fn stated_length(
    report: &Reporter,
    item: &str,
    unit: LengthUnit,
    def: &RodDef,
) -> Result<Option<f64>, CaseError> {
    match def.length {
        Some(length) => Ok(Some(
            report.positive(&format!("{item}.length"), length, &format!(" {unit}"))?
                * unit.metres(),
        )),
        None if def.nominal.is_some() => Ok(None),
        None => Err(report.invalid(
            format!("{item}.length"),
            "missing field `length`",
            "add the field `length` (the stress-free length, in the case's length unit), \
             or give the rod a `nominal` shape (see cases/README.md)",
        )),
    }
}

/// The rod's reference: straight of the stated length, or from its nominal shape.
pub(crate) fn build_reference(
    report: &Reporter,
    item: &str,
    unit: LengthUnit,
    section: Section,
    def: &RodDef,
    length_m: Option<f64>,
    segments: usize,
    clip_stations: &[f64],
) -> Result<(Rod, Option<NominalRod>), CaseError> {
    let Some(shape) = &def.nominal else {
        let length = length_m.expect("stated_length requires a length without a nominal shape");
        let rod = Rod::try_straight(section, length, segments).map_err(|e| {
            report.invalid(item, e.to_string(), "correct the rod's length and segments")
        })?;
        return Ok((rod, None));
    };
    let nominal = build_nominal(
        report,
        &format!("{item}.nominal"),
        unit,
        section,
        shape,
        segments,
        clip_stations,
    )?;
    let nominal_m = nominal.rod.length();
    if let Some(stated) = length_m
        && (stated - nominal_m).abs() > NOMINAL_LENGTH_TOLERANCE * nominal_m
    {
        let m = unit.metres();
        return Err(report.invalid(
            format!("{item}.length"),
            format!(
                "the length {} {unit} does not match the length of the nominal shape, {:.6} {unit} \
                 (they may differ by 1 % at most)",
                stated / m,
                nominal_m / m
            ),
            "omit `length` for a rod with a nominal shape (its stress-free length is the \
             nominal centreline's), or correct the length or the nominal points",
        ));
    }
    Ok((nominal.rod.clone(), Some(nominal)))
}

/// Converts a nominal shape to m and builds the pre-deformed rod; `item` is e.g.
/// `rods[0] 'hose'.nominal`.
fn build_nominal(
    report: &Reporter,
    item: &str,
    unit: LengthUnit,
    section: Section,
    def: &NominalDef,
    segments: usize,
    clip_stations: &[f64],
) -> Result<NominalRod, CaseError> {
    let shape = nominal_shape(report, item, unit, def)?;
    // With clips, a vertex at every clip's station (when the stations are valid; if not,
    // `place_clips` says why).
    let targets = match shape.arc_length() {
        Ok(total) if !clip_stations.is_empty() => {
            crate::clips::station_targets(clip_stations, total, segments)
        }
        _ => None,
    };
    let built = match targets {
        Some(targets) => Rod::try_from_nominal_stations(section, &shape, &targets),
        None => Rod::try_from_nominal(section, &shape, segments),
    };
    built.map_err(|e| {
        let (at, hint) = match &e {
            NominalError::TooFewPoints(_) => (
                format!("{item}.points"),
                "give at least the two end points of the centreline".to_string(),
            ),
            NominalError::NotFinite { what, index } => (
                format!("{item}.{what}[{index}]"),
                "replace NaN/inf by a number".to_string(),
            ),
            NominalError::RepeatedPoint { index } => (
                format!("{item}.points[{index}]"),
                "remove the repeated point".to_string(),
            ),
            NominalError::DoublesBack { index, .. } => (
                format!("{item}.points[{index}]"),
                "check the order of the points around it (a point given twice?)".to_string(),
            ),
            NominalError::FrameCount { .. } => (
                format!("{item}.frames"),
                "give one frame per point, or omit `frames`".to_string(),
            ),
            NominalError::FrameAgainstCentreline { index, .. } => (
                format!("{item}.frames[{index}]"),
                "the tangent must point along the centreline, towards its end".to_string(),
            ),
            NominalError::Stations { .. } | NominalError::Rod(_) => (
                item.to_string(),
                "check the nominal points and the number of segments".to_string(),
            ),
        };
        report.invalid(at, e.to_string(), hint)
    })
}

/// The nominal shape of `def` in m (`item` is e.g. `rods[0] 'hose'.nominal`): its
/// `points`, or the centreline in its `file`, with its frames.
pub(crate) fn nominal_shape(
    report: &Reporter,
    item: &str,
    unit: LengthUnit,
    def: &NominalDef,
) -> Result<NominalShape, CaseError> {
    let u = format!(" {unit}");
    let points = match (&def.file, def.points.is_empty()) {
        (Some(file), true) => read_centreline(
            report,
            item,
            &CentrelineFileDef {
                file: file.clone(),
                object: def.object.clone(),
                unit: def.unit.clone(),
            },
        )?,
        (Some(_), false) => {
            return Err(report.invalid(
                format!("{item}.file"),
                "both `points` and `file` are given",
                "give the centreline either inline (`points`) or from a file (`file`)",
            ));
        }
        (None, _) if def.object.is_some() || def.unit.is_some() => {
            return Err(report.invalid(
                item,
                "`object` and `unit` belong to a centreline `file`",
                "add `file: \"….obj\"` or remove `object` and `unit`",
            ));
        }
        (None, _) => def
            .points
            .iter()
            .enumerate()
            .map(|(k, p)| {
                report
                    .finite3(&format!("{item}.points[{k}]"), p, &u)
                    .map(|v| v * unit.metres())
            })
            .collect::<Result<Vec<_>, _>>()?,
    };
    let frames = match &def.frames {
        None => None,
        Some(frames) => Some(
            frames
                .iter()
                .enumerate()
                .map(|(k, f)| {
                    let at = format!("{item}.frames[{k}]");
                    let t = report.finite3(&format!("{at}.tangent"), &f.tangent, "")?;
                    let n = report.finite3(&format!("{at}.normal"), &f.normal, "")?;
                    frame_from_tangent_normal(&t, &n).map_err(|e| {
                        report.invalid(
                            &at,
                            e.to_string(),
                            "tangent points along the centreline towards its end, normal is \
                             any direction across it",
                        )
                    })
                })
                .collect::<Result<Vec<_>, _>>()?,
        ),
    };
    Ok(NominalShape { points, frames })
}

/// Where a `NominalClamp` end is held: the nominal end position and frame.
pub(crate) fn nominal_end(
    nominal: Option<&NominalRod>,
    at_end: bool,
) -> Option<(Vector3<f64>, UnitQuaternion<f64>)> {
    nominal.map(|n| {
        if at_end {
            (n.end_position(), n.end_frame)
        } else {
            (n.start_position(), n.start_frame)
        }
    })
}

/// The initial guess of a rod with a nominal shape: the nominal configuration, its
/// ends moved onto supports held elsewhere (the offsets spread linearly in arc length,
/// or a rigid shift when only one end is held) and its frames turned onto the moved
/// edges.
pub(crate) fn initial_guess(nominal: &NominalRod, start: &End, end: &End) -> RodState {
    let mut state = nominal.state.clone();
    let s = nominal.rod.arc_lengths();
    let length = nominal.rod.length();
    // Extra whole turns of twist (`twist_turns`), spread along the rod as in
    // `strand_system::initial_state`: the last edge takes them all (a whole number of
    // turns leaves its frame unchanged), edge e the share of its mid arc length.
    let turns = i64::from(end.twist_turns) - i64::from(start.twist_turns);
    if turns != 0 {
        let n = state.frames.len();
        let twist = std::f64::consts::TAU * turns as f64;
        for (e, frame) in state.frames.iter_mut().enumerate() {
            let share = if e + 1 == n {
                1.0
            } else {
                0.5 * (s[e] + s[e + 1]) / length
            };
            *frame *= nalgebra::UnitQuaternion::from_axis_angle(&Vector3::z_axis(), twist * share);
        }
    }
    let offset = |end: &End, nominal_position: Vector3<f64>| {
        end.support.position().map(|p| p - nominal_position)
    };
    let (a, b) = (
        offset(start, nominal.start_position()),
        offset(end, nominal.end_position()),
    );
    let (a, b) = match (a, b) {
        (Some(a), Some(b)) => (a, b),
        (Some(a), None) => (a, a),
        (None, Some(b)) => (b, b),
        (None, None) => return state,
    };
    if a == Vector3::zeros() && b == Vector3::zeros() {
        return state;
    }
    for (j, s) in s.iter().enumerate() {
        let w = s / length;
        let moved = state.positions[j] + a * (1.0 - w) + b * w;
        state.set_position(j, moved);
    }
    for e in 0..state.frames.len() {
        let edge = state.edge_vector(e);
        if edge.norm() > 0.0 {
            state.frames[e] = frame_with_tangent(&edge, &state.frames[e]);
        }
    }
    state
}

/// Replaces the default initial guess of every rod that has a nominal guess.
pub(crate) fn use_guesses(state: &mut strand_system::SystemState, guesses: &[Option<RodState>]) {
    for (rod, guess) in state.rods.iter_mut().zip(guesses) {
        if let Some(guess) = guess {
            rod.clone_from(guess);
        }
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::Vector3;
    use strand_solve::solve;
    use strand_system::Support;

    use crate::{Case, CaseError};

    fn cases_dir() -> std::path::PathBuf {
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../cases")
    }

    fn moulded_hose() -> String {
        std::fs::read_to_string(cases_dir().join("moulded_hose.ron")).unwrap()
    }

    fn with(from: &str, to: &str) -> String {
        let text = moulded_hose();
        assert!(text.contains(from), "test bug: {from:?} not in the case");
        text.replacen(from, to, 1)
    }

    fn message(text: &str) -> String {
        match Case::from_str(text, "cases/x.ron").and_then(|c| c.build(None)) {
            Ok(_) => panic!("expected an error"),
            Err(e @ CaseError::Invalid { .. }) => e.to_string(),
            Err(e) => panic!("expected an invalid item, got {e}"),
        }
    }

    #[test]
    fn the_moulded_hose_case_builds_and_solves() {
        let case = Case::from_path(cases_dir().join("moulded_hose.ron")).unwrap();
        let built = case.build(None).unwrap();
        let spec = &built.model.system().rods[0];
        // The chord polygon of the 299.248 mm centreline.
        assert!(
            (spec.rod.length() - 0.29914).abs() < 1e-5,
            "{}",
            spec.rod.length()
        );
        let Support::Clamped { position, frame } = spec.end.support else {
            panic!("the end must be clamped")
        };
        assert!((position - Vector3::new(0.165, 0.16, 0.0)).norm() < 1e-15);
        let tilt = (frame * Vector3::z() - Vector3::y()).norm();
        assert!(tilt < 1e-4, "end tangent off by {tilt} rad");
        // The initial guess is the nominal shape.
        let guess = &built.initial.rods[0];
        assert!(guess.positions[10].z == 0.0 && (guess.positions[30] - position).norm() == 0.0);

        let solution = solve(&built.model, built.initial.clone(), &built.settings).unwrap();
        assert!(
            solution.report.converged && solution.report.stable,
            "{:?}",
            solution.report
        );
        let weight = spec.rod.mass() * 9.81;
        let lift: f64 = built
            .model
            .reactions(&solution.state)
            .iter()
            .map(|r| r.force.z)
            .sum();
        assert!(
            (lift - weight).abs() < 1e-9 * weight,
            "{lift} N vs {weight} N"
        );
        let sag = solution.state.rods[0]
            .positions
            .iter()
            .map(|p| -p.z)
            .fold(0.0, f64::max);
        assert!(sag > 5e-4 && sag < 5e-3, "sag {sag} m");

        // Without gravity it is already in equilibrium: no Newton step, no stress.
        let weightless = Case::from_str(
            &with("gravity: (0, 0, -9.81)", "gravity: (0, 0, 0)"),
            "cases/moulded_hose.ron",
        )
        .unwrap()
        .build(None)
        .unwrap();
        let rest = solve(
            &weightless.model,
            weightless.initial.clone(),
            &weightless.settings,
        )
        .unwrap();
        assert!(
            rest.report.converged && rest.report.iterations == 0,
            "{:?}",
            rest.report
        );
        assert!(rest.report.residual.combined_n < 1e-12);
        for r in weightless.model.reactions(&rest.state) {
            assert!(r.force.norm() < 1e-12 && r.moment.norm() < 1e-12, "{r:?}");
        }
    }

    #[test]
    fn a_stated_length_must_match_the_nominal_length() {
        let no_length =
            "            // no `length`: a moulded hose is as long as its nominal centreline\n";
        for ok in ["299.25", "297", "301.5"] {
            let text = with(no_length, &format!("            length: {ok},\n"));
            assert!(
                Case::from_str(&text, "x.ron").unwrap().build(None).is_ok(),
                "{ok}"
            );
        }
        let m = message(&with(no_length, "            length: 350,\n"));
        assert!(
            m.starts_with("cases/x.ron: rods[0] 'hose'.length: the length 350 mm does not match")
                && m.contains("299.14")
                && m.contains("hint: omit `length`"),
            "{m}"
        );
    }

    #[test]
    fn nominal_errors_name_the_item() {
        let m = message(&with("(105, 0, 0),", "(0, 0, 0),"));
        assert!(
            m.contains("rods[0] 'hose'.nominal.points[1]: nominal points[1] repeats points[0]"),
            "{m}"
        );
        let m = message(&with("(105, 0, 0),", "(105, NaN, 0),"));
        assert!(
            m.contains("rods[0] 'hose'.nominal.points[1]: must have finite"),
            "{m}"
        );
        let m = message(&with(
            "points: [\n",
            "frames: [(tangent: (1, 0, 0), normal: (0, 0, 1))],\n                points: [\n",
        ));
        assert!(
            m.contains(
                "rods[0] 'hose'.nominal.frames: nominal frames: expected one per point (9), got 1"
            ),
            "{m}"
        );
        // Without a nominal shape, a rod needs its length, and NominalClamp is refused.
        let base = r#"(
            units: (length: "mm"),
            sections: { "paper": Explicit(ea: 30e3, ga: 10e3, ei: 1, gj: 1, mass_per_length: 0) },
            rods: [(
                name: "rod", section: "paper", length: 1000, segments: 19,
                start: Clamp(position: (0, 0, 0), tangent: (1, 0, 0), normal: (0, 1, 0)),
                end: Free(force: (2, 1, 0)),
            )],
            gravity: (0, 0, 0),
        )"#;
        let m = message(&base.replace("length: 1000,", ""));
        assert!(
            m.contains("rods[0] 'rod'.length: missing field `length`"),
            "{m}"
        );
        let m = message(&base.replace("end: Free(force: (2, 1, 0)),", "end: NominalClamp(),"));
        assert!(
            m.contains("rods[0] 'rod'.end: NominalClamp needs the rod's `nominal` shape"),
            "{m}"
        );
    }

    #[test]
    fn frames_and_displaced_mounts_are_accepted() {
        // An arc with its frames (a1 = +z), clamped 5 mm beyond its nominal end.
        let text = r#"(
            units: (length: "mm"),
            sections: { "rubber": Tube(youngs_modulus: 5e6, poisson_ratio: 0.5, density: 1100,
                                       inner_radius: 9.4, outer_radius: 12.9) },
            rods: [(
                name: "arc", section: "rubber", segments: 16,
                nominal: (
                    points: [(0, 0, 0), (70.7107, 29.2893, 0), (100, 100, 0)],
                    frames: [
                        (tangent: (1, 0, 0), normal: (0, 0, 1)),
                        (tangent: (1, 1, 0), normal: (0, 0, 1)),
                        (tangent: (0, 1, 0), normal: (0, 0, 1)),
                    ],
                ),
                start: NominalClamp(),
                end: Clamp(position: (100, 105, 0), tangent: (0, 1, 0), normal: (0, 0, 1)),
            )],
            gravity: (0, 0, 0),
        )"#;
        let built = Case::from_str(text, "arc.ron")
            .unwrap()
            .build(None)
            .unwrap();
        let spec = &built.model.system().rods[0];
        let quarter = 0.05 * std::f64::consts::PI;
        assert!((spec.rod.length() - quarter).abs() < 1e-3 * quarter);
        // The guess reaches the displaced clamp.
        let guess = &built.initial.rods[0];
        assert!((guess.positions[16] - Vector3::new(0.1, 0.105, 0.0)).norm() < 1e-15);
        let solution = solve(&built.model, built.initial.clone(), &built.settings).unwrap();
        assert!(
            solution.report.converged && solution.report.stable,
            "{:?}",
            solution.report
        );
        // Pulled 5 mm along its end tangent: the hose carries a force.
        let pull = built.model.reactions(&solution.state)[1].force;
        assert!(pull.norm() > 0.01, "{pull:?}");
    }
}

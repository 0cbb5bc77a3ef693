//! A start that clears the environment. The default guess of a rod without a route
//! hangs under gravity (a catenary, a sagging Hermite curve, a dangling tail); with a
//! part under the connectors it may pass straight through it, and the solve would
//! reject the case as "starting inside" although the user never said where the hose
//! runs. The guess is then bowed to one of four sides (gravity turned horizontal),
//! else arched upwards (gravity reversed), else bowed half-way up to one of the four
//! sides, else laid straight between the ends (compressed), and the solve settles it
//! where it comes to rest: an equilibrium of the case, not necessarily the one a fitter
//! would choose (a route chooses). Laying the hanging guess over the parts instead
//! (lifting its vertices above them) was tried: the cable then rests across the rims of
//! a box top, which did not converge in 400 iterations; bowed sideways it comes to rest
//! against the box in 27. The straight start is for a hose held inside a groove (its
//! bows leave the clamps into the flanks) or one whose bows cross over themselves: of
//! 80 generated everyday cables (`crates/strand-cli/tests/everyday.rs`, seeds 1 and 2),
//! 7 were refused before it and the half-way bows, none after. Last, a rod dangling
//! from one held end is draped over the parts ([`crate::drape`]): its free tail leaves
//! the nozzle towards the part whichever way gravity is turned for the guess, and 9 of
//! the 60 generated dangling cables of seeds 1–3 (floors as often as grooves) were
//! refused before it, none after. Last of all, a rod held at both ends is routed
//! around the parts between its nozzles and clips ([`crate::detour`]): of 200
//! generated cables between random faces of the bundled engine bay, 28 were refused
//! before it, 8 after (none of which fits a way around the parts in its length); of
//! 120 with one or two clips on random faces, 86 were refused before the ways went
//! from clip to clip (a clipped rod's free end is draped from its last clip). When nothing clears and
//! a free junction's given position holds a hose's end inside or against a part, the
//! junction is moved to the nearest clear place ([`crate::placement`]) and every start
//! is tried again from there.

use nalgebra::Vector3;
use strand_rod::RodState;
use strand_system::{RouteShape, System, SystemState, initial_state, initial_state_with};

use crate::BuiltCase;
use crate::detour::{detoured, shortfall};
use crate::drape::draped;
use crate::nominal::use_guesses;
use crate::placement::placed_bodies;

impl BuiltCase {
    /// The first of the hanging guess (`self.initial`, routes smoothed), the routes as
    /// drawn, the guesses bowed sideways, the guess arched upwards, the guesses bowed
    /// half-way up, the straight start ([`Start::Straight`]), the draped start of
    /// dangling rods ([`Start::Draped`]) and the start routed around the parts of rods
    /// held at both ends ([`Start::Detour`]) that clears every obstacle
    /// ([`BuiltCase::check_start`]), with the rods' warm-start `guesses` and routes kept
    /// in each; when none does and a free junction's given position holds a hose's end
    /// inside or against a part, the same from the junction moved to the nearest clear
    /// place (recorded in `self.moved_bodies`). When none clears, the routes as drawn
    /// if there are routes, else `self.initial` unchanged (the check then names the
    /// overlap); unchanged without an environment. Returns which start was taken.
    pub(crate) fn clear_start(&mut self, guesses: &[Option<RodState>]) -> Start {
        if self.environment.is_empty() || self.check_start().is_ok() {
            return Start::Hanging;
        }
        let system = self.model.system().clone();
        if let Some(start) = self.first_clear(&system, guesses) {
            return start;
        }
        // A free junction whose given position holds a hose's end inside or against a
        // part: every start again from the nearest clear place.
        if let Some((placed, moves)) = placed_bodies(&system, &self.environment) {
            let mut moved = initial_state(&placed);
            use_guesses(&mut moved, guesses);
            let given = std::mem::replace(&mut self.initial, moved);
            let start = if self.check_start().is_ok() {
                Some(Start::Hanging)
            } else {
                self.first_clear(&placed, guesses)
            };
            if let Some(start) = start {
                self.moved_bodies = moves;
                return start;
            }
            self.initial = given;
        }
        self.start_hint = shortfall(&system, &self.initial, &self.environment);
        if system.rods.iter().any(|r| r.route.is_some()) {
            // Nothing clears: the check names the overlap of the route as drawn, the
            // geometry the user gave, not of its smoothed curve.
            let mut as_drawn = initial_state_with(&system, RouteShape::AsDrawn);
            use_guesses(&mut as_drawn, guesses);
            self.initial = as_drawn;
            return Start::RouteAsDrawn;
        }
        Start::Hanging
    }

    /// The first start after the hanging guess (`self.initial`, of `system`) that
    /// clears every obstacle, `self.initial` set to it; `None` (and `self.initial`
    /// unchanged) when none does.
    fn first_clear(&mut self, system: &System, guesses: &[Option<RodState>]) -> Option<Start> {
        if system.rods.iter().any(|r| r.route.is_some()) {
            // A route drawn around a part: its smoothed corners may cut into it.
            let mut candidate = initial_state_with(system, RouteShape::AsDrawn);
            use_guesses(&mut candidate, guesses);
            let smoothed = std::mem::replace(&mut self.initial, candidate);
            if self.check_start().is_ok() {
                return Some(Start::RouteAsDrawn);
            }
            self.initial = smoothed;
        }
        let g = system.gravity;
        // Two horizontal directions (perpendicular to gravity, or to z without it).
        let down = if g.norm() > 0.0 {
            g.normalize()
        } else {
            -Vector3::z()
        };
        let side = down.cross(&Vector3::x());
        let side = if side.norm() > 0.5 {
            side
        } else {
            down.cross(&Vector3::y())
        }
        .normalize();
        let other = down.cross(&side);
        let weight = g.norm().max(1.0);
        let tilted = |a: Vector3<f64>| (a - down).normalize() * weight;
        // Sideways first: an arch is itself an (unstable) equilibrium of a clamped
        // rod that Newton may find; a sideways bow is none and falls. Then bowed
        // half-way up to each side (a hose between the flanks of a groove, whose
        // bottom the hanging guess and whose flanks the sideways bows pass through).
        for (kind, gravity) in [
            (Start::Sideways, side * weight),
            (Start::Sideways, -side * weight),
            (Start::Sideways, other * weight),
            (Start::Sideways, -other * weight),
            (Start::Arched, -down * weight),
            (Start::Sideways, tilted(side)),
            (Start::Sideways, tilted(-side)),
            (Start::Sideways, tilted(other)),
            (Start::Sideways, tilted(-other)),
        ] {
            let mut candidate = initial_state(&System {
                gravity,
                ..system.clone()
            });
            use_guesses(&mut candidate, guesses);
            let hanging = std::mem::replace(&mut self.initial, candidate);
            if self.check_start().is_ok() {
                return Some(kind);
            }
            self.initial = hanging;
        }
        // Last, the ends joined straight (a hose held inside a groove: the chord
        // between two points clear of both flanks stays clear of them), leaving each
        // end along its clamp for one edge, the rod compressed onto that shorter path.
        if let Some(straight) = straightened(system, &self.initial) {
            let mut candidate = initial_state_with(&straight, RouteShape::AsDrawn);
            use_guesses(&mut candidate, guesses);
            let hanging = std::mem::replace(&mut self.initial, candidate);
            if self.check_start().is_ok() {
                return Some(Start::Straight);
            }
            self.initial = hanging;
        }
        // A dangling rod (one end held, the other free) draped over the parts below it,
        // its first heading turned by each right angle in turn.
        for turn in 0..4 {
            let Some(draped) = draped(system, &self.initial, &self.environment, turn) else {
                break;
            };
            if self.routed_clears(system, &draped, guesses) {
                return Some(Start::Draped);
            }
        }
        // A rod held at both ends routed around the parts between its nozzles and
        // clips, its ways clear of them by half an edge beyond the radius (the rod's
        // edges cut their corners), else by the radius alone (a narrow passage).
        for corners in [true, false] {
            let Some(laid) = detoured(system, &self.initial, &self.environment, corners) else {
                continue;
            };
            if self.laid_clears(laid, guesses) {
                return Some(Start::Detour);
            }
        }
        None
    }

    /// Whether the start with the rods `laid` (rod index, state) and the others
    /// keeping their guess in `self.initial` clears every obstacle: `self.initial` set
    /// to it if so, unchanged if not.
    fn laid_clears(&mut self, laid: Vec<(usize, RodState)>, guesses: &[Option<RodState>]) -> bool {
        let mut candidate = self.initial.clone();
        for (r, rod) in laid {
            candidate.rods[r] = rod;
        }
        use_guesses(&mut candidate, guesses);
        let hanging = std::mem::replace(&mut self.initial, candidate);
        match self.check_start() {
            Ok(()) => return true,
            Err(e) if std::env::var_os("STRAND_TRACE").is_some() => eprintln!("laid: {e}"),
            Err(_) => {}
        }
        self.initial = hanging;
        false
    }

    /// Whether the start with the rods `routed` gave a route (and `system` did not)
    /// laid along it as drawn, the other rods keeping their guess in `self.initial`
    /// (their routes smoothed), clears every obstacle: `self.initial` set to it if so,
    /// unchanged if not.
    fn routed_clears(
        &mut self,
        system: &System,
        routed: &System,
        guesses: &[Option<RodState>],
    ) -> bool {
        let mut candidate = initial_state_with(routed, RouteShape::AsDrawn);
        for (r, rod) in candidate.rods.iter_mut().enumerate() {
            if system.rods[r].route.is_some() || routed.rods[r].route.is_none() {
                *rod = self.initial.rods[r].clone();
            }
        }
        use_guesses(&mut candidate, guesses);
        let hanging = std::mem::replace(&mut self.initial, candidate);
        if self.check_start().is_ok() {
            return true;
        }
        self.initial = hanging;
        false
    }
}

/// `system` with a straight route for every rod that has none, both ends held and no
/// clip: from the start vertex one reference edge along the start's tangent in
/// `hanging` (the clamp direction at a clamp), straight to one edge before the end
/// vertex along the end's tangent, then to the end vertex. `None` when no rod gets
/// one.
fn straightened(system: &System, hanging: &SystemState) -> Option<System> {
    let mut straight = system.clone();
    let mut any = false;
    for (r, spec) in straight.rods.iter_mut().enumerate() {
        let clipped = system.clips.iter().any(|c| c.rod.0 == r);
        if spec.route.is_some()
            || clipped
            || !spec.start.support.is_held()
            || !spec.end.support.is_held()
        {
            continue;
        }
        let p = &hanging.rods[r].positions;
        let n = p.len() - 1;
        let (a, b) = (p[0], p[n]);
        let (first, last) = (spec.rod.edge_length(0), spec.rod.edge_length(n - 1));
        let (ta, tb) = ((p[1] - a).normalize(), (b - p[n - 1]).normalize());
        let route = vec![a, a + ta * first, b - tb * last, b];
        if route.iter().any(|v| !v.iter().all(|x| x.is_finite())) {
            continue;
        }
        spec.route = Some(route);
        any = true;
    }
    any.then_some(straight)
}

/// Which default guess a case with an environment starts from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Start {
    /// Hanging under gravity (the default guess; also when nothing else clears).
    Hanging,
    /// The hanging shape with gravity reversed: arched up over the part below.
    Arched,
    /// The routes as drawn, corners unsmoothed ([`RouteShape::AsDrawn`]): their
    /// smoothed curves pass through an obstacle.
    RouteAsDrawn,
    /// The hanging shape with gravity turned horizontal: bowed to one side of a part
    /// between the ends.
    Sideways,
    /// The ends joined by a straight line (leaving each along its clamp for one edge),
    /// the rod compressed onto it: every bowed guess passes through an obstacle.
    Straight,
    /// A dangling rod's hanging guess kept while it clears the parts, the rest of it
    /// fallen over them as a chain would ([`crate::drape`]): every other guess passes
    /// through an obstacle.
    Draped,
    /// A rod held at both ends laid along the shortest ways around the parts between
    /// its nozzles and clips that a lattice search finds ([`crate::detour`]),
    /// compressed onto them: every other guess passes through an obstacle.
    Detour,
    /// A given state (a warm start from a neighbouring solution, e.g. the previous
    /// pose of a motion): no guess was made.
    Given,
}

impl Start {
    /// What the start is, for the terminal summary (`None` for the hanging guess).
    pub fn describe(self) -> Option<&'static str> {
        match self {
            Start::Hanging | Start::Given => None,
            Start::RouteAsDrawn => {
                Some("the routes as drawn (their smoothed corners pass through an obstacle)")
            }
            Start::Sideways => Some(
                "bowed sideways (the hanging guess passes through an obstacle; give a route to choose)",
            ),
            Start::Arched => Some(
                "arched up (the hanging and sideways guesses pass through an obstacle; give a route to choose)",
            ),
            Start::Straight => Some(
                "straight between the ends, compressed (every hanging, bowed and arched guess passes through an obstacle; give a route to choose)",
            ),
            Start::Detour => Some(
                "routed around the parts between its ends and clips, compressed (every hanging, bowed, arched and straight guess passes through an obstacle; give a route to choose)",
            ),
            Start::Draped => Some(
                "draped over the parts below its held end (every hanging, bowed and arched guess passes through an obstacle; give a route to choose)",
            ),
        }
    }
}

#[cfg(test)]
mod tests {
    use std::io::Write;

    use strand_solve::contact::Contact;

    use super::Start;
    use crate::Case;

    /// The bundled `cases/cable_over_box.ron` in a temporary directory, with its box's
    /// top at `top` mm (−30 in the bundled one): its hanging guess sags about 120 mm,
    /// through the box top.
    fn cable_over_box(top: f64) -> (tempfile::TempDir, std::path::PathBuf) {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
        let dir = tempfile::tempdir().unwrap();
        let obj = std::fs::read_to_string(root.join("assets/parts/box.obj")).unwrap();
        let obj = obj.replace(" -30\n", &format!(" {top}\n"));
        std::fs::File::create(dir.path().join("box.obj"))
            .unwrap()
            .write_all(obj.as_bytes())
            .unwrap();
        let text = std::fs::read_to_string(root.join("cases/cable_over_box.ron")).unwrap();
        let path = dir.path().join("cable.ron");
        std::fs::write(&path, text.replace("../assets/parts/box.obj", "box.obj")).unwrap();
        (dir, path)
    }

    /// `built` solved from its start: converged, its rod resting on the parts (a
    /// loaded contact, no penetration beyond 1e-9 m, every vertex outside every closed
    /// mesh) and its weight (its vertices' masses under gravity) carried by the
    /// contacts and the supports' reactions to 1e-8 of it; `what` names the case in
    /// the messages.
    fn assert_at_rest(built: &crate::BuiltCase, what: &str) -> strand_solve::Solution {
        let solution = built
            .solve_from(built.initial.clone(), &built.settings)
            .unwrap();
        let report = &solution.report;
        assert!(report.converged, "{what}: {report:?}");
        let contact = built.contact().unwrap();
        let forces = contact
            .forces(&built.model, &solution.state, &solution.constraints)
            .unwrap();
        assert!(forces.iter().any(|f| f.force_n > 0.0), "{what}: no contact");
        let deepest = forces
            .iter()
            .map(|f| f.gap.gap)
            .fold(f64::INFINITY, f64::min);
        assert!(deepest >= -1e-9, "{what}: penetrates by {deepest:e} m");
        let system = built.model.system();
        let rod = &system.rods[0].rod;
        let mass: f64 = (0..=rod.segments()).map(|j| rod.vertex_mass(j)).sum();
        let weight = mass * system.gravity;
        let mut total = weight;
        for f in &forces {
            total += f.force_n * f.gap.normal.into_inner();
        }
        for r in built.model.reactions(&solution.state) {
            total += r.force;
        }
        assert!(
            total.norm() <= 1e-8 * weight.norm(),
            "{what}: imbalance {total:?} of {} N",
            weight.norm()
        );
        for mesh in &built.environment {
            for p in &solution.state.rods[0].positions {
                assert!(
                    !mesh.encloses(&nalgebra::Point3::from(*p)),
                    "{what}: {p} inside"
                );
            }
        }
        solution
    }

    /// The bundled engine bay's five parts as a case's `environment` entries (mm).
    fn engine_bay_environment() -> String {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/engine_bay");
        let parts = ["radiator", "fan_shroud", "engine", "oil_cooler", "brackets"];
        let entries: Vec<String> = parts
            .iter()
            .map(|p| {
                let obj = root.join(format!("{p}.obj"));
                format!(r#"(name: "{p}", obj: "{}", unit: "mm"),"#, obj.display())
            })
            .collect();
        entries.join("\n")
    }

    #[test]
    fn a_cable_whose_hanging_guess_passes_through_a_part_starts_beside_it_and_rests_against_it() {
        for top in [-30.0, 20.0] {
            let (_dir, path) = cable_over_box(top);
            let built = Case::from_path(&path).unwrap().build(None).unwrap();
            // The hanging guess passes through the box (the old start, rejected).
            let hanging = strand_system::initial_state(built.model.system());
            let contact = built.contact().unwrap();
            let mut start = hanging.clone();
            built.model.enforce_supports(&mut start);
            use strand_solve::Constraints;
            assert!(contact.check_start(&built.model, &start).is_err());
            // The start taken clears it: `check` and `solve` accept the case.
            assert_eq!(built.start, Start::Sideways, "top {top}");
            built.check_start().unwrap();
            // It comes to rest against the box (around its side: lower than across its
            // top): loaded contacts, no penetration, every vertex outside the box, and
            // the box and the connectors together carry the weight.
            let solution = assert_at_rest(&built, &format!("top {top}"));
            assert!(solution.report.stable, "top {top}: unstable");
        }
    }

    /// A 23 mm soft hose (E 4 MPa, 907 mm, 150 segments) from a nozzle beside the fan
    /// hub, pointing down and back, to a pin under the engine block of the bundled
    /// engine bay (`e1_007` of 20 cables generated between random faces of its parts):
    /// its hanging guess, its bows, its arch and the straight chord all pass through a
    /// part (before the detour it was refused with the hint to give a route). It starts
    /// routed around them: every vertex clear, the rod compressed onto the way (never
    /// longer than the rod); it converges, stable, every vertex outside every part,
    /// no penetration, its weight carried by the contacts and its two supports.
    #[test]
    fn a_hose_between_two_parts_of_the_engine_bay_starts_routed_around_them_and_converges() {
        let text = format!(
            r#"(
                units: (length: "mm"),
                sections: {{ "s": Tube(youngs_modulus: 4.01e6, poisson_ratio: 0.45, density: 2009,
                                      inner_radius: 0, outer_radius: 11.535) }},
                connectors: {{
                    "a": (position: (-182.725, -12.604, 168.099), direction: (0.392, -0.052, -0.918),
                          normal: (0.000, -0.998, 0.057)),
                    "b": (position: (347.262, 64.969, -200.907), direction: (0.009, 0.215, -0.977),
                          normal: (0.000, -0.977, -0.215)),
                }},
                rods: [(name: "c", section: "s", length: 907, segments: 150,
                        start: Connector("a"), end: ConnectorPin("b"))],
                environment: [{}],
                gravity: (0, 0, -9.81),
            )"#,
            engine_bay_environment()
        );
        let (_dir, built) = built_in_a_folder(&text);
        assert_eq!(built.start, Start::Detour);
        built.check_start().unwrap();
        let p = &built.initial.rods[0].positions;
        let laid: f64 = p.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
        assert!(laid <= 0.907 + 1e-12, "laid along {laid} m");
        let solution = assert_at_rest(&built, "engine bay");
        assert!(solution.report.stable, "unstable");
    }

    /// A soft 6.7 mm cable (E 8.3 MPa, 2740 mm, 56 segments) from a pin on the fan
    /// shroud through a revolute clip on the oil cooler and a fixed clip on the engine
    /// block to a nozzle on the brackets of the bundled engine bay (`k4_016` of 40
    /// clipped cables generated between random faces of its parts): its hanging guess
    /// and its bows pass through the parts between its stations (before the detour
    /// went from clip to clip it was refused with the hint to give a route). It starts
    /// routed around them between each pair of stations: every clipped vertex at its
    /// clip, the rod between two stations laid along a way no longer than it; it
    /// converges, stable, every vertex outside every part, no penetration, its weight
    /// carried by the contacts, its two clips and its two supports.
    #[test]
    fn a_clipped_cable_in_the_engine_bay_starts_routed_from_clip_to_clip_and_converges() {
        let text = format!(
            r#"(
                units: (length: "mm"),
                sections: {{ "s": Tube(youngs_modulus: 8.264e+06, poisson_ratio: 0.45, density: 2936,
                                      inner_radius: 0, outer_radius: 3.370) }},
                connectors: {{
                    "a": (position: (-205.049, -166.685, 319.675), direction: (0.601, -0.534, 0.595),
                          normal: (-0.664, -0.748, 0.000)),
                    "b": (position: (-95.460, 52.877, -227.926), direction: (-0.787, -0.607, -0.112),
                          normal: (-0.611, 0.791, 0.000)),
                }},
                rods: [(name: "c", section: "s", length: 2739.72, segments: 56,
                        start: ConnectorPin("a"), end: Connector("b"))],
                clips: {{
                    "k0": (rod: "c", at: 520.35, joint: Revolute(axis: (0, 0, 1)),
                           base: (position: (-74.508, -184.250, 60.375), direction: (-0.764, 0.132, -0.632),
                                  normal: (0.577, 0.577, -0.577))),
                    "k1": (rod: "c", at: 1764.83, joint: Fixed,
                           base: (position: (406.697, 258.255, -177.228), direction: (0.786, 0.618, 0.000),
                                  normal: (0.000, 0.000, -1.000))),
                }},
                environment: [{}],
                gravity: (0, 0, -9.81),
            )"#,
            engine_bay_environment()
        );
        let (_dir, built) = built_in_a_folder(&text);
        assert_laid_through_its_stations(&built);
        let solution = assert_at_rest(&built, "clipped");
        assert!(solution.report.stable, "unstable");
    }

    /// A 21 mm hose (E 17 MPa, 2502 mm, 88 segments) from a nozzle on the radiator
    /// through a revolute clip on the brackets and a fixed clip on the radiator's
    /// side, its last 471 mm hanging free (`t3_000` of 40 such cables generated in
    /// the bundled engine bay): its hanging guess passes through the parts between its
    /// stations and, beyond the last clip, through the radiator (before the free
    /// stretch was draped it was refused). It starts routed between its stations and
    /// draped beyond them, every clipped vertex at its clip, and converges, stable, at
    /// rest against the parts.
    #[test]
    fn a_clipped_hose_with_a_free_end_starts_routed_and_draped_and_converges() {
        let text = format!(
            r#"(
                units: (length: "mm"),
                sections: {{ "s": Tube(youngs_modulus: 1.723e+07, poisson_ratio: 0.45, density: 1492,
                                      inner_radius: 0, outer_radius: 10.494) }},
                connectors: {{
                    "a": (position: (-204.451, 132.791, 220.108), direction: (0.976, -0.213, -0.050),
                          normal: (-0.214, -0.977, 0.000)),
                }},
                rods: [(name: "c", section: "s", length: 2502.23, segments: 88,
                        start: Connector("a"), end: Free())],
                clips: {{
                    "k0": (rod: "c", at: 790.65, joint: Revolute(axis: (0, 0, 1)),
                           base: (position: (13.647, 396.183, -252.410), direction: (-0.586, 0.000, -0.811),
                                  normal: (0.000, 1.000, 0.000))),
                    "k1": (rod: "c", at: 2030.93, joint: Fixed,
                           base: (position: (-276.344, -268.604, 305.403), direction: (0.000, -0.993, 0.115),
                                  normal: (-1.000, 0.000, 0.000))),
                }},
                environment: [{}],
                gravity: (0, 0, -9.81),
            )"#,
            engine_bay_environment()
        );
        let (_dir, built) = built_in_a_folder(&text);
        // The hanging guess's free stretch beyond the last clip passes through a part.
        let system = built.model.system();
        let hanging = strand_system::initial_state(system);
        let tail = &hanging.rods[0].positions[system.clips[1].vertex..];
        let radius = system.rods[0].rod.section().outer_radius;
        assert!(
            tail.windows(2).any(|w| {
                let (a, b) = (nalgebra::Point3::from(w[0]), nalgebra::Point3::from(w[1]));
                built
                    .environment
                    .iter()
                    .any(|mesh| mesh.segment_distance(&a, &b, radius).is_some())
            }),
            "the hanging tail clears the parts"
        );
        assert_laid_through_its_stations(&built);
        let solution = assert_at_rest(&built, "free end");
        assert!(solution.report.stable, "unstable");
    }

    /// A 600 mm hose (radius 5 mm, 60 segments) pinned either side of a closed wall
    /// 100 mm thick and 600 mm square, 150 mm from its middle: every guess passes
    /// through the wall, and no way around it fits in 600 mm (around its edge it is
    /// at least `2·√(100² + 300²) + 100` = 732 mm). The error says how long the way the
    /// solver finds is (no shorter than that bound; within 20 % of it: the way is
    /// found on a lattice whose nodes keep half its diagonal more from the wall, 827
    /// mm), how much longer than the rod that is, and where; the same hose made as
    /// long as it says (2 % more) starts clear of the wall (hanging under it) and
    /// converges.
    #[test]
    fn a_hose_too_short_for_the_way_around_a_part_is_told_how_long_the_way_is() {
        let hose = |length_mm: f64| {
            format!(
                r#"(
                    units: (length: "mm"),
                    sections: {{ "s": Explicit(ea: 2e4, ga: 5e3, ei: 5e-3, gj: 4e-3,
                                              mass_per_length: 0.1, outer_radius: 5) }},
                    connectors: {{
                        "a": (position: (-150, 0, 0), direction: (1, 0, 0), normal: (0, 0, 1)),
                        "b": (position: (150, 0, 0), direction: (1, 0, 0), normal: (0, 0, 1)),
                    }},
                    rods: [(name: "c", section: "s", length: {length_mm}, segments: 60,
                            start: ConnectorPin("a"), end: ConnectorPin("b"))],
                    environment: [(name: "wall", obj: "wall.obj", unit: "mm")],
                    gravity: (0, 0, -9.81),
                )"#
            )
        };
        let wall = box_obj([-50.0, -300.0, -300.0], [50.0, 300.0, 300.0]);
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("wall.obj"), &wall).unwrap();
        let build = |length_mm: f64| {
            let path = dir.path().join("hose.ron");
            std::fs::write(&path, hose(length_mm)).unwrap();
            Case::from_path(&path).unwrap().build(None).unwrap()
        };
        let short = build(600.0);
        let Err(strand_solve::SolveError::StartsInside(mut error)) = short.check_start() else {
            panic!("a 600 mm hose starts clear");
        };
        let (rod, hint) = error.start_hint_mut().expect("a start error");
        assert_eq!(rod, "c");
        let strand_solve::StartHint::Lengthen(way) = hint else {
            panic!("hint {hint:?}");
        };
        let strand_solve::WayAround {
            from_s_mm,
            to_s_mm,
            way_mm,
        } = **way;
        assert_eq!((from_s_mm, to_s_mm), (0, 600));
        let around = 2.0 * (100f64.powi(2) + 300f64.powi(2)).sqrt() + 100.0;
        let way = f64::from(way_mm);
        assert!(
            around <= way && way <= 1.2 * around,
            "way {way} mm, around {around} mm"
        );
        let message = error.to_string();
        let more = format!(
            "about {way_mm} mm, {} mm more than the rod's 600 mm",
            way_mm - 600
        );
        assert!(message.contains(&more), "{message}");
        let long = build(1.02 * way);
        long.check_start().unwrap();
        let solution = long
            .solve_from(long.initial.clone(), &long.settings)
            .unwrap();
        assert!(solution.report.converged, "{:?}", solution.report);
    }

    /// An OBJ of the closed axis-aligned box from `min` to `max` (its units).
    fn box_obj(min: [f64; 3], max: [f64; 3]) -> String {
        let mut obj = String::new();
        for k in 0..8 {
            let pick = |bit: usize, i: usize| if k & bit == 0 { min[i] } else { max[i] };
            obj += &format!("v {} {} {}\n", pick(1, 0), pick(2, 1), pick(4, 2));
        }
        for [a, b, c, d] in [
            [1, 3, 4, 2],
            [5, 6, 8, 7],
            [1, 2, 6, 5],
            [3, 7, 8, 4],
            [1, 5, 7, 3],
            [2, 4, 8, 6],
        ] {
            obj += &format!("f {a} {b} {c}\nf {a} {c} {d}\n");
        }
        obj
    }

    /// `text` written into a new folder and built.
    fn built_in_a_folder(text: &str) -> (tempfile::TempDir, crate::BuiltCase) {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("case.ron");
        std::fs::write(&path, text).unwrap();
        let built = Case::from_path(&path).unwrap().build(None).unwrap();
        (dir, built)
    }

    /// `built` starts routed ([`Start::Detour`]), clear, with every station's vertex at
    /// its station and the rod between two stations laid along a way no longer than
    /// it.
    fn assert_laid_through_its_stations(built: &crate::BuiltCase) {
        assert_eq!(built.start, Start::Detour);
        built.check_start().unwrap();
        let system = built.model.system();
        let stations = strand_system::rod_stations(system, 0, &built.initial.bodies);
        let p = &built.initial.rods[0].positions;
        for pair in stations.windows(2) {
            let (a, b) = (&pair[0], &pair[1]);
            assert!(
                (p[a.vertex] - a.position).norm() < 1e-12,
                "vertex {}",
                a.vertex
            );
            assert!(
                (p[b.vertex] - b.position).norm() < 1e-12,
                "vertex {}",
                b.vertex
            );
            let laid: f64 = p[a.vertex..=b.vertex]
                .windows(2)
                .map(|w| (w[1] - w[0]).norm())
                .sum();
            assert!(
                laid <= b.s - a.s + 1e-12,
                "laid along {laid} m of {} m",
                b.s - a.s
            );
        }
    }

    /// A T-junction (0.2 kg) given at the middle of a closed box (200 × 200 × 200 mm,
    /// top at z = 0) that its three hoses (8 mm, 320 mm each) from connectors at
    /// z = 300 mm would hang it above: every guess leaves its ports inside the box.
    /// The start moves it to the nearest clear place (up through the top, 112 mm on
    /// its 8 mm lattice, rather than as far down through the bottom: of places as
    /// near, the one nearest to its connectors), its hoses' ends outside and clear of
    /// the box by their radius; the case converges with the T hanging above the box.
    /// Given clear of the box, the T is not moved; given deep inside a far larger part,
    /// beyond every place the search tests, the error names the junction's position.
    #[test]
    fn a_junction_given_inside_a_part_starts_at_the_nearest_clear_place_and_converges() {
        let dir = tempfile::tempdir().unwrap();
        let part = box_obj([-100.0, -100.0, -200.0], [100.0, 100.0, 0.0]);
        std::fs::write(dir.path().join("box.obj"), part).unwrap();
        let path = dir.path().join("tee.ron");
        let text = r#"(
            units: (length: "mm"),
            sections: { "s": Explicit(ea: 2e4, ga: 5e3, ei: 5e-3, gj: 4e-3,
                                      mass_per_length: 0.1, outer_radius: 4) },
            connectors: {
                "a": (position: (-250, 0, 300), direction: (0, 0, -1), normal: (1, 0, 0)),
                "b": (position: (125, 216.5, 300), direction: (0, 0, -1), normal: (1, 0, 0)),
                "c": (position: (125, -216.5, 300), direction: (0, 0, -1), normal: (1, 0, 0)),
            },
            junctions: {
                "tee": (mass: 0.2, position: (0, 0, -100), ports: {
                    "pa": (position: (-35, 0, 0), direction: (-1, 0, 0), normal: (0, 0, 1)),
                    "pb": (position: (17.5, 30.3, 0), direction: (0.5, 0.866, 0), normal: (0, 0, 1)),
                    "pc": (position: (17.5, -30.3, 0), direction: (0.5, -0.866, 0), normal: (0, 0, 1)),
                }),
            },
            rods: [
                (name: "ha", section: "s", length: 320, segments: 32, start: Connector("a"), end: Port("tee", "pa")),
                (name: "hb", section: "s", length: 320, segments: 32, start: Connector("b"), end: Port("tee", "pb")),
                (name: "hc", section: "s", length: 320, segments: 32, start: Connector("c"), end: Port("tee", "pc")),
            ],
            environment: [(name: "box", obj: "box.obj", unit: "mm")],
            gravity: (0, 0, -9.81),
        )"#;
        std::fs::write(&path, text).unwrap();
        let built = Case::from_path(&path).unwrap().build(None).unwrap();
        built.check_start().unwrap();
        assert_eq!(built.moved_bodies.len(), 1, "{:?}", built.moved_bodies);
        let moved = &built.moved_bodies[0];
        assert_eq!(moved.name, "tee");
        let step = moved.to - moved.from;
        assert!(
            step.z > 0.09 && step.z < 0.13 && step.x.hypot(step.y) < 0.02,
            "moved by {step:?} m"
        );
        let pose = &built.initial.bodies[0];
        assert_eq!(pose.position, moved.to);
        let system = built.model.system();
        for port in &system.bodies[0].ports {
            let p = pose.position + pose.orientation * port.position;
            let outside = (p.x.abs() - 0.1)
                .max(p.y.abs() - 0.1)
                .max(-p.z)
                .max(p.z + 0.2);
            assert!(outside >= 0.004 * 1.05, "port {} at {p} m", port.name);
        }
        let solution = built
            .solve_from(built.initial.clone(), &built.settings)
            .unwrap();
        let report = &solution.report;
        assert!(report.converged && report.stable, "{report:?}");
        let tee = solution.state.bodies[0].position;
        assert!(tee.z > 0.0, "the T hangs at {tee} m");
        // Given clear of the box, it starts where it is given.
        std::fs::write(&path, text.replace("(0, 0, -100)", "(0, 0, 50)")).unwrap();
        let built = Case::from_path(&path).unwrap().build(None).unwrap();
        assert!(built.moved_bodies.is_empty(), "{:?}", built.moved_bodies);
        assert_eq!(built.initial.bodies[0].position.z, 0.05);
        // Given 1 m deep inside a part 2 m wide, beyond the places the search tests
        // (16 spacings of 32 mm): the error names the junction's position to move.
        let deep = box_obj([-1000.0, -1000.0, -2000.0], [1000.0, 1000.0, 0.0]);
        std::fs::write(dir.path().join("box.obj"), deep).unwrap();
        std::fs::write(&path, text.replace("(0, 0, -100)", "(0, 0, -1000)")).unwrap();
        let built = Case::from_path(&path).unwrap().build(None).unwrap();
        match built.check_start() {
            Err(strand_solve::SolveError::StartsInside(error)) => {
                assert!(
                    error.to_string().contains("rod 'ha'")
                        && matches!(
                            error,
                            strand_solve::ConstraintError::StartsEnclosed {
                                hint: strand_solve::StartHint::MoveJunction,
                                ..
                            }
                        ),
                    "{error:?}"
                );
            }
            other => panic!("{other:?}"),
        }
    }

    /// A case in a temporary directory: a 600 mm cable (6 mm, 0.1 kg/m, 60 segments)
    /// dangling from a nozzle `height` mm above a floor and pointing straight at it.
    fn dangling_at_a_floor(height: f64) -> (tempfile::TempDir, std::path::PathBuf) {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(
            dir.path().join("floor.obj"),
            "v -2000 -2000 0\nv 2000 -2000 0\nv 2000 2000 0\nv -2000 2000 0\nf 1 2 3\nf 1 3 4\n",
        )
        .unwrap();
        let path = dir.path().join("dangling.ron");
        let text = r#"(
                units: (length: "mm"),
                sections: { "s": Explicit(ea: 2e4, ga: 5e3, ei: 5e-3, gj: 4e-3,
                                          mass_per_length: 0.1, outer_radius: 3) },
                connectors: { "nozzle": (position: (0, 0, HEIGHT), direction: (0, 0, -1),
                                         normal: (1, 0, 0)) },
                rods: [(name: "cable", section: "s", length: 600, segments: 60,
                        start: Connector("nozzle"), end: Free())],
                environment: [(name: "floor", obj: "floor.obj", unit: "mm")],
                gravity: (0, 0, -9.81),
            )"#;
        std::fs::write(&path, text.replace("HEIGHT", &height.to_string())).unwrap();
        (dir, path)
    }

    /// A nozzle 2 mm above the floor holds the 3 mm cable's end inside it: no start
    /// clears that, and the error says to move the support. Before, the check of the
    /// hanging guess named its centreline through the floor first, with the hint to
    /// give the rod a route.
    #[test]
    fn a_nozzle_within_the_cable_radius_of_a_floor_is_named_as_the_support_to_move() {
        let (_dir, path) = dangling_at_a_floor(2.0);
        let built = Case::from_path(&path).unwrap().build(None).unwrap();
        match built.check_start() {
            Err(strand_solve::SolveError::StartsInside(
                strand_solve::ConstraintError::StartsOverlapping {
                    hint,
                    overlap_mm,
                    s_mm,
                    ..
                },
            )) => {
                assert_eq!(hint, strand_solve::StartHint::EndOverlaps);
                assert!((overlap_mm - 1.0).abs() < 1e-9, "{overlap_mm} mm");
                assert_eq!(s_mm, 0.0);
            }
            other => panic!("{other:?}"),
        }
    }

    /// A 600 mm cable (6 mm, 0.1 kg/m, 60 segments) dangling from a nozzle 30 mm
    /// above a floor and pointing straight at it: its hanging guess and every bowed and
    /// arched one leave the nozzle through the floor. It starts draped: as long as the
    /// rod, every vertex above the floor by more than the radius, the hanging part kept
    /// down to the floor and the rest lying along it; and it comes to rest on the
    /// floor, its weight carried by the connector and the contacts. The same from a
    /// nozzle 3.1 mm above the floor, a hair more than the cable's radius: the drape
    /// starts closer to the floor than the clearance it keeps, so it may move only
    /// where it comes no closer than it is (before, no step was clear and it was
    /// refused).
    #[test]
    fn a_cable_dangling_at_a_floor_starts_draped_over_it_and_rests_on_it() {
        for height in [30.0, 3.1] {
            dangling_at_a_floor_rests_on_it(height);
        }
    }

    fn dangling_at_a_floor_rests_on_it(height: f64) {
        let (_dir, path) = dangling_at_a_floor(height);
        let built = Case::from_path(&path).unwrap().build(None).unwrap();
        assert_eq!(built.start, Start::Draped, "{height} mm");
        built.check_start().unwrap();
        let p = &built.initial.rods[0].positions;
        let length: f64 = p.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
        assert!(
            (length - 0.6).abs() < 1e-9,
            "{height} mm: start length {length} m"
        );
        assert!(
            p.iter().all(|v| v.z > 0.003),
            "{height} mm: a vertex within the radius"
        );
        // Draped, not hanging: most of it lies low along the floor.
        let low = p.iter().filter(|v| v.z < 0.01).count();
        assert!(
            low > p.len() / 2,
            "{height} mm: {low} of {} vertices low",
            p.len()
        );
        assert_at_rest(&built, &format!("{height} mm"));
    }

    #[test]
    fn without_an_environment_the_start_is_the_hanging_guess() {
        let (_dir, path) = cable_over_box(-30.0);
        let text = std::fs::read_to_string(&path).unwrap();
        let without = text.replace(r#"(name: "box", obj: "box.obj", unit: "mm"),"#, "");
        assert_ne!(without, text, "the environment entry was not found");
        std::fs::write(&path, without).unwrap();
        let built = Case::from_path(&path).unwrap().build(None).unwrap();
        assert_eq!(built.start, Start::Hanging);
        assert_eq!(
            built.initial,
            strand_system::initial_state(built.model.system())
        );
        let _ = Contact::default_margin_m(&built.model);
    }
}

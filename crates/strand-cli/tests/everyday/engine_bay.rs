//! The engine-bay family of the everyday inputs: one cable between random faces of
//! the bundled engine bay's parts (`assets/engine_bay`: radiator, fan shroud, engine,
//! oil cooler, brackets; closed solids with chamfers, cylinders, a thin ring), all
//! five meshes in the case. Each connector stands off a random point of a part's
//! surface (picked by area) along its outward normal by the hose's radius and 3–40
//! mm, its nozzle the normal tilted by up to 60°; the cable is 1.05–1.8 × the
//! connectors' distance, clamped or pinned at each end, or (one in four) clamped at
//! `a` and dangling 150–900 mm. Real CAD at real size: the hanging guess passes
//! through a part between the connectors as often as not, and a connector may stand
//! inside another part or too close to one (an input error the check must name).

use super::triangle::obj_triangles;
use super::{
    Case, Environment, Rng, V, cable_case_body, cross, dot, fmt_v, norm, perpendicular, scale,
    section, sub, unit,
};

/// A part of the engine bay: name, OBJ path, triangles in mm.
type Part = (&'static str, String, Vec<[V; 3]>);

/// The bundled engine bay's parts.
fn parts() -> Vec<Part> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/engine_bay");
    ["radiator", "fan_shroud", "engine", "oil_cooler", "brackets"]
        .into_iter()
        .map(|name| {
            let path = dir.join(format!("{name}.obj"));
            let triangles = obj_triangles(&path);
            (name, path.display().to_string(), triangles)
        })
        .collect()
}

/// A point standing `offset` mm off a random point of `triangles` (picked by area)
/// along its outward normal, and a nozzle direction: the normal tilted by up to 60°.
fn stand_off(rng: &mut Rng, triangles: &[[V; 3]], offset: f64) -> (V, V) {
    let (point, normal) = off_surface(rng, triangles, offset);
    let side = unit(cross(normal, rng.direction()));
    let tilt = rng.uniform(0.0, 60f64.to_radians());
    let nozzle = [0, 1, 2].map(|i| tilt.cos() * normal[i] + tilt.sin() * side[i]);
    (point, nozzle)
}

/// A point standing `offset` mm off a random point of `triangles` (picked by area)
/// along its outward normal, and the normal.
fn off_surface(rng: &mut Rng, triangles: &[[V; 3]], offset: f64) -> (V, V) {
    let area = |t: &[V; 3]| 0.5 * norm(cross(sub(t[1], t[0]), sub(t[2], t[0])));
    let total: f64 = triangles.iter().map(area).sum();
    let mut pick = rng.uniform(0.0, total);
    let t = triangles
        .iter()
        .find(|t| {
            pick -= area(t);
            pick <= 0.0
        })
        .unwrap_or(&triangles[triangles.len() - 1]);
    let (mut u, mut v) = (rng.unit(), rng.unit());
    if u + v > 1.0 {
        (u, v) = (1.0 - u, 1.0 - v);
    }
    let normal = unit(cross(sub(t[1], t[0]), sub(t[2], t[0])));
    let point = [0, 1, 2]
        .map(|i| t[0][i] + u * (t[1][i] - t[0][i]) + v * (t[2][i] - t[0][i]) + offset * normal[i]);
    (point, normal)
}

/// A clip on a random part's face between connectors `a` and `b`: its base stands
/// off the face by the radius and 2–15 mm, the cable's direction through it is the
/// chord `a → b` laid into the face's plane and turned about the normal by up to
/// 45°, its joint fixed, revolute about the cable or spherical. Returns the base
/// (position, direction, normal) and the joint.
fn clip_on(rng: &mut Rng, parts: &[Part], radius_mm: f64, a: V, b: V) -> ([V; 3], &'static str) {
    let part = (rng.next() % parts.len() as u64) as usize;
    let offset = radius_mm + rng.uniform(2.0, 15.0);
    let (position, normal) = off_surface(rng, &parts[part].2, offset);
    let chord = unit(sub(b, a));
    let along_face = sub(chord, scale(normal, dot(chord, normal)));
    let along_face = if norm(along_face) > 0.2 {
        unit(along_face)
    } else {
        perpendicular(normal)
    };
    let turn = rng.uniform(-45f64, 45.0).to_radians();
    let side = cross(normal, along_face);
    let direction = [0, 1, 2].map(|i| turn.cos() * along_face[i] + turn.sin() * side[i]);
    let joints = ["Fixed", "Revolute(axis: (0, 0, 1))", "Spherical"];
    let joint = joints[(rng.next() % joints.len() as u64) as usize];
    ([position, direction, normal], joint)
}

/// Case `index` of `seed` of the engine-bay family, 10 to `max_segments` segments,
/// named `bay_s{seed}_{index}`.
pub(super) fn generate_bay(seed: u64, index: usize, max_segments: usize) -> Case {
    bay_case(seed, index, max_segments, false)
}

/// Case `index` of `seed` of the clipped engine-bay family, named
/// `clipped_s{seed}_{index}`: the connectors, section and discretisation of the same
/// case of the engine-bay family, the cable held between them by one or two clips on
/// random faces ([`clip_on`]), each at the arc length its share of the way `a` →
/// clips → `b` (in the order of their projections on the chord) gives at the cable's
/// slack, 1.05–1.8 × that way; one in four ends at its last clip and dangles
/// 150–900 mm beyond it.
pub(super) fn generate_clipped_bay(seed: u64, index: usize, max_segments: usize) -> Case {
    bay_case(seed, index, max_segments, true)
}

/// Case `index` of `seed` of the engine-bay family, with clips if `clipped`.
fn bay_case(seed: u64, index: usize, max_segments: usize, clipped: bool) -> Case {
    let mut rng = Rng(seed.wrapping_mul(0x2000_0003).wrapping_add(index as u64));
    let parts = parts();
    let (diameter_mm, youngs, density, ei, mass_per_length) = section(&mut rng);
    let radius_mm = 0.5 * diameter_mm;
    let segments =
        (rng.log_uniform(10.0, max_segments as f64 + 1.0).floor() as usize).clamp(10, max_segments);
    let first = (rng.next() % parts.len() as u64) as usize;
    let second = (first + 1 + (rng.next() % (parts.len() as u64 - 1)) as usize) % parts.len();
    let offset = |rng: &mut Rng| radius_mm + rng.uniform(3.0, 40.0);
    let (a, da) = {
        let off = offset(&mut rng);
        stand_off(&mut rng, &parts[first].2, off)
    };
    let (b, db) = {
        let off = offset(&mut rng);
        stand_off(&mut rng, &parts[second].2, off)
    };
    let dangling = rng.unit() < 0.25;
    let kind = |rng: &mut Rng| {
        if rng.unit() < 0.3 {
            "ConnectorPin"
        } else {
            "Connector"
        }
    };
    let start = format!("{}(\"a\")", kind(&mut rng));
    let mut clips = Vec::new();
    if clipped {
        for _ in 0..1 + rng.next() % 2 {
            clips.push(clip_on(&mut rng, &parts, radius_mm, a, b));
        }
        clips.sort_by(|p, q| {
            let along = |c: &([V; 3], &str)| dot(sub(c.0[0], a), sub(b, a));
            along(p).total_cmp(&along(q))
        });
    }
    let mut stations = vec![a];
    stations.extend(clips.iter().map(|(base, _)| base[0]));
    if !(dangling && clipped) {
        stations.push(b);
    }
    let legs: Vec<f64> = stations.windows(2).map(|w| norm(sub(w[1], w[0]))).collect();
    let distance: f64 = legs.iter().sum();
    let slack = rng.uniform(1.05, 1.8);
    let (length, end, connector_b) = if dangling {
        let tail = rng.uniform(150.0, 900.0);
        let held = if clipped { slack * distance } else { 0.0 };
        (held + tail, "Free()".to_string(), String::new())
    } else {
        (
            slack * distance,
            format!("{}(\"b\")", kind(&mut rng)),
            format!(
                "\x20       \"b\": (position: {}, direction: {}, normal: {}),\n",
                fmt_v(b),
                fmt_v(db),
                fmt_v(perpendicular(db))
            ),
        )
    };
    let name = if clipped {
        format!("clipped_s{seed}_{index:03}")
    } else {
        format!("bay_s{seed}_{index:03}")
    };
    let mut at = 0.0;
    let clips: String = clips
        .iter()
        .zip(&legs)
        .enumerate()
        .map(|(k, ((base, joint), leg))| {
            at += slack * leg;
            format!(
                "\x20       \"k{k}\": (rod: \"cable\", at: {at:.6}, joint: {joint},\n\
                 \x20           base: (position: {}, direction: {}, normal: {})),\n",
                fmt_v(base[0]),
                fmt_v(base[1]),
                fmt_v(base[2]),
            )
        })
        .collect();
    let environment: String = parts
        .iter()
        .map(|(part, path, _)| {
            format!("\x20       (name: \"{part}\", obj: \"{path}\", unit: \"mm\"),\n")
        })
        .collect();
    let ron = format!(
        "// {name}: generated by crates/strand-cli/tests/everyday/engine_bay.rs (seed {seed}, \
         case {index})\n\
         // {from} -> {to} · D = {diameter_mm:.2} mm · EI = {ei:.3e} N·m² · \
         {mass_per_length:.3} kg/m · L = {length:.1} mm · {segments} segments\n{body}",
        from = parts[first].0,
        to = if dangling { "free" } else { parts[second].0 },
        body = cable_case_body(
            [youngs, density, radius_mm],
            (a, da),
            &connector_b,
            (length, segments, &start, &end),
            &environment,
        )
        .replace(
            "    environment: [",
            &format!("    clips: {{\n{clips}    }},\n    environment: [")
        )
    );
    Case {
        name,
        environment: Environment::EngineBay,
        segments,
        ei,
        diameter_mm,
        mass_per_length,
        slack: length / distance,
        radius_mm,
        triangles: parts.into_iter().flat_map(|(_, _, t)| t).collect(),
        ron,
    }
}

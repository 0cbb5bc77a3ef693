//! "Everyday inputs": seeded random cables a user might draw, solved by the real
//! binary, judged only on the honesty properties that must hold for *any* input.
//!
//! Each case is one cable clamped between two connectors (random positions in a 1 m
//! box, random nozzle directions, length 1.05–1.6 × their distance), a solid round
//! section (outer diameter 3–30 mm, EI 1e-5 … 10 N·m² from a Young's modulus between
//! soft rubber and steel, 0.05–2 kg/m), 10 to `EVERYDAY_MAX_SEGMENTS` segments, under
//! gravity, over one generated environment (OBJ in mm next to the case): a floor
//! plate, a closed box, or a V-groove (90° or 60°, both flanks in one mesh). The
//! geometry is placed within reach of the cable's sag (the hanging guess usually
//! passes through it), below the connectors, so the cable falls onto or into it. No
//! route is given: the solver starts from its gravity-aware guess.
//!
//! Asserted for every case:
//! - the process exits 0, 2 or 3 (no panic, no crash, no kill by the timeout);
//! - exit 2 names the case or mesh file in its message;
//! - exit 0: `result.json` says `converged: true` and `residual_N` is within
//!   `tolerance_N` or, for a solve that stalled at its floor, 4 × `residual_floor_N`
//!   (the solver's round-off rule; the table notes such cases as `round-off`);
//! - exit 3: `result.json` says `converged: false`;
//! - for any written result: no vertex lies closer to any triangle than the outer
//!   radius minus 1e-9 m (brute force, point–triangle distance below), and no edge of
//!   the centreline passes through a triangle (the connectors are outside the
//!   geometry, so a rod inside the box or under a sheet must cross it).
//!
//! The same properties hold for the same cables dangling from connector `a`, and for
//! the engine-bay family (`everyday/engine_bay.rs`): cables between random faces of
//! the bundled engine bay's five parts, against all of them.
//!
//! Knobs (environment variables): `EVERYDAY_CASES` (default 12), `EVERYDAY_SEED`
//! (default 1), `EVERYDAY_MAX_SEGMENTS` (default 300), `EVERYDAY_TIMEOUT_S` (default
//! 120), `EVERYDAY_STRAND` (another `strand` binary with the same CLI, to measure it),
//! `EVERYDAY_DIR` (keep the cases and results there instead of a temporary folder),
//! `EVERYDAY_FIRST` (default 0: the index of the first case, to replay one case of a
//! seed without its predecessors). The table is printed to stdout (`-- --nocapture`).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

#[path = "everyday/engine_bay.rs"]
mod engine_bay;
#[path = "common/triangle.rs"]
mod triangle;

use triangle::{V, along, closest_on_triangle, dot, sub};

fn add(a: V, b: V) -> V {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn scale(a: V, t: f64) -> V {
    [a[0] * t, a[1] * t, a[2] * t]
}
fn cross(a: V, b: V) -> V {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn norm(a: V) -> f64 {
    dot(a, a).sqrt()
}
fn unit(a: V) -> V {
    scale(a, 1.0 / norm(a))
}

/// Distance from `p` to the nearest triangle.
fn distance_to(p: V, triangles: &[[V; 3]]) -> f64 {
    triangles
        .iter()
        .map(|&[a, b, c]| norm(sub(p, closest_on_triangle(p, a, b, c))))
        .fold(f64::INFINITY, f64::min)
}

/// Whether the segment `pq` passes through the interior of triangle `abc`
/// (Möller–Trumbore; touching within `1e-9` of an end or the rim does not count).
fn segment_crosses(p: V, q: V, [a, b, c]: [V; 3]) -> bool {
    let d = sub(q, p);
    let (e1, e2) = (sub(b, a), sub(c, a));
    let h = cross(d, e2);
    let det = dot(e1, h);
    if det.abs() < 1e-14 * norm(d) * norm(e1) * norm(e2) {
        return false;
    }
    let s = sub(p, a);
    let u = dot(s, h) / det;
    let qv = cross(s, e1);
    let v = dot(d, qv) / det;
    let t = dot(e2, qv) / det;
    let eps = 1e-9;
    u > eps && v > eps && u + v < 1.0 - eps && t > eps && t < 1.0 - eps
}

/// SplitMix64: a tiny, fixed, reproducible generator.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
    fn log_uniform(&mut self, lo: f64, hi: f64) -> f64 {
        (lo.ln() + (hi.ln() - lo.ln()) * self.unit()).exp()
    }
    fn direction(&mut self) -> V {
        loop {
            let v = [
                self.uniform(-1.0, 1.0),
                self.uniform(-1.0, 1.0),
                self.uniform(-1.0, 1.0),
            ];
            let n = norm(v);
            if n > 0.1 && n <= 1.0 {
                return scale(v, 1.0 / n);
            }
        }
    }
}

#[derive(Clone, Copy, Debug)]
enum Environment {
    Floor,
    Box,
    Groove90,
    Groove60,
    /// The bundled engine bay's five parts ([`engine_bay`]).
    EngineBay,
}

impl Environment {
    fn label(self) -> &'static str {
        match self {
            Environment::Floor => "floor",
            Environment::Box => "box",
            Environment::Groove90 => "groove90",
            Environment::Groove60 => "groove60",
            Environment::EngineBay => "bay",
        }
    }
}

/// How a generated cable is held.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Ends {
    /// Clamped at both connectors.
    Clamped,
    /// Clamped at connector `a`, its end free: a cable dangling over the part.
    Dangling,
}

/// One generated case: the RON text, its mesh (mm) and what the table shows.
struct Case {
    name: String,
    environment: Environment,
    segments: usize,
    ei: f64,
    diameter_mm: f64,
    mass_per_length: f64,
    slack: f64,
    radius_mm: f64,
    triangles: Vec<[V; 3]>,
    ron: String,
}

fn obj_text(triangles: &[[V; 3]]) -> String {
    let mut text = String::from("# generated by crates/strand-cli/tests/everyday.rs (mm)\n");
    for t in triangles {
        for v in t {
            writeln!(text, "v {:.9} {:.9} {:.9}", v[0], v[1], v[2]).unwrap();
        }
    }
    for k in 0..triangles.len() {
        writeln!(text, "f {} {} {}", 3 * k + 1, 3 * k + 2, 3 * k + 3).unwrap();
    }
    text
}

/// Two triangles of the quad `abcd` (in order).
fn quad(a: V, b: V, c: V, d: V) -> [[V; 3]; 2] {
    [[a, b, c], [a, c, d]]
}

/// The lowest point an inextensible string of length `length` between `a` and `b`
/// can reach: the bottom of the prolate spheroid with foci `a`, `b`.
fn lowest_reach(a: V, b: V, length: f64) -> f64 {
    let d = norm(sub(b, a));
    let uz = (b[2] - a[2]) / d;
    let semi_major = 0.5 * length;
    let semi_minor = (semi_major * semi_major - 0.25 * d * d).sqrt();
    let half =
        (semi_major * semi_major * uz * uz + semi_minor * semi_minor * (1.0 - uz * uz)).sqrt();
    0.5 * (a[2] + b[2]) - half
}

/// A solid round section within the brief's ranges: (D mm, E Pa, density kg/m³,
/// EI N·m², kg/m).
fn section(rng: &mut Rng) -> (f64, f64, f64, f64, f64) {
    loop {
        let diameter_mm = rng.log_uniform(3.0, 30.0);
        let r = 0.5e-3 * diameter_mm;
        let inertia = std::f64::consts::PI * r.powi(4) / 4.0;
        let area = std::f64::consts::PI * r * r;
        // Soft rubber (1 MPa) to steel (210 GPa), restricted to EI in 1e-5 … 10.
        let (e_lo, e_hi) = ((1e-5 / inertia).max(1e6), (10.0 / inertia).min(2.1e11));
        // Density 700 … 9000 kg/m³, restricted to 0.05 … 2 kg/m.
        let (rho_lo, rho_hi) = ((0.05 / area).max(700.0), (2.0 / area).min(9000.0));
        if e_lo >= e_hi || rho_lo >= rho_hi {
            continue;
        }
        let e = rng.log_uniform(e_lo, e_hi);
        let rho = rng.log_uniform(rho_lo, rho_hi);
        return (diameter_mm, e, rho, e * inertia, rho * area);
    }
}

fn fmt_v(v: V) -> String {
    format!("({:.6}, {:.6}, {:.6})", v[0], v[1], v[2])
}

/// Any unit vector perpendicular to `t`.
fn perpendicular(t: V) -> V {
    let other = if t[2].abs() < 0.9 {
        [0.0, 0.0, 1.0]
    } else {
        [1.0, 0.0, 0.0]
    };
    unit(cross(t, other))
}

fn generate(seed: u64, index: usize, max_segments: usize) -> Case {
    generate_with(seed, index, max_segments, Ends::Clamped)
}

/// A generated case held as `ends` says: the same draws either way (a dangling cable
/// has the clamped one's connector `a`, length, section and environment), named
/// `everyday_…` when clamped and `dangling_…` when dangling.
fn generate_with(seed: u64, index: usize, max_segments: usize, ends: Ends) -> Case {
    let mut rng = Rng(seed.wrapping_mul(0x1000_0001).wrapping_add(index as u64));
    let environment = match rng.next() % 4 {
        0 => Environment::Floor,
        1 => Environment::Box,
        2 => Environment::Groove90,
        _ => Environment::Groove60,
    };
    let (diameter_mm, youngs, density, ei, mass_per_length) = section(&mut rng);
    let radius_mm = 0.5 * diameter_mm;
    let segments = rng.log_uniform(10.0, max_segments as f64 + 1.0).floor() as usize;
    let segments = segments.clamp(10, max_segments);
    // Connectors at least 200 mm apart in a 1 m box.
    let (a, b) = loop {
        let mut p = || {
            [
                rng.uniform(-500.0, 500.0),
                rng.uniform(-500.0, 500.0),
                rng.uniform(0.0, 1000.0),
            ]
        };
        let (a, b) = (p(), p());
        if norm(sub(b, a)) >= 200.0 {
            break (a, b);
        }
    };
    let distance = norm(sub(b, a));
    let slack = rng.uniform(1.05, 1.6);
    let length = slack * distance;
    let low = lowest_reach(a, b, length);
    let top = a[2].min(b[2]);
    let mid = scale(add(a, b), 0.5);
    let margin = radius_mm + 30.0;
    let fraction = rng.uniform(0.15, 0.7);
    // The geometry's top: within reach of the sag, below both connectors.
    let level = (low + fraction * (top - margin - low)).min(top - margin);
    let triangles: Vec<[V; 3]> = match environment {
        Environment::Floor => {
            let h = 2500.0;
            let c = [mid[0], mid[1], level];
            quad(
                add(c, [-h, -h, 0.0]),
                add(c, [h, -h, 0.0]),
                add(c, [h, h, 0.0]),
                add(c, [-h, h, 0.0]),
            )
            .to_vec()
        }
        Environment::Box => {
            let (sx, sy) = (rng.uniform(100.0, 400.0), rng.uniform(100.0, 400.0));
            let (cx, cy) = (
                mid[0] + rng.uniform(-50.0, 50.0),
                mid[1] + rng.uniform(-50.0, 50.0),
            );
            let height = rng.uniform(100.0, 400.0);
            let (x0, x1, y0, y1, z0, z1) = (
                cx - 0.5 * sx,
                cx + 0.5 * sx,
                cy - 0.5 * sy,
                cy + 0.5 * sy,
                level - height,
                level,
            );
            let v = |i: u8, j: u8, k: u8| {
                [
                    if i == 0 { x0 } else { x1 },
                    if j == 0 { y0 } else { y1 },
                    if k == 0 { z0 } else { z1 },
                ]
            };
            // Outward counter-clockwise faces.
            [
                quad(v(0, 0, 0), v(0, 1, 0), v(1, 1, 0), v(1, 0, 0)),
                quad(v(0, 0, 1), v(1, 0, 1), v(1, 1, 1), v(0, 1, 1)),
                quad(v(0, 0, 0), v(1, 0, 0), v(1, 0, 1), v(0, 0, 1)),
                quad(v(0, 1, 0), v(0, 1, 1), v(1, 1, 1), v(1, 1, 0)),
                quad(v(0, 0, 0), v(0, 0, 1), v(0, 1, 1), v(0, 1, 0)),
                quad(v(1, 0, 0), v(1, 1, 0), v(1, 1, 1), v(1, 0, 1)),
            ]
            .concat()
        }
        Environment::Groove90 | Environment::Groove60 => {
            // Half the opening angle, from the vertical.
            let half = if matches!(environment, Environment::Groove90) {
                45f64.to_radians()
            } else {
                30f64.to_radians()
            };
            // The crease runs along the connectors' horizontal direction, below
            // their midpoint, deep enough that both connectors are inside the V.
            let horizontal = [b[0] - a[0], b[1] - a[1], 0.0];
            let axis = if norm(horizontal) > 1e-3 * distance {
                unit(horizontal)
            } else {
                [1.0, 0.0, 0.0]
            };
            let lateral = cross([0.0, 0.0, 1.0], axis);
            let crease_z = level.min(top - (radius_mm + 30.0) / half.sin());
            let depth = top - crease_z;
            let offset = rng.uniform(-0.3, 0.3) * depth * half.tan();
            let origin = add([mid[0], mid[1], crease_z], scale(lateral, offset));
            let s = |p: V| dot(sub(p, origin), axis);
            let (s0, s1) = (s(a).min(s(b)) - 300.0, s(a).max(s(b)) + 300.0);
            let rim = rng.uniform(100.0, 300.0);
            let crease = |t: f64| along(origin, axis, t);
            let edge = |t: f64, side: f64| {
                add(
                    crease(t),
                    add(scale(lateral, side * rim * half.tan()), [0.0, 0.0, rim]),
                )
            };
            let mut out = Vec::new();
            for side in [-1.0, 1.0] {
                for t in quad(crease(s0), crease(s1), edge(s1, side), edge(s0, side)) {
                    // Normals up, into the V.
                    let n = cross(sub(t[1], t[0]), sub(t[2], t[0]));
                    out.push(if n[2] > 0.0 { t } else { [t[0], t[2], t[1]] });
                }
            }
            out
        }
        Environment::EngineBay => unreachable!("the engine bay has its own generator"),
    };
    // Nozzle directions: random, but the first stretch (one edge, at least 20 mm)
    // must stay clear of the geometry, or the case would be infeasible by
    // construction rather than everyday.
    let edge = (length / segments as f64).max(20.0);
    let mut nozzle = |p: V| {
        for _ in 0..200 {
            let d = rng.direction();
            let q = along(p, d, edge);
            if distance_to(q, &triangles) > radius_mm + 5.0
                && !triangles.iter().any(|&t| segment_crosses(p, q, t))
            {
                return d;
            }
        }
        [0.0, 0.0, 1.0]
    };
    let (da, db) = (nozzle(a), nozzle(b));
    let name = match ends {
        Ends::Clamped => format!("everyday_s{seed}_{index:03}"),
        Ends::Dangling => format!("dangling_s{seed}_{index:03}"),
    };
    let (connector_b, end) = match ends {
        Ends::Clamped => (
            format!(
                "\x20       \"b\": (position: {}, direction: {}, normal: {}),\n",
                fmt_v(b),
                fmt_v(db),
                fmt_v(perpendicular(db))
            ),
            "Connector(\"b\")",
        ),
        Ends::Dangling => (String::new(), "Free()"),
    };
    let ron = format!(
        "// {name}: generated by crates/strand-cli/tests/everyday.rs (seed {seed}, case {index})\n\
         // {env} · D = {diameter_mm:.2} mm · EI = {ei:.3e} N·m² · {mass_per_length:.3} kg/m · \
         L = {slack:.3} × {distance:.1} mm · {segments} segments\n{body}",
        env = environment.label(),
        body = cable_case_body(
            [youngs, density, radius_mm],
            (a, da),
            &connector_b,
            (length, segments, "Connector(\"a\")", end),
            &format!(
                "\x20       (name: \"{}\", obj: \"{name}.obj\", unit: \"mm\"),\n",
                environment.label()
            ),
        ),
    );
    Case {
        name,
        environment,
        segments,
        ei,
        diameter_mm,
        mass_per_length,
        slack,
        radius_mm,
        triangles,
        ron,
    }
}

/// The text of a one-cable case after its comment lines: the round `section`
/// (Young's modulus Pa, density kg/m³, outer radius mm), connector `a` at `nozzle.0`
/// along `nozzle.1` and the `connector_b` entry (empty when dangling), the cable
/// (`rod`: length mm, segments, its start and end supports) and the `environment`
/// entries, in mm under gravity.
fn cable_case_body(
    section: [f64; 3],
    nozzle: (V, V),
    connector_b: &str,
    rod: (f64, usize, &str, &str),
    environment: &str,
) -> String {
    let [youngs, density, radius_mm] = section;
    let (a, da) = nozzle;
    let (length, segments, start, end) = rod;
    format!(
        "(\n\
         \x20   units: (length: \"mm\"),\n\
         \x20   sections: {{\n\
         \x20       \"round\": Tube(youngs_modulus: {youngs:.6e}, poisson_ratio: 0.4, density: {density:.6}, \
         inner_radius: 0, outer_radius: {radius_mm:.6}),\n\
         \x20   }},\n\
         \x20   connectors: {{\n\
         \x20       \"a\": (position: {pa}, direction: {da}, normal: {na}),\n\
         {connector_b}\
         \x20   }},\n\
         \x20   rods: [\n\
         \x20       (name: \"cable\", section: \"round\", length: {length:.6}, segments: {segments},\n\
         \x20        start: {start}, end: {end}),\n\
         \x20   ],\n\
         \x20   environment: [\n\
         {environment}\
         \x20   ],\n\
         \x20   gravity: (0, 0, -9.81),\n\
         )\n",
        pa = fmt_v(a),
        da = fmt_v(da),
        na = fmt_v(perpendicular(da)),
    )
}

fn env_or<T: std::str::FromStr>(key: &str, default: T) -> T {
    std::env::var(key)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// Runs `binary solve case --out out`, killed after `timeout`: exit code (`None`
/// for a signal or the timeout), whether it timed out, stderr, seconds.
fn run(
    binary: &Path,
    case: &Path,
    out: &Path,
    timeout: Duration,
) -> (Option<i32>, bool, String, f64) {
    let stderr_path = out.with_extension("stderr");
    let stderr = std::fs::File::create(&stderr_path).unwrap();
    let start = Instant::now();
    let mut child = Command::new(binary)
        .arg("solve")
        .arg(case)
        .arg("--out")
        .arg(out)
        .env_remove("RUST_BACKTRACE")
        .stdout(Stdio::null())
        .stderr(stderr)
        .spawn()
        .unwrap();
    let (status, timed_out) = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break (Some(status), false);
        }
        if start.elapsed() > timeout {
            child.kill().unwrap();
            child.wait().unwrap();
            break (None, true);
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    let seconds = start.elapsed().as_secs_f64();
    let text = std::fs::read_to_string(&stderr_path).unwrap_or_default();
    (status.and_then(|s| s.code()), timed_out, text, seconds)
}

/// The first line of `text` that says why, for the table.
fn first_error(text: &str) -> String {
    text.lines()
        .find(|l| l.starts_with("error"))
        .or_else(|| text.lines().next())
        .unwrap_or("")
        .chars()
        .take(140)
        .collect()
}

fn median(values: &mut [f64]) -> f64 {
    if values.is_empty() {
        return f64::NAN;
    }
    values.sort_by(f64::total_cmp);
    let n = values.len();
    if n % 2 == 1 {
        values[n / 2]
    } else {
        0.5 * (values[n / 2 - 1] + values[n / 2])
    }
}

/// The solver's `ROUND_OFF_SPREAD` (strand-solve/src/iteration/mod.rs): an iteration
/// that can make no further progress within this multiple of `residual_floor_N` has
/// converged to round-off, and says `converged: true` with a residual above the
/// tolerance asked for (seen on steel-stiff cables, EA of 1e6 N and more).
const ROUND_OFF_SPREAD: f64 = 4.0;

/// What one case did: its table row, and every honesty property it broke.
struct Outcome {
    row: String,
    violations: Vec<String>,
    exit: Option<i32>,
    iterations: Option<f64>,
    seconds: f64,
}

/// Writes `case`'s RON and OBJ files into `dir`: the RON file's path.
fn write_case(dir: &Path, case: &Case) -> PathBuf {
    let ron_path = dir.join(format!("{}.ron", case.name));
    std::fs::write(&ron_path, &case.ron).unwrap();
    std::fs::write(
        dir.join(format!("{}.obj", case.name)),
        obj_text(&case.triangles),
    )
    .unwrap();
    ron_path
}

/// Writes `case` (RON and OBJ) into `dir`, solves it with `binary` and checks it.
fn solve_and_check(binary: &Path, dir: &Path, case: &Case, timeout: Duration) -> Outcome {
    let ron_path = write_case(dir, case);
    let out = dir.join(format!("out_{}", case.name));
    let (exit, timed_out, stderr, seconds) = run(binary, &ron_path, &out, timeout);
    let mut violations = Vec::new();
    let mut bad = |what: String| violations.push(format!("{}: {what}", case.name));
    let mut note = String::new();
    let (mut iterations, mut residual, mut gap) = (None, String::new(), String::new());
    match exit {
        _ if timed_out => bad(format!("no answer within {timeout:?} (killed)")),
        Some(0) | Some(3) => {}
        Some(2) => {
            note = first_error(&stderr);
            if !stderr.contains(&case.name) {
                bad(format!("exit 2 without naming the file: {note}"));
            }
        }
        other => bad(format!(
            "exit {other:?} (crash, panic or internal error): {}",
            first_error(&stderr)
        )),
    }
    if matches!(exit, Some(0) | Some(3)) && !timed_out {
        match std::fs::read_to_string(out.join("result.json")) {
            Err(e) => bad(format!("exit {exit:?} without result.json: {e}")),
            Ok(text) => {
                let doc: serde_json::Value = serde_json::from_str(&text).unwrap();
                let flag = doc["converged"].as_bool();
                let res = doc["residual_N"].as_f64().unwrap_or(f64::NAN);
                let asked = doc["tolerance_N"].as_f64().unwrap_or(f64::NAN);
                let floor = doc["residual_floor_N"].as_f64().unwrap_or(0.0);
                iterations = doc["iterations"].as_f64();
                residual = format!("{res:.1e}");
                note = doc["termination"].as_str().unwrap_or("").to_string();
                if exit == Some(0) {
                    if flag != Some(true) {
                        bad(format!("exit 0 but converged = {flag:?}"));
                    }
                    // The tolerance asked for, or a stall within ROUND_OFF_SPREAD
                    // times the round-off floor (README, Convergence).
                    let applied = asked.max(ROUND_OFF_SPREAD * floor);
                    // NaN (a missing field) fails too.
                    if res.is_nan() || res > applied {
                        bad(format!(
                            "exit 0 with residual {res:e} N > tolerance {asked:e} N and \
                             > {ROUND_OFF_SPREAD} x floor {floor:e} N"
                        ));
                    } else if res > asked {
                        note.push_str(&format!(" (round-off: {:.1} x floor)", res / floor));
                    }
                } else if flag != Some(false) {
                    bad(format!("exit 3 but converged = {flag:?}"));
                }
                // Brute force: every vertex against every triangle (mm).
                let positions: Vec<V> = doc["rods"][0]["position_m"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|p| [0, 1, 2].map(|i| 1e3 * p[i].as_f64().unwrap()))
                    .collect();
                let (mut worst, mut at) = (f64::INFINITY, 0);
                for (j, p) in positions.iter().enumerate() {
                    let g = distance_to(*p, &case.triangles) - case.radius_mm;
                    if g < worst {
                        (worst, at) = (g, j);
                    }
                }
                gap = format!("{worst:.2e}");
                if worst < -1e-6 {
                    bad(format!(
                        "exit {exit:?}: vertex {at} is {:.3e} mm inside the {} \
                         (clearance below -1e-9 m)",
                        -worst,
                        case.environment.label()
                    ));
                }
                // The connectors are outside the geometry: a rod inside the box or
                // under a sheet has an edge through a triangle.
                for (j, w) in positions.windows(2).enumerate() {
                    if case
                        .triangles
                        .iter()
                        .any(|&t| segment_crosses(w[0], w[1], t))
                    {
                        bad(format!(
                            "exit {exit:?} with edge {j} through the {}",
                            case.environment.label()
                        ));
                        break;
                    }
                }
            }
        }
    }
    let row = format!(
        "{:<20} {:<9} {:>5} {:>9.2e} {:>6.1} {:>6.3} {:>5.2} {:>4} {:>5} {:>9} {:>7.2} {:>9} {}",
        case.name,
        case.environment.label(),
        case.segments,
        case.ei,
        case.diameter_mm,
        case.mass_per_length,
        case.slack,
        if timed_out {
            "kill".to_string()
        } else {
            exit.map_or("sig".into(), |c| c.to_string())
        },
        iterations.map_or(String::new(), |i| i.to_string()),
        residual,
        seconds,
        gap,
        note
    );
    Outcome {
        row,
        violations,
        exit: if timed_out { None } else { exit },
        iterations,
        seconds,
    }
}

fn header() -> String {
    format!(
        "{:<20} {:<9} {:>5} {:>9} {:>6} {:>6} {:>5} {:>4} {:>5} {:>9} {:>7} {:>9} note",
        "case",
        "env",
        "seg",
        "EI N·m²",
        "D mm",
        "kg/m",
        "L/d",
        "exit",
        "iter",
        "resid N",
        "time s",
        "gap mm",
    )
}

/// The binary under test: the package's own, or `EVERYDAY_STRAND`.
fn binary() -> PathBuf {
    std::env::var("EVERYDAY_STRAND")
        .map(PathBuf::from)
        .unwrap_or_else(|_| PathBuf::from(env!("CARGO_BIN_EXE_strand")))
}

#[test]
fn everyday_cables_over_floors_boxes_and_grooves_are_solved_honestly() {
    solve_family(Ends::Clamped);
}

/// The same generated cables and parts, each dangling from its connector `a` (its
/// other end free) and falling onto or into the part: the same honesty properties.
#[test]
fn dangling_cables_over_floors_boxes_and_grooves_are_solved_honestly() {
    solve_family(Ends::Dangling);
}

/// Cables between random faces of the bundled engine bay's parts, clamped, pinned or
/// dangling ([`engine_bay`]): the same honesty properties against all five meshes.
#[test]
fn engine_bay_cables_between_random_faces_are_solved_honestly() {
    solve_family_of("engine bay", engine_bay::generate_bay);
}

/// The engine-bay cables held at both ends, each through one or two clips on random
/// faces of the parts ([`engine_bay::generate_clipped_bay`]): the same honesty
/// properties.
#[test]
fn clipped_engine_bay_cables_are_solved_honestly() {
    solve_family_of("clipped engine bay", engine_bay::generate_clipped_bay);
}

/// Generates the cases the knobs ask for, held as `ends` says, solves each with the
/// binary and asserts the honesty properties of every one.
fn solve_family(ends: Ends) {
    solve_family_of(&format!("{ends:?}"), |seed, index, max_segments| {
        generate_with(seed, index, max_segments, ends)
    });
}

/// [`solve_family`] of the cases `generate(seed, index, max_segments)` makes,
/// `family` naming them in the table.
fn solve_family_of(family: &str, generate: impl Fn(u64, usize, usize) -> Case) {
    let cases: usize = env_or("EVERYDAY_CASES", 12);
    let first: usize = env_or("EVERYDAY_FIRST", 0);
    let seed: u64 = env_or("EVERYDAY_SEED", 1);
    let max_segments: usize = env_or("EVERYDAY_MAX_SEGMENTS", 300);
    let timeout = Duration::from_secs_f64(env_or("EVERYDAY_TIMEOUT_S", 120.0));
    let binary = binary();
    let tmp = tempfile::tempdir().unwrap();
    let dir = std::env::var("EVERYDAY_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|_| tmp.path().to_path_buf());
    std::fs::create_dir_all(&dir).unwrap();

    let mut table = format!(
        "everyday ({family}): {cases} cases, seed {seed}, <= {max_segments} segments, {}\n{}\n",
        binary.display(),
        header()
    );
    let mut violations = Vec::new();
    let (mut converged, mut not_converged, mut invalid) = (0, 0, 0);
    let mut iterations = Vec::new();
    let mut worst_time = 0f64;
    for index in first..first + cases {
        let case = generate(seed, index, max_segments);
        let outcome = solve_and_check(&binary, &dir, &case, timeout);
        match outcome.exit {
            Some(0) => converged += 1,
            Some(2) => invalid += 1,
            Some(3) => not_converged += 1,
            _ => {}
        }
        iterations.extend(outcome.iterations);
        worst_time = worst_time.max(outcome.seconds);
        violations.extend(outcome.violations);
        writeln!(table, "{}", outcome.row).unwrap();
    }
    let worst_iterations = iterations.iter().copied().fold(0.0, f64::max);
    writeln!(
        table,
        "converged {converged}, not converged (exit 3) {not_converged}, input error (exit 2) \
         {invalid}, other {}; iterations median {} max {worst_iterations}; worst time \
         {worst_time:.2} s",
        cases - converged - not_converged - invalid,
        median(&mut iterations),
    )
    .unwrap();
    println!("{table}");
    assert!(
        violations.is_empty(),
        "{} honesty violations (cases in {}):\n{}\n{table}",
        violations.len(),
        dir.display(),
        violations.join("\n")
    );
}

/// Regression: `everyday_s1_017` (seed 1, case 17 of a 3000-segment run: a 18 mm,
/// 1.5 kg/m cable, 361 segments, falling onto a floor). The coarse level's state,
/// prolonged to the fine rod, put an edge's centreline through the floor; the fine
/// solve started there, rejected every trial, and the contact report of that state
/// failed: exit 1 ("contacts: rod 'cable' touches mesh 'floor': its centreline passes
/// through ..."). A prolonged start that is not admissible is now not taken.
#[test]
fn a_coarse_start_through_the_floor_is_not_taken() {
    let tmp = tempfile::tempdir().unwrap();
    let case = replay(1, 17, (361, "floor"));
    assert_converges_clear(tmp.path(), &case);
}

/// Regression: `everyday_s21_025` (seed 21, a stiff 7.5 mm cable, 2391 segments, in a
/// 90° groove) was reported converged (exit 0) at 4.6e-8 N, above the tolerance of
/// 1e-9 N and above 4 times its round-off floor (6.6e-9 N). The solve had stopped at
/// round-off with 3.9e-9 N when no step improved the merit any more, but the residual
/// it reported was computed with the multipliers of that last, rejected step's QP
/// (`g − Aᵀλ = −H d` for the step `d` not taken). The multipliers the stop was judged
/// with are kept now, and a converged report's residual always meets the criterion.
#[test]
fn a_stop_at_round_off_reports_the_residual_it_was_judged_on() {
    let tmp = tempfile::tempdir().unwrap();
    let case = replay(21, 25, (2391, "groove90"));
    assert_converges_clear(tmp.path(), &case);
}

/// Regression: `everyday_s52_010` (seed 52, case 10 of a 10,000-segment run: an 8 mm
/// cable of 7426 segments over a 60° groove) was not solved in 600 s. Its 24-segment
/// coarse level, the start of the fine solve, rests draped over the groove's rim (the
/// coarse kinks catch on it); at every finer discretisation the cable slides along the
/// rim and off it into the groove, and the fine level crept about one edge (0.07 mm)
/// per 2-second iteration. Long rods are now started through levels of a quarter of
/// the segments each (1486, 298, 60), and the 60-segment level slides it off.
#[test]
fn a_cable_caught_on_a_rim_by_its_coarse_level_slides_off_through_the_levels() {
    let tmp = tempfile::tempdir().unwrap();
    let case = replay_up_to(52, 10, 10_000, (7426, "groove60"));
    assert_converges_clear(tmp.path(), &case);
}

/// Case `index` of `seed` (generated up to 3000 segments), checked to be still the one
/// a regression test was written for: its `(segments, environment)`.
fn replay(seed: u64, index: usize, expected: (usize, &str)) -> Case {
    replay_up_to(seed, index, 3000, expected)
}

/// [`replay`] of a run generated up to `max_segments`.
fn replay_up_to(seed: u64, index: usize, max_segments: usize, expected: (usize, &str)) -> Case {
    let case = generate(seed, index, max_segments);
    assert_eq!(
        (case.segments, case.environment.label()),
        expected,
        "the generator changed: find the case again"
    );
    case
}

/// [`replay`] of the dangling family ([`Ends::Dangling`], a run up to 3000 segments).
fn replay_dangling(seed: u64, index: usize, expected: (usize, &str)) -> Case {
    let case = generate_with(seed, index, 3000, Ends::Dangling);
    assert_eq!(
        (case.segments, case.environment.label()),
        expected,
        "the generator changed: find the case again"
    );
    case
}

/// `strand solve` of `case` in `dir` exits 0 and the brute-force check finds no vertex
/// or edge inside a triangle.
fn assert_converges_clear(dir: &Path, case: &Case) {
    let outcome = solve_and_check(&binary(), dir, case, Duration::from_secs(120));
    println!("{}\n{}", header(), outcome.row);
    assert!(outcome.violations.is_empty(), "{:?}", outcome.violations);
    assert_eq!(outcome.exit, Some(0), "{}", outcome.row);
}

/// `strand check` on `case` written into `dir`: its stdout (the start it takes).
fn check(binary: &Path, dir: &Path, case: &Case) -> String {
    let ron_path = write_case(dir, case);
    let output = Command::new(binary)
        .arg("check")
        .arg(&ron_path)
        .output()
        .unwrap();
    assert!(output.status.success(), "{output:?}");
    String::from_utf8(output.stdout).unwrap()
}

/// Regression: cables whose every bowed guess passes through the geometry or through
/// themselves were refused (exit 2, "move the rod's route" although none was given):
/// `everyday_s1_008` (a 60° groove: the hanging guess passes through its crease, the
/// bowed and arched ones leave the clamps into the flanks) and `everyday_s2_004` (a
/// stiff cable over a box whose bowed guesses cross over themselves). Both now start
/// straight between the connectors (inside the V, above the box) and converge, clear
/// of the geometry by the brute-force check.
#[test]
fn cables_that_no_bowed_guess_clears_start_straight_and_converge() {
    let tmp = tempfile::tempdir().unwrap();
    for (seed, index, segments, environment) in [(1, 8, 959, "groove60"), (2, 4, 403, "box")] {
        let case = replay(seed, index, (segments, environment));
        let start = check(&binary(), tmp.path(), &case);
        assert!(start.contains("straight between the ends"), "{start}");
        assert_converges_clear(tmp.path(), &case);
    }
}

/// Regression: cables dangling from one connector over a part were refused (exit 2,
/// "give the rod a route") when the part caught their hanging, bowed and arched
/// guesses alike (the free tail leaves the nozzle towards the part whichever way
/// gravity is turned): 9 of the 60 dangling cables of seeds 1–3, over floors as often
/// as in grooves. They now start draped over the part (the hanging guess kept while it
/// clears, the rest fallen as a chain) and converge, clear of the geometry by the
/// brute-force check. `dangling_s1_012`'s drape leaves the groove over its end, and
/// its coarsest level's start, whose longer edges cut that corner, passed through the
/// groove: that level is now left out (the next one solves) instead of the start
/// check's error ending the solve.
#[test]
fn dangling_cables_that_no_bowed_guess_clears_start_draped_and_converge() {
    let tmp = tempfile::tempdir().unwrap();
    for (seed, index, segments, environment) in [
        (1, 11, 275, "floor"),
        (1, 12, 117, "groove90"),
        (2, 1, 17, "floor"),
        (2, 14, 91, "groove60"),
        (3, 4, 130, "groove90"),
    ] {
        let case = replay_dangling(seed, index, (segments, environment));
        let start = check(&binary(), tmp.path(), &case);
        assert!(start.contains("draped over the parts"), "{start}");
        assert_converges_clear(tmp.path(), &case);
    }
}

/// Regression: `everyday_s1_007` (a limp cable, 409 segments, sliding into a 60°
/// groove) ended in `line_search_failed` at 641 N: the SQP model with the active rows'
/// augmented-Lagrangian term gave a step that went uphill in the merit (its penalty
/// pulled open rows held in the last QP shut), so no trial could be accepted. That
/// iteration now steps with the plain model: it converges (224 iterations).
#[test]
fn a_limp_cable_sliding_into_a_groove_converges() {
    let tmp = tempfile::tempdir().unwrap();
    let case = replay(1, 7, (409, "groove60"));
    assert_converges_clear(tmp.path(), &case);
}

/// Regression (partial): `everyday_s3_027` (seed 3, a limp 18 mm cable, 1108 segments,
/// lying along a 60° groove and over its end) creeps along the groove through ~1150
/// contact rows. A contact row's curvature makes a single iteration's Hessian need a
/// damping of 1e6; that damping, decayed by 3 per exact step (and inherited by the
/// plain step after an ascent), made each such spike cost 20 iterations of steps of
/// 1e-9 m: 772 iterations to converge. Then 429, asserted under a budget of 600; since
/// the levels of nested iteration slide it down the groove, 122 (119 of them on the
/// coarse levels), within the default budget too. The budget of 600 stays the bound.
#[test]
fn a_cable_creeping_along_a_groove_converges_within_600_iterations() {
    let tmp = tempfile::tempdir().unwrap();
    let case = with_solver_settings(replay(3, 27, (1108, "groove60")), "max_iterations: 600");
    assert_converges_clear(tmp.path(), &case);
}

/// The `iterations` line `strand solve` prints for `case` written into `dir`.
fn iterations_line(dir: &Path, case: &Case) -> String {
    let output = Command::new(binary())
        .arg("solve")
        .arg(write_case(dir, case))
        .arg("--out")
        .arg(dir.join("terminal"))
        .output()
        .unwrap();
    let stdout = String::from_utf8(output.stdout).unwrap();
    stdout
        .lines()
        .find(|l| l.starts_with("iterations"))
        .expect("an iterations line")
        .to_string()
}

/// `case` with `settings` (RON fields of `SolverSettings`) as its `solver`.
fn with_solver_settings(mut case: Case, settings: &str) -> Case {
    let gravity = "gravity: (0, 0, -9.81),";
    assert!(case.ron.contains(gravity), "the case file changed");
    assert!(!case.ron.contains("solver:"), "the case file changed");
    case.ron = case
        .ron
        .replace(gravity, &format!("{gravity}\n    solver: ({settings}),"));
    case
}

/// Cables creeping along a 60° groove through about a thousand contact rows, with the
/// solver setting `release_open_rows` (a row the last QP held but open now by more
/// than its force's compliance gap is no longer pulled shut): `everyday_s3_027` (429
/// iterations by default when this was written) and `everyday_s9_035` (seed 9,
/// 1532 segments: by default it stops at 4.3e-7 N after 436 iterations) converge
/// within the default budget.
#[test]
fn cables_creeping_along_a_groove_converge_with_open_rows_released() {
    let tmp = tempfile::tempdir().unwrap();
    for (seed, index, segments) in [(3, 27, 1108), (9, 35, 1532)] {
        let case = replay(seed, index, (segments, "groove60"));
        let case = with_solver_settings(case, "release_open_rows: true");
        assert_converges_clear(tmp.path(), &case);
    }
}

/// Regression: `everyday_s39_013` (seed 39, a 6.9 mm cable, 136 segments, in a 60°
/// groove) creeps along the groove under the held rows' pull: its fine level ran out of
/// its 200 iterations, and the load continuation after it ended at 3.2 N (exit 3, 439
/// iterations). The solver now goes on from where the direct attempt stopped with open
/// rows released (setting `release_retry`): it converges (249 iterations). Without the
/// retry it still ends exit 3, so the retry is what solves it.
#[test]
fn a_cable_creeping_along_a_groove_converges_on_a_retry_with_open_rows_released() {
    let tmp = tempfile::tempdir().unwrap();
    let case = replay(39, 13, (136, "groove60"));
    assert_converges_clear(tmp.path(), &case);
    // The terminal says where the iterations went, and its parts add up: the final
    // solve, the coarse level, the retry and the attempt it replaced.
    let line = iterations_line(tmp.path(), &case);
    let line = line.as_str();
    let numbers = |text: &str| -> Vec<usize> {
        text.split(|c: char| !c.is_ascii_digit())
            .filter_map(|w| w.parse().ok())
            .collect()
    };
    let (total, parts) = line.split_once('(').expect("a breakdown");
    let total = numbers(total)[0];
    let parts: usize = parts
        .split(", ")
        .filter(|p| !p.starts_with("after"))
        .map(|p| numbers(p)[0])
        .sum();
    assert_eq!(parts, total, "{line}");
    assert!(line.contains("attempts that did not converge"), "{line}");
    let without = with_solver_settings(replay(39, 13, (136, "groove60")), "release_retry: false");
    let outcome = solve_and_check(&binary(), tmp.path(), &without, Duration::from_secs(120));
    println!("{}", outcome.row);
    assert_eq!(outcome.exit, Some(3), "{}", outcome.row);
}

/// Regression: `everyday_s74_001` (seed 74, a 12 mm cable of 3233 segments lying in a
/// 90° groove). Its fine level crept: from 2.5e-8 N the residual fell to 2.0e-9 N in
/// 160 iterations, each a full step as predicted that still needed a damping of 5e-5
/// to 3e-4 (the SQP model indefinite), until the budget of 200 ran out; the release
/// retry after it converged in 2 (274 iterations, 9.9 s). The direct attempt now stops
/// where it creeps (`Termination::Creeping`) and the retry takes over (127
/// iterations, 5.8 s): asserted as a direct attempt that ended before its budget.
#[test]
fn a_cable_creeping_in_a_groove_hands_over_to_the_release_retry_before_its_budget() {
    let tmp = tempfile::tempdir().unwrap();
    let case = replay_up_to(74, 1, 10_000, (3233, "groove90"));
    assert_converges_clear(tmp.path(), &case);
    let line = iterations_line(tmp.path(), &case);
    let (before, _) = line
        .split_once(" in attempts that did not converge")
        .unwrap_or_else(|| panic!("a replaced attempt: {line}"));
    let replaced: usize = before
        .rsplit(' ')
        .next()
        .and_then(|w| w.parse().ok())
        .unwrap_or_else(|| panic!("{line}"));
    assert!(replaced < 200, "the direct attempt ran its budget: {line}");
}

/// Regression: `everyday_s69_002` (seed 69, a limp 3.8 mm cable of 144 segments in a
/// 60° groove). Its coarse level (141 unknowns, a budget of 40 iterations) ran out of
/// its budget and then ran the stiffness continuation meant as a solve's last resort:
/// 40 more iterations of a failed stiffening step (148 in all, 80 on the coarse
/// level). A coarse level only proposes a start within its budget: each level's
/// iterations (the solver's trace) are now within it (108 in all).
#[test]
fn a_coarse_level_spends_no_more_than_its_budget() {
    let tmp = tempfile::tempdir().unwrap();
    let case = replay_up_to(69, 2, 10_000, (144, "groove60"));
    assert_converges_clear(tmp.path(), &case);
    let output = Command::new(binary())
        .arg("solve")
        .arg(write_case(tmp.path(), &case))
        .arg("--out")
        .arg(tmp.path().join("traced"))
        .env("STRAND_TRACE", "1")
        .output()
        .unwrap();
    let trace = String::from_utf8(output.stderr).unwrap();
    // "strand-solve: coarse level of 141 unknowns (budget 40): 80 iterations, …"
    let levels: Vec<(usize, usize)> = trace
        .lines()
        .filter_map(|l| l.strip_prefix("strand-solve: coarse level of "))
        .map(|l| {
            let budget = l.split("(budget ").nth(1).and_then(|r| r.split(')').next());
            let spent = l.split("): ").nth(1).and_then(|r| r.split(' ').next());
            let number = |w: Option<&str>| w.and_then(|w| w.parse().ok()).expect(l);
            (number(budget), number(spent))
        })
        .collect();
    assert!(!levels.is_empty(), "no coarse level traced");
    for (budget, spent) in levels {
        assert!(
            spent <= budget,
            "a coarse level spent {spent} of its budget {budget}"
        );
    }
}

/// Regression: `everyday_s6_002` (seed 6, a thin 3.5 mm cable, 1817 segments, in a 90°
/// groove). A coarse step limited by the advancement may stop with an edge's
/// centreline on the groove's flank (its tube sunk by its whole radius), and from
/// there no move of that edge fits between two samples of the advancement. With
/// `release_open_rows` the coarse stiffening step stopped there (`t` of 2e-308 at every
/// iteration) and the fine solve stagnated at 1.4e-7 N (by default it converged, by
/// the luck of a slightly different trial). The advancement now keeps every centreline
/// a tenth of its radius off the surface: it converges either way.
#[test]
fn a_thin_cable_in_a_90_degree_groove_converges() {
    let tmp = tempfile::tempdir().unwrap();
    let case = replay(6, 2, (1817, "groove90"));
    assert_converges_clear(tmp.path(), &case);
    let case = with_solver_settings(case, "release_open_rows: true");
    assert_converges_clear(tmp.path(), &case);
}

/// `case` written into `dir` with connector `a`'s z coordinate moved by `dz_mm`, solved:
/// its clearance to `with` (m) and where along the cable it is (m).
fn clearance_with_a_moved(dir: &Path, case: &Case, dz_mm: f64, with: &str) -> (f64, f64) {
    let doc = result_with_a_moved(dir, case, dz_mm);
    let entry = doc["clearance"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["with"] == with)
        .expect("a clearance to the mesh");
    (
        entry["distance_m"].as_f64().unwrap(),
        entry["s_m"].as_f64().unwrap(),
    )
}

/// Output `name` of `strand sensitivity` of `case` (written into `dir`) with respect to
/// connector `a`'s height: its entry of `sensitivity.json`.
fn sensitivity_to_a_z(dir: &Path, case: &Case, name: &str) -> serde_json::Value {
    let ron_path = write_case(dir, case);
    let out = dir.join("sensitivity");
    let status = Command::new(binary())
        .arg("sensitivity")
        .arg(&ron_path)
        .args(["--param", "a.position.z", "--out"])
        .arg(&out)
        .stdout(Stdio::null())
        .status()
        .unwrap();
    assert!(status.success());
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("sensitivity.json")).unwrap())
            .unwrap();
    doc["outputs"]
        .as_array()
        .unwrap()
        .iter()
        .find(|o| o["name"] == name)
        .unwrap_or_else(|| panic!("no output {name}"))
        .clone()
}

/// `result.json` of `case` solved (in `dir`) with connector `a` raised by `dz_mm`.
fn result_with_a_moved(dir: &Path, case: &Case, dz_mm: f64) -> serde_json::Value {
    let stem = "\"a\": (position: (";
    let start = case.ron.find(stem).expect("connector a") + stem.len();
    let end = start + case.ron[start..].find(')').unwrap();
    let mut xyz: Vec<f64> = case.ron[start..end]
        .split(',')
        .map(|v| v.trim().parse().unwrap())
        .collect();
    xyz[2] += dz_mm;
    let mut moved = Case {
        name: format!("{}_dz{}", case.name, dz_mm.to_bits()),
        ron: case.ron.clone(),
        triangles: case.triangles.clone(),
        ..*case
    };
    moved.ron.replace_range(
        start..end,
        &format!("{:.9}, {:.9}, {:.9}", xyz[0], xyz[1], xyz[2]),
    );
    moved.ron = moved.ron.replace(
        &format!("obj: \"{}.obj\"", case.name),
        &format!("obj: \"{}.obj\"", moved.name),
    );
    let ron_path = write_case(dir, &moved);
    let out = dir.join(format!("out_{}", moved.name));
    let (exit, ..) = run(&binary(), &ron_path, &out, Duration::from_secs(120));
    assert_eq!(exit, Some(0));
    serde_json::from_str(&std::fs::read_to_string(out.join("result.json")).unwrap()).unwrap()
}

/// Sensitivities on an everyday case (`everyday_s32_035`: a cable 29 mm above a 90°
/// groove): the exact derivative of its clearance to the groove with respect to a
/// connector's height equals central differences of full solves at 0.01 mm, and since
/// the nearest place moves along the cable within the difference steps (the full solve
/// at +0.02 mm finds it 2.4 mm further along), it is marked one-sided. The whole table
/// before had extrapolated across that move (1.8093e-4 against 1.8072e-4 m/mm) and
/// marked nothing.
#[test]
fn a_clearance_whose_place_moves_within_the_steps_is_one_sided() {
    let tmp = tempfile::tempdir().unwrap();
    let case = replay(32, 35, (418, "groove90"));
    let output = sensitivity_to_a_z(tmp.path(), &case, "cable.clearance_m.groove90");
    let exact = output["d"]["a.position.z"].as_f64().unwrap();
    let one_sided = output["one_sided"]
        .as_array()
        .is_some_and(|p| p.iter().any(|p| p == "a.position.z"));
    let h = 0.01;
    let at = |k: f64| clearance_with_a_moved(tmp.path(), &case, k * h, "groove90");
    let (base, up, down, up2) = (at(0.0), at(1.0), at(-1.0), at(2.0));
    let central = (up.0 - down.0) / (2.0 * h);
    println!(
        "d clearance / d a.z: exact {exact:.12e}, full solves {central:.12e}; place {} m, at +2h {} m; one-sided {one_sided}",
        base.1, up2.1
    );
    assert!(
        (exact - central).abs() <= 1e-6 * central.abs(),
        "{exact} vs {central}"
    );
    assert!(
        (up2.1 - base.1).abs() > 1e-3,
        "the place moves within the steps"
    );
    assert!(one_sided, "{output}");
}

/// Sensitivities on an everyday case (`everyday_s35_008`: a stiff cable pressed into the
/// crease of a 60° groove, curved contact rows): the derivative of a connector's
/// reaction with respect to its height equals central differences of full solves. The
/// first solve leaves out the rows' curvature; the refinement stopped after eight
/// steps, 8e-5 off (before it refined only to 1e-9 of the stiffness terms: 3e-4 off).
#[test]
fn a_reaction_of_a_cable_pressed_into_a_groove_crease_matches_full_solves() {
    let tmp = tempfile::tempdir().unwrap();
    let case = replay(35, 8, (68, "groove60"));
    let exact = sensitivity_to_a_z(tmp.path(), &case, "a.force_N.z")["d"]["a.position.z"]
        .as_f64()
        .unwrap();
    let reaction = |dz: f64| {
        let doc = result_with_a_moved(tmp.path(), &case, dz);
        let a = doc["reactions"]
            .as_array()
            .unwrap()
            .iter()
            .find(|r| r["name"] == "a")
            .expect("connector a")
            .clone();
        a["force_N"][2].as_f64().unwrap()
    };
    let h = 0.1;
    let central = (reaction(h) - reaction(-h)) / (2.0 * h);
    println!("d a.force_N.z / d a.z: exact {exact:.9e}, full solves {central:.9e}");
    assert!(
        (exact - central).abs() <= 1e-5 * central.abs(),
        "{exact} vs {central}"
    );
}

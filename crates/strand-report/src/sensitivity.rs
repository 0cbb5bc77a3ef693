//! Design sensitivities as other tools read them: the named outputs of a result
//! ([`design_outputs`]), and `sensitivity.json` / `sensitivity.csv`
//! ([`SensitivityDoc`]).
//!
//! Output names: `<rod>.peak_force_N`, `<rod>.peak_moment_Nm`,
//! `<rod>.min_bend_radius_m`, `<rod>.min_clearance_m` and
//! `<rod>.clearance_m.<obstacle>`, `<reaction>.force_N.x|y|z` and
//! `<reaction>.moment_Nm.x|y|z` (connectors, ports), `<clip>.force_N.x|y|z`,
//! `<clip>.moment_Nm.x|y|z` and `<clip>.joint_value` (rad or m),
//! `<body>.position_m.x|y|z` and `<body>.rotation_vector_rad.x|y|z` (free junctions),
//! `<rod>.contact_force_N.<obstacle>.<k>` (the `k`-th pressing contact of the rod on
//! that obstacle along the rod).

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};
use strand_solve::Solution;
use strand_solve::contact::Contact;
use strand_system::Model;

use crate::study::peak;
use crate::{ContactOutputs, ResultDoc, Timing, bend_radii, collect, name_connectors};

/// One named output value of a result, with where a peak or minimum is attained.
#[derive(Clone, Debug, PartialEq)]
pub struct OutputValue {
    /// The output's name (see the module documentation), with its unit.
    pub name: String,
    /// The value in the unit of the name.
    pub value: f64,
    /// Where a peak or minimum is attained (a vertex, an obstacle); 0 when smooth.
    pub arg: usize,
}

/// The result document of `solution` with what sensitivities read: rods, reactions,
/// clips, bodies, contacts and clearances (no environment outlines, no findings, no
/// per-vertex clearances).
pub fn sensitivity_doc(
    case: &str,
    model: &Model,
    solution: &Solution,
    contact: Option<&Contact>,
    connector_names: &[[Option<String>; 2]],
) -> Result<ResultDoc, strand_solve::ConstraintError> {
    let contacts = contact
        .map(|c| ContactOutputs::of(model, solution, c))
        .transpose()?;
    Ok(sensitivity_doc_from(
        case,
        model,
        solution,
        contacts.as_ref(),
        connector_names,
    ))
}

/// [`sensitivity_doc`] with its contacts and clearances already found (`contacts`).
pub fn sensitivity_doc_from(
    case: &str,
    model: &Model,
    solution: &Solution,
    contacts: Option<&ContactOutputs>,
    connector_names: &[[Option<String>; 2]],
) -> ResultDoc {
    let mut doc = collect(case, model, solution, Timing::default());
    if let Some(contacts) = contacts {
        contacts.fill(&mut doc, model);
    }
    name_connectors(&mut doc, connector_names);
    doc
}

/// Relative difference within which a peak's or minimum's value at another place
/// ties with its extreme: a difference rounding alone can make (the sectional
/// quantities of two mirror-image vertices differ by about 1e-13 of their size),
/// far below any change of the extreme over a sensitivity's difference steps that
/// makes its derivative one-sided.
pub const ARG_TIE: f64 = 1e-10;

/// Whether `value` ties with the extreme `extreme` ([`ARG_TIE`]).
pub fn ties(value: f64, extreme: f64) -> bool {
    (value - extreme).abs() <= ARG_TIE * extreme.abs()
}

fn push3(out: &mut Vec<OutputValue>, stem: &str, v: &[f64; 3]) {
    for (axis, x) in ["x", "y", "z"].iter().zip(v) {
        out.push(OutputValue {
            name: format!("{stem}.{axis}"),
            value: *x,
            arg: 0,
        });
    }
}

/// Every named output of `doc`, in a fixed order (rods, reactions, clips, bodies,
/// contacts).
///
/// With `pins` (the outputs of the base design), a peak or minimum is read where the
/// base attains it (the vertex or obstacle of the base's `arg`), while `arg` still
/// says where this document attains it: the derivative of a peak is then the
/// derivative at the base's arg-max, and a differing `arg` marks it one-sided. The
/// base's place stays the `arg` while its value is within [`ARG_TIE`] of the extreme
/// (a tie that only rounding breaks, e.g. the two symmetric peaks of a symmetric
/// hose, does not mark a derivative one-sided).
pub fn design_outputs(doc: &ResultDoc, pins: Option<&[OutputValue]>) -> Vec<OutputValue> {
    let mut out = Vec::new();
    let pinned = |name: &str| {
        pins.and_then(|p| p.iter().find(|o| o.name == name))
            .map(|o| o.arg)
    };
    // The extreme (value, arg), read at the pinned arg if there is one.
    let read = |name: String, values: &[f64], extreme: (f64, usize)| {
        let at_pin = pinned(&name).and_then(|j| Some((values.get(j).copied()?, j)));
        let (value, arg) = match at_pin {
            Some((value, j)) if ties(value, extreme.0) => (value, j),
            Some((value, _)) => (value, extreme.1),
            None => extreme,
        };
        OutputValue { name, value, arg }
    };
    for rod in &doc.rods {
        let forces: Vec<f64> = rod.force_n.iter().map(crate::magnitude).collect();
        let moments: Vec<f64> = rod.moment_nm.iter().map(crate::magnitude).collect();
        out.push(read(
            format!("{}.peak_force_N", rod.name),
            &forces,
            peak(&rod.force_n),
        ));
        out.push(read(
            format!("{}.peak_moment_Nm", rod.name),
            &moments,
            peak(&rod.moment_nm),
        ));
        let radii = bend_radii(rod);
        let smallest = radii
            .iter()
            .enumerate()
            .fold(
                (f64::INFINITY, 0),
                |best, (j, &r)| {
                    if r < best.0 { (r, j) } else { best }
                },
            );
        if smallest.0.is_finite() {
            out.push(read(
                format!("{}.min_bend_radius_m", rod.name),
                &radii,
                smallest,
            ));
        }
        let clearances: Vec<_> = doc.clearance.iter().filter(|c| c.rod == rod.name).collect();
        let distances: Vec<f64> = clearances.iter().map(|c| c.distance_m).collect();
        if let Some((k, nearest)) = clearances
            .iter()
            .enumerate()
            .min_by(|a, b| a.1.distance_m.total_cmp(&b.1.distance_m))
        {
            out.push(read(
                format!("{}.min_clearance_m", rod.name),
                &distances,
                (nearest.distance_m, k),
            ));
        }
        for c in clearances {
            out.push(OutputValue {
                name: format!("{}.clearance_m.{}", rod.name, c.with),
                value: c.distance_m,
                arg: 0,
            });
        }
    }
    // A clip's reaction is listed among the reactions too: its outputs come once,
    // with the clips (which add the joint's value).
    for r in doc.reactions.iter().filter(|r| r.kind != "clip") {
        push3(&mut out, &format!("{}.force_N", r.name), &r.force_n);
        push3(&mut out, &format!("{}.moment_Nm", r.name), &r.moment_nm);
    }
    for c in &doc.clips {
        push3(&mut out, &format!("{}.force_N", c.name), &c.force_n);
        push3(&mut out, &format!("{}.moment_Nm", c.name), &c.moment_nm);
        if let Some(value) = c.value {
            out.push(OutputValue {
                name: format!("{}.joint_value", c.name),
                value,
                arg: 0,
            });
        }
    }
    for b in doc.bodies.iter().filter(|b| !b.fixed) {
        push3(&mut out, &format!("{}.position_m", b.name), &b.position_m);
        let [w, x, y, z] = b.orientation_quaternion_wxyz;
        let q = nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(w, x, y, z));
        let v = q.scaled_axis();
        push3(
            &mut out,
            &format!("{}.rotation_vector_rad", b.name),
            &[v.x, v.y, v.z],
        );
    }
    let mut counts: BTreeMap<(String, String), usize> = BTreeMap::new();
    for c in doc.contacts.iter().filter(|c| c.force_n > 0.0) {
        let k = counts.entry((c.rod.clone(), c.with.clone())).or_insert(0);
        out.push(OutputValue {
            name: format!("{}.contact_force_N.{}.{k}", c.rod, c.with),
            value: c.force_n,
            arg: 0,
        });
        *k += 1;
    }
    out
}

/// A parameter of `sensitivity.json`: its name (as `--param` took it) and unit.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SensitivityParameter {
    /// e.g. `hose2.length`.
    pub name: String,
    /// The unit the derivatives are per, e.g. `mm`.
    pub unit: String,
}

/// An output of `sensitivity.json` with its derivative per parameter.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SensitivityOutput {
    /// e.g. `hose2.peak_force_N`.
    pub name: String,
    /// Its value at the base design, in the unit of the name.
    pub value: f64,
    /// Per parameter name: the derivative, output unit per parameter unit.
    pub d: BTreeMap<String, f64>,
    /// The parameters whose derivative is one-sided here (the arg-max/arg-min jumps,
    /// or a contact or joint stop is about to switch).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub one_sided: Vec<String>,
}

/// `sensitivity.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SensitivityDoc {
    /// The case.
    pub case: String,
    /// Whether the base solve converged.
    pub converged: bool,
    /// Its residual, N.
    pub residual_n: f64,
    /// The parameters.
    pub parameters: Vec<SensitivityParameter>,
    /// Every output.
    pub outputs: Vec<SensitivityOutput>,
    /// Active rows (contacts, joint stops) near a switch: `"<key>: <reason>"`.
    #[serde(default)]
    pub near_switch: Vec<String>,
}

impl SensitivityDoc {
    /// `sensitivity.csv`: one row per output, `output,value,d/d<param> [<unit>/<param
    /// unit>]…,one_sided`.
    pub fn csv(&self) -> String {
        let mut s = String::from("output,value");
        for p in &self.parameters {
            s.push_str(&format!(",d/d{} [per {}]", p.name, p.unit));
        }
        s.push_str(",one_sided\n");
        for o in &self.outputs {
            s.push_str(&format!("{},{:e}", o.name, o.value));
            for p in &self.parameters {
                s.push_str(&format!(
                    ",{:e}",
                    o.d.get(&p.name).copied().unwrap_or(f64::NAN)
                ));
            }
            s.push_str(&format!(",{}\n", o.one_sided.join(" ")));
        }
        s
    }
}

//! `--vary ITEM=VALUES`: one varied parameter of a batch.
//!
//! `ITEM` is a variant item of the case (`rods.hose2.length`, see
//! [`strand_case::VARIANT_ITEMS`]) or its short form without the `rods.`,
//! `junctions.` or `connectors.` prefix (`hose2.length`, `tee.mass`); a component of a
//! vector item is named by a suffix `.x`, `.y` or `.z` (`oil_cooler.position.z`,
//! `gravity.z`, `hose1.end.force.x`).
//!
//! `VALUES` is a range `A..B:STEP` (both ends included, `STEP > 0`, `B` may be below
//! `A`), a list `A,B,C` or one value. A value with a sign (`+30mm`, `-150mm`, `+0`)
//! is an offset from the case's value (`Add`); a value without one is the value itself
//! (`Set`). Each number may carry a unit: `mm`, `cm`, `m` for lengths (default: the
//! case's length unit), `kg`, `g` for masses, `N` for forces (and `ea`, `ga`), `m/s2`
//! for gravity, `deg` (default) or `rad` for the turn of a `direction` about an axis
//! (`oil_cooler.direction.y=-10deg..+10deg:2deg`), `N·m²` (`Nm2`) for `ei` and `gj`,
//! `Pa`, `kPa`, `MPa`, `GPa` for `youngs_modulus`. Components of vectors only take
//! offsets.

use strand_case::schema::{Amount, CaseFile, Change, VariantChange};
use strand_case::{
    ItemQuantity as Quantity, LengthUnit, ShortFormError, VariantItem, expand_short,
};

/// Longest value as written in a variant id (`123456.789`), characters.
pub const MAX_VALUE_CHARS: usize = 24;

/// Most values one `--vary` may produce.
pub const MAX_VALUES: usize = 10_000;

/// Accepted unit suffixes of `quantity` with their size in the base unit (m, kg, N,
/// m/s², deg, N·m², Pa, 1), in the order they are tried: a suffix before every
/// shorter one it ends with, so that `mm` is not read as `m` nor `MPa` as `Pa`.
pub(super) fn units(quantity: Quantity) -> &'static [(&'static str, f64)] {
    match quantity {
        Quantity::Length => &[("mm", 1e-3), ("cm", 1e-2), ("m", 1.0)],
        Quantity::Mass => &[("kg", 1.0), ("g", 1e-3)],
        Quantity::Force => &[("N", 1.0)],
        Quantity::Acceleration => &[("m/s2", 1.0), ("m/s^2", 1.0), ("m/s²", 1.0)],
        Quantity::Count => &[],
        Quantity::Angle => &[
            ("deg", 1.0),
            ("°", 1.0),
            ("rad", 180.0 / std::f64::consts::PI),
        ],
        Quantity::BendingStiffness => &[
            ("N·m²", 1.0),
            ("N·m2", 1.0),
            ("Nm2", 1.0),
            ("Nm^2", 1.0),
            ("Nmm2", 1e-6),
        ],
        Quantity::Modulus => &[("GPa", 1e9), ("MPa", 1e6), ("kPa", 1e3), ("Pa", 1.0)],
    }
}

/// The unit of size 1 of a quantity other than a length (`kg`, `N`, `m/s2`, `deg`,
/// `N·m²`, `Pa`; empty for a count): the unit of the item in the case file.
pub(crate) fn base_unit(quantity: Quantity) -> &'static str {
    units(quantity)
        .iter()
        .find(|(_, size)| *size == 1.0)
        .map_or("", |(u, _)| *u)
}

/// One varied parameter: the item, whether its values are offsets, and the values.
#[derive(Clone, Debug, PartialEq)]
pub struct Vary {
    /// The option as written (`hose2.length=+0mm..+100mm:10mm`).
    pub text: String,
    /// The item as written before `=` (used in ids and column names).
    pub label: String,
    /// The variant item of the case (`rods.hose2.length`).
    pub item: String,
    /// For a vector item, the varied component (0, 1, 2).
    pub component: Option<usize>,
    /// Whether the values are offsets (`Add`) rather than values (`Set`).
    pub offset: bool,
    /// The unit the values are given in (`mm`; empty for counts).
    pub unit: String,
    /// The values, in `unit`.
    pub values: Vec<f64>,
    /// Size of `unit` in the case's unit of the item (1000 for values in m in a case in mm).
    scale: f64,
    /// The value anchoring the warm-start chains: the case's own value in `unit`
    /// (0 for offsets), if known.
    pub base: Option<f64>,
}

/// A `--vary` that cannot be used, with the reason and the fix.
#[derive(Debug, thiserror::Error)]
#[error("--vary {text}: {message} (hint: {hint})")]
pub struct SpecError {
    text: String,
    /// What is wrong.
    pub message: String,
    /// How to fix it.
    pub hint: String,
}

pub(super) fn fail(text: &str, message: impl Into<String>, hint: impl Into<String>) -> SpecError {
    SpecError {
        text: text.to_string(),
        message: message.into(),
        hint: hint.into(),
    }
}

/// A written number: its value in the base unit (m, kg, …; the case unit when no
/// unit is given), whether it has a sign, and the unit written (if any).
pub(super) struct Number {
    pub(super) base_value: f64,
    pub(super) signed: bool,
    pub(super) unit: Option<&'static str>,
}

/// Parses `written` (a number of `quantity` with an optional unit; `default_size`:
/// the size of the unit assumed when none is written) for option `text`.
pub(super) fn parse_number(
    text: &str,
    written: &str,
    quantity: Quantity,
    default_size: f64,
) -> Result<Number, SpecError> {
    let written = written.trim();
    let (digits, unit) = units(quantity)
        .iter()
        .find_map(|(u, size)| written.strip_suffix(u).map(|d| (d, Some((*u, *size)))))
        .unwrap_or((written, None));
    let accepted: Vec<&str> = units(quantity).iter().map(|(u, _)| *u).collect();
    let value: f64 = digits.trim().parse().map_err(|_| {
        fail(
            text,
            format!("'{written}' is not a number with a unit"),
            if accepted.is_empty() {
                "write a whole number, e.g. 40".to_string()
            } else {
                format!(
                    "write e.g. +30{} (units: {})",
                    accepted[0],
                    accepted.join(", ")
                )
            },
        )
    })?;
    if !value.is_finite() {
        return Err(fail(
            text,
            format!("'{written}' is not finite"),
            "write a finite number",
        ));
    }
    Ok(Number {
        base_value: value * unit.map_or(default_size, |(_, size)| size),
        signed: digits.trim_start().starts_with(['+', '-']),
        unit: unit.map(|(u, _)| u),
    })
}

/// The canonical decimal form of `value` (at most 9 decimals, no trailing zeros).
pub fn canonical(value: f64) -> String {
    strand_case::canonical_decimal(value, 9)
}

/// The item of `label` (short or full form) and its quantity and component.
pub fn resolve(
    text: &str,
    label: &str,
    file: &CaseFile,
) -> Result<(String, VariantItem, Option<usize>), SpecError> {
    let (stem, component) = match label.rsplit_once('.') {
        Some((stem, c @ ("x" | "y" | "z"))) => (
            stem,
            Some(["x", "y", "z"].iter().position(|a| *a == c).unwrap_or(0)),
        ),
        _ => (label, None),
    };
    let names = |kind: &str, list: Vec<&str>| {
        format!(
            "{kind}: {}",
            if list.is_empty() {
                "none".to_string()
            } else {
                list.join(", ")
            }
        )
    };
    let hint = format!(
        "vary e.g. <rod>.length, <rod>.segments, <rod>.end.position.z, <rod>.end.force.x, <junction>.mass, <junction>.ports.<port>.direction.z (deg), <connector>.position.x, <connector>.direction.y (deg), <clip>.at, <clip>.base.direction.z (deg), <section>.ei (N·m²), <section>.youngs_modulus (Pa) or gravity.z; {}; {}; {}",
        names("rods", file.rods.iter().map(|r| r.name.as_str()).collect()),
        names(
            "junctions",
            file.junctions.iter().map(|(n, _)| n.as_str()).collect()
        ),
        names(
            "connectors",
            file.connectors.iter().map(|(n, _)| n.as_str()).collect()
        )
    );
    let full = expand_short(file, stem).map_err(|e| match e {
        ShortFormError::Unknown(_) => fail(text, e.to_string(), hint.clone()),
        ShortFormError::Ambiguous { .. } => fail(text, e.to_string(), "write the full item"),
    })?;
    let item = VariantItem::parse(file, &full).map_err(|e| {
        fail(
            text,
            format!("'{label}' is not an item a batch can vary: {}", e.message),
            hint.clone(),
        )
    })?;
    match (item.is_vector(), component) {
        (true, None) => Err(fail(
            text,
            format!("'{label}' is a vector: vary one component"),
            format!("write {label}.x, {label}.y or {label}.z"),
        )),
        (false, Some(_)) => Err(fail(
            text,
            format!("'{stem}' is a number, not a vector"),
            format!("write {stem}=..."),
        )),
        _ => Ok((full, item, component)),
    }
}

impl Vary {
    /// Parses `ITEM=VALUES` against the case file.
    pub fn parse(text: &str, file: &CaseFile) -> Result<Self, SpecError> {
        let Some((label, values)) = text.split_once('=') else {
            return Err(fail(
                text,
                "missing '='",
                "write ITEM=VALUES, e.g. hose2.length=+0mm..+100mm:10mm",
            ));
        };
        let (label, values) = (label.trim(), values.trim());
        let (item, target, component) = resolve(text, label, file)?;
        let quantity = target.quantity();
        let case_unit = LengthUnit::parse(&file.units.length);
        let default_size = match quantity {
            Quantity::Length => case_unit.map_or(1.0, |u| u.metres()),
            _ => 1.0,
        };
        let parse = |w: &str| parse_number(text, w, quantity, default_size);
        // The written numbers, and the range's step if any.
        let (numbers, step) = match values.split_once("..") {
            Some((a, rest)) => {
                let Some((b, step)) = rest.split_once(':') else {
                    return Err(fail(
                        text,
                        "a range needs a step",
                        format!("write {label}=A..B:STEP, e.g. +0mm..+100mm:10mm"),
                    ));
                };
                let step = parse(step)?;
                (vec![parse(a)?, parse(b)?], Some(step))
            }
            None => (
                values
                    .split(',')
                    .map(parse)
                    .collect::<Result<Vec<_>, _>>()?,
                None,
            ),
        };
        let offset = numbers[0].signed;
        if numbers.iter().any(|n| n.signed != offset) {
            return Err(fail(
                text,
                "some values have a sign (offsets) and others not (values)",
                "give every value a sign (+0mm..+100mm: offsets from the case) or none (150mm..250mm: values)",
            ));
        }
        if component.is_some() && !offset {
            return Err(fail(
                text,
                "a vector component can only be offset",
                format!("write signed offsets, e.g. {label}=+0..+20"),
            ));
        }
        if quantity == Quantity::Count && offset {
            return Err(fail(
                text,
                "the number of segments can only be set",
                format!("write values without a sign, e.g. {label}=20,40,80"),
            ));
        }
        // The display unit: the first one written, else the case's (lengths) or base unit.
        let unit: &str =
            numbers
                .iter()
                .chain(&step)
                .find_map(|n| n.unit)
                .unwrap_or(match quantity {
                    Quantity::Length => case_unit.map_or("m", |u| u.symbol()),
                    other => base_unit(other),
                });
        let size = units(quantity)
            .iter()
            .find(|(u, _)| *u == unit)
            .map_or(1.0, |(_, s)| *s);
        let display = |n: &Number| n.base_value / size;
        let mut shown: Vec<f64> = match step {
            None => numbers.iter().map(display).collect(),
            Some(step) => {
                let (a, b, h) = (display(&numbers[0]), display(&numbers[1]), display(&step));
                if h.is_nan() || h <= 0.0 {
                    return Err(fail(text, "the step must be > 0", "write e.g. :10mm"));
                }
                let steps = ((b - a) / h).abs();
                let count = steps.round();
                if (steps - count).abs() > 1e-6 * count.max(1.0) {
                    return Err(fail(
                        text,
                        format!(
                            "{} is not a whole number of steps of {}",
                            canonical(b - a),
                            canonical(h)
                        ),
                        "choose a step that divides the range",
                    ));
                }
                if count + 1.0 > MAX_VALUES as f64 {
                    return Err(fail(
                        text,
                        format!(
                            "the range has {} values (at most {MAX_VALUES})",
                            count + 1.0
                        ),
                        "use a larger step",
                    ));
                }
                let sign = if b < a { -1.0 } else { 1.0 };
                (0..=count as usize)
                    .map(|k| a + sign * k as f64 * h)
                    .collect()
            }
        };
        // Canonical decimals: the value used is exactly the value in the id.
        for v in &mut shown {
            *v = canonical(*v).parse().unwrap_or(*v);
        }
        for (k, v) in shown.iter().enumerate() {
            if shown[..k].contains(v) {
                return Err(fail(
                    text,
                    format!("the value {} appears twice", canonical(*v)),
                    "list every value once",
                ));
            }
            if quantity == Quantity::Count && !(v.fract() == 0.0 && *v >= 1.0) {
                return Err(fail(
                    text,
                    format!("{} is not a whole number ≥ 1", canonical(*v)),
                    "give whole numbers of segments",
                ));
            }
            if quantity == Quantity::Count && *v > crate::limits::MAX_SEGMENTS as f64 {
                return Err(fail(
                    text,
                    format!(
                        "{} segments; at most {} per rod",
                        canonical(*v),
                        crate::limits::MAX_SEGMENTS
                    ),
                    "use fewer segments",
                ));
            }
        }
        let case_size = match quantity {
            Quantity::Length => case_unit.map_or(1.0, |u| u.metres()),
            _ => 1.0,
        };
        // Every value becomes part of a folder name and, in the case's units, a
        // number of the model: both must stay sensible.
        for v in &shown {
            let written = canonical(*v);
            if written.len() > MAX_VALUE_CHARS || !(v * size / case_size).is_finite() {
                return Err(fail(
                    text,
                    if v.is_finite() && (v * size / case_size).is_finite() {
                        format!(
                            "the value {v:e} {unit} is too large ({} digits; at most {MAX_VALUE_CHARS}, it becomes part of the variant's folder name)",
                            written.len()
                        )
                    } else {
                        format!("a value overflows when converted to {unit} and to the case's unit")
                    },
                    "check the value and its unit (e.g. 100mm, not 1e308mm)",
                ));
            }
        }
        let base = if offset {
            Some(0.0)
        } else {
            target.case_value(file).map(|v| v / size)
        };
        Ok(Self {
            text: text.to_string(),
            label: label.to_string(),
            item,
            component,
            offset,
            unit: unit.to_string(),
            values: shown,
            scale: size / case_size,
            base,
        })
    }

    /// The value `k` as written in ids and tables: `+30mm`, `-150mm`, `150mm`.
    pub fn value_text(&self, k: usize) -> String {
        let v = self.values[k];
        let sign = if self.offset && v >= 0.0 { "+" } else { "" };
        format!("{sign}{}{}", canonical(v), self.unit)
    }

    /// The id part of value `k`: `hose2.length_p30mm` (`m` for a minus sign).
    pub fn id_part(&self, k: usize) -> String {
        let value = self.value_text(k).replace('+', "p").replace('-', "m");
        let raw = format!("{}_{value}", self.label);
        raw.chars()
            .map(|c| {
                if c.is_ascii_alphanumeric() || matches!(c, '.' | '_' | '-') {
                    c
                } else {
                    '_'
                }
            })
            .collect()
    }

    /// The change of value `k` for strand-case's variant machinery (in the case's units).
    pub fn change(&self, k: usize) -> VariantChange {
        let x = self.values[k] * self.scale;
        let amount = match self.component {
            Some(c) => {
                let mut v = [0.0; 3];
                v[c] = x;
                Amount::Vector(v)
            }
            None => Amount::Number(x),
        };
        VariantChange {
            item: self.item.clone(),
            change: if self.offset {
                Change::Add(amount)
            } else {
                Change::Set(amount)
            },
        }
    }

    /// The index of the value nearest the case's own value (the first if unknown):
    /// where this parameter's warm-start chains start.
    pub fn anchor(&self) -> usize {
        let Some(base) = self.base else { return 0 };
        let mut best = 0;
        for (k, v) in self.values.iter().enumerate() {
            if (v - base).abs() < (self.values[best] - base).abs() {
                best = k;
            }
        }
        best
    }
}

/// Parses `--shard I/N` (1 ≤ I ≤ N).
pub fn parse_shard(text: &str) -> Result<(usize, usize), String> {
    let parsed = text.split_once('/').and_then(|(i, n)| {
        Some((
            i.trim().parse::<usize>().ok()?,
            n.trim().parse::<usize>().ok()?,
        ))
    });
    match parsed {
        Some((i, n)) if n >= 1 && (1..=n).contains(&i) => Ok((i, n)),
        _ => Err(format!(
            "--shard {text}: expected I/N with 1 ≤ I ≤ N, e.g. --shard 1/4 (Slurm: --shard $((SLURM_ARRAY_TASK_ID+1))/$SLURM_ARRAY_TASK_COUNT)"
        )),
    }
}

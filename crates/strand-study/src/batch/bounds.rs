//! `--vary ITEM=LO..HI`: the bounds of one design variable of `strand optimize`.
//!
//! `ITEM` is named as in `batch --vary` (see [`super::spec`]); `LO..HI` is a range
//! without a step. Signed bounds (`-20mm..+40mm`) are offsets from the case's value;
//! unsigned ones (`150mm..300mm`) are values, for items whose value the case states
//! (rod lengths, junction masses, connector position components, gravity components,
//! section stiffnesses). A `direction` is turned by offsets only (`-10deg..+10deg`).
//! Units as in `batch --vary` (default: the case's length unit, kg, N, m/s²).

use strand_case::schema::CaseFile;
use strand_case::{ItemQuantity as Quantity, LengthUnit};

use super::spec::{SpecError, base_unit, fail, parse_number, resolve};

/// The bounds of one design variable.
#[derive(Clone, Debug, PartialEq)]
pub struct Bounds {
    /// The item as written before `=` (the variable's name in `optimum.json`).
    pub label: String,
    /// The variant item (`rods.hose2.length`).
    pub item: String,
    /// The component of a vector item.
    pub component: Option<usize>,
    /// What kind of number the item is.
    pub quantity: Quantity,
    /// The item resolved against the case.
    pub target: strand_case::VariantItem,
    /// The item's unit in the case (`mm` for lengths in a case in mm, `kg`, `N`, `m/s2`).
    pub unit: String,
    /// Lower and upper offsets from the case's value, in `unit`.
    pub lower: f64,
    /// See `lower`.
    pub upper: f64,
    /// The case's value in `unit`, if the case states it.
    pub origin: Option<f64>,
}

/// Parses `ITEM=LO..HI` against the case file.
pub fn parse_bounds(text: &str, file: &CaseFile) -> Result<Bounds, SpecError> {
    let fail = |message: String, hint: String| fail(text, message, hint);
    let Some((label, range)) = text.split_once('=') else {
        return Err(fail(
            "missing '='".into(),
            "write ITEM=LO..HI, e.g. hose2.length=150mm..300mm".into(),
        ));
    };
    let (label, range) = (label.trim(), range.trim());
    let (item, target, component) = resolve(text, label, file)?;
    let quantity = target.quantity();
    if quantity == Quantity::Count {
        return Err(fail(
            format!("'{label}' is a number of segments, not a continuous design variable"),
            "vary lengths, positions, masses, forces or gravity".into(),
        ));
    }
    let case_unit = LengthUnit::parse(&file.units.length);
    let case_size = match quantity {
        Quantity::Length => case_unit.map_or(1.0, |u| u.metres()),
        _ => 1.0,
    };
    let Some((lo, hi)) = range.split_once("..") else {
        return Err(fail(
            format!("'{range}' is not a range"),
            format!("write {label}=LO..HI, e.g. {label}=150mm..300mm or {label}=-20mm..+20mm"),
        ));
    };
    if hi.contains(':') {
        return Err(fail(
            "an optimisation range takes no step".into(),
            format!("write {label}=LO..HI without :STEP"),
        ));
    }
    let lo = parse_number(text, lo, quantity, case_size)?;
    let hi = parse_number(text, hi, quantity, case_size)?;
    if lo.signed != hi.signed {
        return Err(fail(
            "one bound has a sign (an offset) and the other not (a value)".into(),
            "give both a sign (-20mm..+40mm: offsets from the case) or neither (150mm..300mm: values)".into(),
        ));
    }
    // Values in the item's unit in the case.
    let (mut lower, mut upper) = (lo.base_value / case_size, hi.base_value / case_size);
    let origin = match component {
        Some(c) => target.case_component(file, c),
        None => target.case_value(file),
    }
    .map(|v| v / case_size);
    if !lo.signed {
        let Some(origin) = origin else {
            return Err(fail(
                format!("the case states no value of '{label}' to take the bounds from"),
                format!("give offsets from the case, e.g. {label}=-20..+20"),
            ));
        };
        lower -= origin;
        upper -= origin;
    }
    if lower >= upper {
        return Err(fail(
            "the lower bound is not below the upper bound".into(),
            format!("write {label}=LO..HI with LO < HI"),
        ));
    }
    let unit = match quantity {
        Quantity::Length => case_unit.map_or("m", |u| u.symbol()),
        other => base_unit(other),
    };
    Ok(Bounds {
        label: label.to_string(),
        item,
        component,
        quantity,
        target,
        unit: unit.to_string(),
        lower,
        upper,
        origin,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cooler() -> CaseFile {
        strand_case::Case::from_path(
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../cases/cooler_hose.ron"),
        )
        .unwrap()
        .file
    }

    #[test]
    fn values_become_offsets_from_the_case_in_its_unit() {
        let b = parse_bounds("hose2.length=15cm..0.3m", &cooler()).unwrap();
        assert_eq!(b.item, "rods.hose2.length");
        assert_eq!(b.unit, "mm");
        assert_eq!(b.origin, Some(190.0));
        assert!((b.lower + 40.0).abs() < 1e-9 && (b.upper - 110.0).abs() < 1e-9);
        let z = parse_bounds("oil_cooler.position.z=-20mm..+1cm", &cooler()).unwrap();
        assert_eq!((z.component, z.origin), (Some(2), Some(75.0)));
        assert!((z.lower + 20.0).abs() < 1e-9 && (z.upper - 10.0).abs() < 1e-9);
        let m = parse_bounds("tee.mass=500g..2kg", &cooler()).unwrap();
        assert!((m.lower + 0.5).abs() < 1e-12 && (m.upper - 1.0).abs() < 1e-12);
    }

    #[test]
    fn directions_are_offsets_in_degrees_and_stiffnesses_values_or_offsets() {
        let d = parse_bounds("oil_cooler.direction.y=-0.1rad..+5deg", &cooler()).unwrap();
        assert_eq!(
            (d.item.as_str(), d.unit.as_str()),
            ("connectors.oil_cooler.direction", "deg")
        );
        assert!((d.lower + 0.1 * 180.0 / std::f64::consts::PI).abs() < 1e-12);
        assert_eq!((d.upper, d.origin), (5.0, None));
        let e = parse_bounds("hose_small.youngs_modulus=4MPa..6MPa", &cooler()).unwrap();
        assert_eq!((e.unit.as_str(), e.origin), ("Pa", Some(5e6)));
        assert!((e.lower + 1e6).abs() < 1e-6 && (e.upper - 1e6).abs() < 1e-6);
        let no_value = parse_bounds("oil_cooler.direction.y=0deg..5deg", &cooler())
            .unwrap_err()
            .to_string();
        assert!(no_value.contains("states no value"), "{no_value}");
    }

    #[test]
    fn bad_ranges_name_the_option_and_the_fix() {
        for bad in [
            "hose2.length",
            "hose2.length=150mm",
            "hose2.length=300mm..150mm",
            "hose2.length=150mm..300mm:1mm",
            "hose2.length=-10mm..300mm",
            "hose2.segments=10..20",
            "nothing.length=1..2",
            "hose2.length=1kg..2kg",
        ] {
            let e = parse_bounds(bad, &cooler()).unwrap_err().to_string();
            assert!(e.contains(bad) && e.contains("hint"), "{e}");
        }
    }
}

//! Boundary checks of everything in a case that becomes a file name or a loop bound,
//! made before anything is written (exit 2 with the item and a hint): names short
//! enough for the file system, segment counts the model can build, lengths whose
//! conversion to metres stays physical.

use strand_case::{Case, LengthUnit};

use crate::error::{Result, StudyError};

/// Longest name, bytes, of a case, rod, section, junction, connector or variant: it
/// becomes a file or folder name (`<rod>.csv`, `out/<case>/<variant>/`, batch ids),
/// and file systems allow 255 bytes per name.
pub const MAX_NAME_BYTES: usize = 200;

/// Most segments of one rod (in the case file, `--segments` or a batch's
/// `--vary <rod>.segments`): at 100 000 a three-hose case takes ~4 s and ~1 GB to
/// build, before any solve.
pub const MAX_SEGMENTS: usize = 100_000;

/// Longest rod, m (1000 km): beyond, the model's numbers lose their meaning.
pub const MAX_LENGTH_M: f64 = 1e6;

/// `name` shortened for a message.
pub fn shown(name: &str) -> String {
    if name.chars().count() <= 40 {
        name.to_string()
    } else {
        format!("{}…", name.chars().take(40).collect::<String>())
    }
}

fn invalid(message: String) -> StudyError {
    StudyError::Input(message)
}

/// Checks the names, segment counts and lengths of `case` (see the module docs).
pub fn check_case(case: &Case) -> Result<()> {
    let origin = &case.origin;
    let file = &case.file;
    let long = |kind: &str, name: &str, why: &str| {
        (name.len() > MAX_NAME_BYTES).then(|| {
            invalid(format!(
                "{origin}: {kind} '{}' has a name of {} bytes; at most {MAX_NAME_BYTES} (it becomes {why}) (hint: use a shorter name)",
                shown(name),
                name.len()
            ))
        })
    };
    let named = std::iter::once(("case file", case.name.as_str(), "the output folder's name"))
        .chain(
            file.rods
                .iter()
                .map(|r| ("rod", r.name.as_str(), "a file name, <rod>.csv")),
        )
        .chain(
            file.sections
                .iter()
                .map(|(n, _)| ("section", n.as_str(), "part of messages and ids")),
        )
        .chain(
            file.junctions
                .iter()
                .map(|(n, _)| ("junction", n.as_str(), "part of batch variant ids")),
        )
        .chain(
            file.connectors
                .iter()
                .map(|(n, _)| ("connector", n.as_str(), "part of batch variant ids")),
        )
        .chain(
            file.variants
                .iter()
                .map(|(n, _)| ("variant", n.as_str(), "a folder name")),
        );
    for (kind, name, why) in named {
        if let Some(e) = long(kind, name, why) {
            return Err(e);
        }
    }
    let metres = LengthUnit::parse(&file.units.length).map_or(1.0, |u| u.metres());
    for rod in &file.rods {
        if rod.segments > MAX_SEGMENTS {
            return Err(invalid(format!(
                "{origin}: rods.{}.segments: {} segments; at most {MAX_SEGMENTS} per rod (building the model is quadratic in them) (hint: use fewer segments)",
                shown(&rod.name),
                rod.segments
            )));
        }
        // NaN and infinite lengths are the case validation's (it names their line);
        // here: finite values that are, or overflow to, beyond any rod.
        if let Some(length) = rod.length
            && length.is_finite()
            && !(length * metres).abs().le(&MAX_LENGTH_M)
        {
            return Err(invalid(format!(
                "{origin}: rods.{}.length: {length:e} {} is beyond {MAX_LENGTH_M:e} m (hint: check the value and units.length)",
                shown(&rod.name),
                file.units.length
            )));
        }
    }
    Ok(())
}

/// [`check_case`] for tools and tests outside the crate: the message of the first
/// problem, if any.
pub fn case_problem(case: &Case) -> Option<String> {
    check_case(case).err().map(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn case(text: &str) -> Case {
        Case::from_str(text, "cases/x.ron").unwrap()
    }

    #[test]
    fn long_names_many_segments_and_huge_lengths_are_named() {
        let text = std::fs::read_to_string(
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../cases/elastica_fig2.ron"),
        )
        .unwrap();
        assert!(check_case(&case(&text)).is_ok());
        let first_rod = text
            .split("name: \"")
            .nth(1)
            .unwrap()
            .split('"')
            .next()
            .unwrap();
        let long = "r".repeat(10_000);
        let e = check_case(&case(&text.replacen(
            &format!("name: \"{first_rod}\""),
            &format!("name: \"{long}\""),
            1,
        )))
        .unwrap_err();
        assert!(
            e.to_string()
                .contains("has a name of 10000 bytes; at most 200"),
            "{e}"
        );
        assert_eq!(e.kind(), crate::ErrorKind::Input);
        let e = check_case(&case(&text.replacen(
            "segments: 19",
            "segments: 1000000",
            1,
        )))
        .unwrap_err();
        assert!(
            e.to_string()
                .contains("segments: 1000000 segments; at most 100000"),
            "{e}"
        );
        let e =
            check_case(&case(&text.replacen("length: 1000,", "length: 1e300,", 1))).unwrap_err();
        assert!(e.to_string().contains("length: 1e300 mm is beyond"), "{e}");
    }
}

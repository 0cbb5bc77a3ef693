//! Centrelines from CAD files: a rod's `nominal` shape (or its `route`) as a CSV of
//! points or as an OBJ polyline.
//!
//! ```ron
//! nominal: (file: "hose1.csv"),                                // x_mm,y_mm,z_mm header
//! nominal: (file: "routes.obj", object: "hose1", unit: "mm"),  // `l` elements of `o hose1`
//! route_file: (file: "routes.obj", object: "hose1_route", unit: "mm"),
//! ```
//!
//! **CSV.** Blank lines and lines starting with `#` are skipped. The first other line is
//! the header: three columns `x`, `y`, `z` naming their unit, as `x_mm`, `x [mm]`,
//! `x (mm)` or `x/mm` (`mm` or `m`, the same for all three). Every further line holds
//! the three coordinates of one point, separated by commas, semicolons or tabs.
//!
//! **OBJ polyline.** The `l` elements of the object (`o name` or `g name`) named by
//! `object`, in file order, joined end to start into one polyline (CAD systems write one
//! `l` per segment or one `l` for the whole line; `l 1/1 2/2` texture indices are
//! ignored, negative indices count back from the last vertex). OBJ has no unit: give
//! `unit`.
//!
//! Paths are relative to the case file's folder. Errors name the case file, the field,
//! the centreline file and its line.

use std::path::Path;

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::error::{CaseError, Reporter};
use crate::units::LengthUnit;

/// A centreline in a file: `(file: "routes.obj", object: "hose1", unit: "mm")`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CentrelineFileDef {
    /// The CSV or OBJ file, relative to the case file's folder (or absolute).
    pub file: String,
    /// For an OBJ file: the name of the object (`o`/`g`) whose `l` elements form the
    /// centreline.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub object: Option<String>,
    /// For an OBJ file: the unit of its coordinates, `"mm"` or `"m"` (a CSV file names
    /// its unit in its header).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub unit: Option<String>,
}

/// The points (m) of the centreline in `def`; `item` is the field, e.g.
/// `rods[0] 'hose'.nominal`.
pub(crate) fn read_centreline(
    report: &Reporter,
    item: &str,
    def: &CentrelineFileDef,
) -> Result<Vec<Vector3<f64>>, CaseError> {
    let folder = Path::new(report.origin)
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_default();
    let path = folder.join(&def.file);
    let field = format!("{item}.file");
    let text = std::fs::read_to_string(&path).map_err(|e| {
        report.invalid(
            &field,
            format!("cannot read the centreline file {}: {e}", path.display()),
            "check the path (relative paths are resolved against the case file's folder)",
        )
    })?;
    let is_obj = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("obj"));
    let failure = |line: usize, problem: String, hint: &str| {
        let at = if line > 0 {
            format!(":{line}")
        } else {
            String::new()
        };
        report.invalid(&field, format!("{}{at}: {problem}", path.display()), hint)
    };
    let points = if is_obj {
        let unit = match def.unit.as_deref().map(|u| (u, LengthUnit::parse(u))) {
            Some((_, Some(unit))) => unit,
            Some((u, None)) => {
                return Err(report.invalid(
                    format!("{item}.unit"),
                    format!("unknown length unit \"{u}\""),
                    format!(
                        "use {} (the unit of the OBJ file's coordinates)",
                        LengthUnit::ACCEPTED
                    ),
                ));
            }
            None => {
                return Err(report.invalid(
                    format!("{item}.unit"),
                    format!("missing `unit` for the OBJ file {}", path.display()),
                    "OBJ files carry no unit: add `unit: \"mm\"` (or \"m\")",
                ));
            }
        };
        let Some(object) = def.object.as_deref() else {
            return Err(report.invalid(
                format!("{item}.object"),
                format!("missing `object` for the OBJ file {}", path.display()),
                "name the object (`o name` in the file) whose `l` elements are the centreline",
            ));
        };
        obj_polyline(&text, object)
            .map_err(|(line, problem, hint)| failure(line, problem, hint))?
            .into_iter()
            .map(|p| p * unit.metres())
            .collect()
    } else {
        if def.unit.is_some() || def.object.is_some() {
            return Err(report.invalid(
                &field,
                format!(
                    "{} is read as CSV: `unit` and `object` are for OBJ files only",
                    path.display()
                ),
                "remove `unit` and `object` (a CSV file names its unit in its header, e.g. \
                 x_mm,y_mm,z_mm), or give an .obj file",
            ));
        }
        csv_points(&text).map_err(|(line, problem, hint)| failure(line, problem, hint))?
    };
    Ok(points)
}

/// A problem in a centreline file: line (1-based, 0 for the whole file), what, hint.
type Problem = (usize, String, &'static str);

const CSV_HINT: &str = "write a header naming the unit (x_mm,y_mm,z_mm) and then one point \
                        per line (x,y,z)";

/// The points of a CSV centreline, in m.
fn csv_points(text: &str) -> Result<Vec<Vector3<f64>>, Problem> {
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(k, l)| (k + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
    let split = |l: &str| -> Vec<String> {
        l.split([',', ';', '\t'])
            .map(|w| w.trim().to_string())
            .collect()
    };
    let Some((header_line, header)) = lines.next() else {
        return Err((0, "the file holds no header and no points".into(), CSV_HINT));
    };
    let columns = split(header);
    let units: Vec<Option<LengthUnit>> = columns.iter().map(|c| column_unit(c)).collect();
    let unit = match units.as_slice() {
        [Some(a), Some(b), Some(c)] if a == b && b == c => *a,
        _ => {
            return Err((
                header_line,
                format!(
                    "the header `{header}` does not name one length unit for the three columns \
                     x, y, z"
                ),
                CSV_HINT,
            ));
        }
    };
    let mut points = Vec::new();
    for (line, row) in lines {
        let values: Vec<Option<f64>> = split(row).iter().map(|w| w.parse().ok()).collect();
        match values.as_slice() {
            [Some(x), Some(y), Some(z)] => {
                let p = Vector3::new(*x, *y, *z);
                if !p.iter().all(|v| v.is_finite()) {
                    return Err((
                        line,
                        format!("the point `{row}` is not finite"),
                        "replace NaN/inf by numbers",
                    ));
                }
                points.push(p * unit.metres());
            }
            _ => {
                return Err((
                    line,
                    format!("expected three numbers x, y, z, found `{row}`"),
                    CSV_HINT,
                ));
            }
        }
    }
    Ok(points)
}

/// The unit named by a CSV column header such as `x_mm`, `x [mm]`, `x (mm)`, `x/mm`.
fn column_unit(column: &str) -> Option<LengthUnit> {
    let rest = column.trim().get(1..)?.trim();
    let unit = rest
        .trim_start_matches(['_', '/', '[', '(', ' '])
        .trim_end_matches([']', ')', ' ']);
    if unit.len() == rest.len() {
        return None;
    }
    LengthUnit::parse(unit.trim())
}

/// The polyline (file units) of the `l` elements of object `object` in OBJ text.
fn obj_polyline(text: &str, object: &str) -> Result<Vec<Vector3<f64>>, Problem> {
    let mut vertices: Vec<Vector3<f64>> = Vec::new();
    let mut current = String::new();
    let mut objects: Vec<String> = Vec::new();
    let mut chain: Vec<usize> = Vec::new();
    for (k, raw) in text.lines().enumerate() {
        let line = k + 1;
        let content = raw.split('#').next().unwrap_or("");
        let mut words = content.split_whitespace();
        match words.next() {
            Some("v") => {
                let values: Vec<f64> = words.take(3).filter_map(|w| w.parse().ok()).collect();
                if values.len() != 3 || !values.iter().all(|v| v.is_finite()) {
                    return Err((
                        line,
                        format!("bad vertex `{}`", raw.trim()),
                        "write vertices as `v x y z` with finite numbers",
                    ));
                }
                vertices.push(Vector3::new(values[0], values[1], values[2]));
            }
            Some("o") | Some("g") => {
                current = words.collect::<Vec<_>>().join(" ");
                if !objects.contains(&current) {
                    objects.push(current.clone());
                }
            }
            Some("l") if current == object => {
                let mut element = Vec::new();
                for w in words {
                    let index: i64 = w.split('/').next().unwrap_or("").parse().map_err(|_| {
                        (
                            line,
                            format!("bad vertex index `{w}`"),
                            "write line elements as `l i j ...` with vertex numbers",
                        )
                    })?;
                    let resolved = if index < 0 {
                        vertices.len() as i64 + index
                    } else {
                        index - 1
                    };
                    if resolved < 0 || resolved as usize >= vertices.len() {
                        return Err((
                            line,
                            format!(
                                "vertex index {index} refers to no vertex ({} defined so far)",
                                vertices.len()
                            ),
                            "line elements may only use vertices defined before them",
                        ));
                    }
                    element.push(resolved as usize);
                }
                if element.len() < 2 {
                    return Err((
                        line,
                        "a line element needs at least 2 vertices".into(),
                        "write `l i j ...`",
                    ));
                }
                match chain.last() {
                    None => chain = element,
                    Some(&last) if vertices[last] == vertices[element[0]] => {
                        chain.extend(&element[1..]);
                    }
                    Some(_) => {
                        return Err((
                            line,
                            format!(
                                "this line element does not start where the previous one of \
                                 object '{object}' ends: the polyline is not connected"
                            ),
                            "export the centreline as one connected polyline, its segments in \
                             order from the rod's start to its end",
                        ));
                    }
                }
            }
            _ => {}
        }
    }
    if chain.is_empty() {
        let listed = if objects.is_empty() {
            "none".to_string()
        } else {
            objects.join(", ")
        };
        return Err((
            0,
            format!("object '{object}' has no line elements (`l`); objects in the file: {listed}"),
            "name the object holding the centreline polyline",
        ));
    }
    Ok(chain.into_iter().map(|i| vertices[i]).collect())
}

#[cfg(test)]
#[path = "centreline_tests.rs"]
mod tests;

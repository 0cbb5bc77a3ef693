//! `DIR/batch.json`: what a batch directory holds — the case (name and a
//! fingerprint of its content), the varied parameters with their values and every
//! variant's id. A re-run (resume), another shard or `strand merge` checks that it
//! works on the same batch; the summary is made from it and the variant files alone.

use std::path::Path;

use serde::{Deserialize, Serialize};
use strand_case::Case;

use super::checksum::fnv1a;
use super::plan::Plan;

/// One varied parameter as recorded.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Parameter {
    /// The `--vary` option as written.
    pub vary: String,
    /// The item as written (`hose2.length`).
    pub label: String,
    /// Unit of the values (`mm`).
    pub unit: String,
    /// The values, in `unit`.
    pub values: Vec<f64>,
    /// The values as written in ids and tables (`+30mm`).
    pub texts: Vec<String>,
    /// Index of the value nearest the case's own.
    pub anchor: usize,
}

/// One variant as recorded.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Entry {
    /// The variant's id (its directory under `variants/`).
    pub id: String,
    /// Value index of every parameter.
    pub index: Vec<usize>,
}

/// The whole `batch.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    /// Case name.
    pub case: String,
    /// The case file as named on the command line (informative; not compared).
    pub origin: String,
    /// Fingerprint of the parsed case file (FNV-1a, hex).
    pub fingerprint: String,
    /// `--segments`, if given.
    pub segments: Option<usize>,
    /// The varied parameters, in `--vary` order.
    pub parameters: Vec<Parameter>,
    /// Every variant, in grid order.
    pub variants: Vec<Entry>,
}

impl Manifest {
    /// The manifest of `plan` on `case`.
    pub fn new(case: &Case, plan: &Plan, segments: Option<usize>) -> Self {
        let content = serde_json::to_vec(&case.file).unwrap_or_default();
        Self {
            case: case.name.clone(),
            origin: case.origin.clone(),
            fingerprint: fnv1a(&content),
            segments,
            parameters: plan
                .varies
                .iter()
                .map(|v| Parameter {
                    vary: v.text.clone(),
                    label: v.label.clone(),
                    unit: v.unit.clone(),
                    values: v.values.clone(),
                    texts: (0..v.values.len()).map(|k| v.value_text(k)).collect(),
                    anchor: v.anchor(),
                })
                .collect(),
            variants: plan
                .variants
                .iter()
                .map(|v| Entry {
                    id: v.id.clone(),
                    index: v.index.clone(),
                })
                .collect(),
        }
    }

    /// Whether `other` describes the same batch (the case's path may differ).
    pub fn same_batch(&self, other: &Manifest) -> bool {
        Manifest {
            origin: String::new(),
            ..self.clone()
        } == Manifest {
            origin: String::new(),
            ..other.clone()
        }
    }

    /// The batch's identity: FNV-1a of the manifest without the case's path (what
    /// [`Manifest::same_batch`] compares), as held in the directory's lock files.
    pub fn identity(&self) -> String {
        let bare = Manifest {
            origin: String::new(),
            ..self.clone()
        };
        fnv1a(&serde_json::to_vec(&bare).unwrap_or_default())
    }

    /// Reads `DIR/batch.json` (`Ok(None)` if there is none).
    pub fn read(dir: &Path) -> Result<Option<Self>, String> {
        let path = dir.join("batch.json");
        match std::fs::read_to_string(&path) {
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
            Err(e) => Err(format!("cannot read {}: {e}", path.display())),
            Ok(text) => serde_json::from_str(&text).map(Some).map_err(|e| {
                format!(
                    "{} is not a batch manifest ({e}); it is written by `strand batch`",
                    path.display()
                )
            }),
        }
    }

    /// One line naming the batch, for messages.
    pub fn describe(&self) -> String {
        let varies: Vec<&str> = self.parameters.iter().map(|p| p.vary.as_str()).collect();
        format!(
            "case '{}' ({}), --vary {}, {} variants",
            self.case,
            self.origin,
            varies.join(" --vary "),
            self.variants.len()
        )
    }
}

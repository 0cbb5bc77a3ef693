//! # strand-case
//!
//! Case files: one RON file describes a system (units, sections, rods with their ends,
//! loads and route hints, gravity, solver settings). This crate parses it
//! ([`schema`]), validates it and converts every length to m, and builds the
//! [`strand_system::Model`] to solve ([`BuiltCase`]). It never prints: every problem is
//! a typed [`CaseError`] whose message names the file, the `line:column` of a syntax
//! or type error or the item path of a semantic error (`rods[0] 'hose'.length`), and a
//! hint how to fix it.
//!
//! ```ron
//! (
//!     units: (length: "mm"),
//!     sections: { "paper": Explicit(ea: 30e3, ga: 10e3, ei: 1, gj: 1, mass_per_length: 0) },
//!     rods: [(
//!         name: "rod", section: "paper", length: 1000, segments: 19,
//!         start: Clamp(position: (0, 0, 0), tangent: (1, 0, 0), normal: (0, 1, 0)),
//!         end: Free(force: (2, 1, 0)),
//!     )],
//!     gravity: (0, 0, 0),
//! )
//! ```
//!
//! Named variants of the case (`variants: { "longer": [(item: "rods.hose.length",
//! change: Add(50))] }`) are built with [`Case::build_variant`]; [`warm_start`] carries
//! a solution of the case onto a variant's model.
//!
//! Named `connectors` (nozzles fixed in space) and `junctions` (rigid bodies with
//! ports, free-hanging or mounted) hold rod ends written `Connector("name")`,
//! `ConnectorPin("name")`, `Port("junction", "port")` or `PortPin("junction", "port")`;
//! [`BuiltCase::connector_names`] names the connector reactions.
//!
//! Units: see [`schema`]; `cases/README.md` documents the format for users.

mod attach;
mod build;
pub mod centreline;
mod clearance;
mod clips;
mod design;
mod detour;
mod drape;
mod ends;
mod environment;
mod error;
mod limits;
pub mod motion;
mod nominal;
mod placement;
pub mod schema;
mod sections;
mod solve;
mod start;
mod units;
mod variant;
mod warm;

#[cfg(test)]
mod design_rhs_tests;
#[cfg(test)]
mod design_tests;
#[cfg(test)]
mod shipped_cases;
#[cfg(test)]
mod tests;

use std::path::Path;

use strand_system::SystemState;

pub use build::{BuiltCase, ROUTE_END_TOLERANCE};
pub use design::{AffineLine, CaseDesign, DesignParameter, DesignedCase};
pub use ends::{FrameError, frame_from_tangent_normal};
pub use environment::EnvironmentCache;
pub use error::CaseError;
pub use limits::ConnectorLimit;
pub use nominal::NOMINAL_LENGTH_TOLERANCE;
pub use placement::BodyMove;
pub use schema::CaseFile;
pub use start::Start;
pub use units::{LengthUnit, canonical_decimal};
pub use variant::{
    BASE_VARIANT, ItemError, ItemQuantity, RodEnd, ShortFormError, VARIANT_ITEMS, VariantItem,
    expand_short,
};
pub use warm::{resample_rod_state, warm_start};

/// A parsed (not yet validated) case file with its origin.
#[derive(Clone, Debug, PartialEq)]
pub struct Case {
    /// Case name: the file stem of the origin (`cases/helix_fig4.ron` → `helix_fig4`).
    pub name: String,
    /// The file as named by the user (used in every message).
    pub origin: String,
    /// The file's content.
    pub file: CaseFile,
    /// Environment meshes built so far, shared by clones of the case, its variants
    /// and batch runs (see [`EnvironmentCache`]).
    pub environment: EnvironmentCache,
    /// Environment meshes (by name) that a motion pose moved ([`Case::at_pose`]), with
    /// their rigid map (world, m): every build places them there.
    placed: Vec<(String, nalgebra::Isometry3<f64>)>,
}

impl Case {
    /// Reads and parses a case file.
    pub fn from_path(path: impl AsRef<Path>) -> Result<Self, CaseError> {
        let path = path.as_ref();
        let origin = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|source| {
            let hint = match source.kind() {
                std::io::ErrorKind::NotFound => {
                    "check the path (case files live in cases/ and end in .ron)"
                }
                std::io::ErrorKind::InvalidData => "save the file as UTF-8 text",
                _ => "check that the file exists and is readable",
            };
            CaseError::Read {
                origin: origin.clone(),
                source,
                hint: hint.to_string(),
            }
        })?;
        Self::from_str(&text, &origin)
    }

    /// Parses case text; `origin` names it in messages and gives the case name.
    pub fn from_str(text: &str, origin: &str) -> Result<Self, CaseError> {
        let options = ron::Options::default()
            .with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME);
        let file: CaseFile = options
            .from_str(text)
            .map_err(|e| CaseError::from_ron(origin, &e))?;
        let name = Path::new(origin)
            .file_stem()
            .and_then(|s| s.to_str())
            .filter(|s| !s.is_empty())
            .unwrap_or("case");
        Ok(Self {
            name: name.to_string(),
            origin: origin.to_string(),
            file,
            environment: EnvironmentCache::default(),
            placed: Vec::new(),
        })
    }

    /// Validates the case and builds the model; `segments` overrides the number of
    /// segments of every rod (e.g. for convergence studies).
    pub fn build(&self, segments: Option<usize>) -> Result<BuiltCase, CaseError> {
        self.build_file(&self.file, segments, build::BuildExtras::default())
    }

    /// Builds `file` (this case's file, changed) with the case's name, origin and
    /// environment cache.
    pub(crate) fn build_file<'a>(
        &'a self,
        file: &CaseFile,
        segments: Option<usize>,
        mut extras: build::BuildExtras<'a>,
    ) -> Result<BuiltCase, CaseError> {
        if extras.moved_meshes.is_empty() {
            extras.moved_meshes = &self.placed;
        }
        build::build(
            &self.name,
            &self.origin,
            file,
            segments,
            &self.environment,
            extras,
        )
    }

    /// The names of the case's variants, in file order.
    pub fn variant_names(&self) -> Vec<&str> {
        self.file.variants.iter().map(|(n, _)| n.as_str()).collect()
    }

    /// The case file with variant `name` applied (see `cases/README.md`, Variants).
    /// An unknown variant is an error listing the defined ones; an unknown item or a
    /// change that does not fit its item is an error naming the variant and the item.
    pub fn variant_file(&self, name: &str) -> Result<CaseFile, CaseError> {
        let report = error::Reporter {
            origin: &self.origin,
        };
        variant::apply(&report, &self.file, name)
    }

    /// The case with its named variant `name` applied to its file (see
    /// [`Case::variant_file`]), not yet validated: same name, origin, environment
    /// cache and motion pose. [`Case::build_variant`] builds it with the build's
    /// errors naming the variant.
    pub fn with_variant(&self, name: &str) -> Result<Case, CaseError> {
        Ok(Case {
            name: self.name.clone(),
            origin: self.origin.clone(),
            file: self.variant_file(name)?,
            environment: self.environment.clone(),
            placed: self.placed.clone(),
        })
    }

    /// Validates variant `name` of the case and builds its model, like [`Case::build`]
    /// (`segments` overrides every rod's number of segments, the variant's included).
    /// Errors in the changed file name the variant.
    pub fn build_variant(
        &self,
        name: &str,
        segments: Option<usize>,
    ) -> Result<BuiltCase, CaseError> {
        let file = self.variant_file(name)?;
        self.build_file(&file, segments, build::BuildExtras::default())
            .map_err(|e| variant::in_variant(e, name))
    }

    /// The case file with `changes` applied (items and changes as under `variants`;
    /// not yet validated: [`Case::build_with_changes`] validates and builds it);
    /// `label` names the changes in messages.
    pub fn file_with_changes(
        &self,
        label: &str,
        changes: &[schema::VariantChange],
    ) -> Result<CaseFile, CaseError> {
        let report = error::Reporter {
            origin: &self.origin,
        };
        variant::apply_changes(&report, &self.file, label, changes)
    }

    /// Validates the case with `changes` applied (items and changes as under
    /// `variants`, see [`VARIANT_ITEMS`]) and builds its model, like
    /// [`Case::build_variant`] for an unnamed variant: `label` names the changes in
    /// messages (e.g. the batch variant's id). The case's own named variants are not
    /// involved.
    pub fn build_with_changes(
        &self,
        label: &str,
        changes: &[schema::VariantChange],
        segments: Option<usize>,
    ) -> Result<BuiltCase, CaseError> {
        let file = self.file_with_changes(label, changes)?;
        self.build_file(&file, segments, build::BuildExtras::default())
            .map_err(|e| variant::in_variant(e, label))
    }

    /// The case with `changes` applied to its file (items and changes as under
    /// `variants`, see [`VARIANT_ITEMS`]), not yet validated: same name, origin and
    /// environment cache. `label` names the changes in messages. Use it to run a batch
    /// or study on a changed case; [`Case::build_with_changes`] builds it with the
    /// build's errors naming `label` too.
    pub fn with_changes(
        &self,
        label: &str,
        changes: &[schema::VariantChange],
    ) -> Result<Case, CaseError> {
        Ok(Case {
            name: self.name.clone(),
            origin: self.origin.clone(),
            file: self.file_with_changes(label, changes)?,
            environment: self.environment.clone(),
            placed: self.placed.clone(),
        })
    }

    /// [`Case::build_with_changes`] for one of many nearby builds of a design (the
    /// steps of a sensitivity): its `initial` is `initial` (a state of the same rods
    /// and segments, e.g. the base build's), not computed again nor checked against
    /// the environment — computing the hanging guess is most of a build's time. Where
    /// an end carries a moment, whose potential is measured from the guess's end
    /// frame, the guess is still computed for that (as for a warm-started motion
    /// pose). With `clip_vertices` (the rod vertex of every clip, in clip order, e.g.
    /// the base build's), each clip on a straight rod keeps its vertex while the clips
    /// stay in order: moving a clip along its rod then stretches the edges on either
    /// side instead of changing the mesh. With `like` (a model of the same case, e.g.
    /// the base build's), the model reuses its symbolic phase where the rods,
    /// segments, bodies and clips are the same ([`strand_system::Model::try_new_like`]:
    /// the same model, built faster).
    pub fn build_with_changes_reusing(
        &self,
        label: &str,
        changes: &[schema::VariantChange],
        initial: &SystemState,
        clip_vertices: Option<&[usize]>,
        like: Option<&strand_system::Model>,
    ) -> Result<BuiltCase, CaseError> {
        let file = self.file_with_changes(label, changes)?;
        let extras = build::BuildExtras {
            warm: Some(initial),
            clip_vertices,
            like,
            ..build::BuildExtras::default()
        };
        self.build_file(&file, None, extras)
            .map_err(|e| variant::in_variant(e, label))
    }

    /// [`Case::build_with_changes`] for a variant that will be solved from a start of
    /// its own (a batch variant warm-started from its solved neighbour): no default
    /// guess is computed or checked against the environment, `initial` is `placeholder`
    /// (e.g. the neighbour's state; the caller solves from its own start), and with
    /// `like` (e.g. the neighbour's model) the model reuses its symbolic phase where
    /// the structure is the same. The model is the one [`Case::build_with_changes`]
    /// builds; a cold solve needs that build's `initial` instead.
    pub fn build_with_changes_for_start(
        &self,
        label: &str,
        changes: &[schema::VariantChange],
        segments: Option<usize>,
        placeholder: &SystemState,
        like: Option<&strand_system::Model>,
    ) -> Result<BuiltCase, CaseError> {
        let file = self.file_with_changes(label, changes)?;
        let extras = build::BuildExtras {
            warm: Some(placeholder),
            like,
            ..build::BuildExtras::default()
        };
        self.build_file(&file, segments, extras)
            .map_err(|e| variant::in_variant(e, label))
    }
}

//! A case as a parameterised [`Design`] for [`strand_solve::sensitivity`]: each
//! parameter is a variant item (`rods.hose2.length`, `connectors.oil_cooler.position`
//! with a component, `junctions.tee.mass`, `gravity`, …; see [`crate::VARIANT_ITEMS`])
//! changed by an offset in the item's own unit (the case's length unit, kg, N, m/s²).
//!
//! ```no_run
//! use strand_case::{Case, CaseDesign, DesignParameter};
//! let case = Case::from_path("cases/cooler_hose.ron").unwrap();
//! let design = CaseDesign::new(&case, vec![DesignParameter {
//!     item: "rods.hose2.length".into(),
//!     component: None,
//!     scale: 1000.0, // 1 m in mm
//! }]);
//! ```

use strand_solve::Constraints;
use strand_solve::contact::Contact;
use strand_solve::sensitivity::{Design, Designed};
use strand_system::Model;

use crate::schema::{Amount, Change, VariantChange};
use crate::{BuiltCase, Case, CaseError};

/// One parameter of a [`CaseDesign`].
#[derive(Clone, Debug, PartialEq)]
pub struct DesignParameter {
    /// The variant item, e.g. `rods.hose2.length` (see [`crate::VARIANT_ITEMS`]).
    pub item: String,
    /// For a vector item, the component (0, 1, 2 for x, y, z).
    pub component: Option<usize>,
    /// The parameter's typical size in the item's unit (the difference steps are a
    /// small fraction of it): e.g. 1000 for a length in mm, 1 for a mass in kg.
    pub scale: f64,
}

/// A case whose parameters are variant items, offset from the case's values.
#[derive(Clone, Debug)]
pub struct CaseDesign<'c> {
    case: &'c Case,
    parameters: Vec<DesignParameter>,
    /// Offsets of the design's zero from the case's values (item units).
    centre: Vec<f64>,
    /// The first build's initial state and clip vertices, reused by the later builds
    /// (their guesses are never used: the steps start from the base equilibrium; the
    /// clips stay on the base's vertices, so a clip moved along its rod keeps the
    /// mesh).
    initial: std::sync::OnceLock<(strand_system::SystemState, Vec<usize>)>,
}

impl<'c> CaseDesign<'c> {
    /// The design of `case` over `parameters`.
    pub fn new(case: &'c Case, parameters: Vec<DesignParameter>) -> Self {
        let centre = vec![0.0; parameters.len()];
        Self {
            case,
            parameters,
            centre,
            initial: std::sync::OnceLock::new(),
        }
    }

    /// The design of `case` over `parameters` whose zero offsets are `centre` (one per
    /// parameter, item units) from the case's values: the design an optimiser
    /// differentiates at its current point.
    pub fn centred_at(case: &'c Case, parameters: Vec<DesignParameter>, centre: Vec<f64>) -> Self {
        assert_eq!(
            centre.len(),
            parameters.len(),
            "one centre offset per parameter"
        );
        Self {
            case,
            parameters,
            centre,
            initial: std::sync::OnceLock::new(),
        }
    }

    /// The case.
    pub fn case(&self) -> &'c Case {
        self.case
    }

    /// The parameters.
    pub fn parameters(&self) -> &[DesignParameter] {
        &self.parameters
    }

    /// The variant changes that offset every parameter by `offsets` (item units) from
    /// the design's centre.
    pub fn changes(&self, offsets: &[f64]) -> Vec<VariantChange> {
        self.parameters
            .iter()
            .zip(offsets.iter().zip(&self.centre).map(|(x, c)| x + c))
            .filter(|(_, x)| *x != 0.0)
            .map(|(p, x)| VariantChange {
                item: p.item.clone(),
                change: Change::Add(match p.component {
                    None => Amount::Number(x),
                    Some(c) => {
                        let mut v = [0.0; 3];
                        v[c] = x;
                        Amount::Vector(v)
                    }
                }),
            })
            .collect()
    }
}

/// A built case with its contact constraints.
pub struct DesignedCase {
    /// The built case.
    pub built: BuiltCase,
    /// Contact with its environment, if it has one.
    pub contact: Option<Contact>,
}

impl DesignedCase {
    /// Wraps a built case with its contact.
    pub fn new(built: BuiltCase) -> Self {
        let contact = built.contact();
        Self { built, contact }
    }
}

impl Designed for DesignedCase {
    fn model(&self) -> &Model {
        &self.built.model
    }
    fn constraints(&self) -> Option<&dyn Constraints> {
        self.contact.as_ref().map(|c| c as &dyn Constraints)
    }
}

impl Design for CaseDesign<'_> {
    type Built = DesignedCase;
    type Error = CaseError;

    fn parameter_count(&self) -> usize {
        self.parameters.len()
    }

    fn step(&self, parameter: usize) -> f64 {
        self.parameters[parameter].scale
    }

    /// The first build computes the case's initial guess; later builds reuse it and
    /// keep its clip vertices ([`Case::build_with_changes_reusing`]): a design is
    /// built many times at small offsets, its guesses are never solved from, and its
    /// mesh must not change with a clip's station (an edge handed from one piece to
    /// the next where the allocation ties would make the model jump).
    fn build(&self, offsets: &[f64]) -> Result<DesignedCase, CaseError> {
        let changes = self.changes(offsets);
        let built = match self.initial.get() {
            Some((initial, clip_vertices)) => self.case.build_with_changes_reusing(
                "sensitivity",
                &changes,
                initial,
                Some(clip_vertices),
            )?,
            None if changes.is_empty() => self.case.build(None)?,
            None => self
                .case
                .build_with_changes("sensitivity", &changes, None)?,
        };
        let _ = self.initial.get_or_init(|| {
            let vertices = built
                .model
                .system()
                .clips
                .iter()
                .map(|c| c.vertex)
                .collect();
            (built.initial.clone(), vertices)
        });
        Ok(DesignedCase::new(built))
    }
}

//! Inequality constraints of the minimisation, linearised at an iterate: joint limits
//! and (through [`Constraints`]) contact. Each is a row `value + Σ_k gradient_k d_k ≥ 0`
//! in the step `d`; its multiplier is the force (N) or moment (N·m) that holds it.

use nalgebra::DMatrix;
use strand_system::{HessianPattern, Model, SystemState};

/// Why a state is not admissible for the inequality constraints (contact), with the
/// rod and obstacle names and lengths in mm, as the user reads them.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ConstraintError {
    /// A rod's centreline passes through an obstacle's surface or another centreline
    /// (no normal: the gap is undefined).
    #[error(
        "rod '{rod}' {what}: its centreline passes through ({:.1}, {:.1}, {:.1}) mm",
        .point_mm[0], .point_mm[1], .point_mm[2]
    )]
    CentrelineTouches {
        /// The rod's name.
        rod: String,
        /// What it touches, e.g. `touches mesh 'bracket'` or `edge 4 crosses rod 1 edge 2`.
        what: String,
        /// Where, mm.
        point_mm: [f64; 3],
    },
    /// A rod starts with its centreline through an obstacle's surface or another
    /// centreline (found by the start check: [`Constraints::check_start`]).
    #[error(
        "rod '{rod}' starts with its centreline through an obstacle ({what}) at ({:.1}, \
         {:.1}, {:.1}) mm\n  hint: {hint}",
        .point_mm[0], .point_mm[1], .point_mm[2]
    )]
    StartsThrough {
        /// The rod's name.
        rod: String,
        /// What it passes through, e.g. `edge 4 touches mesh 'bracket'`.
        what: String,
        /// Where, mm.
        point_mm: [f64; 3],
        /// What to change.
        hint: StartHint,
    },
    /// A rod starts overlapping an obstacle or another rod.
    #[error(
        "rod '{rod}' starts inside {kind} '{obstacle}': the hose surface overlaps it by \
         {overlap_mm:.3} mm at s = {s_mm:.1} mm, centreline point ({:.1}, {:.1}, {:.1}) mm\n  \
         hint: {hint}",
        .point_mm[0], .point_mm[1], .point_mm[2]
    )]
    StartsOverlapping {
        /// The rod's name.
        rod: String,
        /// `mesh` or `rod`.
        kind: &'static str,
        /// The obstacle's name.
        obstacle: String,
        /// Depth of the overlap, mm.
        overlap_mm: f64,
        /// Arc length of the deepest point, mm.
        s_mm: f64,
        /// The deepest centreline point, mm.
        point_mm: [f64; 3],
        /// What to change.
        hint: StartHint,
    },
    /// A rod starts inside a closed mesh.
    #[error(
        "rod '{rod}' starts inside mesh '{mesh}': its centreline is enclosed by the closed \
         mesh at s = {s_mm:.1} mm, centreline point ({:.1}, {:.1}, {:.1}) mm\n  hint: {hint}",
        .point_mm[0], .point_mm[1], .point_mm[2]
    )]
    StartsEnclosed {
        /// The rod's name.
        rod: String,
        /// The mesh's name.
        mesh: String,
        /// Arc length of the first enclosed vertex, mm.
        s_mm: f64,
        /// That vertex, mm.
        point_mm: [f64; 3],
        /// What to change.
        hint: StartHint,
    },
    /// Any other failure of the gap computation (e.g. an invalid margin).
    #[error(transparent)]
    Gaps(#[from] strand_contact::GapError),
}

impl ConstraintError {
    /// The rod a start error names and its hint (`None` for the other errors).
    pub fn start_hint_mut(&mut self) -> Option<(&str, &mut StartHint)> {
        match self {
            ConstraintError::StartsThrough { rod, hint, .. }
            | ConstraintError::StartsOverlapping { rod, hint, .. }
            | ConstraintError::StartsEnclosed { rod, hint, .. } => Some((rod, hint)),
            _ => None,
        }
    }
}

/// What a user changes when a rod starts inside an obstacle: it depends on whether
/// the start is the rod's own `route` or the solver's guess.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum StartHint {
    /// The rod has a route: move it (or the supports, or the obstacle).
    MoveRoute,
    /// The rod has no route: the start is the solver's guess (hanging, bowed, arched,
    /// straight between the ends or, dangling, draped), none of which clears; a route
    /// chooses the way.
    GiveRoute,
    /// An end of the rod is held inside the part: no route can help.
    MoveSupport,
    /// An end of the rod is held closer to the part than the hose's radius: its
    /// surface overlaps the part whatever the route.
    EndOverlaps,
    /// An end of the rod is held at a port of a free junction whose given `position`
    /// (only the guess of where it hangs) puts the end inside the part or within the
    /// hose's radius of it, and no start from a clear place nearby cleared either.
    MoveJunction,
    /// The rod has no route and its stretch between two stations (held ends and
    /// clips) is shorter than the shortest way around the parts found between them.
    Lengthen(Box<WayAround>),
}

/// A stretch of a rod between two stations (held ends and clips) and the shortest way
/// around the parts found between them ([`StartHint::Lengthen`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct WayAround {
    /// Arc length (mm, rounded) where the stretch starts.
    pub from_s_mm: u32,
    /// Arc length (mm, rounded) where it ends.
    pub to_s_mm: u32,
    /// The shortest way found between its stations (mm, rounded up), leaving and
    /// reaching them along their clamps and clips.
    pub way_mm: u32,
}

impl std::fmt::Display for StartHint {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            StartHint::Lengthen(way) => {
                let WayAround {
                    from_s_mm,
                    to_s_mm,
                    way_mm,
                } = **way;
                let stretch = to_s_mm.saturating_sub(from_s_mm);
                return write!(
                    f,
                    "the rod has no `route`, and no start the solver guesses clears the \
                     obstacles: between s = {from_s_mm} mm and s = {to_s_mm} mm (its ends or \
                     clips there) the shortest way around the parts the solver finds is \
                     about {way_mm} mm, {} mm more than the rod's {stretch} mm there: \
                     lengthen the rod there (its `length`, or a clip's `at`), move its \
                     supports or clips, or give the rod a `route` (a list of points, or \
                     `route_file`) that passes clear of the parts",
                    way_mm.saturating_sub(stretch)
                );
            }
            StartHint::MoveRoute => {
                "move the rod's `route`, supports or the obstacle so that the hose starts \
                 clear of it"
            }
            StartHint::GiveRoute => {
                "the rod has no `route`, and no start the solver guesses (hanging, bowed \
                 sideways or up, straight between the ends, a dangling end draped over the \
                 parts, the shortest way around the parts within the rod's length) clears \
                 the obstacles: give the rod a `route` (a list of points, or `route_file`) \
                 that passes clear of them, or move its supports or the obstacle (a longer \
                 rod may find a way around them)"
            }
            StartHint::MoveSupport => {
                "the rod's end is held there, inside the part: move its connector, pin, \
                 clamp or port, or the part, so that the end lies outside it"
            }
            StartHint::EndOverlaps => {
                "the rod's end is held there, closer to the part than the hose's radius, \
                 so no route clears it: move its connector, pin, clamp or port, or the \
                 part, so that the hose's end clears the part"
            }
            StartHint::MoveJunction => {
                "the rod's end is held there by a port of a free junction, whose \
                 `position` (the guess of where it hangs) puts it inside or against the \
                 part, and no start from a clear place near it clears the obstacles: give \
                 the junction a `position` clear of the parts, or the rods a `route`"
            }
        })
    }
}

/// Identifies a constraint across iterates, so its multiplier carries over.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum RowKey {
    /// The lower (`upper == false`) or upper stop of clip `clip`'s joint.
    Limit {
        /// Clip index.
        clip: usize,
        /// Whether this is the upper stop.
        upper: bool,
    },
    /// A contact pair, numbered by the [`Constraints`] that made it.
    Contact(u64),
}

/// One linearised inequality `value + gradient · d ≥ 0`.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// Identity of the constraint.
    pub key: RowKey,
    /// Constraint value at the iterate (a gap in m, or a joint's distance to its stop
    /// in rad or m).
    pub value: f64,
    /// Sparse gradient with respect to the unknowns: `(unknown index, ∂value/∂d)`.
    pub gradient: Vec<(usize, f64)>,
    /// Second derivatives of the value with respect to position unknowns (a contact
    /// gap curved across a ridge, a mesh vertex or another rod); `None` where flat.
    pub curvature: Option<RowCurvature>,
}

/// The second derivatives of a row's value with respect to some position blocks.
#[derive(Clone, Debug, PartialEq)]
pub struct RowCurvature {
    /// The unknown blocks (3 unknowns each), in the order of `hessian`'s 3×3 blocks.
    pub blocks: Vec<usize>,
    /// `∂²value/∂d∂d` over those blocks (symmetric, `3·blocks.len()` square), in the
    /// row's unit per m² (m⁻¹ for a gap).
    pub hessian: DMatrix<f64>,
}

impl RowCurvature {
    /// Adds `factor` times this curvature into the upper-triangular `values` of
    /// `pattern` (pairs of blocks the pattern does not couple, such as two rods in
    /// contact, are left out).
    pub fn add_into(&self, pattern: &HessianPattern, values: &mut [f64], factor: f64) {
        for (a, &block_a) in self.blocks.iter().enumerate() {
            for (b, &block_b) in self.blocks.iter().enumerate() {
                if block_a > block_b {
                    continue;
                }
                let Some(offsets) = pattern.find_offsets(block_a, block_b) else {
                    continue;
                };
                for k in 0..3 {
                    for i in 0..3 {
                        // Upper triangle only (a diagonal block stores rows 0..=k).
                        if block_a == block_b && (a != b || i > k) {
                            continue;
                        }
                        values[offsets[k] + i] += factor * self.hessian[(3 * a + i, 3 * b + k)];
                    }
                }
            }
        }
    }
}

impl Row {
    /// `value + gradient · step`: the linearised constraint after `step`.
    pub fn linearised(&self, step: &[f64]) -> f64 {
        self.value + self.gradient.iter().map(|&(k, a)| a * step[k]).sum::<f64>()
    }
}

/// A rod vertex of a feature whose rows [`Constraints::rows_leaving_far`] left out: the
/// feature's gaps are all above `clearance_m`, so its rows cannot be active in a step
/// that moves the vertex (to first order) by less than that.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FarVertex {
    /// Rod index.
    pub rod: usize,
    /// Vertex index along the rod.
    pub vertex: usize,
    /// A lower bound of the left-out rows' gaps, m.
    pub clearance_m: f64,
}

/// Inequality constraints beyond joint limits (contact), evaluated at every iterate.
pub trait Constraints: Sync {
    /// Appends the rows at `state`: the constraints that can become active within one
    /// step (e.g. contact pairs within a search margin). `Err` with a message when the
    /// state is not admissible (a centreline passes through an obstacle).
    fn rows(
        &self,
        model: &Model,
        state: &SystemState,
        out: &mut Vec<Row>,
    ) -> Result<(), ConstraintError>;

    /// Appends at least the rows at `state` whose gradients touch only unknowns that
    /// `unknowns` flags (one flag per unknown), each as [`Constraints::rows`] makes
    /// it: for a caller that reads only some rows (the active ones, whose gradients'
    /// unknowns it flags). The default appends every row; an implementation may
    /// search less.
    fn rows_touching(
        &self,
        model: &Model,
        state: &SystemState,
        unknowns: &[bool],
        out: &mut Vec<Row>,
    ) -> Result<(), ConstraintError> {
        let _ = unknowns;
        self.rows(model, state, out)
    }

    /// Whether a row whose gradient touches only unknowns that `unknowns` flags may
    /// differ at `(moved, moved_state)` from the same row at `(model, state)`, in value
    /// or gradient, the unknowns being the same: `false` promises that such rows read
    /// nothing the two differ in (a sensitivity's right-hand side then takes the
    /// active rows' part along a parameter as zero without evaluating them). The
    /// default, `true`, promises nothing.
    fn rows_may_differ(
        &self,
        model: &Model,
        state: &SystemState,
        moved: (&Model, &SystemState),
        unknowns: &[bool],
    ) -> bool {
        let _ = (model, state, moved, unknowns);
        true
    }

    /// [`Constraints::rows`] less the rows of features far from every obstacle: each
    /// left-out feature's vertices are listed in `far` with a lower bound of its gaps.
    /// A step that moves every listed vertex by less than its clearance satisfies the
    /// left-out rows strictly (their linearisation changes by at most the move), so a
    /// QP without them has the same solution; a caller checks that and asks for every
    /// row otherwise. The default leaves nothing out.
    fn rows_leaving_far(
        &self,
        model: &Model,
        state: &SystemState,
        out: &mut Vec<Row>,
        far: &mut Vec<FarVertex>,
    ) -> Result<(), ConstraintError> {
        let _ = far;
        self.rows(model, state, out)
    }

    /// Checks a starting state: `Err` names where it violates a constraint (a hose that
    /// starts inside an obstacle).
    fn check_start(&self, model: &Model, state: &SystemState) -> Result<(), ConstraintError>;

    /// Largest translation of any vertex in one step, m, so that no obstacle outside the
    /// search margin can be reached within one step (for moves whose clearance is not
    /// measured, see [`Constraints::advancement`]).
    fn max_translation_m(&self) -> f64;

    /// The largest multiple of the straight move from `state` to `target` that cannot
    /// reach an obstacle outside the search margin, from the clearance of every moving
    /// part at `state` (conservative advancement; at least what
    /// [`Constraints::max_translation_m`] allows).
    fn advancement(
        &self,
        model: &Model,
        state: &SystemState,
        target: &SystemState,
    ) -> Result<f64, ConstraintError>;
}

/// The joint-limit rows at `state`: `d_i − lower_i ≥ 0` and `upper_i − d_i ≥ 0` for
/// every limited joint (`lower_i`, `upper_i` the stops minus the current value).
pub fn limit_rows(model: &Model, state: &SystemState, out: &mut Vec<Row>) {
    let system = model.system();
    for (clip, spec) in system.clips.iter().enumerate() {
        let (Some((lower, upper)), Some(block)) = (spec.limits, model.dofs().clip(clip)) else {
            continue;
        };
        let index = 3 * block;
        let value = state.clips[clip].value;
        out.push(Row {
            key: RowKey::Limit { clip, upper: false },
            value: value - lower,
            gradient: vec![(index, 1.0)],
            curvature: None,
        });
        out.push(Row {
            key: RowKey::Limit { clip, upper: true },
            value: upper - value,
            gradient: vec![(index, -1.0)],
            curvature: None,
        });
    }
}

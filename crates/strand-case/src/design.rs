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

use std::collections::HashMap;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Mutex, OnceLock};

use strand_solve::Constraints;
use strand_solve::contact::Contact;
use strand_solve::sensitivity::{Design, Designed, ModelLine};
use strand_system::Model;

use crate::schema::{Amount, Change, VariantChange};
use crate::{BuiltCase, Case, CaseError, VariantItem};

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
pub struct CaseDesign<'c> {
    case: &'c Case,
    parameters: Vec<DesignParameter>,
    /// Offsets of the design's zero from the case's values (item units).
    centre: Vec<f64>,
    /// The first build's initial state and clip vertices, reused by the later builds
    /// (their guesses are never used: the steps start from the base equilibrium; the
    /// clips stay on the base's vertices, so a clip moved along its rod keeps the
    /// mesh).
    initial: OnceLock<strand_system::SystemState>,
    /// The clip vertices of the first build, kept by the later ones.
    clip_vertices: OnceLock<Vec<usize>>,
    /// The design at zero offsets, built once, and its model's real numbers.
    base: OnceLock<(DesignedCase, Vec<f64>)>,
    /// Per parameter, how the model's real numbers move per unit of it where they
    /// move affinely ([`along`]), `None` where they do not (full builds then).
    directions: Vec<OnceLock<Option<Vec<f64>>>>,
    /// Full builds through the case builder so far (the work a design avoids).
    full_builds: AtomicUsize,
    /// The designs moved along one affine parameter and not asked for again yet, by
    /// parameter and offset (its bits), up to [`MOVED_KEPT`]: the right-hand sides of
    /// the sensitivities and the outputs' largest difference step visit the same
    /// points (`±h`, `±2h`), so the second visit takes the first one's design (and
    /// a third moves it anew).
    moved: Mutex<HashMap<(usize, u64), DesignedCase>>,
    /// Whether moved designs are kept for a second visit
    /// ([`CaseDesign::keep_moved_designs`]).
    keep_moved: AtomicBool,
}

/// Most designs moved along one parameter that a [`CaseDesign`] keeps (ten
/// parameters' four largest difference steps, and room for their smaller ones).
pub const MOVED_KEPT: usize = 128;

impl std::fmt::Debug for CaseDesign<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CaseDesign")
            .field("case", &self.case.origin)
            .field("parameters", &self.parameters)
            .field("centre", &self.centre)
            .field("full_builds", &self.full_builds())
            .finish_non_exhaustive()
    }
}

impl<'c> CaseDesign<'c> {
    /// The design of `case` over `parameters`.
    pub fn new(case: &'c Case, parameters: Vec<DesignParameter>) -> Self {
        let centre = vec![0.0; parameters.len()];
        Self::centred_at(case, parameters, centre)
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
        let directions = parameters.iter().map(|_| OnceLock::new()).collect();
        Self {
            case,
            parameters,
            centre,
            initial: OnceLock::new(),
            clip_vertices: OnceLock::new(),
            base: OnceLock::new(),
            directions,
            full_builds: AtomicUsize::new(0),
            moved: Mutex::new(HashMap::new()),
            keep_moved: AtomicBool::new(true),
        }
    }

    /// The design whose builds start from `state` (a state of the case's rods and
    /// segments, e.g. its solved equilibrium) instead of computing the case's initial
    /// guess: the steps of a sensitivity never solve from their guess, and computing
    /// it is most of a cold build.
    pub fn starting_from(self, state: &strand_system::SystemState) -> Self {
        let _ = self.initial.set(state.clone());
        self
    }

    /// How many times the design has run the case builder (the base design, the two
    /// probes per parameter of [`Design::build`]'s affine path, and every build that
    /// path does not cover).
    pub fn full_builds(&self) -> usize {
        self.full_builds.load(Ordering::Relaxed)
    }

    /// Whether parameter `parameter` moves the model's real numbers affinely, so that
    /// [`Design::build`] moves the base model along it without the case builder
    /// (probing it with two full builds on first use).
    pub fn is_affine(&self, parameter: usize) -> Result<bool, CaseError> {
        Ok(self.direction(parameter)?.is_some())
    }

    /// The design analysis: builds the base design and probes every parameter (two
    /// full builds each, [`CaseDesign::is_affine`]), so that every later build of an
    /// affine parameter moves the base model. Done once per design; the sensitivities
    /// of an equilibrium then build nothing through the case builder, and
    /// [`CaseDesign::recentred`] carries the probes to the next design point.
    pub fn analyse(&self) -> Result<(), CaseError> {
        for parameter in 0..self.parameters.len() {
            self.direction(parameter)?;
        }
        Ok(())
    }

    /// The design of the same case and parameters centred at `centre` (one offset per
    /// parameter from the case's values, item units), reusing this design's analysis
    /// where it still holds: when every parameter is probed here, the new base has
    /// this base's structure, and its real numbers are this base's moved by
    /// `Σ_j (centre_j − self.centre_j) · direction_j` to [`AFFINE_TOLERANCE`] (the
    /// real numbers are affine along the whole step, not only within the probes; a
    /// parameter that is not affine must not have moved), the probes are taken over
    /// and the new design builds only its base. Otherwise the new design probes
    /// afresh on first use. The new base is built here (one full build, two without a
    /// start, as [`CaseDesign::build`] does at zero offsets).
    pub fn recentred(&self, centre: Vec<f64>) -> Result<CaseDesign<'c>, CaseError> {
        let next = Self::centred_at(self.case, self.parameters.clone(), centre);
        let directions: Option<Vec<Option<&[f64]>>> = self
            .directions
            .iter()
            .map(|d| d.get().map(|d| d.as_deref()))
            .collect();
        let (Some((old, old_reals)), Some(directions)) = (self.base.get(), directions) else {
            return Ok(next);
        };
        let (new, new_reals) = next.base()?;
        let same_structure = new
            .built
            .model
            .system()
            .with_reals(old_reals)
            .ok()
            .is_some_and(|s| &s == old.built.model.system())
            && same_beyond_reals(&old.built, &new.built);
        let mut predicted = old_reals.clone();
        for ((direction, c_new), c_old) in directions.iter().zip(&next.centre).zip(&self.centre) {
            let step = c_new - c_old;
            match direction {
                Some(d) => predicted
                    .iter_mut()
                    .zip(*d)
                    .for_each(|(x, d)| *x += step * d),
                None if step != 0.0 => return Ok(next),
                None => {}
            }
        }
        let on_line = new_reals
            .iter()
            .zip(&predicted)
            .zip(old_reals)
            .all(|((x, p), o)| {
                let size = x.abs().max(p.abs()).max(o.abs());
                (x - p).abs() <= 3.0 * AFFINE_TOLERANCE * size
            });
        if same_structure && on_line && new_reals.len() == predicted.len() {
            for (cell, direction) in next.directions.iter().zip(directions) {
                let _ = cell.set(direction.map(<[f64]>::to_vec));
            }
        }
        Ok(next)
    }

    /// The line along which parameter `parameter` moves the design's model where it
    /// moves it affinely ([`CaseDesign::is_affine`]): the base design (built on first
    /// use), its model's real numbers ([`strand_system::System::reals`]) and their
    /// change per unit of the parameter. The model at offset `t` is the base's with
    /// the real numbers `reals + t · direction`, as [`Design::build`] makes it. `None`
    /// where the parameter is not affine.
    pub fn affine_line(&self, parameter: usize) -> Result<Option<AffineLine<'_>>, CaseError> {
        let Some(direction) = self.direction(parameter)? else {
            return Ok(None);
        };
        let (base, reals) = self.base()?;
        Ok(Some(AffineLine {
            base,
            reals,
            direction,
            moved: nonzero(direction),
        }))
    }

    /// Whether a design moved along one affine parameter is kept for a second visit
    /// at the same offset ([`MOVED_KEPT`]; the default) or dropped after use: a caller
    /// whose outputs are read without building the design at the path's points
    /// (`strand_study`'s local readings) visits each offset once, and keeping would
    /// only copy the designs. Returns the previous setting; turning it off drops the
    /// designs kept.
    pub fn keep_moved_designs(&self, keep: bool) -> bool {
        if !keep && let Ok(mut moved) = self.moved.lock() {
            moved.clear();
        }
        self.keep_moved.swap(keep, Ordering::Relaxed)
    }

    /// Whether every parameter has been probed ([`CaseDesign::analyse`], or taken over
    /// by [`CaseDesign::recentred`]).
    pub fn is_analysed(&self) -> bool {
        self.directions.iter().all(|d| d.get().is_some())
    }

    /// The design at zero offsets (built on first use).
    fn base(&self) -> Result<&(DesignedCase, Vec<f64>), CaseError> {
        if let Some(base) = self.base.get() {
            return Ok(base);
        }
        let zero = vec![0.0; self.parameters.len()];
        let cold = self.initial.get().is_none();
        let mut built = self.full_build(&zero)?;
        if cold {
            // Built like every later build (warm: no guess, so the dead moments'
            // reference frames are the builder's default where no moment acts), so
            // that the probes of a parameter differ from it only where it acts.
            built = self.full_build(&zero)?;
        }
        let reals = built.built.model.system().reals();
        Ok(self.base.get_or_init(|| (built, reals)))
    }

    /// The derivative of the model's real numbers ([`strand_system::System::reals`])
    /// per unit of parameter `parameter`, from full builds at `−h` and `+2h`
    /// (`h` = [`AFFINE_PROBE`] times its scale): `Some` only where the two builds
    /// have the base's structure and environment and their real numbers lie on a line
    /// through the base's to [`AFFINE_TOLERANCE`] (lengths, positions, masses, loads,
    /// stiffnesses — but not a frame's turn, whose quaternion moves on a circle, nor a
    /// mesh position, which is not part of the model).
    fn direction(&self, parameter: usize) -> Result<Option<&[f64]>, CaseError> {
        let cell = &self.directions[parameter];
        if let Some(d) = cell.get() {
            return Ok(d.as_deref());
        }
        let (base, _) = self.base()?;
        let h = AFFINE_PROBE * self.parameters[parameter].scale;
        let at = |t: f64| {
            let mut offsets = vec![0.0; self.parameters.len()];
            offsets[parameter] = t;
            self.full_build(&offsets)
        };
        let (minus, plus) = (at(-h)?, at(2.0 * h)?);
        let direction = affine_direction(base, &minus, &plus, h);
        Ok(cell.get_or_init(|| direction).as_deref())
    }

    /// The design at `offsets` through the case builder.
    fn full_build(&self, offsets: &[f64]) -> Result<DesignedCase, CaseError> {
        self.full_builds.fetch_add(1, Ordering::Relaxed);
        let changes = self.changes(offsets);
        let like = self.base.get().map(|(b, _)| &b.built.model);
        let built = if changes.is_empty() && self.initial.get().is_none() {
            self.case.build(None)?
        } else {
            // Errors name the point (a design's parameters can make the case invalid,
            // e.g. a rod shorter than its ends' distance), not a variant.
            let point = describe(&changes);
            let in_design = |e| crate::variant::in_design(e, &point);
            let file = self
                .case
                .file_with_changes("design", &changes)
                .map_err(in_design)?;
            let extras = crate::build::BuildExtras {
                warm: self.initial.get(),
                clip_vertices: self.clip_vertices.get().map(Vec::as_slice),
                like: self.initial.get().and(like),
                ..crate::build::BuildExtras::default()
            };
            self.case
                .build_file(&file, None, extras)
                .map_err(in_design)?
        };
        let _ = self.initial.get_or_init(|| built.initial.clone());
        let _ = self.clip_vertices.get_or_init(|| {
            built
                .model
                .system()
                .clips
                .iter()
                .map(|c| c.vertex)
                .collect()
        });
        Ok(DesignedCase::new(built))
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

/// The changes of a design point, as `item +x` in the items' units (e.g.
/// `rods.cable.length -300, connectors.a.position +(0, 0, 5)`).
fn describe(changes: &[VariantChange]) -> String {
    // Six decimals in the item's unit, trailing zeros dropped.
    let short = |x: f64| crate::canonical_decimal(x, 6);
    let amount = |a: &Amount| match a {
        Amount::Number(x) if *x >= 0.0 => format!("+{}", short(*x)),
        Amount::Number(x) => short(*x),
        Amount::Vector(v) => format!("+({}, {}, {})", short(v[0]), short(v[1]), short(v[2])),
    };
    changes
        .iter()
        .map(|c| match &c.change {
            Change::Add(a) => format!("{} {}", c.item, amount(a)),
            Change::Set(a) => format!("{} = {}", c.item, amount(a)),
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// How a design's model moves along one affine parameter
/// ([`CaseDesign::affine_line`]).
#[derive(Clone)]
pub struct AffineLine<'d> {
    /// The design at zero offsets.
    pub base: &'d DesignedCase,
    /// Its model's real numbers ([`strand_system::System::reals`]; m, kg, N, …).
    pub reals: &'d [f64],
    /// Their change per unit of the parameter (the parameter's unit).
    pub direction: &'d [f64],
    /// The indices where `direction` is not zero (ascending).
    pub moved: Vec<usize>,
}

impl AffineLine<'_> {
    /// The base model's system with its real numbers moved to the parameter's offset
    /// `t` (its unit): the system of the design built there.
    pub fn system_at(&self, t: f64) -> Result<strand_system::System, strand_system::SystemError> {
        moved_system(self.base, self.reals, self.direction, &self.moved, t)
    }

    /// Moves `system` (the base's, or one [`AffineLine::system_at`] or this method made)
    /// to the offset `t` in place: the system at `t` without a copy.
    pub fn move_system(
        &self,
        system: &mut strand_system::System,
        t: f64,
    ) -> Result<(), strand_system::SystemError> {
        system.set_reals_changed(&self.moved, &|k| self.reals[k] + t * self.direction[k])
    }
}

/// A built case with its contact constraints.
#[derive(Clone)]
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

    /// At zero offsets the base design (built once). Moved along one parameter that
    /// moves the model's real numbers affinely ([`CaseDesign::is_affine`]: checked
    /// against two full builds on first use), the base model with its real numbers
    /// moved along that line ([`strand_system::Model::try_new_like`]: no case
    /// builder, the base's symbolic phase; a second build at the same offset takes
    /// the first one's, [`MOVED_KEPT`]). Otherwise the case builder: its first
    /// build computes the case's initial guess; later builds reuse it and keep its
    /// clip vertices ([`Case::build_with_changes_reusing`]): a design is built many
    /// times at small offsets, its guesses are never solved from, and its mesh must
    /// not change with a clip's station (an edge handed from one piece to the next
    /// where the allocation ties would make the model jump).
    fn build(&self, offsets: &[f64]) -> Result<DesignedCase, CaseError> {
        let mut moved = offsets
            .iter()
            .enumerate()
            .filter(|(_, x)| **x != 0.0)
            .map(|(j, _)| j);
        match (moved.next(), moved.next()) {
            (None, _) => Ok(self.base()?.0.clone()),
            (Some(j), None) => match self.direction(j)? {
                Some(direction) => {
                    let key = (j, offsets[j].to_bits());
                    let kept = self.moved.lock().ok().and_then(|mut m| m.remove(&key));
                    if let Some(built) = kept {
                        return Ok(built);
                    }
                    let (base, reals) = self.base()?;
                    let built = along(base, reals, direction, offsets[j], &self.case.origin)
                        .map_err(|e| {
                            crate::variant::in_design(e, &describe(&self.changes(offsets)))
                        })?;
                    if self.keep_moved.load(Ordering::Relaxed)
                        && let Ok(mut moved) = self.moved.lock()
                        && moved.len() < MOVED_KEPT
                    {
                        moved.insert(key, built.clone());
                    }
                    Ok(built)
                }
                None => self.full_build(offsets),
            },
            _ => self.full_build(offsets),
        }
    }

    /// The line of [`CaseDesign::affine_line`]: where the parameter moves the model's
    /// real numbers affinely (checked against two full builds on first use), the
    /// right-hand sides need no design built along it.
    fn model_line(&self, parameter: usize) -> Result<Option<ModelLine<'_>>, CaseError> {
        Ok(self.affine_line(parameter)?.map(|line| ModelLine {
            reals: line.reals,
            direction: line.direction,
            moved: line.moved,
        }))
    }

    fn enters_linearly(&self, parameter: usize) -> bool {
        VariantItem::parse(&self.case.file, &self.parameters[parameter].item).is_ok_and(|item| {
            matches!(
                item,
                VariantItem::Gravity
                    | VariantItem::JunctionMass(_)
                    | VariantItem::EndForce { .. }
                    | VariantItem::Section { .. }
            )
        })
    }
}

/// The probe step of [`CaseDesign::is_affine`] as a fraction of the parameter's scale
/// (the sensitivities' own difference step by default).
pub const AFFINE_PROBE: f64 = 1e-4;

/// The largest departure from a line, relative to the size of each real number, that
/// [`CaseDesign::is_affine`] takes for round-off (a quadratic dependence shows as
/// `(h/scale)²` ≈ 1e-8 relative at the probe step, a frame's turn as 1e-7).
pub const AFFINE_TOLERANCE: f64 = 1e-12;

/// `(plus − minus) / 3h` where the builds at `−h` (`minus`) and `+2h` (`plus`) have
/// the base's structure and everything else that is not the model's real numbers,
/// and `plus + 2 minus − 3 base` vanishes to round-off (the three lie on a line).
fn affine_direction(
    base: &DesignedCase,
    minus: &DesignedCase,
    plus: &DesignedCase,
    h: f64,
) -> Option<Vec<f64>> {
    let (b, m, p) = (&base.built, &minus.built, &plus.built);
    if !(same_beyond_reals(b, m) && same_beyond_reals(b, p)) {
        return None;
    }
    let system = b.model.system();
    let r0 = system.reals();
    let (rm, rp) = (m.model.system().reals(), p.model.system().reals());
    // Same structure: the other system with the base's real numbers is the base.
    for other in [m.model.system(), p.model.system()] {
        if other.with_reals(&r0).ok().as_ref() != Some(system) {
            return None;
        }
    }
    let on_line = r0.iter().zip(&rm).zip(&rp).all(|((x0, xm), xp)| {
        let size = x0.abs().max(xm.abs()).max(xp.abs());
        (xp + 2.0 * xm - 3.0 * x0).abs() <= 3.0 * AFFINE_TOLERANCE * size
    });
    on_line.then(|| {
        rp.iter()
            .zip(&rm)
            .map(|(xp, xm)| (xp - xm) / (3.0 * h))
            .collect()
    })
}

/// Whether `o` has everything of `b` that is not the model's real numbers: the same
/// environment meshes, connector names, limits and sections.
fn same_beyond_reals(b: &BuiltCase, o: &BuiltCase) -> bool {
    let same_environment = o.environment.len() == b.environment.len()
        && o.environment
            .iter()
            .zip(&b.environment)
            .all(|(x, y)| std::sync::Arc::ptr_eq(x, y));
    same_environment
        && o.connector_names == b.connector_names
        && o.min_bend_radius == b.min_bend_radius
        && o.min_clearance == b.min_clearance
        && o.connector_limits == b.connector_limits
        && o.sections == b.sections
}

/// The indices of the entries of `direction` that are not zero.
fn nonzero(direction: &[f64]) -> Vec<usize> {
    (0..direction.len())
        .filter(|&k| direction[k] != 0.0)
        .collect()
}

/// The base design's system with its real numbers `base_reals` moved by
/// `t · direction` (`moved`: the indices where `direction` is not zero; the others
/// keep their values, and the rods none of them falls in are not visited).
fn moved_system(
    base: &DesignedCase,
    base_reals: &[f64],
    direction: &[f64],
    moved: &[usize],
    t: f64,
) -> Result<strand_system::System, strand_system::SystemError> {
    base.built
        .model
        .system()
        .with_reals_changed(moved, &|k| base_reals[k] + t * direction[k])
}

/// The base design (its model's real numbers `base_reals`) with them moved by
/// `t · direction` (the
/// base's symbolic phase reused, the model validated); everything else is the base's.
fn along(
    base: &DesignedCase,
    base_reals: &[f64],
    direction: &[f64],
    t: f64,
    origin: &str,
) -> Result<DesignedCase, CaseError> {
    let b = &base.built;
    let system_error = |source| CaseError::System {
        origin: origin.to_string(),
        source,
    };
    let moved =
        moved_system(base, base_reals, direction, &nonzero(direction), t).map_err(system_error)?;
    let model = Model::try_new_like(moved, &b.model).map_err(system_error)?;
    Ok(DesignedCase::new(BuiltCase {
        name: b.name.clone(),
        origin: b.origin.clone(),
        length_unit: b.length_unit,
        model,
        initial: b.initial.clone(),
        settings: b.settings.clone(),
        connector_names: b.connector_names.clone(),
        min_bend_radius: b.min_bend_radius.clone(),
        min_clearance: b.min_clearance.clone(),
        connector_limits: b.connector_limits.clone(),
        sections: b.sections.clone(),
        environment: b.environment.clone(),
        start: b.start,
        moved_bodies: b.moved_bodies.clone(),
        clip_projections: b.clip_projections.clone(),
        start_hint: b.start_hint.clone(),
    }))
}

//! The description of a system: rods, their supports and loads.

use nalgebra::{UnitQuaternion, Vector3};
use strand_rod::{Rod, RodState};

/// Typed index of a rod in a [`System`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct RodHandle(pub usize);

/// How a rod end is held.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Support {
    /// Nothing holds the end (zero end moment, only end loads act).
    Free,
    /// The end vertex is held at `position` (m); the end frame is free.
    Pinned {
        /// Prescribed position in m.
        position: Vector3<f64>,
    },
    /// The end vertex is held at `position` (m) and the boundary frame is `frame`
    /// (`a3` pointing along the rod, from vertex 0 towards vertex N, at both ends).
    Clamped {
        /// Prescribed position in m.
        position: Vector3<f64>,
        /// Prescribed boundary frame.
        frame: UnitQuaternion<f64>,
    },
}

impl Support {
    /// The prescribed position, if any.
    pub fn position(&self) -> Option<Vector3<f64>> {
        match self {
            Support::Free => None,
            Support::Pinned { position } | Support::Clamped { position, .. } => Some(*position),
        }
    }

    /// The prescribed boundary frame, if any.
    pub fn frame(&self) -> Option<UnitQuaternion<f64>> {
        match self {
            Support::Clamped { frame, .. } => Some(*frame),
            _ => None,
        }
    }
}

/// Dead loads at a rod end.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EndLoad {
    /// Force on the end vertex in N (world frame).
    pub force: Vector3<f64>,
    /// Moment on the end edge in N·m (world frame), see [`strand_rod::element::dead_moment`].
    pub moment: Vector3<f64>,
    /// Frame from which the end rotation is measured for the moment's potential.
    pub moment_reference: UnitQuaternion<f64>,
}

impl Default for EndLoad {
    fn default() -> Self {
        Self {
            force: Vector3::zeros(),
            moment: Vector3::zeros(),
            moment_reference: UnitQuaternion::identity(),
        }
    }
}

/// One end of a rod.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct End {
    /// How the end is held.
    pub support: Support,
    /// Dead loads at this end.
    pub load: EndLoad,
}

impl End {
    /// A free end without loads.
    pub fn free() -> Self {
        Self {
            support: Support::Free,
            load: EndLoad::default(),
        }
    }

    /// A clamped end.
    pub fn clamped(position: Vector3<f64>, frame: UnitQuaternion<f64>) -> Self {
        Self {
            support: Support::Clamped { position, frame },
            load: EndLoad::default(),
        }
    }

    /// A pinned end.
    pub fn pinned(position: Vector3<f64>) -> Self {
        Self {
            support: Support::Pinned { position },
            load: EndLoad::default(),
        }
    }

    /// The same end with a dead force (N) added.
    pub fn with_force(mut self, force: Vector3<f64>) -> Self {
        self.load.force = force;
        self
    }
}

/// A rod in a system.
#[derive(Clone, Debug, PartialEq)]
pub struct RodSpec {
    /// Name used in results and messages.
    pub name: String,
    /// The rod's reference geometry and section.
    pub rod: Rod,
    /// End at vertex 0 (`s = 0`).
    pub start: End,
    /// End at vertex N (`s = L`).
    pub end: End,
    /// Optional route (points in m) for the initial guess.
    pub route: Option<Vec<Vector3<f64>>>,
}

/// Rods, supports and gravity.
#[derive(Clone, Debug, PartialEq)]
pub struct System {
    /// The rods.
    pub rods: Vec<RodSpec>,
    /// Gravitational acceleration in m/s² (e.g. `(0, 0, −9.81)`).
    pub gravity: Vector3<f64>,
}

/// A configuration of the whole system: one [`RodState`] per rod.
#[derive(Debug, PartialEq)]
pub struct SystemState {
    /// Per-rod configurations, in the order of [`System::rods`].
    pub rods: Vec<RodState>,
}

impl Clone for SystemState {
    fn clone(&self) -> Self {
        Self {
            rods: self.rods.clone(),
        }
    }

    /// Reuses the allocations of `self`.
    fn clone_from(&mut self, source: &Self) {
        self.rods.clone_from(&source.rods);
    }
}

/// Why a system is not solvable as given.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SystemError {
    /// The system has no rods.
    #[error("the system has no rods")]
    Empty,
    /// A vector is not finite.
    #[error("rod '{rod}': {what} is not finite")]
    NotFinite {
        /// Rod name.
        rod: String,
        /// What is not finite.
        what: String,
    },
    /// Nothing holds the rod: its position is undetermined.
    #[error(
        "rod '{rod}' is free at both ends: attach at least one end (clamp or pin) so its position is determined"
    )]
    Unsupported {
        /// Rod name.
        rod: String,
    },
    /// The ends are farther apart than the rod can reach.
    #[error(
        "rod '{rod}' is {length_m:.6} m long but its ends are held {distance_m:.6} m apart: \
         lengthen the rod or move the supports closer"
    )]
    TooShort {
        /// Rod name.
        rod: String,
        /// Reference length in m.
        length_m: f64,
        /// Distance between the prescribed end positions in m.
        distance_m: f64,
    },
    /// Two rods share a name.
    #[error("two rods are named '{0}': rod names must be unique")]
    DuplicateName(String),
}

impl System {
    /// The rod behind a handle.
    pub fn rod(&self, handle: RodHandle) -> &RodSpec {
        &self.rods[handle.0]
    }

    /// Checks what the mechanics cannot: finiteness, supports, and that prescribed ends
    /// are reachable (the axial strain needed must stay below 10 %).
    pub fn validate(&self) -> Result<(), SystemError> {
        if self.rods.is_empty() {
            return Err(SystemError::Empty);
        }
        if !self.gravity.iter().all(|x| x.is_finite()) {
            return Err(SystemError::NotFinite {
                rod: "-".into(),
                what: "gravity".into(),
            });
        }
        let mut names = std::collections::HashSet::new();
        for spec in &self.rods {
            if !names.insert(spec.name.as_str()) {
                return Err(SystemError::DuplicateName(spec.name.clone()));
            }
            let finite = |v: &Vector3<f64>| v.iter().all(|x| x.is_finite());
            for (label, end) in [("start", &spec.start), ("end", &spec.end)] {
                let bad = |what: &str| SystemError::NotFinite {
                    rod: spec.name.clone(),
                    what: format!("{label} {what}"),
                };
                if end.support.position().is_some_and(|p| !finite(&p)) {
                    return Err(bad("position"));
                }
                if end
                    .support
                    .frame()
                    .is_some_and(|q| !q.coords.iter().all(|x| x.is_finite()))
                {
                    return Err(bad("frame"));
                }
                if !finite(&end.load.force) || !finite(&end.load.moment) {
                    return Err(bad("load"));
                }
            }
            if spec.start.support == Support::Free && spec.end.support == Support::Free {
                return Err(SystemError::Unsupported {
                    rod: spec.name.clone(),
                });
            }
            if let (Some(a), Some(b)) = (spec.start.support.position(), spec.end.support.position())
            {
                let length_m = spec.rod.length();
                let distance_m = (b - a).norm();
                if distance_m > 1.1 * length_m {
                    return Err(SystemError::TooShort {
                        rod: spec.name.clone(),
                        length_m,
                        distance_m,
                    });
                }
            }
        }
        Ok(())
    }
}

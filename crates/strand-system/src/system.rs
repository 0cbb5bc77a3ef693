//! The description of a system: rods, their supports and loads.

use nalgebra::{UnitQuaternion, Vector3};
use strand_rod::sectional::BoundaryFrames;
use strand_rod::{Rod, RodState};

/// Typed index of a rod in a [`System`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct RodHandle(pub usize);

/// Typed index of a rigid body (junction) in a [`System`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct BodyHandle(pub usize);

/// Position (m) and orientation of a rigid body in the world frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    /// Position of the body's origin in m.
    pub position: Vector3<f64>,
    /// Orientation (body frame to world).
    pub orientation: UnitQuaternion<f64>,
}

impl Pose {
    /// A point given in body coordinates (m), in world coordinates (m).
    pub fn transform_point(&self, local: &Vector3<f64>) -> Vector3<f64> {
        self.position + self.orientation * local
    }
}

/// The joint of a clip between its base frame and its output frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Joint {
    /// No freedom: the output frame is fixed to the base.
    Fixed,
    /// Rotation by an angle (rad) about `axis` (unit, base coordinates) through the
    /// base origin: a hinge, or a clip that lets the hose turn about its own axis.
    Revolute {
        /// Unit axis in base coordinates.
        axis: Vector3<f64>,
    },
    /// Translation by a distance (m) along `axis` (unit, base coordinates): a clip
    /// sliding on a rail.
    Prismatic {
        /// Unit axis in base coordinates.
        axis: Vector3<f64>,
    },
    /// Free rotation about the base origin (a ball joint).
    Spherical,
}

/// A clip: a joint from a base frame (fixed in space, or on a body) to an output frame
/// that holds a rod at one of its interior vertices (the vertex sits at the output
/// origin; the curvature term there is split into two half-cells around the output
/// frame, whose `a3` points along the rod).
///
/// A clip based on a free body moves with it: a clip mounted on a hanging T-junction,
/// or a hose-to-hose clip (a light body holding two rods through one clip each).
#[derive(Clone, Debug, PartialEq)]
pub struct ClipSpec {
    /// Name used in reactions and results.
    pub name: String,
    /// The body carrying the base frame, or `None` for a base fixed in the world.
    pub body: Option<BodyHandle>,
    /// The clip (index into [`System::clips`], an earlier one) whose output frame
    /// carries this clip's base: a chain of joints. Excludes `body`.
    pub parent: Option<usize>,
    /// Base frame (m): in the world, or in the coordinates of the body or the parent
    /// clip's output frame.
    pub base: Pose,
    /// The joint.
    pub joint: Joint,
    /// Output frame relative to the joint's moving frame (m).
    pub offset: Pose,
    /// The rod held.
    pub rod: RodHandle,
    /// The interior vertex held (`0 < vertex < N`).
    pub vertex: usize,
    /// Lower and upper limit of a revolute (rad) or prismatic (m) joint, if any.
    pub limits: Option<(f64, f64)>,
}

/// Joint coordinates of a clip: `value` is the angle (rad) of a revolute joint or the
/// distance (m) of a prismatic one; `rotation` that of a spherical joint.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointState {
    /// Angle in rad or distance in m.
    pub value: f64,
    /// Rotation of a spherical joint.
    pub rotation: UnitQuaternion<f64>,
}

impl Default for JointState {
    fn default() -> Self {
        Self {
            value: 0.0,
            rotation: UnitQuaternion::identity(),
        }
    }
}

impl ClipSpec {
    /// The joint's motion `(translation, rotation)` in base coordinates.
    pub fn joint_motion(&self, state: &JointState) -> (Vector3<f64>, UnitQuaternion<f64>) {
        match self.joint {
            Joint::Fixed => (Vector3::zeros(), UnitQuaternion::identity()),
            Joint::Revolute { axis } => (
                Vector3::zeros(),
                UnitQuaternion::from_scaled_axis(axis * state.value),
            ),
            Joint::Prismatic { axis } => (axis * state.value, UnitQuaternion::identity()),
            Joint::Spherical => (Vector3::zeros(), state.rotation),
        }
    }
}

/// A port of a body: a frame in body coordinates where a rod end attaches. Its `a3`
/// points out of the body, into the attached rod.
#[derive(Clone, Debug, PartialEq)]
pub struct Port {
    /// Name used in reactions (`<body>.<port>`).
    pub name: String,
    /// Origin of the port in body coordinates, m.
    pub position: Vector3<f64>,
    /// Orientation of the port relative to the body.
    pub frame: UnitQuaternion<f64>,
}

/// A rigid body with ports: a T- or Y-junction, a branch, a bracket.
#[derive(Clone, Debug, PartialEq)]
pub struct BodySpec {
    /// Name used in results and messages.
    pub name: String,
    /// Mass in kg.
    pub mass: f64,
    /// Centre of mass in body coordinates, m.
    pub center_of_mass: Vector3<f64>,
    /// Pose: the initial guess of a free body, the pose of a fixed one.
    pub pose: Pose,
    /// Whether the body is mounted (pose prescribed) rather than free-hanging.
    pub fixed: bool,
    /// The ports.
    pub ports: Vec<Port>,
}

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
    /// The end is attached to port `port` of body `body`: its vertex is at the port's
    /// origin and, if `clamped`, its boundary frame is the port frame (with `a3`
    /// reversed at a rod's end vertex, so that it keeps pointing along the rod).
    Port {
        /// The body.
        body: BodyHandle,
        /// Index of the port in [`BodySpec::ports`].
        port: usize,
        /// Whether the port also fixes the end frame (otherwise a ball joint).
        clamped: bool,
    },
}

impl Support {
    /// Whether the end vertex is held (by a connector or a body port), i.e. not an
    /// unknown of its own.
    pub fn is_held(&self) -> bool {
        !matches!(self, Support::Free)
    }

    /// The prescribed position, if any (fixed in space; a port moves with its body).
    pub fn position(&self) -> Option<Vector3<f64>> {
        match self {
            Support::Free | Support::Port { .. } => None,
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
    /// Whole turns of twist (2π rad each, right-handed about the rod's tangent) by which
    /// this end's boundary frame is wound beyond the shortest rotation from the rod's
    /// other end. A boundary frame is a rotation, so it fixes the twist of a rod only
    /// modulo one turn; this integer says which turn is meant. The initial guess spreads
    /// the total twist `φ₀ + 2π (end.twist_turns − start.twist_turns)` along the rod
    /// (`φ₀ ∈ (−π, π]` the shortest twist), and Newton converges to the state of that
    /// winding. Non-zero only where both ends have a boundary frame (clamp, clamped port).
    pub twist_turns: i32,
}

impl End {
    /// A free end without loads.
    pub fn free() -> Self {
        Self {
            support: Support::Free,
            load: EndLoad::default(),
            twist_turns: 0,
        }
    }

    /// A clamped end.
    pub fn clamped(position: Vector3<f64>, frame: UnitQuaternion<f64>) -> Self {
        Self {
            support: Support::Clamped { position, frame },
            load: EndLoad::default(),
            twist_turns: 0,
        }
    }

    /// A pinned end.
    pub fn pinned(position: Vector3<f64>) -> Self {
        Self {
            support: Support::Pinned { position },
            load: EndLoad::default(),
            twist_turns: 0,
        }
    }

    /// The same end wound by `turns` extra whole turns (see [`End::twist_turns`]).
    pub fn with_twist_turns(mut self, turns: i32) -> Self {
        self.twist_turns = turns;
        self
    }

    /// Whether the end has a boundary frame (a clamp or a clamped port).
    pub fn has_frame(&self) -> bool {
        matches!(
            self.support,
            Support::Clamped { .. } | Support::Port { clamped: true, .. }
        )
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

/// Rods, rigid bodies, supports and gravity.
#[derive(Clone, Debug, PartialEq)]
pub struct System {
    /// The rods.
    pub rods: Vec<RodSpec>,
    /// Rigid bodies (junctions) whose ports hold rod ends.
    pub bodies: Vec<BodySpec>,
    /// Clips holding rods at interior vertices.
    pub clips: Vec<ClipSpec>,
    /// Gravitational acceleration in m/s² (e.g. `(0, 0, −9.81)`).
    pub gravity: Vector3<f64>,
}

/// A configuration of the whole system: one [`RodState`] per rod, one [`Pose`] per body.
#[derive(Debug, PartialEq)]
pub struct SystemState {
    /// Per-rod configurations, in the order of [`System::rods`].
    pub rods: Vec<RodState>,
    /// Per-body poses, in the order of [`System::bodies`].
    pub bodies: Vec<Pose>,
    /// Per-clip joint coordinates, in the order of [`System::clips`].
    pub clips: Vec<JointState>,
}

impl Clone for SystemState {
    fn clone(&self) -> Self {
        Self {
            rods: self.rods.clone(),
            bodies: self.bodies.clone(),
            clips: self.clips.clone(),
        }
    }

    /// Reuses the allocations of `self`.
    fn clone_from(&mut self, source: &Self) {
        self.rods.clone_from(&source.rods);
        self.bodies.clone_from(&source.bodies);
        self.clips.clone_from(&source.clips);
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
    /// Two places that hold a rod (its ends, clips fixed in the world) are farther
    /// apart than the rod between them can reach.
    #[error("{0}")]
    ClipOutOfReach(Box<ClipReach>),
    /// Two rods share a name.
    #[error("two rods are named '{0}': rod names must be unique")]
    DuplicateName(String),
    /// A rod end names a body or port that does not exist.
    #[error("rod '{rod}': {what}")]
    UnknownAttachment {
        /// Rod name.
        rod: String,
        /// What is missing.
        what: String,
    },
    /// A body's data are invalid.
    #[error("body '{body}': {what}")]
    InvalidBody {
        /// Body name.
        body: String,
        /// What is wrong and how to fix it.
        what: String,
    },
    /// A clip's data are invalid.
    #[error("clip '{clip}': {what}")]
    InvalidClip {
        /// Clip name.
        clip: String,
        /// What is wrong and how to fix it.
        what: String,
    },
    /// Extra twist turns where they have no meaning, or more than the rod can resolve.
    #[error("rod '{rod}': {what}")]
    InvalidTwist {
        /// Rod name.
        rod: String,
        /// What is wrong and how to fix it.
        what: String,
    },
    /// A group of rods and free bodies is held by nothing.
    #[error(
        "rod '{rod}' and everything attached to it are held by no connector or mounted body: \
         attach at least one end of the group to a connector or a fixed body"
    )]
    Floating {
        /// A rod of the floating group.
        rod: String,
    },
}

/// Two holders of a rod farther apart than the rod between them reaches
/// ([`SystemError::ClipOutOfReach`]).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error(
    "rod '{rod}': {to} (at {to_s_m:.6} m along the rod) is held {distance_m:.6} m from \
     {from} (at {from_s_m:.6} m), but only {arc_m:.6} m of rod lies between them: move \
     the clip's base or its place along the rod (`at`), or lengthen the rod"
)]
pub struct ClipReach {
    /// Rod name.
    pub rod: String,
    /// The first holder along the rod: `its start` or `clip 'name'`.
    pub from: String,
    /// Its reference arc length, m.
    pub from_s_m: f64,
    /// The next holder along the rod: `clip 'name'` or `its end`.
    pub to: String,
    /// Its reference arc length, m.
    pub to_s_m: f64,
    /// The least distance between where they hold the rod, m.
    pub distance_m: f64,
    /// The rod's reference length between them, m.
    pub arc_m: f64,
}

impl System {
    /// The rod behind a handle.
    pub fn rod(&self, handle: RodHandle) -> &RodSpec {
        &self.rods[handle.0]
    }

    /// The size of the loads applied to the system, N: the weight of every rod and of
    /// every body that is not fixed, plus the magnitude of every dead force at a rod
    /// end and of every dead moment there divided by its rod's length (a moment `M`
    /// acts like a force `M/L` at the rod's scale). 0 for a system moved only by its
    /// supports (no gravity, no dead loads).
    pub fn applied_load_n(&self) -> f64 {
        let g = self.gravity.norm();
        let rods: f64 = self
            .rods
            .iter()
            .map(|r| {
                let length = r.rod.length();
                let end = |end: &End| end.load.force.norm() + end.load.moment.norm() / length;
                g * r.rod.mass() + end(&r.start) + end(&r.end)
            })
            .sum();
        let bodies: f64 = self
            .bodies
            .iter()
            .filter(|b| !b.fixed)
            .map(|b| g * b.mass)
            .sum();
        rods + bodies
    }

    /// The fixed rotation from a body's frame to the boundary frame of a rod end attached
    /// to its port: the port frame at a rod's start, the port frame turned by π about
    /// its `a1` at a rod's end (so that `a3` points along the rod, into the port).
    pub fn port_offset(&self, body: BodyHandle, port: usize, at_end: bool) -> UnitQuaternion<f64> {
        let frame = self.bodies[body.0].ports[port].frame;
        if at_end {
            frame * UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI)
        } else {
            frame
        }
    }

    /// World position (m) of a rod end held where nothing moves it (a connector, pin or
    /// clamp, or a port of a fixed body), for the given body poses; `None` otherwise.
    fn fixed_end_position(&self, end: &End, at_end: bool, poses: &[Pose]) -> Option<Vector3<f64>> {
        match end.support {
            Support::Port { body, .. } if !self.bodies[body.0].fixed => None,
            _ => self.end_placement(end, at_end, poses).0,
        }
    }

    /// World position (m) and boundary frame of a held rod end for the given body poses:
    /// `(None, None)` for a free end, no frame for a pinned end or ball-joint port.
    pub fn end_placement(
        &self,
        end: &End,
        at_end: bool,
        poses: &[Pose],
    ) -> (Option<Vector3<f64>>, Option<UnitQuaternion<f64>>) {
        match end.support {
            Support::Free => (None, None),
            Support::Pinned { position } => (Some(position), None),
            Support::Clamped { position, frame } => (Some(position), Some(frame)),
            Support::Port {
                body,
                port,
                clamped,
            } => {
                let pose = &poses[body.0];
                let position = pose.transform_point(&self.bodies[body.0].ports[port].position);
                let frame =
                    clamped.then(|| pose.orientation * self.port_offset(body, port, at_end));
                (Some(position), frame)
            }
        }
    }

    /// The boundary frames of rod `rod`'s ends for the given body poses (a port's frame
    /// moves with its body) and the external forces lumped at its end vertices (the
    /// half cell's weight `h̄ ρ_L g`, and at a held end the dead end load, which goes
    /// straight into the support: see [`BoundaryFrames::end_loads`]), without clips:
    /// [`crate::Model::boundary_frames`] adds the clips' frames.
    pub fn ends_boundary(&self, rod: usize, poses: &[Pose]) -> BoundaryFrames {
        let spec = &self.rods[rod];
        let end_load = |j: usize| {
            let end = if j == 0 { &spec.start } else { &spec.end };
            let weight = spec.rod.vertex_mass(j) * self.gravity;
            if end.support.is_held() {
                weight + end.load.force
            } else {
                weight
            }
        };
        BoundaryFrames {
            start: self.end_placement(&spec.start, false, poses).1,
            end: self.end_placement(&spec.end, true, poses).1,
            clips: Vec::new(),
            end_loads: [0, spec.rod.segments()].map(end_load),
        }
    }

    /// The initial (or fixed) poses of the bodies.
    pub fn body_poses(&self) -> Vec<Pose> {
        self.bodies.iter().map(|b| b.pose).collect()
    }

    /// Checks bodies, attachments and that every group of rods and free bodies is held.
    fn validate_bodies(&self) -> Result<(), SystemError> {
        let finite = |v: &Vector3<f64>| v.iter().all(|x| x.is_finite());
        let mut names = std::collections::HashSet::new();
        for body in &self.bodies {
            let invalid = |what: String| SystemError::InvalidBody {
                body: body.name.clone(),
                what,
            };
            if !names.insert(body.name.as_str()) {
                return Err(invalid(
                    "two bodies have this name: body names must be unique".into(),
                ));
            }
            if !(body.mass.is_finite() && body.mass >= 0.0) {
                return Err(invalid(format!(
                    "mass must be a finite number ≥ 0 kg (got {})",
                    body.mass
                )));
            }
            if !finite(&body.center_of_mass) || !finite(&body.pose.position) {
                return Err(invalid("centre of mass and position must be finite".into()));
            }
            if body.ports.iter().any(|p| !finite(&p.position)) {
                return Err(invalid("port positions must be finite".into()));
            }
        }
        for spec in &self.rods {
            for end in [&spec.start, &spec.end] {
                if let Support::Port { body, port, .. } = end.support {
                    let Some(b) = self.bodies.get(body.0) else {
                        return Err(SystemError::UnknownAttachment {
                            rod: spec.name.clone(),
                            what: format!(
                                "body #{} does not exist ({} bodies)",
                                body.0,
                                self.bodies.len()
                            ),
                        });
                    };
                    if port >= b.ports.len() {
                        return Err(SystemError::UnknownAttachment {
                            rod: spec.name.clone(),
                            what: format!(
                                "body '{}' has no port #{port} ({} ports)",
                                b.name,
                                b.ports.len()
                            ),
                        });
                    }
                }
            }
        }
        for (b, body) in self.bodies.iter().enumerate() {
            let attached = self.rods.iter().any(|r| {
                [&r.start, &r.end]
                    .iter()
                    .any(|e| matches!(e.support, Support::Port { body, .. } if body.0 == b))
            }) || self.clips.iter().any(|c| c.body.is_some_and(|h| h.0 == b));
            if !attached && !body.fixed {
                return Err(SystemError::InvalidBody {
                    body: body.name.clone(),
                    what: "no rod is attached to this free body: attach a rod to one of its ports (or hold one with a clip on it) or remove it".into(),
                });
            }
        }
        self.check_held_groups()
    }

    /// The first clip of `clip`'s chain (the one whose base is on the world or a body).
    pub fn chain_root(&self, mut clip: usize) -> usize {
        while let Some(parent) = self.clips[clip].parent {
            clip = parent;
        }
        clip
    }

    /// The base frame of clip `clip` in the world, for joint coordinates `joints` and
    /// body poses `bodies` (through its chain of parent clips).
    pub fn clip_base(&self, clip: usize, joints: &[JointState], bodies: &[Pose]) -> Pose {
        let spec = &self.clips[clip];
        let carrier = match (spec.parent, spec.body) {
            (Some(parent), _) => self.clip_output(parent, joints, bodies),
            (None, Some(body)) => bodies[body.0],
            (None, None) => return spec.base,
        };
        Pose {
            position: carrier.transform_point(&spec.base.position),
            orientation: carrier.orientation * spec.base.orientation,
        }
    }

    /// The output frame of clip `clip` in the world (through its chain of parents).
    pub fn clip_output(&self, clip: usize, joints: &[JointState], bodies: &[Pose]) -> Pose {
        let base = self.clip_base(clip, joints, bodies);
        let spec = &self.clips[clip];
        let (translation, rotation) = spec.joint_motion(&joints[clip]);
        Pose {
            position: base.transform_point(&(translation + rotation * spec.offset.position)),
            orientation: base.orientation * rotation * spec.offset.orientation,
        }
    }

    /// The clip holding vertex `vertex` of rod `rod`, if any: a scan of every clip,
    /// `O(clips)`; per-vertex loops use the index of [`crate::Dofs::clip_at`].
    pub fn clip_at(&self, rod: usize, vertex: usize) -> Option<usize> {
        self.clips
            .iter()
            .position(|c| c.rod.0 == rod && c.vertex == vertex)
    }

    /// Checks that every clip holds an existing interior vertex, one clip per vertex,
    /// with a unit axis.
    fn validate_clips(&self) -> Result<(), SystemError> {
        let mut held = std::collections::HashSet::with_capacity(self.clips.len());
        for (i, clip) in self.clips.iter().enumerate() {
            let invalid = |what: String| SystemError::InvalidClip {
                clip: clip.name.clone(),
                what,
            };
            let Some(rod) = self.rods.get(clip.rod.0) else {
                return Err(invalid(format!("rod #{} does not exist", clip.rod.0)));
            };
            let n = rod.rod.segments();
            if clip.vertex == 0 || clip.vertex >= n {
                return Err(invalid(format!(
                    "vertex {} of rod '{}' is not an interior vertex (1..{}): hold the rod's ends with a connector or a port",
                    clip.vertex,
                    rod.name,
                    n - 1
                )));
            }
            if !held.insert((clip.rod, clip.vertex)) {
                return Err(invalid(format!(
                    "another clip already holds vertex {} of rod '{}'",
                    clip.vertex, rod.name
                )));
            }
            let is_unit = |a: &Vector3<f64>| (a.norm() - 1.0).abs() < 1e-9;
            if let Joint::Revolute { axis } | Joint::Prismatic { axis } = clip.joint
                && !is_unit(&axis)
            {
                return Err(invalid(format!(
                    "joint axis {axis:?} must be a unit vector"
                )));
            }
            if let Some((lower, upper)) = clip.limits {
                if !matches!(clip.joint, Joint::Revolute { .. } | Joint::Prismatic { .. }) {
                    return Err(invalid(
                        "only revolute and prismatic joints take limits".into(),
                    ));
                }
                if !(lower.is_finite()
                    && upper.is_finite()
                    && lower <= 0.0
                    && 0.0 <= upper
                    && lower < upper)
                {
                    return Err(invalid(format!(
                        "limits ({lower}, {upper}) must be finite with lower ≤ 0 ≤ upper and lower < upper (the joint starts at 0)"
                    )));
                }
            }
            if let Some(body) = clip.body
                && body.0 >= self.bodies.len()
            {
                return Err(invalid(format!("body #{} does not exist", body.0)));
            }
            if let Some(parent) = clip.parent {
                if parent >= i {
                    return Err(invalid(format!(
                        "its parent must be an earlier clip (got clip #{parent})"
                    )));
                }
                if clip.body.is_some() {
                    return Err(invalid(
                        "a clip is carried by a body or by a clip, not both".into(),
                    ));
                }
            }
            let finite = |v: &Vector3<f64>| v.iter().all(|x| x.is_finite());
            if !finite(&clip.base.position) || !finite(&clip.offset.position) {
                return Err(invalid("base and offset positions must be finite".into()));
            }
        }
        Ok(())
    }

    /// Union–find over rods and bodies: every connected group must touch the ground
    /// (a connector or a fixed body).
    fn check_held_groups(&self) -> Result<(), SystemError> {
        let rods = self.rods.len();
        let ground = rods + self.bodies.len();
        let mut parent: Vec<usize> = (0..=ground).collect();
        fn find(parent: &mut [usize], mut i: usize) -> usize {
            while parent[i] != i {
                parent[i] = parent[parent[i]];
                i = parent[i];
            }
            i
        }
        let union = |parent: &mut Vec<usize>, a: usize, b: usize| {
            let (ra, rb) = (find(parent, a), find(parent, b));
            parent[ra] = rb;
        };
        for (b, body) in self.bodies.iter().enumerate() {
            if body.fixed {
                union(&mut parent, rods + b, ground);
            }
        }
        for (c, clip) in self.clips.iter().enumerate() {
            let root = &self.clips[self.chain_root(c)];
            let carrier = root.body.map_or(ground, |b| rods + b.0);
            union(&mut parent, clip.rod.0, carrier);
        }
        for (r, spec) in self.rods.iter().enumerate() {
            for end in [&spec.start, &spec.end] {
                match end.support {
                    Support::Free => {}
                    Support::Pinned { .. } | Support::Clamped { .. } => {
                        union(&mut parent, r, ground)
                    }
                    Support::Port { body, .. } => union(&mut parent, r, rods + body.0),
                }
            }
        }
        let ground_root = find(&mut parent, ground);
        for (r, spec) in self.rods.iter().enumerate() {
            if find(&mut parent, r) != ground_root {
                return Err(SystemError::Floating {
                    rod: spec.name.clone(),
                });
            }
        }
        Ok(())
    }

    /// Extra twist turns need a boundary frame at both ends, and enough edges that the
    /// twist per vertex stays below a half turn (the discrete curvature measures
    /// relative rotations in (−π, π)).
    fn validate_twist(&self, spec: &RodSpec) -> Result<(), SystemError> {
        let turns = i64::from(spec.end.twist_turns) - i64::from(spec.start.twist_turns);
        if turns == 0 {
            return Ok(());
        }
        let invalid = |what: String| SystemError::InvalidTwist {
            rod: spec.name.clone(),
            what,
        };
        if !(spec.start.has_frame() && spec.end.has_frame()) {
            return Err(invalid(format!(
                "{turns} extra twist turn(s) (`twist_turns` of its ends) need both ends \
                 clamped (a clamp, connector or clamped port): a pinned or free end cannot \
                 hold a twist"
            )));
        }
        // Total twist up to (|turns| + 1/2) turns over N vertices: below π/2 per vertex.
        let needed = 4 * turns.unsigned_abs() + 2;
        let segments = spec.rod.segments() as u64;
        if segments < needed {
            return Err(invalid(format!(
                "{turns} extra twist turn(s) (`twist_turns` of its ends) need at least \
                 {needed} segments (got {segments}): the twist per segment must stay below a \
                 quarter turn; raise the rod's `segments` or lower `twist_turns`"
            )));
        }
        Ok(())
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
        let clipped_rods: std::collections::HashSet<&str> = self
            .clips
            .iter()
            .filter_map(|c| self.rods.get(c.rod.0).map(|r| r.name.as_str()))
            .collect();
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
            self.validate_twist(spec)?;
            let clipped = clipped_rods.contains(spec.name.as_str());
            if spec.start.support == Support::Free && spec.end.support == Support::Free && !clipped
            {
                return Err(SystemError::Unsupported {
                    rod: spec.name.clone(),
                });
            }
        }
        self.validate_bodies()?;
        self.validate_clips()?;
        let poses = self.body_poses();
        for spec in &self.rods {
            if let (Some(a), Some(b)) = (
                self.fixed_end_position(&spec.start, false, &poses),
                self.fixed_end_position(&spec.end, true, &poses),
            ) {
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
        self.validate_clip_reach(&poses)
    }

    /// Checks that every clip fixed in the world lies within reach of the places next
    /// to it along its rod that hold the rod (its fixed ends and such clips): the rod
    /// between them must not need more than 10 % of axial strain, as for the ends.
    fn validate_clip_reach(&self, poses: &[Pose]) -> Result<(), SystemError> {
        // The clips fixed in the world, per rod (one pass over the clips, not one per rod).
        let mut world_clips: Vec<Vec<&ClipSpec>> = vec![Vec::new(); self.rods.len()];
        for clip in &self.clips {
            if clip.body.is_none()
                && clip.parent.is_none()
                && let Some(list) = world_clips.get_mut(clip.rod.0)
            {
                list.push(clip);
            }
        }
        for (spec, clips) in self.rods.iter().zip(&world_clips) {
            if clips.is_empty() {
                continue; // the ends alone are checked by `validate`
            }
            // (arc length m, what, centre m, radius m): where each holder keeps the rod.
            let mut held: Vec<(f64, String, Vector3<f64>, f64)> = Vec::new();
            for (end, at_end, s, what) in [
                (&spec.start, false, 0.0, "its start"),
                (&spec.end, true, spec.rod.length(), "its end"),
            ] {
                if let Some(p) = self.fixed_end_position(end, at_end, poses) {
                    held.push((s, what.to_string(), p, 0.0));
                }
            }
            let arcs = spec.rod.arc_lengths();
            for clip in clips {
                let offset = clip.base.orientation * clip.offset.position;
                let (centre, radius) = match clip.joint {
                    Joint::Fixed => (clip.base.position + offset, 0.0),
                    Joint::Revolute { .. } | Joint::Spherical => {
                        (clip.base.position, clip.offset.position.norm())
                    }
                    // A rail may carry the clip anywhere along it.
                    Joint::Prismatic { .. } => continue,
                };
                let s = arcs.get(clip.vertex).copied().unwrap_or(0.0);
                held.push((s, format!("clip '{}'", clip.name), centre, radius));
            }
            held.sort_by(|a, b| a.0.total_cmp(&b.0));
            for pair in held.windows(2) {
                let ((s0, from, c0, r0), (s1, to, c1, r1)) = (&pair[0], &pair[1]);
                let distance_m = ((c1 - c0).norm() - r0 - r1).max(0.0);
                let arc_m = s1 - s0;
                if distance_m > 1.1 * arc_m {
                    return Err(SystemError::ClipOutOfReach(Box::new(ClipReach {
                        rod: spec.name.clone(),
                        from: from.clone(),
                        from_s_m: *s0,
                        to: to.clone(),
                        to_s_m: *s1,
                        distance_m,
                        arc_m,
                    })));
                }
            }
        }
        Ok(())
    }
}

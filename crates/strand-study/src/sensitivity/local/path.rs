//! The local readings at a point of a parameter's first-order path without building
//! the design there: where the parameter moves the model affinely
//! ([`strand_case::CaseDesign::affine_line`]), the point's system is the base's with
//! its real numbers moved, and only the vertices and edges the readings look at (and
//! the bodies) are moved by `t · dδ/dp` from the base state: no model (numbering,
//! validation), no retraction of every unknown, no reactions of supports nobody reads.
//! The numbers are those of [`LocalOutputs::read`] on the built design and the
//! retracted state, to round-off.

use strand_case::AffineLine;
use strand_rod::sectional::BoundaryFrames;
use strand_rod::sectional_at::{VertexSectional, sectional_at};
use strand_rod::so3;
use strand_solve::sensitivity::{PathPlace, Sample};
use strand_system::{Dofs, Model, System, SystemError, SystemState};

use super::{LocalOutputs, Reading};

/// Per rod, the vertices and edges the readings of a plan look at (sorted, unique).
#[derive(Clone, Debug, Default, PartialEq)]
pub(super) struct Window {
    pub(super) vertices: Vec<usize>,
    pub(super) edges: Vec<usize>,
}

impl Window {
    /// Adds the vertices `first..=last` and edges between them, within a rod of
    /// `segments` edges.
    pub(super) fn add(&mut self, first: usize, last: usize, segments: usize) {
        let last = last.min(segments);
        self.vertices.extend(first..=last);
        self.edges.extend(first..last);
    }

    /// Sorts and deduplicates.
    pub(super) fn finish(&mut self) {
        for list in [&mut self.vertices, &mut self.edges] {
            list.sort_unstable();
            list.dedup();
        }
    }
}

/// The first-order path of one affine parameter for a plan's local readings.
pub struct LocalPath<'a> {
    plan: &'a LocalOutputs,
    line: AffineLine<'a>,
    base: &'a SystemState,
    /// `dδ/dp` of the parameter (the solver's chart at the base state).
    tangent: &'a [f64],
    /// The system at the last point read (moved in place from point to point).
    system: System,
}

impl<'a> LocalPath<'a> {
    /// The path of the parameter whose design moves along `line`, with the base
    /// equilibrium `base` and its derivative `tangent` (`dδ/dp`, per unit of the
    /// parameter), read by `plan`.
    pub fn new(
        plan: &'a LocalOutputs,
        line: AffineLine<'a>,
        base: &'a SystemState,
        tangent: &'a [f64],
    ) -> Self {
        let system = line.base.built.model.system().clone();
        Self {
            plan,
            line,
            base,
            tangent,
            system,
        }
    }

    /// The plan's outputs at the point `t` (the parameter's unit) of the path, as
    /// [`LocalOutputs::read`] reads them there; at [`PathPlace::Outermost`] every
    /// vertex of every rod is moved (for the peaks' own args).
    pub fn read(&mut self, t: f64, place: PathPlace) -> Result<Vec<Sample>, SystemError> {
        let model = &self.line.base.built.model;
        self.line.move_system(&mut self.system, t)?;
        let system = &self.system;
        let whole: Vec<Window> = if place == PathPlace::Outermost {
            system
                .rods
                .iter()
                .map(|spec| {
                    let n = spec.rod.segments();
                    Window {
                        vertices: (0..=n).collect(),
                        edges: (0..n).collect(),
                    }
                })
                .collect()
        } else {
            Vec::new()
        };
        let windows = if whole.is_empty() {
            &self.plan.windows
        } else {
            &whole
        };
        let state = self.moved_state(system, model, t, windows);
        let frames: Vec<BoundaryFrames> = (0..system.rods.len())
            .map(|r| system.ends_boundary(r, &state.bodies))
            .collect();
        Ok(self.plan.read_with(system, &state, &frames, place))
    }

    /// The sectional quantities of the vertices `vertices[r]` of every rod `r` at the
    /// point `t` of the path (as [`LocalPath::read`] would compute them there, with
    /// only their edges and vertices moved): the exact values at the outermost points
    /// of the few vertices that could hold a peak there.
    pub(super) fn sectional_at_vertices(
        &mut self,
        t: f64,
        vertices: &[Vec<usize>],
    ) -> Result<Vec<Vec<VertexSectional>>, SystemError> {
        let model = &self.line.base.built.model;
        self.line.move_system(&mut self.system, t)?;
        let system = &self.system;
        let windows: Vec<Window> = system
            .rods
            .iter()
            .zip(vertices)
            .map(|(spec, list)| {
                let mut window = Window::default();
                for &j in list {
                    window.add(j.saturating_sub(1), j + 1, spec.rod.segments());
                }
                window.finish();
                window
            })
            .collect();
        let state = self.moved_state(system, model, t, &windows);
        Ok(vertices
            .iter()
            .enumerate()
            .map(|(r, list)| {
                if list.is_empty() {
                    return Vec::new();
                }
                let frames = system.ends_boundary(r, &state.bodies);
                list.iter()
                    .map(|&j| sectional_at(&system.rods[r].rod, &state.rods[r], &frames, j))
                    .collect()
            })
            .collect())
    }

    /// The base state moved by `t · tangent` on the vertices and edges of `windows`
    /// (one per rod), the held ends on the point's supports and ports.
    fn moved_state(
        &self,
        system: &System,
        model: &Model,
        t: f64,
        windows: &[Window],
    ) -> SystemState {
        let dofs: &Dofs = model.dofs();
        let step = |b: usize| {
            let v = &self.tangent[3 * b..3 * b + 3];
            nalgebra::Vector3::new(t * v[0], t * v[1], t * v[2])
        };
        let mut state = self.base.clone();
        for (b, pose) in state.bodies.iter_mut().enumerate() {
            match dofs.body(b) {
                Some((translation, rotation)) => {
                    pose.position += step(translation);
                    pose.orientation *= so3::exp(&step(rotation));
                    pose.orientation.renormalize_fast();
                }
                None if system.bodies[b].fixed => *pose = system.bodies[b].pose,
                None => {}
            }
        }
        for ((r, spec), window) in system.rods.iter().enumerate().zip(windows) {
            let rod_state = &mut state.rods[r];
            for &j in &window.vertices {
                match dofs.vertex(r, j) {
                    Some(b) => rod_state.translate_vertex(j, &step(b)),
                    None => {
                        let (end, at_end) = if j == 0 {
                            (&spec.start, false)
                        } else {
                            (&spec.end, true)
                        };
                        if let (Some(position), _) =
                            system.end_placement(end, at_end, &state.bodies)
                        {
                            rod_state.set_position(j, position);
                        }
                    }
                }
            }
            for &e in &window.edges {
                let q = &mut rod_state.frames[e];
                *q *= so3::exp(&step(dofs.edge(r, e)));
                q.renormalize_fast();
            }
        }
        state
    }
}

impl LocalOutputs {
    /// Whether the plan reads the energy (which has no local reading along a path:
    /// [`LocalPath`] is for plans without it).
    pub fn reads_energy(&self) -> bool {
        self.readings.contains(&Reading::Energy)
    }
}

//! Numbering of the unknowns: 3-blocks of vertex positions and edge rotation increments.
//! Vertices held by a support are eliminated (they have no block).

use std::sync::atomic::{AtomicU64, Ordering};

use crate::system::{Joint, System};

/// The clips of a system indexed by rod and vertex: one sorted list of
/// `(vertex, clip)` per rod, so that a per-vertex query costs `O(log clips of the rod)`
/// instead of a scan of every clip (which made model building quadratic).
#[derive(Debug, Default)]
pub struct ClipIndex {
    by_rod: Vec<Vec<(usize, usize)>>,
    /// Entries examined by [`ClipIndex::clip_at`] so far: a work counter that tests use
    /// to check that model building stays `O(n log n)`.
    probes: AtomicU64,
}

impl Clone for ClipIndex {
    fn clone(&self) -> Self {
        Self {
            by_rod: self.by_rod.clone(),
            probes: AtomicU64::new(self.probes()),
        }
    }
}

impl ClipIndex {
    /// Indexes the clips of `system` (`O(clips · log clips)`); clips naming a rod that
    /// does not exist are left out (validation reports them).
    pub fn new(system: &System) -> Self {
        let mut by_rod = vec![Vec::new(); system.rods.len()];
        for (c, clip) in system.clips.iter().enumerate() {
            if let Some(list) = by_rod.get_mut(clip.rod.0) {
                list.push((clip.vertex, c));
            }
        }
        for list in &mut by_rod {
            // Stable: with two clips on one vertex (invalid), the first one is found,
            // as a scan would.
            list.sort_by_key(|&(vertex, _)| vertex);
        }
        Self {
            by_rod,
            probes: AtomicU64::new(0),
        }
    }

    /// The clip holding vertex `vertex` of rod `rod`, if any (the first one in the
    /// system's order).
    pub fn clip_at(&self, rod: usize, vertex: usize) -> Option<usize> {
        let list = self.by_rod.get(rod)?;
        let first = list.partition_point(|&(v, _)| v < vertex);
        let steps = usize::BITS - list.len().leading_zeros() + 1;
        self.probes.fetch_add(u64::from(steps), Ordering::Relaxed);
        list.get(first)
            .filter(|&&(v, _)| v == vertex)
            .map(|&(_, c)| c)
    }

    /// The clips on rod `rod` as `(vertex, clip)`, sorted by vertex.
    pub fn on_rod(&self, rod: usize) -> &[(usize, usize)] {
        self.by_rod.get(rod).map_or(&[], Vec::as_slice)
    }

    /// Number of clip entries examined by [`ClipIndex::clip_at`] since construction
    /// (about `log₂` of the rod's clip count per query).
    pub fn probes(&self) -> u64 {
        self.probes.load(Ordering::Relaxed)
    }
}

/// What a 3-block of unknowns is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BlockKind {
    /// A vertex position (m); its gradient is a force (N).
    Position,
    /// An edge rotation increment (rad); its gradient is a moment (N·m).
    Rotation,
}

/// Block numbering of a system's unknowns.
#[derive(Clone, Debug)]
pub struct Dofs {
    vertex_blocks: Vec<Vec<Option<usize>>>,
    edge_blocks: Vec<Vec<usize>>,
    body_blocks: Vec<Option<(usize, usize)>>,
    clip_blocks: Vec<Option<usize>>,
    kinds: Vec<BlockKind>,
    force_scale: Vec<f64>,
    clips: ClipIndex,
}

impl Dofs {
    /// Whether `other` numbers the same unknowns the same way (every block of every
    /// vertex, edge, body and clip, and the clips' vertices); the force scales, which
    /// follow the rods' lengths, may differ.
    pub fn same_numbering(&self, other: &Dofs) -> bool {
        self.vertex_blocks == other.vertex_blocks
            && self.edge_blocks == other.edge_blocks
            && self.body_blocks == other.body_blocks
            && self.clip_blocks == other.clip_blocks
            && self.kinds == other.kinds
            && self.clips.by_rod == other.clips.by_rod
    }

    /// Numbers the unknowns rod by rod, interleaving vertices and edges along each rod
    /// (a narrow band before any fill-reducing ordering). Linear in the number of
    /// vertices (times `log` of the clips per rod).
    pub fn new(system: &System) -> Self {
        let mut dofs = Self {
            vertex_blocks: vec![],
            edge_blocks: vec![],
            body_blocks: vec![],
            clip_blocks: vec![],
            kinds: vec![],
            force_scale: vec![],
            clips: ClipIndex::new(system),
        };
        for (r, spec) in system.rods.iter().enumerate() {
            let n = spec.rod.segments();
            let length = spec.rod.length();
            let mut vertices = vec![None; n + 1];
            let mut edges = Vec::with_capacity(n);
            for j in 0..=n {
                let held = (j == 0 && spec.start.support.is_held())
                    || (j == n && spec.end.support.is_held())
                    || dofs.clips.clip_at(r, j).is_some();
                if !held {
                    vertices[j] = Some(dofs.push(BlockKind::Position, 1.0));
                }
                if j < n {
                    edges.push(dofs.push(BlockKind::Rotation, length));
                }
            }
            dofs.vertex_blocks.push(vertices);
            dofs.edge_blocks.push(edges);
        }
        // Free bodies last: they couple the ends of several rods (an arrow-head pattern
        // that keeps each rod's band intact).
        let longest_rod = system
            .rods
            .iter()
            .map(|r| r.rod.length())
            .fold(0.0, f64::max);
        for body in &system.bodies {
            let blocks = (!body.fixed).then(|| {
                (
                    dofs.push(BlockKind::Position, 1.0),
                    dofs.push(BlockKind::Rotation, longest_rod),
                )
            });
            dofs.body_blocks.push(blocks);
        }
        // Clip joints: a scalar joint (revolute, prismatic) occupies the first component
        // of a 3-block; the two spare components carry a unit stiffness and stay zero.
        for clip in &system.clips {
            let block = match clip.joint {
                Joint::Fixed => None,
                Joint::Revolute { .. } | Joint::Spherical => {
                    Some(dofs.push(BlockKind::Rotation, longest_rod))
                }
                Joint::Prismatic { .. } => Some(dofs.push(BlockKind::Position, 1.0)),
            };
            dofs.clip_blocks.push(block);
        }
        dofs
    }

    /// The clip index built with the numbering.
    pub fn clips(&self) -> &ClipIndex {
        &self.clips
    }

    /// The clip holding vertex `vertex` of rod `rod`, if any (`O(log clips)`).
    pub fn clip_at(&self, rod: usize, vertex: usize) -> Option<usize> {
        self.clips.clip_at(rod, vertex)
    }

    /// Joint block of clip `clip`, `None` for a fixed joint.
    pub fn clip(&self, clip: usize) -> Option<usize> {
        self.clip_blocks[clip]
    }

    /// Translation and rotation blocks of body `body`, `None` if it is fixed.
    pub fn body(&self, body: usize) -> Option<(usize, usize)> {
        self.body_blocks[body]
    }

    fn push(&mut self, kind: BlockKind, scale: f64) -> usize {
        self.kinds.push(kind);
        self.force_scale.push(scale);
        self.kinds.len() - 1
    }

    /// Number of 3-blocks.
    pub fn block_count(&self) -> usize {
        self.kinds.len()
    }

    /// Number of scalar unknowns (3 per block).
    pub fn len(&self) -> usize {
        3 * self.kinds.len()
    }

    /// Whether there are no unknowns at all.
    pub fn is_empty(&self) -> bool {
        self.kinds.is_empty()
    }

    /// Block of vertex `j` of rod `rod`, `None` if it is held by a support.
    pub fn vertex(&self, rod: usize, vertex: usize) -> Option<usize> {
        self.vertex_blocks[rod][vertex]
    }

    /// Block of the rotation of edge `e` of rod `rod`.
    pub fn edge(&self, rod: usize, edge: usize) -> usize {
        self.edge_blocks[rod][edge]
    }

    /// Kind of a block.
    pub fn kind(&self, block: usize) -> BlockKind {
        self.kinds[block]
    }

    /// Length (m) that turns the block's gradient into a force: 1 for positions, the
    /// rod's length for rotations (a moment imbalance `M` acts like a force `M/L` at the
    /// rod's scale). The edge length would make the measure mesh-dependent: frames
    /// stored to round-off leave a moment residual of about `EI · 1e-16 / h̄`, which
    /// divided by `h` again grows as `1/h²` under refinement.
    pub fn force_scale(&self, block: usize) -> f64 {
        self.force_scale[block]
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::{UnitQuaternion, Vector3};
    use strand_rod::{Rod, Section};

    use crate::Model;
    use crate::system::{ClipSpec, End, Joint, Pose, RodHandle, RodSpec, System};

    /// A straight rod of `segments` edges with a fixed clip on every 4th vertex.
    fn clipped_rod(segments: usize) -> System {
        let section = Section::try_explicit(1e4, 1e4, 1.0, 1.0, 0.1, 0.0).unwrap();
        let along_x =
            UnitQuaternion::from_axis_angle(&Vector3::y_axis(), std::f64::consts::FRAC_PI_2);
        let h = 1.0 / segments as f64;
        let clips = (1..segments)
            .filter(|j| j % 4 == 0)
            .map(|j| ClipSpec {
                name: format!("c{j}"),
                body: None,
                parent: None,
                base: Pose {
                    position: Vector3::x() * (j as f64 * h),
                    orientation: along_x,
                },
                joint: Joint::Fixed,
                offset: Pose {
                    position: Vector3::zeros(),
                    orientation: UnitQuaternion::identity(),
                },
                rod: RodHandle(0),
                vertex: j,
                limits: None,
            })
            .collect();
        System {
            rods: vec![RodSpec {
                name: "rod".into(),
                rod: Rod::try_straight(section, 1.0, segments).unwrap(),
                start: End::clamped(Vector3::zeros(), along_x),
                end: End::free(),
                route: None,
            }],
            bodies: vec![],
            clips,
            gravity: Vector3::new(0.0, 0.0, -9.81),
        }
    }

    /// Model building asks the clip index once per vertex, each query costing about
    /// `log₂` of the clips: the work grows like `n log n`, not `n²` (issue 11: a scan
    /// of every clip per vertex). Counted, not timed.
    #[test]
    fn model_building_work_grows_linearly() {
        let work = |segments: usize| {
            let model = Model::try_new(clipped_rod(segments)).unwrap();
            let probes = model.dofs().clips().probes() as f64;
            assert!(probes > 0.0);
            probes
        };
        let (small, large) = (work(1000), work(8000));
        // n log n: 8 · log(2000)/log(250) ≈ 11; a scan per vertex would give 64.
        assert!(
            large / small < 12.0,
            "work ratio {} for 8× the size",
            large / small
        );
        // Per vertex, a handful of probes of a binary search over 2000 clips.
        assert!(
            large / 8001.0 < 3.0 * 12.0,
            "{} probes per vertex",
            large / 8001.0
        );
    }
}

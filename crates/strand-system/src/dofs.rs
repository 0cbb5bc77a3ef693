//! Numbering of the unknowns: 3-blocks of vertex positions and edge rotation increments.
//! Vertices held by a support are eliminated (they have no block).

use crate::system::{Joint, System};

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
}

impl Dofs {
    /// Numbers the unknowns rod by rod, interleaving vertices and edges along each rod
    /// (a narrow band before any fill-reducing ordering).
    pub fn new(system: &System) -> Self {
        let mut dofs = Self {
            vertex_blocks: vec![],
            edge_blocks: vec![],
            body_blocks: vec![],
            clip_blocks: vec![],
            kinds: vec![],
            force_scale: vec![],
        };
        for spec in &system.rods {
            let n = spec.rod.segments();
            let mut vertices = vec![None; n + 1];
            let mut edges = Vec::with_capacity(n);
            for j in 0..=n {
                let held = (j == 0 && spec.start.support.is_held())
                    || (j == n && spec.end.support.is_held())
                    || system
                        .clips
                        .iter()
                        .any(|c| c.rod.0 == dofs.vertex_blocks.len() && c.vertex == j);
                if !held {
                    vertices[j] = Some(dofs.push(BlockKind::Position, 1.0));
                }
                if j < n {
                    edges.push(dofs.push(BlockKind::Rotation, spec.rod.length()));
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

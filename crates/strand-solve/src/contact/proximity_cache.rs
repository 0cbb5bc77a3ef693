//! Incremental proximity: each rod feature (vertex sphere, edge capsule) keeps the
//! candidate triangles of every mesh near it from its last BVH search, and the next
//! evaluations (Newton iterates, line-search trials, advancement samples) look only at
//! those while the feature stays within the slack of where it was searched.
//!
//! **Why the contacts are those of a full search.** A search at segment `[a0, a1]` for
//! reach `r` and slack `σ` keeps the triangles [`ObstacleMesh::triangles_near`] lists:
//! those within `R = r + σ` that can matter for the local contacts of any segment
//! `[p0, p1]` with `|p0 − a0| ≤ σ` and `|p1 − a1| ≤ σ` and a reach up to `r` (the proof
//! is in its documentation; in short, every point `p0 + s (p1 − p0)` is within `(1 −
//! s)|p0 − a0| + s |p1 − a1| ≤ σ` of `a0 + s (a1 − a0)`, so every distance changes by at
//! most `σ`). [`ObstacleMesh::local_contacts_among`] computes the exact closest points
//! on the kept triangles with the same algorithm as a full search
//! ([`ObstacleMesh::local_contacts`]): the same contacts. A feature that moved farther,
//! or asks a longer reach, is searched again and keeps the new list. The mesh is
//! rigid and fixed within one [`super::Contact`], and distances are measured in world
//! coordinates, which a rigid placement preserves.
//!
//! **Far features.** A kept list also bounds its feature's distance from below however
//! far it moved ([`KeptTriangles::distance_lower_bound`]): the solver's rows leave out
//! the features more than [`super::FAR_MARGINS`] search margins clear of a mesh by that
//! bound, without a search or a closest point ([`Candidates::leave_far`],
//! `Constraints::rows_leaving_far`), and check each step against their clearances.

use std::collections::HashMap;
use std::sync::Mutex;

use nalgebra::Point3;
use strand_contact::{KeptTriangles, LocalContact, ObstacleMesh};

use crate::constraints::FarVertex;

/// How contact asks the meshes for the triangles near each rod feature.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProximitySettings {
    /// Keep each feature's candidate triangles between evaluations (`true`, the
    /// default) or search the BVH at every evaluation (`false`: for comparison; the
    /// contacts are the same either way).
    pub incremental: bool,
    /// How far a feature may move (in search margins) before it is searched again
    /// (negative counts as 0). Larger searches less often, and keeps more triangles
    /// per feature where the kept disc is short enough to list (on a fine surface, whose
    /// discs are not listed, it keeps more patches). Default 0.5 (0.1 until the kept
    /// discs of fine surfaces were no longer listed).
    pub slack_margins: f64,
}

impl Default for ProximitySettings {
    fn default() -> Self {
        Self {
            incremental: true,
            slack_margins: 0.5,
        }
    }
}

impl ProximitySettings {
    /// A full BVH search for every feature at every evaluation.
    pub fn full_queries() -> Self {
        Self {
            incremental: false,
            ..Self::default()
        }
    }
}

/// The kept candidates of the features of one rod near one mesh: vertex `j` at `2 j`,
/// edge `j` at `2 j + 1`.
type RodMeshLists = Vec<Option<KeptTriangles>>;

/// The kept candidates of every feature: shared by the evaluations of one solve.
/// A clone starts empty (a clone is another solve).
#[derive(Default)]
pub(super) struct ProximityCache {
    kept: Mutex<HashMap<(usize, usize), RodMeshLists>>,
}

impl Clone for ProximityCache {
    fn clone(&self) -> Self {
        Self::default()
    }
}

#[cfg(test)]
thread_local! {
    /// BVH searches made for features on this thread (tests only: the planted-bug
    /// test that a feature moved beyond its slack is searched again).
    pub(crate) static SEARCHES: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
}

/// The candidate lists of one evaluation, taken out of the cache for it.
pub(super) struct Candidates<'a> {
    cache: &'a ProximityCache,
    kept: HashMap<(usize, usize), RodMeshLists>,
    slack_m: f64,
    /// Leaving out the features farther than this (m) beyond their radius, with the
    /// vertices of those left out ([`Candidates::leave_far`]).
    far: Option<FarFeatures>,
}

/// The features an evaluation leaves out for being far from the meshes.
struct FarFeatures {
    /// Least clearance (m, beyond the rod's radius) of a feature left out.
    beyond_m: f64,
    /// The vertices of the features left out, with their clearances.
    vertices: Vec<FarVertex>,
}

/// The lists of one rod near one mesh, for one evaluation.
pub(super) struct FeatureLists<'a> {
    lists: &'a mut RodMeshLists,
    slack_m: f64,
    rod: usize,
    far: Option<&'a mut FarFeatures>,
}

/// Per vertex and per edge of a rod, the clearance (m) of those left out for being far
/// from a mesh ([`FeatureLists::far_features`]).
pub(super) struct FarMarks {
    /// Per vertex: its clearance (m) where its sphere is left out.
    pub(super) vertices: Vec<Option<f64>>,
    /// Per edge: its clearance (m) where its capsule is left out.
    pub(super) edges: Vec<Option<f64>>,
}

impl ProximityCache {
    /// The kept lists for one evaluation, with `slack_m` (m) of slack for the features
    /// searched again. Evaluations on other threads meanwhile start empty.
    pub(super) fn begin(&self, slack_m: f64) -> Candidates<'_> {
        let kept = std::mem::take(&mut *self.kept.lock().unwrap_or_else(|e| e.into_inner()));
        Candidates {
            cache: self,
            kept,
            slack_m,
            far: None,
        }
    }
}

impl Candidates<'_> {
    /// The lists of the features of rod `rod` (with `vertices` vertices) near mesh
    /// `mesh` (its index in the contact).
    pub(super) fn of(&mut self, rod: usize, mesh: usize, vertices: usize) -> FeatureLists<'_> {
        let lists = self.kept.entry((rod, mesh)).or_default();
        lists.resize_with(2 * vertices, || None);
        FeatureLists {
            lists,
            slack_m: self.slack_m,
            rod,
            far: self.far.as_mut(),
        }
    }

    /// Leaves out the features whose kept lists put them farther than `beyond_m` (m)
    /// beyond their radius from a mesh ([`FeatureLists::far_features`]).
    pub(super) fn leave_far(&mut self, beyond_m: f64) {
        self.far = Some(FarFeatures {
            beyond_m,
            vertices: Vec::new(),
        });
    }

    /// The lower bound (m) of the distance from edge `edge` of rod `rod`, now at
    /// segment `[p0, p1]` (world, m), to mesh `mesh` (its index in the contact) that
    /// the edge's kept list gives however far it moved
    /// ([`KeptTriangles::distance_lower_bound`]), without searching; `None` when it
    /// has no list.
    pub(super) fn edge_distance_lower_bound(
        &self,
        rod: usize,
        mesh: usize,
        edge: usize,
        p0: &Point3<f64>,
        p1: &Point3<f64>,
    ) -> Option<f64> {
        let kept = self.kept.get(&(rod, mesh))?.get(2 * edge + 1)?.as_ref()?;
        Some(kept.distance_lower_bound(p0, p1))
    }

    /// The vertices of the features left out so far, taken.
    pub(super) fn far_vertices(&mut self) -> Vec<FarVertex> {
        self.far
            .as_mut()
            .map(|far| std::mem::take(&mut far.vertices))
            .unwrap_or_default()
    }
}

impl FeatureLists<'_> {
    /// The triangles of `mesh` that can matter within `reach` (m) of vertex or edge
    /// `index` (`edge`) at segment `[p0, p1]` (world, m): its kept list if neither end
    /// moved by more than the slack searched with and the reach is not longer, else a
    /// new search. Ask it for the contacts with [`ObstacleMesh::local_contacts_kept`]
    /// (only the part that can matter after the move) or look at all of it
    /// ([`KeptTriangles::all`]).
    pub(super) fn near(
        &mut self,
        edge: bool,
        index: usize,
        mesh: &ObstacleMesh,
        p0: &Point3<f64>,
        p1: &Point3<f64>,
        reach: f64,
    ) -> &KeptTriangles {
        let slot = &mut self.lists[2 * index + usize::from(edge)];
        if !slot.as_ref().is_some_and(|kept| kept.covers(p0, p1, reach)) {
            #[cfg(test)]
            SEARCHES.with(|c| c.set(c.get() + 1));
            *slot = Some(mesh.keep_triangles_near(p0, p1, reach, self.slack_m));
        }
        slot.as_ref().expect("just kept")
    }

    /// The lower bound of the distance from vertex or edge `index` (`edge`) at segment
    /// `[p0, p1]` (world, m) to `mesh` that its kept list gives however far it moved
    /// ([`KeptTriangles::distance_lower_bound`]), without searching; `None` when it
    /// has no list yet.
    pub(super) fn distance_lower_bound(
        &self,
        edge: bool,
        index: usize,
        p0: &Point3<f64>,
        p1: &Point3<f64>,
    ) -> Option<f64> {
        self.lists[2 * index + usize::from(edge)]
            .as_ref()
            .map(|kept| kept.distance_lower_bound(p0, p1))
    }

    /// With far features left out ([`Candidates::leave_far`]): per vertex and edge of
    /// the rod (centreline `vertices`, m; `radius`, m), the clearance of those whose
    /// kept list's lower bound ([`KeptTriangles::distance_lower_bound`]) is more than
    /// the evaluation's `beyond_m` beyond the radius, except the vertices of an edge
    /// that is not left out (its rows depend on its vertices' contacts). Those within
    /// `margin_m` (m) of the mesh are listed as far vertices (an edge's at both of
    /// them), once per vertex with the least of its features' clearances; farther ones
    /// make no rows at all. `None` when nothing is left out.
    pub(super) fn far_features(
        &mut self,
        vertices: &[Point3<f64>],
        radius: f64,
        margin_m: f64,
    ) -> Option<FarMarks> {
        let beyond = self.far.as_ref()?.beyond_m;
        let clearance = |bound: Option<f64>| bound.map(|b| b - radius).filter(|&c| c > beyond);
        let mut marks = FarMarks {
            vertices: (0..vertices.len())
                .map(|j| {
                    let p = &vertices[j];
                    clearance(self.distance_lower_bound(false, j, p, p))
                })
                .collect(),
            edges: vertices
                .windows(2)
                .enumerate()
                .map(|(e, ab)| clearance(self.distance_lower_bound(true, e, &ab[0], &ab[1])))
                .collect(),
        };
        for (e, edge) in marks.edges.iter().enumerate() {
            if edge.is_none() {
                marks.vertices[e] = None;
                marks.vertices[e + 1] = None;
            }
        }
        // Per vertex, the least clearance of its left-out features within the margin
        // (its sphere, its two edges): one entry, checked once per step.
        let mut least = vec![f64::INFINITY; vertices.len()];
        let within = |c: &Option<f64>| c.filter(|&c| c <= margin_m);
        for (j, c) in marks.vertices.iter().enumerate() {
            if let Some(c) = within(c) {
                least[j] = least[j].min(c);
            }
        }
        for (e, c) in marks.edges.iter().enumerate() {
            if let Some(c) = within(c) {
                least[e] = least[e].min(c);
                least[e + 1] = least[e + 1].min(c);
            }
        }
        let far = self.far.as_mut().expect("checked above");
        let rod = self.rod;
        far.vertices
            .extend(least.iter().enumerate().filter(|(_, c)| c.is_finite()).map(
                |(vertex, &clearance_m)| FarVertex {
                    rod,
                    vertex,
                    clearance_m,
                },
            ));
        Some(marks)
    }

    /// Lets vertex or edge `index` (`edge`) measure its patches from the triangles of
    /// `contacts`, its own contacts just found among its kept candidates
    /// ([`KeptTriangles::follow`]): its next evaluation looks at fewer triangles, with
    /// the same answer.
    pub(super) fn follow(
        &mut self,
        edge: bool,
        index: usize,
        mesh: &ObstacleMesh,
        contacts: &[LocalContact],
    ) {
        if let Some(kept) = &mut self.lists[2 * index + usize::from(edge)] {
            kept.follow(mesh, contacts);
        }
    }
}

impl Drop for Candidates<'_> {
    /// Puts the lists back for the next evaluation.
    fn drop(&mut self) {
        let kept = std::mem::take(&mut self.kept);
        *self.cache.kept.lock().unwrap_or_else(|e| e.into_inner()) = kept;
    }
}

//! Vertex and edge gaps of one rod against one mesh: one per local contact (smooth
//! patch) of every vertex sphere and of every edge that crosses a convex feature.

use nalgebra::Point3;
use strand_contact::{Gap, LocalContact, Obstacle, ObstacleMesh, RodGeometry};
use strand_system::Model;

use super::proximity_cache::Candidates;
use super::{Contact, Feature, Tag};
use crate::constraints::ConstraintError;

/// How much nearer than both its vertices (relative to `1 + edge length`, m) an edge's
/// interior point must be to give a gap of its own.
const EDGE_BAND: f64 = 1e-12;

impl Contact {
    /// Vertex and edge gaps of rod `rod` against mesh `index`, appended to `out`.
    ///
    /// Every vertex is a sphere of the rod's radius with one gap per local contact
    /// (one per smooth patch it is near: both flanks of a groove, the three faces of a
    /// corner, one for a tessellated floor). An edge adds a gap of its own on a patch
    /// only where its nearest point on that patch lies strictly inside it and nearer
    /// than both its vertices (the edge crosses a convex feature), or at the inner ends
    /// of a stretch lying along the patch; where it crosses the patch, also at the ends
    /// of its nearly tied stretch (`LocalContact::near_tie`: the next ridges of a finely
    /// faceted surface, within about 1e-9 m of its nearest distance, which a small turn
    /// of the edge brings into contact at first order: without them the hose over a
    /// 256-facet drum crept towards lying on a face for 20 iterations).
    ///
    /// With `lists` each feature looks only at its kept candidate triangles
    /// (incremental proximity, [`super::proximity_cache`]; the same gaps as a full
    /// search), else every search goes through the mesh's BVH. With `only`, just the
    /// edges it marks and their vertices are listed (in the same order, with the
    /// same numbers). Where the lists leave far features out
    /// ([`super::proximity_cache::Candidates::leave_far`]), those are skipped and their
    /// vertices listed far.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn mesh_gaps(
        &self,
        model: &Model,
        rod: usize,
        geometry: &RodGeometry,
        index: usize,
        mesh: &ObstacleMesh,
        margin_m: f64,
        lists: Option<&mut Candidates>,
        only: Option<&[bool]>,
        out: &mut Vec<(Gap, Tag)>,
    ) -> Result<(), ConstraintError> {
        let reach = geometry.radius + margin_m;
        let vertices = geometry.vertices;
        let mut lists = lists.map(|l| l.of(rod, index, vertices.len()));
        // Features far from the mesh, left out where the evaluation asks for that.
        let far = lists
            .as_mut()
            .and_then(|l| l.far_features(vertices, geometry.radius, margin_m));
        let last_edge = vertices.len() - 2;
        let edge_listed = |edge: usize| {
            only.is_none_or(|only| only[edge])
                && far.as_ref().is_none_or(|f| f.edges[edge].is_none())
        };
        let vertex_listed = |j: usize| {
            ((j > 0 && only.is_none_or(|only| only[j - 1]))
                || (j <= last_edge && only.is_none_or(|only| only[j])))
                && far.as_ref().is_none_or(|f| f.vertices[j].is_none())
        };
        let touches = |point: &Point3<f64>| ConstraintError::CentrelineTouches {
            rod: model.system().rods[rod].name.clone(),
            what: format!("touches mesh '{}'", mesh.name()),
            point_mm: [point.x * 1e3, point.y * 1e3, point.z * 1e3],
        };
        let gap_of = |contact: &LocalContact, edge: usize, s: f64, point: Point3<f64>| {
            let near = &contact.proximity;
            let normal = near.normal.ok_or_else(|| touches(&near.point_on_mesh))?;
            let feature = Feature::on_mesh(mesh, near.triangle, near.barycentric, &normal);
            let gap = Gap {
                rod,
                edge,
                s,
                with: Obstacle::Mesh(index),
                point,
                witness: near.point_on_mesh,
                normal,
                gap: near.distance - geometry.radius,
            };
            Ok::<_, ConstraintError>((gap, feature))
        };
        // Per vertex: its local contacts (patch, distance).
        let mut vertex_contacts: Vec<Vec<(usize, f64)>> = vec![Vec::new(); vertices.len()];
        for (j, p) in vertices.iter().enumerate() {
            if !vertex_listed(j) || !Self::in_reach(mesh, p, p, reach) {
                continue;
            }
            let (edge, s) = if j <= last_edge {
                (j, 0.0)
            } else {
                (last_edge, 1.0)
            };
            let contacts = match lists.as_mut() {
                Some(lists) => {
                    let kept = lists.near(false, j, mesh, p, p, reach);
                    let contacts = mesh.local_contacts_kept(p, p, reach, kept, kept.moved_by(p, p));
                    lists.follow(false, j, mesh, &contacts);
                    contacts
                }
                None => mesh.local_contacts(p, p, reach),
            };
            for contact in contacts {
                vertex_contacts[j].push((contact.patch, contact.proximity.distance));
                let (gap, feature) = gap_of(&contact, edge, s, *p)?;
                out.push((gap, Tag::new(contact.patch, 0, feature)));
            }
        }
        // A vertex's distance to a patch: its contact there, else its nearest contact.
        let distance_to = |j: usize, patch: usize| {
            let contacts = &vertex_contacts[j];
            contacts
                .iter()
                .find(|(p, _)| *p == patch)
                .or_else(|| contacts.first())
                .map_or(f64::INFINITY, |(_, d)| *d)
        };
        for edge in 0..=last_edge {
            let (a, b) = (&vertices[edge], &vertices[edge + 1]);
            if !edge_listed(edge) || !Self::in_reach(mesh, a, b, reach) {
                continue;
            }
            // The edge's candidates serve its nearest points too: the contact of such a
            // point on patch P depends only on triangles within the edge's distance to
            // P (plus a guard) of it, all kept for the edge (`triangles_near`).
            // The edge and its points look only at the part of its list that can matter
            // after the edge's move (`local_contacts_kept`).
            let kept = lists
                .as_mut()
                .map(|l| l.near(true, edge, mesh, a, b, reach));
            let moved = kept.map_or(0.0, |kept| kept.moved_by(a, b));
            let contacts_of = |p0: &Point3<f64>, p1: &Point3<f64>| match kept {
                Some(kept) => mesh.local_contacts_kept(p0, p1, reach, kept, moved),
                None => mesh.local_contacts(p0, p1, reach),
            };
            let edge_contacts = contacts_of(a, b);
            for contact in &edge_contacts {
                let near = &contact.proximity;
                let patch = contact.patch;
                // Where the edge runs along the patch over a stretch (lying on a face and
                // overhanging its ridge), the stretch's inner ends hold it; otherwise an
                // interior point nearer than both vertices (the edge crosses a ridge).
                let [low, high] = near.tie;
                let band = EDGE_BAND * (1.0 + (b - a).norm());
                let interior = near.s > 0.0 && near.s < 1.0;
                let nearer = near.distance + band
                    < distance_to(edge, patch).min(distance_to(edge + 1, patch));
                // Where the edge crosses the patch (its nearest points strictly inside
                // it), the ends of the nearly tied stretch hold it too: the next ridges
                // of a finely faceted surface, which a small turn of the edge brings
                // into contact at first order.
                let [near_low, near_high] = contact.near_tie;
                let mut points: Vec<(f64, u8)> = if high - low > 1e-9 {
                    [(low, 1), (high, 2)]
                        .into_iter()
                        .filter(|(s, _)| *s > 0.0 && *s < 1.0)
                        .collect()
                } else if interior && nearer {
                    vec![(near.s, 0)]
                } else {
                    vec![]
                };
                let crossing = low > 0.0 && high < 1.0 && (high - low > 1e-9 || nearer);
                if crossing {
                    if low - near_low > 1e-9 && near_low > 0.0 {
                        points.push((near_low, 3));
                    }
                    if near_high - high > 1e-9 && near_high < 1.0 {
                        points.push((near_high, 4));
                    }
                }
                for (s, end) in points {
                    // The point's own contact on the patch (exact for a point).
                    let point = a + (b - a) * s;
                    let Some(at) = contacts_of(&point, &point)
                        .into_iter()
                        .find(|c| c.patch == patch)
                    else {
                        continue;
                    };
                    let (gap, feature) = gap_of(&at, edge, s, point)?;
                    out.push((gap, Tag::new(patch, end, feature)));
                }
            }
            if let Some(lists) = lists.as_mut() {
                lists.follow(true, edge, mesh, &edge_contacts);
            }
        }
        Ok(())
    }

    /// Whether segment `[a, b]` is within `reach` (m) of the mesh's bounding box: most
    /// features are far from most meshes, ruled out without a BVH search.
    pub(super) fn in_reach(
        mesh: &ObstacleMesh,
        a: &Point3<f64>,
        b: &Point3<f64>,
        reach: f64,
    ) -> bool {
        super::nearby::count_mesh_pair();
        let [low, high] = mesh.bounding_box();
        let outside = (0..3)
            .map(|k| {
                (low[k] - a[k].max(b[k]))
                    .max(a[k].min(b[k]) - high[k])
                    .max(0.0)
            })
            .fold(0.0, |sum: f64, d| sum + d * d);
        outside <= reach * reach
    }
}

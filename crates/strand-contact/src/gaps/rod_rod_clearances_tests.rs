//! Rod–rod clearances ([`super::rod_rod_clearances`]) against the least of every pair
//! of edges within the reach ([`super::rod_rod_gaps`], the brute-force reference), and
//! their work at two discretisations (counted, not timed).

use nalgebra::Point3;

use super::edge_tree::NODES_VISITED;
use super::{Gap, Obstacle, RodGeometry, rod_rod_clearances, rod_rod_gaps};

/// Excluded like the solver's near neighbours: closer than π r along the rod (edge
/// lengths `h` per rod).
fn near_along(h: Vec<f64>, radius: f64) -> impl Fn(usize, usize, usize, usize) -> bool {
    move |ra, a, rb, b| ra == rb && (b - a - 1) as f64 * h[ra] < std::f64::consts::PI * radius
}

/// The first least gap (clamped at zero) of each pair of rods among `gaps` (listed in
/// `(rod, edge, partner)` order), as a report picks it.
fn least_per_pair(gaps: &[Gap]) -> Vec<Gap> {
    let mut out: Vec<Gap> = Vec::new();
    for gap in gaps {
        let Obstacle::Rod { rod: b, .. } = gap.with else {
            unreachable!("rod–rod gaps only")
        };
        let same =
            |g: &Gap| matches!(g.with, Obstacle::Rod { rod, .. } if rod == b) && g.rod == gap.rod;
        match out.iter_mut().find(|g| same(g)) {
            Some(g) if gap.gap.max(0.0) < g.gap.max(0.0) => *g = *gap,
            Some(_) => {}
            None => out.push(*gap),
        }
    }
    out.sort_by_key(|g| match g.with {
        Obstacle::Rod { rod, .. } => (g.rod, rod),
        _ => unreachable!(),
    });
    out
}

/// A hairpin (two straight legs 30 mm apart joined by a half circle), a straight rod
/// crossing over both legs 12 mm above them, and a straight rod far away.
fn scene(segments: usize) -> Vec<Vec<Point3<f64>>> {
    let h = 0.6 / segments as f64;
    let hairpin: Vec<Point3<f64>> = (0..=segments)
        .map(|j| {
            let s = j as f64 * h;
            let (leg, turn) = (0.25, std::f64::consts::PI * 0.015);
            if s <= leg {
                Point3::new(s, 0.0, 0.0)
            } else if s <= leg + turn {
                let angle = (s - leg) / 0.015;
                Point3::new(leg + 0.015 * angle.sin(), 0.015 * (1.0 - angle.cos()), 0.0)
            } else {
                Point3::new(leg - (s - leg - turn), 0.03, 0.0)
            }
        })
        .collect();
    let across: Vec<Point3<f64>> = (0..=segments / 4)
        .map(|j| Point3::new(0.1, -0.05 + 0.13 * j as f64 / (segments / 4) as f64, 0.012))
        .collect();
    let far: Vec<Point3<f64>> = (0..=10)
        .map(|j| Point3::new(5.0 + 0.01 * j as f64, 5.0, 5.0))
        .collect();
    vec![hairpin, across, far]
}

#[test]
fn rod_rod_clearances_are_the_least_of_every_pair_of_edges() {
    for segments in [120, 481] {
        let centrelines = scene(segments);
        let h: Vec<f64> = (centrelines.iter()).map(|v| (v[1] - v[0]).norm()).collect();
        let radius = 0.004;
        let rods: Vec<RodGeometry> = (centrelines.iter())
            .map(|v| RodGeometry {
                vertices: v,
                radius,
            })
            .collect();
        let reach = 0.1;
        let all = rod_rod_gaps(&rods, reach, near_along(h.clone(), radius)).unwrap();
        let expected = least_per_pair(&all);
        let got = rod_rod_clearances(&rods, reach, near_along(h, radius)).unwrap();
        // Each rod with itself (its own edges past the excluded run; the hairpin's legs
        // and turn), the hairpin with the crossing rod; the far rod with no other.
        assert_eq!(got.len(), expected.len(), "{got:?}");
        assert_eq!(got.len(), 4, "{got:?}");
        for (g, e) in got.iter().zip(&expected) {
            assert_eq!((g.rod, g.edge, g.with), (e.rod, e.edge, e.with));
            assert_eq!(g.gap.to_bits(), e.gap.to_bits());
        }
    }
}

/// Tree nodes visited for a straight rod of `segments` edges (1 m) with a 0.1 m reach.
fn nodes(segments: usize, clearances: bool) -> u64 {
    let h = 1.0 / segments as f64;
    let vertices: Vec<Point3<f64>> = (0..=segments)
        .map(|j| Point3::new(j as f64 * h, 0.0, 0.0))
        .collect();
    let radius = 0.002;
    let rods = [RodGeometry {
        vertices: &vertices,
        radius,
    }];
    NODES_VISITED.with(|c| c.set(0));
    if clearances {
        rod_rod_clearances(&rods, 0.1, near_along(vec![h], radius)).unwrap();
    } else {
        rod_rod_gaps(&rods, 0.1, near_along(vec![h], radius)).unwrap();
    }
    NODES_VISITED.with(|c| c.get())
}

/// A straight rod's own edges within a report's reach beyond the excluded run are
/// `reach / h` per edge: listing them grows 16× for 4× the segments; the clearance
/// search, whose reach shrinks to the first partner's gap, about 4× (times a log).
#[test]
fn rod_rod_clearance_work_grows_linearly_in_the_segments() {
    let (small, large) = (nodes(500, true), nodes(2000, true));
    let ratio = large as f64 / small as f64;
    assert!(
        ratio < 6.0,
        "clearance search grew {ratio:.1}× for 4× the segments"
    );
    // The planted bug: the list of every pair within the reach (at 2000 segments 400k
    // gaps, 50 MB; the 8027-segment cable that found it listed 13M).
    let listing = nodes(2000, false) as f64 / nodes(500, false) as f64;
    assert!(
        listing > 10.0,
        "listing grew {listing:.1}× (expected about 16×)"
    );
}

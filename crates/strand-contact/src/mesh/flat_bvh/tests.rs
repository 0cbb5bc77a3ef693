//! The tree's shape against its definition: boxes the unions of their children's,
//! leaves in cluster order, the splits at the highest differing Morton bit, and the
//! checks a cache file read back must pass.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::build::split_point;
use super::search::STACK_CAPACITY;
use super::{FlatBvh, LEAF, NodeBox};

/// A random box per cluster (independent of the codes: the tree must not care).
fn random_boxes(rng: &mut ChaCha8Rng, clusters: usize) -> Vec<NodeBox> {
    (0..clusters)
        .map(|_| {
            let low: [f64; 3] = std::array::from_fn(|_| rng.random_range(-1.0..1.0));
            let size: [f64; 3] = std::array::from_fn(|_| rng.random_range(0.0..0.1));
            [
                low[0],
                low[1],
                low[2],
                low[0] + size[0],
                low[1] + size[1],
                low[2] + size[2],
            ]
        })
        .collect()
}

/// Sorted random codes of `bits` bits (few bits: long runs of equal codes).
fn random_codes(rng: &mut ChaCha8Rng, clusters: usize, bits: u32) -> Vec<u64> {
    let mut codes: Vec<u64> = (0..clusters)
        .map(|_| rng.random::<u64>() >> (64 - bits))
        .collect();
    codes.sort_unstable();
    codes
}

/// Checks the subtree at `node` over clusters `first..`, returns (its cluster count,
/// its box, its depth).
fn check(
    tree: &FlatBvh,
    leaf_boxes: &[NodeBox],
    node: usize,
    first: usize,
) -> (usize, NodeBox, usize) {
    let link = tree.links[node];
    if link & LEAF != 0 {
        assert_eq!((link & !LEAF) as usize, first, "leaves in cluster order");
        assert_eq!(tree.boxes[node], leaf_boxes[first]);
        return (1, leaf_boxes[first], 1);
    }
    let (m, a, da) = check(tree, leaf_boxes, node + 1, first);
    assert_eq!(
        link as usize,
        node + 2 * m,
        "the right child follows the left subtree"
    );
    let (n, b, db) = check(tree, leaf_boxes, link as usize, first + m);
    let union: NodeBox = std::array::from_fn(|k| {
        if k < 3 {
            a[k].min(b[k])
        } else {
            a[k].max(b[k])
        }
    });
    assert_eq!(
        tree.boxes[node], union,
        "node {node}: the union of its children"
    );
    (m + n, union, 1 + da.max(db))
}

#[test]
fn every_node_box_is_the_union_of_its_children_and_the_leaves_come_in_order() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for (clusters, bits) in [
        (1, 63),
        (2, 63),
        (3, 1),
        (17, 4),
        (1000, 63),
        (5000, 12),
        (9000, 63),
        (4097, 0),
    ] {
        let codes = if bits == 0 {
            vec![7; clusters]
        } else {
            random_codes(&mut rng, clusters, bits)
        };
        let leaf_boxes = random_boxes(&mut rng, clusters);
        let tree = FlatBvh::build(&codes, &|c| leaf_boxes[c]);
        assert_eq!(tree.boxes.len(), 2 * clusters - 1);
        assert!(tree.is_well_formed(clusters));
        let (count, _, depth) = check(&tree, &leaf_boxes, 0, 0);
        assert_eq!(count, clusters);
        assert!(depth <= 94, "depth {depth}");
        let mut met = Vec::new();
        tree.depth_first(|_, _| true, |leaf| met.push(leaf as usize));
        assert_eq!(met, (0..clusters).collect::<Vec<_>>());
    }
    let empty = FlatBvh::build(&[], &|_| unreachable!());
    assert!(empty.boxes.is_empty() && empty.is_well_formed(0));
}

#[test]
fn a_run_is_split_where_its_highest_differing_bit_changes() {
    assert_eq!(split_point(&[0b000, 0b001, 0b100, 0b101]), 2);
    assert_eq!(split_point(&[0b000, 0b011, 0b100]), 2);
    assert_eq!(split_point(&[0b100, 0b101, 0b101, 0b110]), 3);
    assert_eq!(split_point(&[5, 5, 5, 5, 5]), 2);
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    for _ in 0..500 {
        let n = rng.random_range(2..40);
        let bits = rng.random_range(1..10);
        let codes = random_codes(&mut rng, n, bits);
        let split = split_point(&codes);
        assert!((1..n).contains(&split));
        if codes[0] != codes[n - 1] {
            // Every code before the split is below every code after it in the
            // highest bit where the run's ends differ.
            let bit = 63 - (codes[0] ^ codes[n - 1]).leading_zeros();
            assert!(codes[..split].iter().all(|c| c >> bit & 1 == 0));
            assert!(codes[split..].iter().all(|c| c >> bit & 1 == 1));
        }
    }
}

#[test]
fn damaged_arrays_are_not_well_formed() {
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    let clusters = 300;
    let codes = random_codes(&mut rng, clusters, 63);
    let leaf_boxes = random_boxes(&mut rng, clusters);
    let tree = FlatBvh::build(&codes, &|c| leaf_boxes[c]);
    assert!(tree.is_well_formed(clusters));
    assert!(!tree.is_well_formed(clusters + 1));
    let mut short = tree.clone();
    short.links.pop();
    assert!(!short.is_well_formed(clusters));
    for _ in 0..200 {
        let mut damaged = tree.clone();
        let node = rng.random_range(0..damaged.links.len());
        let old = damaged.links[node];
        let new = match rng.random_range(0..3) {
            0 => old ^ LEAF,
            1 => old.wrapping_add(1),
            _ => rng.random_range(0..damaged.links.len() as u32) | (old & LEAF),
        };
        if new == old {
            continue;
        }
        damaged.links[node] = new;
        assert!(
            !damaged.is_well_formed(clusters),
            "node {node}: {old} -> {new}"
        );
    }
    // A chain deeper than the searches' stack: node k of the left spine has the rest
    // of the spine on its left and a leaf on its right.
    let deep = STACK_CAPACITY + 5;
    let mut chain = FlatBvh {
        boxes: vec![[0.0; 6]; 2 * deep - 1],
        links: vec![0; 2 * deep - 1],
    };
    for k in 0..deep - 1 {
        let right = 2 * deep - 2 - k;
        chain.links[k] = right as u32;
        chain.links[right] = LEAF | (deep - 1 - k) as u32;
    }
    chain.links[deep - 1] = LEAF;
    assert!(!chain.is_well_formed(deep));
    // The same chain within the stack is well formed.
    let shallow = 40;
    let mut chain = FlatBvh {
        boxes: vec![[0.0; 6]; 2 * shallow - 1],
        links: vec![0; 2 * shallow - 1],
    };
    for k in 0..shallow - 1 {
        let right = 2 * shallow - 2 - k;
        chain.links[k] = right as u32;
        chain.links[right] = LEAF | (shallow - 1 - k) as u32;
    }
    chain.links[shallow - 1] = LEAF;
    assert!(chain.is_well_formed(shallow));
}

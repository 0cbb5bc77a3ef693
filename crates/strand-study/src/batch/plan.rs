//! The batch plan: every combination of the varied values (the grid), the
//! deterministic variant ids, the warm-start tree and the split into shards.
//!
//! **Grid.** Variants are numbered in grid order: the first `--vary` varies slowest.
//!
//! **Warm-start tree.** Each parameter has an *anchor*, the value nearest the case's
//! own (`+0` for offsets). The variant at all anchors starts from the solved case
//! itself; every other variant starts from its neighbour one step closer to the
//! anchor in the *last* parameter that is not at its anchor. So the variants along
//! each parameter line form chains that walk away from the case in single steps
//! (continuation), and the chains of different lines run in parallel. The tree
//! depends only on the `--vary` options, never on `--jobs` or `--shard`, so results
//! are the same however the batch is run.
//!
//! **Shards.** `--shard I/N` takes the I-th of N contiguous blocks of the tree's
//! depth-first order (sizes differ by at most one). A shard also solves the ancestors
//! of its variants that other shards own (without writing them), so every variant is
//! warm-started exactly as in the unsharded batch.

use strand_case::schema::VariantChange;

use super::spec::Vary;

/// One variant of the grid.
#[derive(Clone, Debug, PartialEq)]
pub struct Variant {
    /// Deterministic, filesystem-safe id: `hose2.length_p30mm__tee.mass_1.5kg`.
    pub id: String,
    /// Value index of every parameter.
    pub index: Vec<usize>,
    /// The variant it is warm-started from (`None`: the case itself).
    pub parent: Option<usize>,
}

/// The grid, its warm-start tree and its depth-first order.
#[derive(Clone, Debug)]
pub struct Plan {
    /// The varied parameters.
    pub varies: Vec<Vary>,
    /// The variants in grid order.
    pub variants: Vec<Variant>,
    /// Children of every variant in the warm-start tree, in grid order.
    pub children: Vec<Vec<usize>>,
    /// Variants started from the case itself (one: the all-anchor variant).
    pub roots: Vec<usize>,
    /// Depth-first order of the tree (parents before children).
    pub order: Vec<usize>,
}

/// Longest variant id, bytes: a folder name, within the 255 bytes file systems allow.
pub const MAX_ID_BYTES: usize = 240;

/// Most variants one batch may have.
pub const MAX_VARIANTS: usize = 1_000_000;

impl Plan {
    /// The plan of `varies` (at least one). Errors when the grid is too large or two
    /// variants would get the same id.
    pub fn new(varies: Vec<Vary>) -> Result<Self, String> {
        let count = varies
            .iter()
            .try_fold(1usize, |n, v| n.checked_mul(v.values.len()))
            .filter(|n| *n <= MAX_VARIANTS)
            .ok_or_else(|| {
                format!("--vary: the grid has more than {MAX_VARIANTS} variants; use fewer values")
            })?;
        let labels: Vec<&str> = varies.iter().map(|v| v.label.as_str()).collect();
        for (k, label) in labels.iter().enumerate() {
            if labels[..k].contains(label) {
                return Err(format!(
                    "--vary: '{label}' is varied twice; give each item one --vary"
                ));
            }
        }
        let anchors: Vec<usize> = varies.iter().map(Vary::anchor).collect();
        let sizes: Vec<usize> = varies.iter().map(|v| v.values.len()).collect();
        let flat = |index: &[usize]| index.iter().zip(&sizes).fold(0, |n, (i, s)| n * s + i);
        let mut variants = Vec::with_capacity(count);
        for n in 0..count {
            let mut index = vec![0; sizes.len()];
            let mut rest = n;
            for d in (0..sizes.len()).rev() {
                index[d] = rest % sizes[d];
                rest /= sizes[d];
            }
            let id = varies
                .iter()
                .zip(&index)
                .map(|(v, &k)| v.id_part(k))
                .collect::<Vec<_>>()
                .join("__");
            let parent = (0..index.len())
                .rev()
                .find(|&d| index[d] != anchors[d])
                .map(|d| {
                    let mut up = index.clone();
                    up[d] = if index[d] > anchors[d] {
                        index[d] - 1
                    } else {
                        index[d] + 1
                    };
                    flat(&up)
                });
            variants.push(Variant { id, index, parent });
        }
        if let Some(long) = variants.iter().find(|v| v.id.len() > MAX_ID_BYTES) {
            return Err(format!(
                "--vary: the variant id '{}' is {} bytes long; at most {MAX_ID_BYTES} (it is a folder name) (hint: vary fewer items at once, or name them by their short form, e.g. hose2.length)",
                crate::limits::shown(&long.id),
                long.id.len()
            ));
        }
        let mut ids: Vec<&str> = variants.iter().map(|v| v.id.as_str()).collect();
        ids.sort_unstable();
        if let Some(w) = ids.windows(2).find(|w| w[0] == w[1]) {
            return Err(format!("--vary: two variants get the same id '{}'", w[0]));
        }
        let mut children = vec![Vec::new(); count];
        let mut roots = Vec::new();
        for (n, v) in variants.iter().enumerate() {
            match v.parent {
                Some(p) => children[p].push(n),
                None => roots.push(n),
            }
        }
        let mut order = Vec::with_capacity(count);
        let mut stack: Vec<usize> = roots.iter().rev().copied().collect();
        while let Some(n) = stack.pop() {
            order.push(n);
            stack.extend(children[n].iter().rev());
        }
        Ok(Self {
            varies,
            variants,
            children,
            roots,
            order,
        })
    }

    /// Which variants shard `i` of `n` (1-based) owns: a contiguous block of the
    /// depth-first order.
    pub fn owned(&self, shard: Option<(usize, usize)>) -> Vec<bool> {
        let total = self.variants.len();
        let Some((i, n)) = shard else {
            return vec![true; total];
        };
        let (from, to) = ((i - 1) * total / n, i * total / n);
        let mut owned = vec![false; total];
        for &v in &self.order[from..to] {
            owned[v] = true;
        }
        owned
    }

    /// The ancestors of variant `n` on its own parameter line, nearest first, at most
    /// `count`, with their values of that parameter; and `n`'s own value. Empty for a
    /// root (started from the case itself).
    pub fn line_samples(&self, n: usize, count: usize) -> (Vec<(usize, f64)>, f64) {
        let index = &self.variants[n].index;
        let Some(parent) = self.variants[n].parent else {
            return (Vec::new(), 0.0);
        };
        let Some(d) = (0..index.len()).find(|&d| self.variants[parent].index[d] != index[d]) else {
            return (Vec::new(), 0.0);
        };
        let values = &self.varies[d].values;
        let mut samples = vec![(parent, values[self.variants[parent].index[d]])];
        let mut at = parent;
        while samples.len() < count {
            let Some(up) = self.variants[at].parent else {
                break;
            };
            let (a, b) = (&self.variants[at].index, &self.variants[up].index);
            if (0..a.len()).any(|k| k != d && a[k] != b[k]) {
                break;
            }
            samples.push((up, values[b[d]]));
            at = up;
        }
        (samples, values[index[d]])
    }

    /// The changes of variant `n` to the case (one per varied parameter), in the
    /// case's units.
    pub fn changes(&self, n: usize) -> Vec<VariantChange> {
        self.varies
            .iter()
            .zip(&self.variants[n].index)
            .map(|(v, &k)| v.change(k))
            .collect()
    }

    /// The owned variants and all their ancestors (what a shard must solve).
    pub fn needed(&self, owned: &[bool]) -> Vec<bool> {
        let mut needed = owned.to_vec();
        for n in 0..owned.len() {
            if owned[n] {
                let mut up = self.variants[n].parent;
                while let Some(p) = up {
                    if needed[p] {
                        break;
                    }
                    needed[p] = true;
                    up = self.variants[p].parent;
                }
            }
        }
        needed
    }
}

//! Work counters of the mesh queries on the calling thread: BVH nodes visited, triangle
//! bounding boxes tested and exact segment–triangle closest points computed.
//!
//! Complexity tests count work instead of timing it: a query whose cost grows with
//! the mesh density shows it in these counts at two densities of the same surface,
//! without a timer. The counters are plain thread-local integers (a few increments per
//! node), always on.

use std::cell::Cell;

thread_local! {
    static WORK: Cell<QueryWork> = const { Cell::new(QueryWork::ZERO) };
}

/// Work done by the mesh queries of one thread since it started (read it before and
/// after and subtract with [`QueryWork::since`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct QueryWork {
    /// BVH nodes (inner and leaf) visited by the searches.
    pub bvh_nodes: u64,
    /// Triangle bounding boxes tested against a query segment.
    pub box_tests: u64,
    /// Exact segment–triangle closest points computed.
    pub exact_tests: u64,
}

impl QueryWork {
    const ZERO: Self = Self {
        bvh_nodes: 0,
        box_tests: 0,
        exact_tests: 0,
    };

    /// The work done between `earlier` and `self` (both read on the same thread).
    pub fn since(&self, earlier: &QueryWork) -> QueryWork {
        QueryWork {
            bvh_nodes: self.bvh_nodes - earlier.bvh_nodes,
            box_tests: self.box_tests - earlier.box_tests,
            exact_tests: self.exact_tests - earlier.exact_tests,
        }
    }
}

/// The work counted on this thread so far.
pub fn query_work() -> QueryWork {
    WORK.with(Cell::get)
}

/// Adds to this thread's counters.
#[inline]
fn add(f: impl FnOnce(&mut QueryWork)) {
    WORK.with(|w| {
        let mut now = w.get();
        f(&mut now);
        w.set(now);
    });
}

/// Counts one BVH node visited.
#[inline]
pub(crate) fn count_node() {
    add(|w| w.bvh_nodes += 1);
}

/// Counts one triangle box tested.
#[inline]
pub(crate) fn count_box() {
    add(|w| w.box_tests += 1);
}

/// Counts one exact segment–triangle closest-point computation.
#[inline]
pub(crate) fn count_exact() {
    add(|w| w.exact_tests += 1);
}

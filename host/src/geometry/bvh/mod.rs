//! Bounding volume hierarchy: binned SAH build, collapsed to an eight-wide tree whose eight
//! child boxes are tested at once with SIMD, and an iterative closest-first traversal.
//!
//! The build sorts primitives into [`BIN_COUNT`] bins of their centroids along each axis and
//! takes the split with the lowest surface-area-heuristic cost (Wald 2007, "On fast construction
//! of SAH-based bounding volume hierarchies"). Nodes above `PARALLEL_NODE_THRESHOLD`
//! primitives (the top levels) compute their bounds, bins and a stable partition in parallel
//! chunks; below, subtrees are built in parallel with `rayon::join`. Bins and bounds merge by
//! exact min/max and integer sums, so the tree depends only on the input, never on the thread
//! count or scheduling. The binary tree is
//! then collapsed into eight-wide nodes (each binary node pulls up the grandchildren of its
//! largest-area interior children until it has eight; small subtrees of triangles become one
//! leaf where the surface area heuristic accepts it), as Embree does on AVX machines: a ray
//! then makes one eight-box SIMD test where the binary tree needed up to seven node visits
//! with one scalar box test each. Nodes store their children's boxes as structure-of-arrays
//! (256 bytes, four cache lines) and are laid out depth-first. Trees of
//! [`QUANTISE_MIN_PRIMITIVES`] or more primitives store them quantised instead (8-bit steps on
//! a per-node grid, rounded outward, 128 bytes): more instructions per box test, less memory
//! traffic where the nodes no longer fit in the caches.
//!
//! Two traversal kernels share one loop and one node layout: on CPUs with AVX2 (detected at
//! run time, `is_x86_feature_detected!`, so the binary still runs on any x86-64) the eight
//! boxes are one 256-bit operation, elsewhere two four-wide halves (`glam::Vec4`, SSE2 on
//! x86-64). Both do the same IEEE operations in the same order on every lane, so they visit the
//! same nodes in the same order and find bit-identical hits (test `kernels_visit_identically`).
//!
//! Why our own and not the `obvhs` crate (compressed eight-wide BVH, PLOC builder): measured on
//! the same triangles and rays with the same watertight triangle test (`docs/performance.md`,
//! "obvhs against the own BVH"), it traced 7–9% slower on 1k and 82k triangles and 16% faster
//! on 1.3 M than the earlier four-wide tree here, no clear win; and the traversal here must
//! keep the conservative box test (far distance enlarged by `1 + 2γ₃`) that the watertight
//! triangle test relies on, visit spheres and quads as primitives through one callback, and
//! give the same tree for any thread count.
//!
//! Files: `build.rs` (binary SAH tree), `collapse.rs` (binary to eight-wide), `wide_node.rs`
//! (the float and the quantised node layout), `traverse.rs` (both kernels for both layouts and
//! the loop), `tests.rs`.

mod build;
mod collapse;
mod kernel;
mod parts;
mod stats;
#[cfg(test)]
mod tests;
mod traverse;
mod tree;
mod wide_node;

pub use build::{BIN_COUNT, MAX_LEAF_SIZE, MAX_LEAF_SIZE_OTHER};
pub use collapse::{MERGE_LEAF_PRIMITIVES, WIDE_MERGE_MIN_PRIMITIVES};
pub use kernel::TraversalKernel;
pub use stats::{BvhStatistics, VisitCounts};

pub use tree::{Bvh, NodeLayout, QUANTISE_MIN_PRIMITIVES};

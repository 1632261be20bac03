//! The BVH ([`Bvh`]): its node layouts, its build, and the queries built on the traversal.

use super::build::{
    build_prims, build_prims_owned, build_tree, MAX_LEAF_SIZE, MAX_LEAF_SIZE_OTHER,
};
use super::collapse::{collapse, collapse_float};
use super::kernel::TraversalKernel;
use super::wide_node::{QuantNode, WideNode};
use crate::geometry::huge_pages::HugePageBuf;
use crate::geometry::Aabb;
use glam::Vec3A;
use rayon::prelude::*;

/// Trees over at least this many primitives get quantised nodes ([`NodeLayout::Auto`]): below,
/// the float nodes fit in the caches and their box test needs fewer instructions; above, the
/// memory traffic of 256-byte nodes costs more (`docs/performance.md`, "Quantised nodes").
pub const QUANTISE_MIN_PRIMITIVES: usize = 262_144;

/// How the eight-wide nodes store their child boxes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum NodeLayout {
    /// Quantised from [`QUANTISE_MIN_PRIMITIVES`] primitives on, float below.
    #[default]
    Auto,
    /// Six f32 planes per node (256 bytes).
    Float,
    /// 8-bit steps on a per-node grid, rounded outward (128 bytes); where a node cannot be
    /// quantised (extreme extents), the whole tree stays float.
    Quantised,
}

/// A BVH over primitives given by their bounds.
#[derive(Clone, Debug, Default)]
pub struct Bvh {
    /// Float nodes; empty when the tree is quantised.
    pub(super) nodes: HugePageBuf<WideNode>,
    /// Quantised nodes (the same tree, boxes rounded outward); empty when it is float.
    pub(super) qnodes: HugePageBuf<QuantNode>,
    /// Primitive indices (into the list given to [`Bvh::build`]) in leaf order.
    pub(super) order: Vec<u32>,
    /// Bounds of everything in the tree.
    pub(super) bounds: Option<Aabb>,
    /// The box-test kernel [`Bvh::traverse`] uses; [`TraversalKernel::Avx2`] only where the
    /// CPU has it.
    pub(super) kernel: TraversalKernel,
}

impl Bvh {
    /// Builds over primitives with the given bounds. Primitives with empty or non-finite bounds
    /// are left out (they can never be hit).
    pub fn build(bounds: &[Aabb]) -> Bvh {
        Self::build_with_layout(bounds, NodeLayout::Auto)
    }

    /// [`Bvh::build`] with a chosen node layout (benchmarks and tests compare them; the
    /// closest hits are the same either way).
    pub fn build_with_layout(bounds: &[Aabb], layout: NodeLayout) -> Bvh {
        Self::build_with_options(bounds, layout, true)
    }

    /// [`Bvh::build_with_layout`], saying whether the collapse may merge small subtrees into
    /// one leaf (up to [`MERGE_LEAF_PRIMITIVES`] primitives in trees over at least
    /// [`WIDE_MERGE_MIN_PRIMITIVES`], four below, where the surface area heuristic accepts it).
    /// Its cost model counts four-triangle passes (a leaf of triangles is tested four at a
    /// time), so callers whose primitives are not all triangles (analytic spheres, quads: tested
    /// one by one, several triangle tests each) pass `false`; their leaves then hold at most
    /// [`MAX_LEAF_SIZE_OTHER`] primitives. The closest hits are the same either way.
    pub fn build_with_options(bounds: &[Aabb], layout: NodeLayout, merge_leaves: bool) -> Bvh {
        // In parallel and in order, with the root's bounds in the same pass.
        let (prims, root) = build_prims(bounds);
        Self::build_from_prims(prims, root, layout, merge_leaves)
    }

    /// [`Bvh::build_with_options`] over boxes the caller no longer needs: the build's
    /// primitive references are written over the boxes' own storage instead of a new buffer
    /// (the same tree, with one large allocation and its page faults less).
    pub fn build_owned(bounds: Vec<Aabb>, layout: NodeLayout, merge_leaves: bool) -> Bvh {
        let (prims, root) = build_prims_owned(bounds);
        Self::build_from_prims(prims, root, layout, merge_leaves)
    }

    fn build_from_prims(
        mut prims: Vec<super::build::BuildPrim>,
        root: super::build::NodeBounds,
        layout: NodeLayout,
        merge_leaves: bool,
    ) -> Bvh {
        if prims.is_empty() {
            return Bvh::default();
        }
        // Quads and spheres (no merged leaves) in leaves of at most two.
        let max_leaf = if merge_leaves {
            MAX_LEAF_SIZE
        } else {
            MAX_LEAF_SIZE_OTHER
        };
        let binary = build_tree(&mut prims, 0, 0, root, max_leaf);
        let order: Vec<u32> = prims.par_iter().map(|p| p.index).collect();
        let root = &binary[0];
        let bounds = Some(Aabb {
            min: Vec3A::from(root.min),
            max: Vec3A::from(root.max),
        });
        let merge = if merge_leaves {
            super::collapse::merge_limit(order.len())
        } else {
            0
        };
        let quantise = match layout {
            NodeLayout::Auto => order.len() >= QUANTISE_MIN_PRIMITIVES,
            NodeLayout::Float => false,
            NodeLayout::Quantised => true,
        };
        // The primitive references are freed beside the collapse: giving back a large
        // buffer's pages is serial work in the kernel (milliseconds at a million primitives).
        // Each node is quantised from its own float boxes as the collapse makes it (the same
        // for any thread count); where one cannot be, the whole tree stays float.
        let ((), (nodes, qnodes)) = rayon::join(
            move || drop(prims),
            move || {
                let quantised = if quantise {
                    collapse::<QuantNode>(binary, merge)
                } else {
                    Err(binary)
                };
                match quantised {
                    Ok(q) => (HugePageBuf::default(), q),
                    Err(binary) => (collapse_float(binary, merge), HugePageBuf::default()),
                }
            },
        );
        Bvh {
            nodes,
            qnodes,
            order,
            bounds,
            kernel: TraversalKernel::best_available(),
        }
    }

    /// 64-bit FNV-1a hash of every node's bits and of the leaf order. Equal trees give equal
    /// fingerprints, so a change meant to keep the tree (a faster build) can be checked on
    /// scenes too large for a stored copy (the scaling bench prints it).
    pub fn fingerprint(&self) -> u64 {
        let mut h = 0xcbf2_9ce4_8422_2325u64;
        let mut mix = |w: u32| {
            for b in w.to_le_bytes() {
                h = (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
            }
        };
        for n in &self.nodes {
            for a in [&n.min_x, &n.min_y, &n.min_z, &n.max_x, &n.max_y, &n.max_z] {
                a.iter().for_each(|v| mix(v.to_bits()));
            }
            n.child.iter().for_each(|&c| mix(c));
            n.count.iter().for_each(|&c| mix(u32::from(c)));
            mix(n.slots);
        }
        for n in &self.qnodes {
            for v in n.origin.iter().chain(&n.scale) {
                mix(v.to_bits());
            }
            for q in n.lo.iter().chain(&n.hi).flatten() {
                mix(u32::from(*q));
            }
            n.child.iter().for_each(|&c| mix(c));
            n.count.iter().for_each(|&c| mix(u32::from(c)));
            mix(n.slots);
        }
        self.order.iter().for_each(|&i| mix(i));
        h
    }

    /// The node layout in use ([`NodeLayout::Float`] or [`NodeLayout::Quantised`]).
    pub fn layout(&self) -> NodeLayout {
        if self.qnodes.is_empty() {
            NodeLayout::Float
        } else {
            NodeLayout::Quantised
        }
    }

    /// Primitive indices (into the list given to [`Bvh::build`]) in leaf order.
    pub fn order_ref(&self) -> &[u32] {
        &self.order
    }

    /// Every leaf as `(first, count)`: primitives `first..first + count` in leaf order, sorted
    /// by `first`. The leaves partition the leaf order, so a caller can store each leaf's
    /// primitives together (e.g. transposed, for [`Bvh::traverse_leaves`]).
    pub fn leaves(&self) -> Vec<(u32, u32)> {
        let mut leaves: Vec<(u32, u32)> = if self.qnodes.is_empty() {
            self.nodes
                .par_iter()
                .flat_map_iter(|n| leaf_slots(&n.child, &n.count, n.slots))
                .collect()
        } else {
            self.qnodes
                .par_iter()
                .flat_map_iter(|n| leaf_slots(&n.child, &n.count, n.slots))
                .collect()
        };
        leaves.par_sort_unstable();
        leaves
    }

    /// Number of nodes (for statistics and memory estimates).
    pub fn node_count(&self) -> usize {
        self.nodes.len() + self.qnodes.len()
    }

    /// Bytes held by the node and order arrays.
    pub fn memory_bytes(&self) -> usize {
        self.nodes.len() * std::mem::size_of::<WideNode>()
            + self.qnodes.len() * std::mem::size_of::<QuantNode>()
            + self.order.len() * 4
    }

    /// Bounds of everything in the tree (empty box for an empty tree).
    pub fn bounds(&self) -> Aabb {
        self.bounds.unwrap_or(Aabb::EMPTY)
    }

    /// The box-test kernel in use.
    pub fn kernel(&self) -> TraversalKernel {
        self.kernel
    }

    /// Chooses the box-test kernel (for benchmarks and tests that compare them). Asking for
    /// [`TraversalKernel::Avx2`] on a CPU without AVX2 keeps the portable one. Hits are the
    /// same either way.
    pub fn set_kernel(&mut self, kernel: TraversalKernel) {
        self.kernel = match kernel {
            TraversalKernel::Avx2 if TraversalKernel::best_available() != kernel => {
                TraversalKernel::Portable
            }
            k => k,
        };
    }
}

/// The leaf slots of one wide node as `(first, count)`.
fn leaf_slots<'a>(
    child: &'a [u32; super::wide_node::WIDTH],
    count: &'a [u16; super::wide_node::WIDTH],
    slots: u32,
) -> impl Iterator<Item = (u32, u32)> + 'a {
    (0..(slots as usize).min(super::wide_node::WIDTH))
        .filter(move |&k| count[k] > 0)
        .map(move |k| (child[k], u32::from(count[k])))
}

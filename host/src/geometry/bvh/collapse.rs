//! Collapsing the binary build tree into eight-wide nodes, float or quantised, near the root
//! in parallel.
//!
//! Every wide node is made from its float form on the spot ([`WideOut::from_float`]), so a
//! quantised tree never holds the float nodes (a pass less over all nodes, half the bytes
//! written). Subtrees are collapsed in parallel into parts whose child references count from
//! the part's start; the parts are then copied once, in parallel, into their final slots
//! ([`place_parts`]), which is exactly the depth-first layout of a sequential collapse.

use glam::Vec3A;
use rayon::prelude::*;

use super::build::Node;
use super::parts::place_parts_huge;
use super::wide_node::{QuantNode, WideNode, WIDTH};
use crate::geometry::huge_pages::HugePageBuf;
use crate::geometry::Aabb;

/// A wide node layout the collapse writes.
pub(super) trait WideOut: Copy + Send + Sync {
    /// The stored form of a float node (child references are set afterwards); `None` where
    /// the layout cannot hold it, which makes the whole collapse give `None`.
    fn from_float(w: &WideNode) -> Option<Self>;
    /// Adds `base` to the child reference of every interior slot.
    fn rebase(&mut self, base: u32);
    /// Sets the child reference of `slot`.
    fn set_child(&mut self, slot: usize, child: u32);
}

/// Adds `base` to the references of the used slots with no primitive count (interior ones).
fn rebase_slots(child: &mut [u32; WIDTH], count: &[u16; WIDTH], slots: u32, base: u32) {
    for k in 0..(slots as usize).min(WIDTH) {
        if count[k] == 0 {
            child[k] += base;
        }
    }
}

impl WideOut for WideNode {
    fn from_float(w: &WideNode) -> Option<Self> {
        Some(*w)
    }
    fn rebase(&mut self, base: u32) {
        rebase_slots(&mut self.child, &self.count, self.slots, base);
    }
    fn set_child(&mut self, slot: usize, child: u32) {
        self.child[slot] = child;
    }
}

impl WideOut for QuantNode {
    fn from_float(w: &WideNode) -> Option<Self> {
        QuantNode::from_wide(w)
    }
    fn rebase(&mut self, base: u32) {
        rebase_slots(&mut self.child, &self.count, self.slots, base);
    }
    fn set_child(&mut self, slot: usize, child: u32) {
        self.child[slot] = child;
    }
}

/// Collapses the binary tree (depth-first, first child next, `offset` the second) into wide
/// nodes, depth-first. Each wide node takes its binary node's two children and repeatedly
/// replaces the interior one with the largest surface area by its two children, up to eight.
/// Small binary subtrees become one leaf slot where the surface area heuristic accepts it
/// ([`as_leaf`]); `merge` is [`MERGE_LEAF_PRIMITIVES`] to allow merging, 0 for none (the
/// heuristic counts every primitive test the same, which holds for triangles only: scenes with
/// analytic spheres or quads, whose tests cost several triangle tests, keep their binary
/// leaves).
///
/// Consumes the binary tree: its pages are given back (serial work in the kernel, a few
/// milliseconds at a million primitives) while the parts are placed. Gives it back where `T`
/// cannot hold a node (see [`WideOut::from_float`]).
pub(super) fn collapse<T: WideOut>(
    binary: Vec<Node>,
    merge: usize,
) -> Result<HugePageBuf<T>, Vec<Node>> {
    let root = if binary[0].count > 0 {
        Children::one(0, 0.0)
    } else {
        Children::of(&binary, 0)
    };
    let mut parts = Vec::new();
    let Some(total) = collapse_parts(&binary, root, 0, merge, &mut parts) else {
        return Err(binary);
    };
    let ((), nodes) = rayon::join(
        move || drop(binary),
        move || place_parts_huge(parts, total, |w: &mut T, start, _| w.rebase(start as u32)),
    );
    Ok(nodes)
}

/// [`collapse`] into float nodes, which hold every node.
pub(super) fn collapse_float(binary: Vec<Node>, merge: usize) -> HugePageBuf<WideNode> {
    collapse(binary, merge).unwrap_or_default()
}

/// Binary subtrees with at most this many primitives can become one leaf of the wide tree
/// (their primitives are contiguous in leaf order). The binary SAH splits small nodes as if a
/// box test cost one primitive test; in the wide tree a level costs an eight-box test on up to
/// four cache lines, so merging cuts node memory and node visits where the merged leaf costs
/// few extra primitive tests ([`MERGE_EXTRA_TESTS`]; `docs/performance.md`, "Larger leaves from
/// the collapse").
pub const MERGE_LEAF_PRIMITIVES: usize = 8;

/// Trees over fewer primitives merge only up to [`PASS_PRIMITIVES`] ([`merge_limit`]): their
/// nodes stay in the caches, so a node test saved is worth less than the second pass of a
/// larger leaf (1,280 triangles: +10% instructions per closest-hit ray with leaves of up to
/// eight, no faster by the clock); at 82k triangles the larger leaves are as fast, at 1.3 M the
/// saved node loads are worth more (closest hit −11%; `docs/performance.md`, "Huge pages, tree
/// statistics and leaves of up to eight in large trees").
pub const WIDE_MERGE_MIN_PRIMITIVES: usize = 16_384;

/// Leaves up to this size are tested in one four-lane pass (`leaf_triangles.rs`); larger merged
/// leaves take one pass per four.
const PASS_PRIMITIVES: usize = 4;

/// How many more four-triangle passes per visit of a merged leaf's box a merge of more than
/// [`PASS_PRIMITIVES`] may cost, against its separate binary leaves weighted by area: about the
/// wide node test it saves where the separate leaves would need a node of their own (Embree's
/// builder prices a node and a block of four alike). Below 0.75 almost nothing merges on the
/// scaling bench's spheres.
pub(super) const MERGE_EXTRA_PASSES: f32 = 1.0;

/// The largest merged leaf [`collapse`] may make for a tree over `primitives` primitives.
pub(super) fn merge_limit(primitives: usize) -> usize {
    if primitives >= WIDE_MERGE_MIN_PRIMITIVES {
        MERGE_LEAF_PRIMITIVES
    } else {
        PASS_PRIMITIVES
    }
}

/// How many more four-triangle passes per visit of a merged leaf's box a merge of at most
/// [`PASS_PRIMITIVES`] may cost, against its separate binary leaves weighted by area. Such a
/// leaf is one pass, as each of its parts is, so the merge pays where the merged box is not
/// much likelier to be reached than the parts together: small triangles of a smooth surface
/// merge, large ones far apart within their box (the Cornell box's walls) stay apart. A
/// saved node test is about a quarter of a pass (45 against some 195 instructions at 1,280
/// triangles), but per-triangle work after the pass (the lanes that pass the edge tests) grows
/// with the merged box, so the allowance is smaller (`docs/performance.md`, "Small leaves
/// merged by passes"): 0.1 makes the 1,280-triangle sphere's tree 140 → 79 wide nodes
/// (Embree's has 75) for +1% closest-hit instructions on the Cornell box; 0.2 costs the
/// Cornell box 3%, 0.5 23%. (Priced by primitive tests, as before the leaves were tested in
/// passes, almost nothing merged below 16,384 primitives.)
pub(super) const MERGE_SMALL_EXTRA_PASSES: f32 = 0.1;

/// The leaf slot binary node `i` becomes, `(first primitive, count)`: a binary leaf, or an
/// interior node whose subtree holds at most `merge` primitives and whose merged leaf the
/// surface area heuristic accepts, counted in four-triangle passes (see
/// [`MERGE_SMALL_EXTRA_PASSES`] and [`MERGE_EXTRA_PASSES`]); `None` otherwise. Visits at most
/// about twice `merge` nodes.
pub(super) fn as_leaf(binary: &[Node], i: usize, merge: usize) -> Option<(u32, u16)> {
    let n = &binary[i];
    if n.count > 0 {
        return Some((n.offset, n.count));
    }
    let (first, count, passes) = small_subtree(binary, i, merge)?;
    let area = node_area(n);
    // Expected four-triangle passes per visit of this box: the merged leaf's, against the
    // area-weighted passes of its separate leaves plus the allowance.
    let merged = (count as usize).div_ceil(PASS_PRIMITIVES) as f32;
    let allowance = if count as usize <= PASS_PRIMITIVES {
        MERGE_SMALL_EXTRA_PASSES
    } else {
        MERGE_EXTRA_PASSES
    };
    (merged * area <= passes + allowance * area).then_some((first, count))
}

/// `(first primitive, count, Σ passes · area)` over the binary leaves of the subtree under
/// binary node `i` if it holds at most `limit` primitives (passes: ⌈count / 4⌉).
fn small_subtree(binary: &[Node], i: usize, limit: usize) -> Option<(u32, u16, f32)> {
    let n = &binary[i];
    if n.count > 0 {
        return (n.count as usize <= limit).then(|| {
            let passes = (n.count as usize).div_ceil(PASS_PRIMITIVES) as f32;
            (n.offset, n.count, passes * node_area(n))
        });
    }
    // Each child holds at least one primitive.
    let (first, l, pl) = small_subtree(binary, i + 1, limit.checked_sub(1)?)?;
    let (_, r, pr) = small_subtree(binary, n.offset as usize, limit - l as usize)?;
    Some((first, l + r, pl + pr))
}

pub(super) fn binary_children(binary: &[Node], i: usize) -> [usize; 2] {
    [i + 1, binary[i].offset as usize]
}

pub(super) fn node_area(n: &Node) -> f32 {
    Aabb {
        min: Vec3A::from(n.min),
        max: Vec3A::from(n.max),
    }
    .surface_area()
}

/// Wide levels whose subtrees are collapsed in parallel (8² = 64 tasks at most).
pub(super) const PARALLEL_COLLAPSE_DEPTH: usize = 2;

/// The binary nodes that become one wide node's children (at most [`WIDTH`]), with their
/// surface areas (computed once per node, not once per expansion step).
#[derive(Clone, Copy)]
pub(super) struct Children {
    node: [usize; WIDTH],
    area: [f32; WIDTH],
    len: usize,
}

impl Children {
    fn one(i: usize, area: f32) -> Children {
        let mut c = Children {
            node: [0; WIDTH],
            area: [0.0; WIDTH],
            len: 1,
        };
        c.node[0] = i;
        c.area[0] = area;
        c
    }

    /// The two children of binary node `i`.
    pub(super) fn of(binary: &[Node], i: usize) -> Children {
        let [l, r] = binary_children(binary, i);
        let mut c = Children::one(l, node_area(&binary[l]));
        c.node[1] = r;
        c.area[1] = node_area(&binary[r]);
        c.len = 2;
        c
    }

    pub(super) fn nodes(&self) -> &[usize] {
        &self.node[..self.len]
    }
}

/// Expands `c` by repeatedly replacing the interior child with the largest box by its two
/// children, up to [`WIDTH`].
pub(super) fn expand_children(binary: &[Node], mut c: Children, merge: usize) -> Children {
    while c.len < WIDTH {
        // The interior child with the largest box (first such on ties, for determinism).
        let mut pick = None::<(usize, f32)>;
        for k in 0..c.len {
            if as_leaf(binary, c.node[k], merge).is_some() {
                continue;
            }
            let a = c.area[k];
            match pick {
                Some((_, ba)) if ba >= a => {}
                _ => pick = Some((k, a)),
            }
        }
        let Some((k, _)) = pick else { break };
        let [l, r] = binary_children(binary, c.node[k]);
        c.node.copy_within(k + 1..c.len, k + 2);
        c.area.copy_within(k + 1..c.len, k + 2);
        c.node[k] = l;
        c.area[k] = node_area(&binary[l]);
        c.node[k + 1] = r;
        c.area[k + 1] = node_area(&binary[r]);
        c.len += 1;
    }
    c
}

/// The float wide node over `children` (already expanded): boxes, leaf references and
/// counts; interior children's references are set by the caller.
fn wide_node(binary: &[Node], children: &Children, merge: usize) -> WideNode {
    let mut w = WideNode::EMPTY;
    w.set_slots(children.len);
    for (slot, &c) in children.nodes().iter().enumerate() {
        w.set_box(slot, &binary[c]);
        if let Some((first, count)) = as_leaf(binary, c, merge) {
            w.child[slot] = first;
            w.count[slot] = count;
        }
    }
    w
}

/// Appends the parts of the wide subtree over `children` to `parts` in depth-first order and
/// returns its node count. Interior child references count from the start of the part
/// holding the node. Near the root every wide node is a part of its own and its interior
/// children's subtrees are collapsed in parallel; from [`PARALLEL_COLLAPSE_DEPTH`] on a
/// subtree is one part, collapsed by [`fill_wide`].
fn collapse_parts<T: WideOut>(
    binary: &[Node],
    children: Children,
    depth: usize,
    merge: usize,
    parts: &mut Vec<Vec<T>>,
) -> Option<usize> {
    if depth >= PARALLEL_COLLAPSE_DEPTH {
        let mut out = Vec::with_capacity(wide_bound(binary, &children));
        fill_wide(binary, children, merge, &mut out)?;
        let n = out.len();
        parts.push(out);
        return Some(n);
    }
    let children = expand_children(binary, children, merge);
    let me = parts.len();
    parts.push(vec![T::from_float(&wide_node(binary, &children, merge))?]);
    let subs: Vec<Option<(Vec<Vec<T>>, usize)>> = children
        .nodes()
        .par_iter()
        .map(|&c| {
            let mut p = Vec::new();
            let n = if as_leaf(binary, c, merge).is_none() {
                collapse_parts(binary, Children::of(binary, c), depth + 1, merge, &mut p)?
            } else {
                0
            };
            Some((p, n))
        })
        .collect();
    // The node is its part's first element: its children's subtrees follow it in slot order.
    let mut next = 1;
    for (slot, (&c, sub)) in children.nodes().iter().zip(subs).enumerate() {
        let (p, n) = sub?;
        if as_leaf(binary, c, merge).is_none() {
            parts[me][0].set_child(slot, next as u32);
            next += n;
            parts.extend(p);
        }
    }
    Some(next)
}

/// An upper bound of the wide nodes over `children`: every wide node stands for a distinct
/// interior binary node, and a binary subtree of s nodes has (s − 1) / 2 interior ones. The
/// subtree of node c ends after its last descendant, found by following second children.
fn wide_bound(binary: &[Node], children: &Children) -> usize {
    children
        .nodes()
        .iter()
        .map(|&c| {
            let mut last = c;
            while binary[last].count == 0 {
                last = binary[last].offset as usize;
            }
            (last + 1 - c) / 2
        })
        .sum::<usize>()
        + 1
}

/// Appends the wide subtree over `children` (binary node indices) to `out`, depth-first:
/// expands them until there are [`WIDTH`], stores the node, then the subtrees of its
/// interior children. Child references are indices into `out`.
pub(super) fn fill_wide<T: WideOut>(
    binary: &[Node],
    children: Children,
    merge: usize,
    out: &mut Vec<T>,
) -> Option<()> {
    let children = expand_children(binary, children, merge);
    let me = out.len();
    out.push(T::from_float(&wide_node(binary, &children, merge))?);
    for (slot, &c) in children.nodes().iter().enumerate() {
        if as_leaf(binary, c, merge).is_none() {
            let idx = out.len() as u32;
            out[me].set_child(slot, idx);
            fill_wide(binary, Children::of(binary, c), merge, out)?;
        }
    }
    Some(())
}

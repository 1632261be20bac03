//! Collapsing the binary build tree into eight-wide nodes, near the root in parallel.

use glam::Vec3A;
use rayon::prelude::*;

use super::build::Node;
use super::wide_node::{WideNode, WIDTH};
use crate::geometry::Aabb;

/// Collapses the binary tree (depth-first, first child next, `offset` the second) into wide
/// nodes, depth-first. Each wide node takes its binary node's two children and repeatedly
/// replaces the interior one with the largest surface area by its two children, up to eight.
/// Small binary subtrees become one leaf slot where the surface area heuristic accepts it
/// ([`as_leaf`]).
///
/// `merge` is [`MERGE_LEAF_PRIMITIVES`] to allow merging, 0 for none (the heuristic counts
/// every primitive test the same, which holds for triangles only: scenes with analytic spheres
/// or quads, whose tests cost several triangle tests, keep their binary leaves).
pub(super) fn collapse(binary: &[Node], merge: usize) -> Vec<WideNode> {
    let root_children = if binary[0].count > 0 {
        vec![0]
    } else {
        binary_children(binary, 0).to_vec()
    };
    wide_subtree(binary, root_children, 0, merge)
}

/// Binary subtrees with at most this many primitives can become one leaf of the wide tree
/// (their primitives are contiguous in leaf order). The binary SAH splits small nodes as if a
/// box test cost one primitive test; in the wide tree a level costs an eight-box test on up to
/// four cache lines, so merging cuts node memory and node visits where the merged leaf costs
/// few extra primitive tests ([`MERGE_EXTRA_TESTS`]; `docs/performance.md`, "Larger leaves from
/// the collapse").
pub const MERGE_LEAF_PRIMITIVES: usize = 4;

/// How many more primitive tests per visit of a merged leaf's box the merge may cost, against
/// its separate binary leaves weighted by area (the surface area heuristic's hit
/// probabilities). Small triangles of a smooth surface merge; large ones far apart within
/// their box (the Cornell box's walls) stay apart. Measured (`docs/performance.md`, "Larger
/// leaves from the collapse"): 2 already costs the Cornell box 9.5% more instructions in
/// closest-hit queries, 1.5 none, 1 merges almost nothing on the spheres of the scaling bench.
pub(super) const MERGE_EXTRA_TESTS: f32 = 1.5;

/// The leaf slot binary node `i` becomes, `(first primitive, count)`: a binary leaf, or an
/// interior node whose subtree holds at most `merge` primitives and whose merged leaf the
/// surface area heuristic accepts (see [`MERGE_EXTRA_TESTS`]); `None` otherwise. Visits at
/// most about twice `merge` nodes.
pub(super) fn as_leaf(binary: &[Node], i: usize, merge: usize) -> Option<(u32, u16)> {
    let n = &binary[i];
    if n.count > 0 {
        return Some((n.offset, n.count));
    }
    let (first, count, tests) = small_subtree(binary, i, merge)?;
    let area = node_area(n);
    // Expected triangle tests per visit of this box: all `count` as one leaf, against the
    // area-weighted tests of its separate leaves plus the allowance.
    (count as f32 * area <= tests + MERGE_EXTRA_TESTS * area).then_some((first, count))
}

/// `(first primitive, count, Σ count · area over its binary leaves)` of the subtree under
/// binary node `i` if it holds at most `limit` primitives.
fn small_subtree(binary: &[Node], i: usize, limit: usize) -> Option<(u32, u16, f32)> {
    let n = &binary[i];
    if n.count > 0 {
        return (n.count as usize <= limit)
            .then(|| (n.offset, n.count, n.count as f32 * node_area(n)));
    }
    // Each child holds at least one primitive.
    let (first, l, tl) = small_subtree(binary, i + 1, limit.checked_sub(1)?)?;
    let (_, r, tr) = small_subtree(binary, n.offset as usize, limit - l as usize)?;
    Some((first, l + r, tl + tr))
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

/// The wide subtree over `children` (binary node indices) with its root at index 0 and child
/// indices relative to it. Near the root the interior children's subtrees are collapsed in
/// parallel and appended in slot order, which is exactly the depth-first layout
/// [`fill_wide`] makes, so the result is the same for any thread count.
pub(super) fn wide_subtree(
    binary: &[Node],
    children: Vec<usize>,
    depth: usize,
    merge: usize,
) -> Vec<WideNode> {
    let mut out = vec![WideNode::EMPTY];
    if depth >= PARALLEL_COLLAPSE_DEPTH {
        fill_wide(binary, children, 0, &mut out, merge);
        return out;
    }
    let children = expand_children(binary, children, merge);
    let subs = children
        .par_iter()
        .map(|&c| match as_leaf(binary, c, merge) {
            Some(leaf) => Err(leaf),
            None => Ok(wide_subtree(
                binary,
                binary_children(binary, c).to_vec(),
                depth + 1,
                merge,
            )),
        })
        .collect::<Vec<_>>();
    out[0].slots = children.len() as u32;
    for (slot, (&c, sub)) in children.iter().zip(subs).enumerate() {
        out[0].set_box(slot, &binary[c]);
        match sub {
            Err((first, count)) => {
                out[0].child[slot] = first;
                out[0].count[slot] = count;
            }
            Ok(sub) => {
                let base = out.len() as u32;
                out[0].child[slot] = base;
                out.extend(sub.into_iter().map(|mut w| {
                    for k in 0..w.slots as usize {
                        if w.count[k] == 0 {
                            w.child[k] += base;
                        }
                    }
                    w
                }));
            }
        }
    }
    out
}

/// Expands `children` (binary node indices) by repeatedly replacing the interior one with the
/// largest box by its two children, up to [`WIDTH`].
pub(super) fn expand_children(
    binary: &[Node],
    mut children: Vec<usize>,
    merge: usize,
) -> Vec<usize> {
    while children.len() < WIDTH {
        // The interior child with the largest box (first such on ties, for determinism).
        let pick = children
            .iter()
            .enumerate()
            .filter(|(_, &c)| as_leaf(binary, c, merge).is_none())
            .fold(None::<(usize, f32)>, |best, (k, &c)| {
                let a = node_area(&binary[c]);
                match best {
                    Some((_, ba)) if ba >= a => best,
                    _ => Some((k, a)),
                }
            });
        let Some((k, _)) = pick else { break };
        let c = children[k];
        let [l, r] = binary_children(binary, c);
        children[k] = l;
        children.insert(k + 1, r);
    }
    children
}

/// Fills wide node `me` with the subtrees `children` (binary node indices), expanding interior
/// ones until there are [`WIDTH`], then builds the wide nodes of the interior children.
pub(super) fn fill_wide(
    binary: &[Node],
    children: Vec<usize>,
    me: usize,
    out: &mut Vec<WideNode>,
    merge: usize,
) {
    let children = expand_children(binary, children, merge);
    out[me].slots = children.len() as u32;
    for (slot, &c) in children.iter().enumerate() {
        out[me].set_box(slot, &binary[c]);
        if let Some((first, count)) = as_leaf(binary, c, merge) {
            out[me].child[slot] = first;
            out[me].count[slot] = count;
        } else {
            let idx = out.len();
            out.push(WideNode::EMPTY);
            out[me].child[slot] = idx as u32;
            fill_wide(binary, binary_children(binary, c).to_vec(), idx, out, merge);
        }
    }
}

//! Collapsing the binary build tree into eight-wide nodes, near the root in parallel.

use glam::Vec3A;
use rayon::prelude::*;

use super::build::Node;
use super::wide_node::{WideNode, WIDTH};
use crate::geometry::Aabb;

/// Collapses the binary tree (depth-first, first child next, `offset` the second) into wide
/// nodes, depth-first. Each wide node takes its binary node's two children and repeatedly
/// replaces the interior one with the largest surface area by its two children, up to eight.
pub(super) fn collapse(binary: &[Node]) -> Vec<WideNode> {
    let root_children = if binary[0].count > 0 {
        vec![0]
    } else {
        binary_children(binary, 0).to_vec()
    };
    wide_subtree(binary, root_children, 0)
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
pub(super) fn wide_subtree(binary: &[Node], children: Vec<usize>, depth: usize) -> Vec<WideNode> {
    let mut out = vec![WideNode::EMPTY];
    if depth >= PARALLEL_COLLAPSE_DEPTH {
        fill_wide(binary, children, 0, &mut out);
        return out;
    }
    let children = expand_children(binary, children);
    let subs: Vec<Option<Vec<WideNode>>> = children
        .par_iter()
        .map(|&c| {
            (binary[c].count == 0)
                .then(|| wide_subtree(binary, binary_children(binary, c).to_vec(), depth + 1))
        })
        .collect();
    out[0].slots = children.len() as u32;
    for (slot, (&c, sub)) in children.iter().zip(subs).enumerate() {
        let n = &binary[c];
        out[0].set_box(slot, n);
        match sub {
            None => {
                out[0].child[slot] = n.offset;
                out[0].count[slot] = n.count;
            }
            Some(sub) => {
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
pub(super) fn expand_children(binary: &[Node], mut children: Vec<usize>) -> Vec<usize> {
    while children.len() < WIDTH {
        // The interior child with the largest box (first such on ties, for determinism).
        let pick = children
            .iter()
            .enumerate()
            .filter(|(_, &c)| binary[c].count == 0)
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
pub(super) fn fill_wide(binary: &[Node], children: Vec<usize>, me: usize, out: &mut Vec<WideNode>) {
    let children = expand_children(binary, children);
    out[me].slots = children.len() as u32;
    for (slot, &c) in children.iter().enumerate() {
        let n = &binary[c];
        out[me].set_box(slot, n);
        if n.count > 0 {
            out[me].child[slot] = n.offset;
            out[me].count[slot] = n.count;
        } else {
            let idx = out.len();
            out.push(WideNode::EMPTY);
            out[me].child[slot] = idx as u32;
            fill_wide(binary, binary_children(binary, c).to_vec(), idx, out);
        }
    }
}

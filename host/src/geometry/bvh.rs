//! Bounding volume hierarchy: binned SAH build, flattened depth-first nodes, iterative
//! near-first traversal.
//!
//! The build sorts primitives into [`BIN_COUNT`] bins of their centroids along each axis and
//! takes the split with the lowest surface-area-heuristic cost (Wald 2007, "On fast construction
//! of SAH-based bounding volume hierarchies"). Large subtrees are built on two threads with
//! `rayon::join`; the result depends only on the input, never on scheduling. Nodes are 32 bytes
//! and stored depth-first, so an interior node's first child is the next node in the array.

use glam::Vec3A;

use super::{Aabb, Ray};

/// Number of centroid bins per axis in the SAH build.
pub const BIN_COUNT: usize = 16;
/// Leaves hold at most this many primitives.
pub const MAX_LEAF_SIZE: usize = 4;
/// Cost of visiting a node relative to one primitive test, in the SAH.
const TRAVERSAL_COST: f32 = 1.0;
/// Subtrees with more primitives than this are built in parallel.
const PARALLEL_THRESHOLD: usize = 16 * 1024;
/// Traversal stack depth; the build keeps the tree shallower than this (see `build_range`).
const STACK_SIZE: usize = 64;

/// One flattened node (32 bytes).
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
struct Node {
    min: [f32; 3],
    /// Leaf: first primitive (in [`Bvh::order`] order). Interior: index of the second child.
    offset: u32,
    max: [f32; 3],
    /// Number of primitives; 0 for interior nodes.
    count: u16,
    /// Split axis of an interior node (decides near-first order).
    axis: u8,
    _pad: u8,
}

/// A BVH over primitives given by their bounds.
#[derive(Clone, Debug, Default)]
pub struct Bvh {
    nodes: Vec<Node>,
    /// Primitive indices (into the list given to [`Bvh::build`]) in leaf order.
    order: Vec<u32>,
}

#[derive(Clone, Copy)]
struct BuildPrim {
    bounds: Aabb,
    centroid: Vec3A,
    index: u32,
}

impl Bvh {
    /// Builds over primitives with the given bounds. Primitives with empty or non-finite bounds
    /// are left out (they can never be hit).
    pub fn build(bounds: &[Aabb]) -> Bvh {
        let mut prims: Vec<BuildPrim> = bounds
            .iter()
            .enumerate()
            .filter(|(_, b)| !b.is_empty() && b.min.is_finite() && b.max.is_finite())
            .map(|(i, b)| BuildPrim {
                bounds: *b,
                centroid: b.centroid(),
                index: i as u32,
            })
            .collect();
        if prims.is_empty() {
            return Bvh::default();
        }
        let nodes = build_range(&mut prims, 0, 0);
        let order = prims.iter().map(|p| p.index).collect();
        Bvh { nodes, order }
    }

    /// Primitive indices (into the list given to [`Bvh::build`]) in leaf order.
    pub fn order_ref(&self) -> &[u32] {
        &self.order
    }

    /// Number of nodes (for statistics and memory estimates).
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Bytes held by the node and order arrays.
    pub fn memory_bytes(&self) -> usize {
        self.nodes.len() * std::mem::size_of::<Node>() + self.order.len() * 4
    }

    /// Bounds of everything in the tree (empty box for an empty tree).
    pub fn bounds(&self) -> Aabb {
        self.nodes.first().map_or(Aabb::EMPTY, |n| Aabb {
            min: Vec3A::from(n.min),
            max: Vec3A::from(n.max),
        })
    }

    /// Visits, near-first, every primitive whose leaf box the ray reaches before `t_max`.
    /// `test(slot, t_max)` gets the primitive's position in leaf order (primitive
    /// `order_ref()[slot]` of the build input; callers usually store their primitives in that
    /// order) and returns the hit distance if the primitive is hit closer than `t_max`;
    /// the search then shrinks to that distance. With `any_hit` the walk stops at the first hit.
    /// Returns the closest distance found (or the first, for `any_hit`).
    #[inline]
    pub fn traverse<F: FnMut(u32, f32) -> Option<f32>>(
        &self,
        ray: &Ray,
        mut t_max: f32,
        any_hit: bool,
        mut test: F,
    ) -> Option<f32> {
        if self.nodes.is_empty() {
            return None;
        }
        let inv_dir = Vec3A::ONE / ray.dir;
        let dir_neg = [ray.dir.x < 0.0, ray.dir.y < 0.0, ray.dir.z < 0.0];
        let mut stack = [0u32; STACK_SIZE];
        let mut sp = 0usize;
        let mut current = 0u32;
        let mut found = None;
        loop {
            let node = &self.nodes[current as usize];
            let bounds = Aabb {
                min: Vec3A::from(node.min),
                max: Vec3A::from(node.max),
            };
            if bounds.hit(ray.origin, inv_dir, t_max) {
                if node.count > 0 {
                    let first = node.offset as usize;
                    for slot in first..first + node.count as usize {
                        if let Some(t) = test(slot as u32, t_max) {
                            t_max = t;
                            found = Some(t);
                            if any_hit {
                                return found;
                            }
                        }
                    }
                } else if dir_neg[node.axis as usize] {
                    // Second child is nearer along a negative direction.
                    stack[sp] = current + 1;
                    sp += 1;
                    current = node.offset;
                    continue;
                } else {
                    stack[sp] = node.offset;
                    sp += 1;
                    current += 1;
                    continue;
                }
            }
            if sp == 0 {
                return found;
            }
            sp -= 1;
            current = stack[sp];
        }
    }
}

fn leaf(prims: &[BuildPrim], bounds: Aabb, first: usize) -> Node {
    Node {
        min: bounds.min.into(),
        offset: first as u32,
        max: bounds.max.into(),
        count: prims.len() as u16,
        axis: 0,
        _pad: 0,
    }
}

/// Builds the subtree for `prims` (whose first element is primitive `first` of the final
/// order) and returns its nodes with child offsets relative to the subtree's own start.
fn build_range(prims: &mut [BuildPrim], first: usize, depth: usize) -> Vec<Node> {
    let mut out = Vec::new();
    build_into(prims, first, depth, &mut out);
    out
}

/// Chooses a split position (number of primitives going left) or `None` for a leaf.
fn choose_split(prims: &mut [BuildPrim], bounds: &Aabb, depth: usize) -> Option<(usize, usize)> {
    let n = prims.len();
    if n <= 1 {
        return None;
    }
    let centroid_bounds = prims.iter().fold(Aabb::EMPTY, |b, p| b.grow(p.centroid));
    let axis = centroid_bounds.longest_axis();
    let extent = centroid_bounds.max - centroid_bounds.min;
    // Deep trees must not overflow the traversal stack: force median splits near the limit.
    let force_split = depth + 8 >= STACK_SIZE || n > u16::MAX as usize;
    if extent[axis] <= 0.0 {
        // All centroids coincide: SAH cannot separate them; split by index if too many.
        return if n > MAX_LEAF_SIZE {
            Some((axis, n / 2))
        } else {
            None
        };
    }
    if force_split {
        prims.select_nth_unstable_by(n / 2, |a, b| a.centroid[axis].total_cmp(&b.centroid[axis]));
        return Some((axis, n / 2));
    }

    // Bin along every axis with a non-zero centroid extent; keep the cheapest split.
    let mut best: Option<(f32, usize, usize)> = None; // (cost, axis, bin boundary)
    for ax in 0..3 {
        if extent[ax] <= 0.0 {
            continue;
        }
        let mut counts = [0u32; BIN_COUNT];
        let mut boxes = [Aabb::EMPTY; BIN_COUNT];
        let scale = BIN_COUNT as f32 / extent[ax];
        for p in prims.iter() {
            let b = bin_of(p.centroid[ax], centroid_bounds.min[ax], scale);
            counts[b] += 1;
            boxes[b] = boxes[b].union(&p.bounds);
        }
        // Sweep from the right to get suffix areas, then from the left.
        let mut right_area = [0.0f32; BIN_COUNT];
        let mut right_count = [0u32; BIN_COUNT];
        let mut acc = Aabb::EMPTY;
        let mut cnt = 0;
        for i in (1..BIN_COUNT).rev() {
            acc = acc.union(&boxes[i]);
            cnt += counts[i];
            right_area[i] = acc.surface_area();
            right_count[i] = cnt;
        }
        let mut acc = Aabb::EMPTY;
        let mut cnt = 0;
        for i in 0..BIN_COUNT - 1 {
            acc = acc.union(&boxes[i]);
            cnt += counts[i];
            let rc = right_count[i + 1];
            if cnt == 0 || rc == 0 {
                continue;
            }
            let cost = cnt as f32 * acc.surface_area() + rc as f32 * right_area[i + 1];
            if best.is_none_or(|(c, _, _)| cost < c) {
                best = Some((cost, ax, i + 1));
            }
        }
    }
    let area = bounds.surface_area();
    let (cost, ax, boundary) = best?;
    let split_cost = TRAVERSAL_COST + if area > 0.0 { cost / area } else { 0.0 };
    if n <= MAX_LEAF_SIZE && n as f32 <= split_cost {
        return None;
    }
    let min = centroid_bounds.min[ax];
    let scale = BIN_COUNT as f32 / extent[ax];
    let mid = partition(prims, |p| bin_of(p.centroid[ax], min, scale) < boundary);
    if mid == 0 || mid == n {
        return if n > MAX_LEAF_SIZE {
            Some((ax, n / 2))
        } else {
            None
        };
    }
    Some((ax, mid))
}

#[inline]
fn bin_of(c: f32, min: f32, scale: f32) -> usize {
    (((c - min) * scale) as usize).min(BIN_COUNT - 1)
}

fn partition<F: Fn(&BuildPrim) -> bool>(prims: &mut [BuildPrim], left: F) -> usize {
    let mut i = 0;
    for j in 0..prims.len() {
        if left(&prims[j]) {
            prims.swap(i, j);
            i += 1;
        }
    }
    i
}

fn build_into(prims: &mut [BuildPrim], first: usize, depth: usize, out: &mut Vec<Node>) {
    let bounds = prims.iter().fold(Aabb::EMPTY, |b, p| b.union(&p.bounds));
    let Some((axis, mid)) = choose_split(prims, &bounds, depth) else {
        out.push(leaf(prims, bounds, first));
        return;
    };
    let me = out.len();
    out.push(Node {
        min: bounds.min.into(),
        offset: 0,
        max: bounds.max.into(),
        count: 0,
        axis: axis as u8,
        _pad: 0,
    });
    let (left, right) = prims.split_at_mut(mid);
    if prims_len(left, right) > PARALLEL_THRESHOLD {
        let (l, r) = rayon::join(
            || build_range(left, first, depth + 1),
            || build_range(right, first + mid, depth + 1),
        );
        append_shifted(out, l);
        out[me].offset = out.len() as u32;
        append_shifted(out, r);
    } else {
        build_into(left, first, depth + 1, out);
        out[me].offset = out.len() as u32;
        build_into(right, first + mid, depth + 1, out);
    }
}

fn prims_len(a: &[BuildPrim], b: &[BuildPrim]) -> usize {
    a.len() + b.len()
}

/// Appends a separately built subtree, rebasing its interior offsets to its new position.
fn append_shifted(out: &mut Vec<Node>, sub: Vec<Node>) {
    let base = out.len() as u32;
    out.extend(sub.into_iter().map(|mut n| {
        if n.count == 0 {
            n.offset += base;
        }
        n
    }));
}

#[cfg(test)]
mod tests {
    use super::*;

    // Determinism: the parallel build must produce the identical tree (same leaf order, same
    // node bounds and offsets) on 1 and on 2 threads; compared exactly.
    #[test]
    fn build_is_independent_of_thread_count() {
        let mut bounds = Vec::new();
        let mut s = 777u64;
        for _ in 0..(PARALLEL_THRESHOLD * 3) {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let p = Vec3A::new(
                (s >> 40) as f32,
                ((s >> 16) & 0xffffff) as f32,
                (s & 0xffff) as f32,
            );
            bounds.push(Aabb {
                min: p,
                max: p + Vec3A::splat(3.0),
            });
        }
        let build_on = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| Bvh::build(&bounds))
        };
        let (a, b) = (build_on(1), build_on(2));
        assert_eq!(a.order, b.order);
        assert_eq!(a.nodes.len(), b.nodes.len());
        for (x, y) in a.nodes.iter().zip(&b.nodes) {
            assert_eq!(
                (x.min, x.max, x.offset, x.count, x.axis),
                (y.min, y.max, y.offset, y.count, y.axis)
            );
        }
    }

    // Every primitive must appear exactly once in the leaf order (a permutation), and every
    // leaf's box must contain its primitives' boxes.
    #[test]
    fn order_is_permutation_and_boxes_nest() {
        let mut bounds = Vec::new();
        let mut s = 12345u64;
        for _ in 0..5000 {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let x = (s >> 40) as f32 / (1u64 << 24) as f32;
            let y = ((s >> 20) & 0xfffff) as f32 / (1u64 << 20) as f32;
            let p = Vec3A::new(x * 100.0, y * 10.0, x * y);
            bounds.push(Aabb {
                min: p,
                max: p + Vec3A::splat(0.1),
            });
        }
        let bvh = Bvh::build(&bounds);
        let mut seen = vec![false; bounds.len()];
        for &i in &bvh.order {
            assert!(!seen[i as usize]);
            seen[i as usize] = true;
        }
        assert!(seen.iter().all(|&s| s));
        for n in &bvh.nodes {
            if n.count > 0 {
                let nb = Aabb {
                    min: n.min.into(),
                    max: n.max.into(),
                };
                for &i in &bvh.order[n.offset as usize..n.offset as usize + n.count as usize] {
                    let b = bounds[i as usize];
                    assert!(nb.min.cmple(b.min).all() && nb.max.cmpge(b.max).all());
                }
            }
        }
    }
}

//! The binary SAH build: centroid bins per axis, the cheapest split by the surface-area
//! heuristic, the top levels in parallel chunks and subtrees with `rayon::join`; the same tree
//! for any thread count (see the parent module).

use std::mem::MaybeUninit;

use glam::Vec3A;
use rayon::prelude::*;

use crate::geometry::Aabb;

/// Number of centroid bins per axis in the SAH build.
pub const BIN_COUNT: usize = 16;
/// Leaves hold at most this many primitives.
pub const MAX_LEAF_SIZE: usize = 4;
/// Cost of visiting a node relative to one primitive test, in the SAH.
pub(super) const TRAVERSAL_COST: f32 = 1.0;
/// Subtrees with more primitives than this are built in parallel.
pub(super) const PARALLEL_THRESHOLD: usize = 16 * 1024;
/// Nodes with more primitives than this compute their bounds, bins and partition in parallel
/// (the top levels, where `rayon::join` over subtrees has nothing to split yet).
pub(super) const PARALLEL_NODE_THRESHOLD: usize = 64 * 1024;
/// Primitives per parallel task in those passes.
pub(super) const CHUNK: usize = 16 * 1024;
/// Binary tree depth limit; the build keeps the tree shallower than this (see `choose_split`).
pub(super) const MAX_DEPTH: usize = 64;

/// One node of the binary build tree (32 bytes), stored depth-first.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
pub(super) struct Node {
    pub(super) min: [f32; 3],
    /// Leaf: first primitive (in [`Bvh::order`] order). Interior: index of the second child.
    pub(super) offset: u32,
    pub(super) max: [f32; 3],
    /// Number of primitives; 0 for interior nodes.
    pub(super) count: u16,
    /// Split axis of an interior node.
    pub(super) axis: u8,
    pub(super) _pad: u8,
}

#[derive(Clone, Copy)]
pub(super) struct BuildPrim {
    pub(super) bounds: Aabb,
    pub(super) centroid: Vec3A,
    pub(super) index: u32,
}

pub(super) fn leaf(prims: &[BuildPrim], bounds: Aabb, first: usize) -> Node {
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
pub(super) fn build_range(prims: &mut [BuildPrim], first: usize, depth: usize) -> Vec<Node> {
    let mut out = Vec::new();
    build_into(prims, first, depth, &mut out);
    out
}

/// Chooses a split position (number of primitives going left) or `None` for a leaf.
pub(super) fn choose_split(
    prims: &mut [BuildPrim],
    bounds: &Aabb,
    depth: usize,
) -> Option<(usize, usize)> {
    let n = prims.len();
    if n <= 1 {
        return None;
    }
    let centroid_bounds = centroid_bounds(prims);
    let axis = centroid_bounds.longest_axis();
    let extent = centroid_bounds.max - centroid_bounds.min;
    // Deep trees must not overflow the traversal stack: force median splits near the limit.
    let force_split = depth + 8 >= MAX_DEPTH;
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
    let bins = bin_all(prims, &centroid_bounds);
    let mut best: Option<(f32, usize, usize)> = None; // (cost, axis, bin boundary)
    for ax in 0..3 {
        if extent[ax] <= 0.0 {
            continue;
        }
        let (counts, boxes) = (&bins.counts[ax], &bins.boxes[ax]);
        // Only the non-empty bins matter: a boundary after an empty bin costs the same as the
        // one just after the last non-empty bin before it, which comes first and so wins the
        // strict `<` below. Skipping them gives the same split as sweeping all bins, for far
        // less work in the many small nodes near the leaves.
        let mut used = [0usize; BIN_COUNT];
        let mut k = 0;
        for (i, &c) in counts.iter().enumerate() {
            if c > 0 {
                used[k] = i;
                k += 1;
            }
        }
        let used = &used[..k];
        // Sweep from the right to get the area and count right of each used bin's start.
        let mut right_area = [0.0f32; BIN_COUNT];
        let mut right_count = [0u32; BIN_COUNT];
        let mut acc = Aabb::EMPTY;
        let mut cnt = 0;
        for (j, &i) in used.iter().enumerate().skip(1).rev() {
            acc = acc.union(&boxes[i]);
            cnt += counts[i];
            right_area[j] = acc.surface_area();
            right_count[j] = cnt;
        }
        let mut acc = Aabb::EMPTY;
        let mut cnt = 0;
        for (j, &i) in used.iter().enumerate().take(k.saturating_sub(1)) {
            acc = acc.union(&boxes[i]);
            cnt += counts[i];
            let rc = right_count[j + 1];
            let cost = cnt as f32 * acc.surface_area() + rc as f32 * right_area[j + 1];
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
    let mid = if n > PARALLEL_NODE_THRESHOLD {
        partition_stable_parallel(prims, |p| bin_of(p.centroid[ax], min, scale) < boundary)
    } else {
        partition(prims, |p| bin_of(p.centroid[ax], min, scale) < boundary)
    };
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
pub(super) fn bin_of(c: f32, min: f32, scale: f32) -> usize {
    (((c - min) * scale) as usize).min(BIN_COUNT - 1)
}

pub(super) fn partition<F: Fn(&BuildPrim) -> bool>(prims: &mut [BuildPrim], left: F) -> usize {
    let mut i = 0;
    for j in 0..prims.len() {
        if left(&prims[j]) {
            prims.swap(i, j);
            i += 1;
        }
    }
    i
}

/// Primitive counts and bounds per bin along each axis.
pub(super) struct Bins {
    pub(super) counts: [[u32; BIN_COUNT]; 3],
    pub(super) boxes: [[Aabb; BIN_COUNT]; 3],
}

impl Bins {
    const EMPTY: Bins = Bins {
        counts: [[0; BIN_COUNT]; 3],
        boxes: [[Aabb::EMPTY; BIN_COUNT]; 3],
    };

    fn add(&mut self, prims: &[BuildPrim], centroids: &Aabb) {
        let extent = centroids.max - centroids.min;
        for ax in 0..3 {
            if extent[ax] <= 0.0 {
                continue;
            }
            let scale = BIN_COUNT as f32 / extent[ax];
            for p in prims {
                let b = bin_of(p.centroid[ax], centroids.min[ax], scale);
                self.counts[ax][b] += 1;
                self.boxes[ax][b] = self.boxes[ax][b].union(&p.bounds);
            }
        }
    }

    fn merge(mut self, o: Bins) -> Bins {
        for ax in 0..3 {
            for b in 0..BIN_COUNT {
                self.counts[ax][b] += o.counts[ax][b];
                self.boxes[ax][b] = self.boxes[ax][b].union(&o.boxes[ax][b]);
            }
        }
        self
    }
}

/// Bins `prims` along all three axes; in parallel chunks for large nodes. Counts add and boxes
/// take min/max, both exact, so the result does not depend on how the chunks are combined.
pub(super) fn bin_all(prims: &[BuildPrim], centroids: &Aabb) -> Bins {
    if prims.len() > PARALLEL_NODE_THRESHOLD {
        prims
            .par_chunks(CHUNK)
            .map(|c| {
                let mut b = Bins::EMPTY;
                b.add(c, centroids);
                b
            })
            .reduce(|| Bins::EMPTY, Bins::merge)
    } else {
        let mut b = Bins::EMPTY;
        b.add(prims, centroids);
        b
    }
}

/// Union of the primitives' bounds (parallel for large nodes; min/max are exact, so the
/// result is the same however the chunks combine).
pub(super) fn prim_bounds(prims: &[BuildPrim]) -> Aabb {
    if prims.len() > PARALLEL_NODE_THRESHOLD {
        prims
            .par_chunks(CHUNK)
            .map(|c| c.iter().fold(Aabb::EMPTY, |b, p| b.union(&p.bounds)))
            .reduce(|| Aabb::EMPTY, |a, b| a.union(&b))
    } else {
        prims.iter().fold(Aabb::EMPTY, |b, p| b.union(&p.bounds))
    }
}

/// Bounds of the primitives' centroids (parallel for large nodes, exact as [`prim_bounds`]).
pub(super) fn centroid_bounds(prims: &[BuildPrim]) -> Aabb {
    if prims.len() > PARALLEL_NODE_THRESHOLD {
        prims
            .par_chunks(CHUNK)
            .map(|c| c.iter().fold(Aabb::EMPTY, |b, p| b.grow(p.centroid)))
            .reduce(|| Aabb::EMPTY, |a, b| a.union(&b))
    } else {
        prims.iter().fold(Aabb::EMPTY, |b, p| b.grow(p.centroid))
    }
}

/// Stable partition in parallel chunks: each chunk counts its left primitives, the prefix sums
/// give every chunk its own ranges of the output, and chunks copy there independently. The
/// result (both sides in input order) depends only on the input, never on the thread count.
pub(super) fn partition_stable_parallel<F: Fn(&BuildPrim) -> bool + Sync>(
    prims: &mut [BuildPrim],
    left: F,
) -> usize {
    let lefts: Vec<usize> = prims
        .par_chunks(CHUNK)
        .map(|c| c.iter().filter(|p| left(p)).count())
        .collect();
    let mid: usize = lefts.iter().sum();
    // Left uninitialised (every element is written below by exactly one chunk): a copy of the
    // input here was a serial pass over the largest node, the first touch of its pages too.
    let mut out: Vec<MaybeUninit<BuildPrim>> = Vec::with_capacity(prims.len());
    out.resize_with(prims.len(), MaybeUninit::uninit);
    let (mut l_rest, mut r_rest) = out.split_at_mut(mid);
    let mut targets = Vec::with_capacity(lefts.len());
    for (k, &nl) in lefts.iter().enumerate() {
        let len = CHUNK.min(prims.len() - k * CHUNK);
        let (l, lr) = std::mem::take(&mut l_rest).split_at_mut(nl);
        let (r, rr) = std::mem::take(&mut r_rest).split_at_mut(len - nl);
        (l_rest, r_rest) = (lr, rr);
        targets.push((l, r));
    }
    prims
        .par_chunks(CHUNK)
        .zip(targets.into_par_iter())
        .for_each(|(src, (l, r))| {
            let (mut i, mut j) = (0, 0);
            for p in src {
                if left(p) {
                    l[i].write(*p);
                    i += 1;
                } else {
                    r[j].write(*p);
                    j += 1;
                }
            }
        });
    prims
        .par_chunks_mut(CHUNK)
        .zip(out.par_chunks(CHUNK))
        .for_each(|(d, s)| {
            for (d, s) in d.iter_mut().zip(s) {
                // SAFETY: the chunks' left and right ranges tile `out` exactly (their lengths
                // sum to each chunk's length), so every element was written above.
                *d = unsafe { s.assume_init() };
            }
        });
    mid
}

pub(super) fn build_into(prims: &mut [BuildPrim], first: usize, depth: usize, out: &mut Vec<Node>) {
    let bounds = prim_bounds(prims);
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

pub(super) fn prims_len(a: &[BuildPrim], b: &[BuildPrim]) -> usize {
    a.len() + b.len()
}

/// Appends a separately built subtree, rebasing its interior offsets to its new position.
pub(super) fn append_shifted(out: &mut Vec<Node>, sub: Vec<Node>) {
    let base = out.len() as u32;
    out.extend(sub.into_iter().map(|mut n| {
        if n.count == 0 {
            n.offset += base;
        }
        n
    }));
}

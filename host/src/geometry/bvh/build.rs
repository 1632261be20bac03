//! The binary SAH build: centroid bins per axis, the cheapest split by the surface-area
//! heuristic, the top levels in parallel chunks and subtrees with `rayon::join`; the same tree
//! for any thread count (see the parent module).

use std::mem::MaybeUninit;

use glam::Vec3A;
use rayon::prelude::*;

use super::parts::place_parts;
use crate::geometry::Aabb;

/// Number of centroid bins per axis in the SAH build.
pub const BIN_COUNT: usize = 16;
/// Leaves hold at most this many primitives.
pub const MAX_LEAF_SIZE: usize = 4;
/// Leaves of a tree that holds quads or spheres hold at most this many primitives: two quads
/// are four triangle lanes, one four-lane pass (`leaf_triangles.rs`), where a third takes a
/// second pass; a sphere's test costs several triangle tests. The SAH's leaf test counts one
/// per primitive, which let the window room's floor, ceiling, back and front walls share a
/// leaf whose box is the whole room: every ray inside it then tested eight triangles (two
/// passes) before the wall it goes to (10.3% of the scene's path-tracing instructions).
pub const MAX_LEAF_SIZE_OTHER: usize = 2;
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

/// A primitive reference of the build: its box and its index in the input (32 bytes, half a
/// cache line). The top levels' passes move every reference once per level and the subtrees
/// below partition them in place, so their size is the build's memory traffic; the centroid
/// is recomputed from the box where needed (`(min + max) · 0.5`, the same bits every time)
/// instead of being stored (it made the reference 64 bytes).
#[derive(Clone, Copy)]
#[repr(C, align(16))]
pub(super) struct BuildPrim {
    min: [f32; 3],
    pub(super) index: u32,
    max: [f32; 3],
    _pad: u32,
}

impl BuildPrim {
    pub(super) fn new(bounds: &Aabb, index: u32) -> BuildPrim {
        BuildPrim {
            min: bounds.min.into(),
            index,
            max: bounds.max.into(),
            _pad: 0,
        }
    }

    #[inline(always)]
    pub(super) fn bounds(&self) -> Aabb {
        Aabb {
            min: Vec3A::from_array(self.min),
            max: Vec3A::from_array(self.max),
        }
    }

    /// The box's centre, [`Aabb::centroid`].
    #[inline(always)]
    pub(super) fn centroid(&self) -> Vec3A {
        self.bounds().centroid()
    }

    /// One coordinate of [`BuildPrim::centroid`] (the same IEEE operations on one lane).
    #[inline(always)]
    pub(super) fn centroid_on(&self, axis: usize) -> f32 {
        (self.min[axis] + self.max[axis]) * 0.5
    }
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

/// The bounds of a node's primitives and of their centroids. The root computes them in one
/// pass; every other node gets them from its parent's split (the bins on the split axis give
/// the children's boxes, the partition collects their centroid boxes), so no node passes over
/// its primitives just to find its bounds.
#[derive(Clone, Copy)]
pub(super) struct NodeBounds {
    pub(super) bounds: Aabb,
    pub(super) centroids: Aabb,
}

impl NodeBounds {
    const EMPTY: NodeBounds = NodeBounds {
        bounds: Aabb::EMPTY,
        centroids: Aabb::EMPTY,
    };

    fn add(self, p: &BuildPrim) -> NodeBounds {
        NodeBounds {
            bounds: self.bounds.union(&p.bounds()),
            centroids: self.centroids.grow(p.centroid()),
        }
    }

    fn union(self, o: NodeBounds) -> NodeBounds {
        NodeBounds {
            bounds: self.bounds.union(&o.bounds),
            centroids: self.centroids.union(&o.centroids),
        }
    }

    /// Both boxes of `prims` in one pass (parallel for large nodes; min/max are exact, so the
    /// result is the same however the chunks combine).
    pub(super) fn of(prims: &[BuildPrim]) -> NodeBounds {
        if prims.len() > PARALLEL_NODE_THRESHOLD {
            prims
                .par_chunks(CHUNK)
                .map(|c| c.iter().fold(NodeBounds::EMPTY, NodeBounds::add))
                .reduce(|| NodeBounds::EMPTY, NodeBounds::union)
        } else {
            prims.iter().fold(NodeBounds::EMPTY, NodeBounds::add)
        }
    }
}

/// Whether a primitive with these bounds goes into the tree (non-empty, finite); the others
/// can never be hit.
fn usable(b: &Aabb) -> bool {
    !b.is_empty() && b.min.is_finite() && b.max.is_finite()
}

/// The primitives with non-empty, finite bounds, in input order, and their [`NodeBounds`]
/// (the root's), in one parallel pass: each chunk counts its usable boxes, prefix sums place
/// every chunk's output, and the chunks write their primitives and fold their bounds at once.
pub(super) fn build_prims(bounds: &[Aabb]) -> (Vec<BuildPrim>, NodeBounds) {
    let counts: Vec<usize> = bounds
        .par_chunks(CHUNK)
        .map(|c| c.iter().filter(|b| usable(b)).count())
        .collect();
    let total = counts.iter().sum();
    let mut prims: Vec<BuildPrim> = Vec::with_capacity(total);
    let mut rest = &mut prims.spare_capacity_mut()[..total];
    let mut targets = Vec::with_capacity(counts.len());
    for &n in &counts {
        let (t, r) = std::mem::take(&mut rest).split_at_mut(n);
        targets.push(t);
        rest = r;
    }
    let root = bounds
        .par_chunks(CHUNK)
        .zip(targets)
        .enumerate()
        .map(|(k, (src, dst))| {
            let mut nb = NodeBounds::EMPTY;
            let usable_prims = src.iter().enumerate().filter(|(_, b)| usable(b));
            for ((i, b), d) in usable_prims.zip(dst.iter_mut()) {
                let p = BuildPrim::new(b, (k * CHUNK + i) as u32);
                nb = nb.add(&p);
                d.write(p);
            }
            nb
        })
        .reduce(|| NodeBounds::EMPTY, NodeBounds::union);
    // SAFETY: the chunks' targets tile the first `total` slots, and chunk k's target has
    // exactly as many slots as chunk k has usable boxes, each of which wrote one.
    unsafe { prims.set_len(total) };
    (prims, root)
}

// A box and a primitive reference have one size and one alignment, so the references can be
// written over the boxes' own storage ([`build_prims_owned`]).
const _: () = assert!(
    std::mem::size_of::<Aabb>() == std::mem::size_of::<BuildPrim>()
        && std::mem::align_of::<Aabb>() == std::mem::align_of::<BuildPrim>()
);

/// [`build_prims`] over boxes given by value: every reference is written over its own box
/// (both 32 bytes, 16-aligned), in parallel chunks, so the list needs no new buffer (at a
/// million primitives a new one was 42 MB whose pages the kernel first had to fault in and
/// zero, the least parallel pass of the build). Where some boxes are unusable the references
/// are then moved down over them in order (one serial pass; a scene's triangles, spheres and
/// quads always have usable boxes). The same references in the same order, and the same
/// root bounds, as [`build_prims`].
pub(super) fn build_prims_owned(bounds: Vec<Aabb>) -> (Vec<BuildPrim>, NodeBounds) {
    let mut bounds = std::mem::ManuallyDrop::new(bounds);
    let (len, cap, ptr) = (bounds.len(), bounds.capacity(), bounds.as_mut_ptr());
    // SAFETY: `ptr` holds `len` initialised boxes, and the `ManuallyDrop` vector is never
    // used again, so this slice is the only access to them.
    let slots = unsafe { std::slice::from_raw_parts_mut(ptr, len) };
    let (root, unusable) = slots
        .par_chunks_mut(CHUNK)
        .enumerate()
        .map(|(k, chunk)| {
            let mut nb = NodeBounds::EMPTY;
            let mut unusable = 0usize;
            for (i, slot) in chunk.iter_mut().enumerate() {
                let b = *slot;
                if usable(&b) {
                    let p = BuildPrim::new(&b, (k * CHUNK + i) as u32);
                    nb = nb.add(&p);
                    // SAFETY: a `BuildPrim` fits the slot exactly (size and alignment are
                    // asserted equal above), and `b` was read out of it first.
                    unsafe { (slot as *mut Aabb).cast::<BuildPrim>().write(p) };
                } else {
                    unusable += 1;
                }
            }
            (nb, unusable)
        })
        .reduce(
            || (NodeBounds::EMPTY, 0),
            |a, b| (a.0.union(b.0), a.1 + b.1),
        );
    let mut total = len;
    if unusable > 0 {
        // Move the references down over the unusable boxes, keeping their order. A slot is
        // told apart by its box's coordinates, which the reference written over it kept.
        total = 0;
        for r in 0..len {
            // SAFETY: `r < len`; every slot holds a box or a reference written over one, and
            // reading either as a box gives its coordinates (any bits are a valid `f32`, and
            // what `Vec3A` does not use is never looked at).
            let b = unsafe { ptr.add(r).read() };
            if usable(&b) {
                // SAFETY: `total ≤ r < len`, both slots inside the buffer; the slot at `r`
                // holds a reference (it is usable), copied whole.
                unsafe {
                    std::ptr::copy(
                        ptr.add(r).cast::<BuildPrim>(),
                        ptr.add(total).cast::<BuildPrim>(),
                        1,
                    )
                };
                total += 1;
            }
        }
        debug_assert_eq!(total, len - unusable);
    }
    // SAFETY: the allocation came from a `Vec<Aabb>` of capacity `cap`, and `BuildPrim` has
    // `Aabb`'s size and alignment (asserted above), so it is the same layout; the first
    // `total` slots now hold references (the usable ones, moved down in order).
    let prims = unsafe { Vec::from_raw_parts(ptr.cast::<BuildPrim>(), total, cap) };
    (prims, root)
}

/// Builds the tree for `prims` (whose first element is primitive `first` of the final order)
/// and returns its nodes depth-first, interior offsets counted from the first node.
#[cfg(test)]
pub(super) fn build_range(prims: &mut [BuildPrim], first: usize, depth: usize) -> Vec<Node> {
    let root = NodeBounds::of(prims);
    build_tree(prims, first, depth, root, MAX_LEAF_SIZE)
}

/// [`build_range`] with the root's bounds known and leaves of at most `max_leaf` (at most
/// [`MAX_LEAF_SIZE`]) primitives. Subtrees above [`PARALLEL_THRESHOLD`]
/// primitives are built in parallel into separate parts whose interior offsets are distances
/// (second child minus node), which do not change when a part moves; the parts are then
/// copied once, in parallel, into their final places, turning distances into indices. (Each
/// `rayon::join` used to append its two subtrees to its node's list, rebasing every offset: a
/// copy of the whole tree per parallel level, the root's on one thread.)
pub(super) fn build_tree(
    prims: &mut [BuildPrim],
    first: usize,
    depth: usize,
    root: NodeBounds,
    max_leaf: usize,
) -> Vec<Node> {
    // The top nodes partition from one buffer into the other and back (see `build_parts`);
    // the scratch buffer's pages are only touched by those partitions, in parallel.
    let mut scratch: Vec<BuildPrim> = Vec::new();
    if prims.len() > PARALLEL_NODE_THRESHOLD {
        scratch.reserve_exact(prims.len());
    }
    let spare_len = prims.len().min(scratch.capacity());
    let spare = &mut scratch.spare_capacity_mut()[..spare_len];
    let mut parts = Vec::new();
    let node = Subtree {
        first,
        depth,
        nb: root,
        max_leaf: max_leaf.clamp(1, MAX_LEAF_SIZE),
    };
    let total = build_parts(prims, spare, true, node, &mut parts);
    // Freed beside the copying of the parts: giving back its pages is serial work in the
    // kernel (about 3 ms at a million primitives), which used to wait for the copy. It
    // coexists with both copies of the nodes there, but the boxes the references were written
    // over (`build_prims_owned`) no longer do, so the peak is lower than when it was freed
    // first.
    let ((), nodes) = rayon::join(
        move || drop(scratch),
        move || {
            place_parts(parts, total, |n, start, i| {
                if n.count == 0 {
                    n.offset += (start + i) as u32;
                }
            })
        },
    );
    nodes
}

/// A subtree to build: its first primitive's place in the final order, its depth, its
/// primitives' bounds and the largest leaf it may make.
#[derive(Clone, Copy)]
struct Subtree {
    first: usize,
    depth: usize,
    nb: NodeBounds,
    max_leaf: usize,
}

/// Appends the parts of the subtree over `data` to `parts` in depth-first order; returns its
/// node count. Interior offsets are distances from the node to its second child.
///
/// Nodes above [`PARALLEL_NODE_THRESHOLD`] primitives partition `data` stably into `spare`
/// (as long, free), which then holds their children's primitives while `data` becomes the
/// children's free space: one pass per top level, where partitioning into a new buffer and
/// copying back took two and a new allocation. `home` says whether `data` lies in the final
/// primitive array; a subtree that is not there moves back once, when it gets small enough
/// for in-place partitions (in its own task, so in parallel with its siblings).
fn build_parts(
    data: &mut [BuildPrim],
    spare: &mut [MaybeUninit<BuildPrim>],
    home: bool,
    node: Subtree,
    parts: &mut Vec<Vec<Node>>,
) -> usize {
    let n = data.len();
    if !home && (n <= PARALLEL_NODE_THRESHOLD) {
        let data = move_to(data, spare);
        return build_parts(data, &mut [], true, node, parts);
    }
    let Subtree {
        first,
        depth,
        nb,
        max_leaf,
    } = node;
    if n <= PARALLEL_THRESHOLD {
        // A binary tree over n primitives has at most 2n − 1 nodes; reserving them saves
        // the growing vector's copies, and giving back the unused tail (about half: leaves
        // hold several primitives) keeps it from raising the peak memory.
        let mut out = Vec::with_capacity(2 * n);
        build_into(data, first, depth, nb, max_leaf, &mut out);
        out.shrink_to_fit();
        parts.push(out);
        return parts.last().map_or(0, Vec::len);
    }
    let split = if n > PARALLEL_NODE_THRESHOLD {
        split_large(data, spare, &nb, depth)
    } else {
        choose_split(data, &nb, depth, max_leaf).map(|s| (s, false))
    };
    let Some((split, moved)) = split else {
        let data = if home { data } else { move_to(data, spare) };
        parts.push(vec![leaf(data, nb.bounds, first)]);
        return 1;
    };
    // After a partition into `spare` the primitives are there and `data` is free.
    let (data, spare, home) = if moved {
        // SAFETY: `split_large` wrote every element of `spare` (see `partition_into`).
        (unsafe { assume_init(spare) }, as_uninit(data), !home)
    } else {
        (data, spare, home)
    };
    let me = parts.len();
    parts.push(vec![interior(&nb.bounds, split.axis)]);
    let (left, right) = data.split_at_mut(split.mid);
    let (l_spare, r_spare) = spare.split_at_mut(split.mid.min(spare.len()));
    let left_node = Subtree {
        first,
        depth: depth + 1,
        nb: split.left,
        max_leaf,
    };
    let right_node = Subtree {
        first: first + split.mid,
        depth: depth + 1,
        nb: split.right,
        max_leaf,
    };
    let ((lparts, llen), (rparts, rlen)) = rayon::join(
        || {
            let mut p = Vec::new();
            let n = build_parts(left, l_spare, home, left_node, &mut p);
            (p, n)
        },
        || {
            let mut p = Vec::new();
            let n = build_parts(right, r_spare, home, right_node, &mut p);
            (p, n)
        },
    );
    parts[me][0].offset = 1 + llen as u32;
    parts.extend(lparts);
    parts.extend(rparts);
    1 + llen + rlen
}

/// Copies `data` into `dst` (as long) in parallel chunks and returns it as initialised.
fn move_to<'a>(data: &[BuildPrim], dst: &'a mut [MaybeUninit<BuildPrim>]) -> &'a mut [BuildPrim] {
    assert_eq!(
        data.len(),
        dst.len(),
        "a subtree's two buffers have one length"
    );
    dst.par_chunks_mut(CHUNK)
        .zip(data.par_chunks(CHUNK))
        .for_each(|(d, s)| {
            for (d, s) in d.iter_mut().zip(s) {
                d.write(*s);
            }
        });
    // SAFETY: every element of `dst` was written just above.
    unsafe { assume_init(dst) }
}

/// Views initialised primitives as free space. Only whole primitives are ever written
/// through it, so the slice stays initialised.
fn as_uninit(s: &mut [BuildPrim]) -> &mut [MaybeUninit<BuildPrim>] {
    // SAFETY: `MaybeUninit<T>` has `T`'s layout, and every initialised value is a valid
    // `MaybeUninit<T>`.
    unsafe { &mut *(s as *mut [BuildPrim] as *mut [MaybeUninit<BuildPrim>]) }
}

/// # Safety
/// Every element of `s` must have been written.
unsafe fn assume_init(s: &mut [MaybeUninit<BuildPrim>]) -> &mut [BuildPrim] {
    // SAFETY: same layout, and the caller guarantees that every element is initialised.
    unsafe { &mut *(s as *mut [MaybeUninit<BuildPrim>] as *mut [BuildPrim]) }
}

fn interior(bounds: &Aabb, axis: usize) -> Node {
    Node {
        min: bounds.min.into(),
        offset: 0,
        max: bounds.max.into(),
        count: 0,
        axis: axis as u8,
        _pad: 0,
    }
}

/// A node's split: the axis, the number of primitives going left (they are moved to the
/// front) and the bounds of both sides.
pub(super) struct Split {
    pub(super) axis: usize,
    pub(super) mid: usize,
    pub(super) left: NodeBounds,
    pub(super) right: NodeBounds,
}

impl Split {
    /// The SAH split at bin `boundary` of axis `ax`, `mid` primitives left with centroid
    /// bounds `lc`, the rest with `rc`. The sides' boxes are the unions of their bins' boxes
    /// on that axis: the same primitives' bounds, combined by exact min/max.
    fn from_bins(bins: &Bins, ax: usize, boundary: usize, mid: usize, lc: Aabb, rc: Aabb) -> Split {
        let side = |r: std::ops::Range<usize>| {
            bins.boxes[ax][r]
                .iter()
                .fold(Aabb::EMPTY, |acc, b| acc.union(b))
        };
        Split {
            axis: ax,
            mid,
            left: NodeBounds {
                bounds: side(0..boundary),
                centroids: lc,
            },
            right: NodeBounds {
                bounds: side(boundary..BIN_COUNT),
                centroids: rc,
            },
        }
    }

    /// Split at `mid` without SAH bins (the halves' bounds computed from the primitives).
    fn at(prims: &[BuildPrim], axis: usize, mid: usize) -> Split {
        Split {
            axis,
            mid,
            left: NodeBounds::of(&prims[..mid]),
            right: NodeBounds::of(&prims[mid..]),
        }
    }
}

/// Chooses a split (and partitions `prims` in place for it) or `None` for a leaf of at most
/// `max_leaf` primitives (at most [`MAX_LEAF_SIZE`]). For nodes
/// of at most [`PARALLEL_NODE_THRESHOLD`] primitives; larger ones use [`split_large`], which
/// gives the same split.
pub(super) fn choose_split(
    prims: &mut [BuildPrim],
    nb: &NodeBounds,
    depth: usize,
    max_leaf: usize,
) -> Option<Split> {
    let n = prims.len();
    if n <= 1 {
        return None;
    }
    let centroid_bounds = nb.centroids;
    let axis = centroid_bounds.longest_axis();
    let extent = centroid_bounds.max - centroid_bounds.min;
    if extent[axis] <= 0.0 {
        // All centroids coincide: SAH cannot separate them; split by index if too many.
        return (n > max_leaf).then(|| Split::at(prims, axis, n / 2));
    }
    // Deep trees must not overflow the traversal stack: force median splits near the limit.
    if depth + 8 >= MAX_DEPTH {
        prims.select_nth_unstable_by(n / 2, |a, b| {
            a.centroid_on(axis).total_cmp(&b.centroid_on(axis))
        });
        return Some(Split::at(prims, axis, n / 2));
    }
    let mut bins = Bins::EMPTY;
    bins.add(prims, &centroid_bounds);
    let (cost, ax, boundary) = best_split(&bins, extent)?;
    let area = nb.bounds.surface_area();
    let split_cost = TRAVERSAL_COST + if area > 0.0 { cost / area } else { 0.0 };
    if n <= max_leaf && n as f32 <= split_cost {
        return None;
    }
    let (min, scale) = (centroid_bounds.min[ax], BIN_COUNT as f32 / extent[ax]);
    let (mid, lc, rc) = partition(prims, |p| bin_of(p.centroid_on(ax), min, scale) < boundary);
    if mid == 0 || mid == n {
        return (n > max_leaf).then(|| Split::at(prims, ax, n / 2));
    }
    Some(Split::from_bins(&bins, ax, boundary, mid, lc, rc))
}

/// [`choose_split`] for nodes above [`PARALLEL_NODE_THRESHOLD`] primitives: bins in parallel
/// chunks and partitions stably from `data` into `spare` (then `true`: the primitives are in
/// `spare`, every element written) or splits in place (`false`). Such nodes are never leaves
/// unless no split exists at all (then `None`, nothing moved).
fn split_large(
    data: &mut [BuildPrim],
    spare: &mut [MaybeUninit<BuildPrim>],
    nb: &NodeBounds,
    depth: usize,
) -> Option<(Split, bool)> {
    let n = data.len();
    let centroid_bounds = nb.centroids;
    let axis = centroid_bounds.longest_axis();
    let extent = centroid_bounds.max - centroid_bounds.min;
    if extent[axis] <= 0.0 {
        return Some((Split::at(data, axis, n / 2), false));
    }
    if depth + 8 >= MAX_DEPTH {
        data.select_nth_unstable_by(n / 2, |a, b| {
            a.centroid_on(axis).total_cmp(&b.centroid_on(axis))
        });
        return Some((Split::at(data, axis, n / 2), false));
    }
    // Each chunk's bins are kept: their counts place the chunk's output in the partition.
    // Counts add and boxes take min/max, both exact, so the merged bins do not depend on how
    // the chunks were scheduled.
    let chunks: Vec<Bins> = data
        .par_chunks(CHUNK)
        .map(|c| {
            let mut b = Bins::EMPTY;
            b.add(c, &centroid_bounds);
            b
        })
        .collect();
    let mut bins = Bins::EMPTY;
    for c in &chunks {
        bins.merge(c);
    }
    // (The SAH leaf test of `choose_split` never applies above `MAX_LEAF_SIZE`.)
    let (_, ax, boundary) = best_split(&bins, extent)?;
    let lefts: Vec<usize> = chunks
        .iter()
        .map(|b| b.counts[ax][..boundary].iter().sum::<u32>() as usize)
        .collect();
    let (min, scale) = (centroid_bounds.min[ax], BIN_COUNT as f32 / extent[ax]);
    let goes_left = |p: &BuildPrim| bin_of(p.centroid_on(ax), min, scale) < boundary;
    let (mid, lc, rc) = partition_into(data, spare, &lefts, goes_left);
    if mid == 0 || mid == n {
        // SAFETY: `partition_into` wrote every element of `spare`.
        let moved = unsafe { assume_init(spare) };
        return Some((Split::at(moved, ax, n / 2), true));
    }
    Some((Split::from_bins(&bins, ax, boundary, mid, lc, rc), true))
}

/// The cheapest split by the SAH over the bins of every axis with a non-zero centroid
/// extent: (cost, axis, first bin of the right side).
fn best_split(bins: &Bins, extent: Vec3A) -> Option<(f32, usize, usize)> {
    let mut best: Option<(f32, usize, usize)> = None;
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
    best
}

#[inline]
pub(super) fn bin_of(c: f32, min: f32, scale: f32) -> usize {
    (((c - min) * scale) as usize).min(BIN_COUNT - 1)
}

/// In-place (unstable) partition; also returns the centroid bounds of both sides, gathered
/// in the same pass.
pub(super) fn partition<F: Fn(&BuildPrim) -> bool>(
    prims: &mut [BuildPrim],
    left: F,
) -> (usize, Aabb, Aabb) {
    let (mut lc, mut rc) = (Aabb::EMPTY, Aabb::EMPTY);
    let mut i = 0;
    for j in 0..prims.len() {
        if left(&prims[j]) {
            lc = lc.grow(prims[j].centroid());
            prims.swap(i, j);
            i += 1;
        } else {
            rc = rc.grow(prims[j].centroid());
        }
    }
    (i, lc, rc)
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

    /// Adds `prims` to the bins of every axis with a non-zero centroid extent. One pass:
    /// each primitive's box is loaded once and its three bins come from one vector
    /// operation, lane for lane the IEEE operations of [`bin_of`] (the clamp to
    /// `0 ..= BIN_COUNT − 1` before the truncation gives what the saturating cast and the
    /// `min` after it give, NaN included), so the bins are those of three passes of
    /// [`bin_of`], filled in the same order.
    fn add(&mut self, prims: &[BuildPrim], centroids: &Aabb) {
        let extent = centroids.max - centroids.min;
        let used = [extent.x > 0.0, extent.y > 0.0, extent.z > 0.0];
        if !used.contains(&true) {
            return;
        }
        let scale = Vec3A::splat(BIN_COUNT as f32) / extent;
        let top = Vec3A::splat((BIN_COUNT - 1) as f32);
        for p in prims {
            let b = p.bounds();
            let bins = ((b.centroid() - centroids.min) * scale)
                .max(Vec3A::ZERO)
                .min(top)
                .to_array();
            for ax in 0..3 {
                if used[ax] {
                    let k = bins[ax] as usize;
                    self.counts[ax][k] += 1;
                    self.boxes[ax][k] = self.boxes[ax][k].union(&b);
                }
            }
        }
    }

    fn merge(&mut self, o: &Bins) {
        for ax in 0..3 {
            for b in 0..BIN_COUNT {
                self.counts[ax][b] += o.counts[ax][b];
                self.boxes[ax][b] = self.boxes[ax][b].union(&o.boxes[ax][b]);
            }
        }
    }
}

/// Stable partition in parallel chunks (both sides keep the input order), counting each
/// chunk's left primitives first, into a new buffer copied back. The result depends only on
/// the input, never on the thread count.
#[cfg(test)]
pub(super) fn partition_stable_parallel<F: Fn(&BuildPrim) -> bool + Sync>(
    prims: &mut [BuildPrim],
    left: F,
) -> usize {
    let lefts: Vec<usize> = prims
        .par_chunks(CHUNK)
        .map(|c| c.iter().filter(|p| left(p)).count())
        .collect();
    let mut out: Vec<BuildPrim> = Vec::with_capacity(prims.len());
    let (mid, _, _) = partition_into(
        prims,
        &mut out.spare_capacity_mut()[..prims.len()],
        &lefts,
        left,
    );
    // SAFETY: `partition_into` wrote every element.
    unsafe { out.set_len(prims.len()) };
    prims.copy_from_slice(&out);
    mid
}

/// Stable partition of `src` into `dst` (as long) in parallel chunks of [`CHUNK`] whose left
/// counts `lefts` are known (from the chunks' bins): prefix sums give every chunk its own
/// ranges of `dst`, and chunks copy there independently, gathering both sides' centroid
/// bounds as they go. Writes every element of `dst`; returns the left count and the sides'
/// centroid bounds.
pub(super) fn partition_into<F: Fn(&BuildPrim) -> bool + Sync>(
    src: &[BuildPrim],
    dst: &mut [MaybeUninit<BuildPrim>],
    lefts: &[usize],
    left: F,
) -> (usize, Aabb, Aabb) {
    assert_eq!(
        src.len(),
        dst.len(),
        "partition source and target have one length"
    );
    let mid: usize = lefts.iter().sum();
    let (mut l_rest, mut r_rest) = dst.split_at_mut(mid);
    let mut targets = Vec::with_capacity(lefts.len());
    for (k, &nl) in lefts.iter().enumerate() {
        let len = CHUNK.min(src.len() - k * CHUNK);
        let (l, lr) = std::mem::take(&mut l_rest).split_at_mut(nl);
        let (r, rr) = std::mem::take(&mut r_rest).split_at_mut(len - nl);
        (l_rest, r_rest) = (lr, rr);
        targets.push((l, r));
    }
    // The chunks' left and right ranges tile `dst` exactly (their lengths sum to each
    // chunk's length, the left ones to `mid`), so every element is written once.
    let (lc, rc) = src
        .par_chunks(CHUNK)
        .zip(targets.into_par_iter())
        .map(|(src, (l, r))| {
            let (mut i, mut j) = (0, 0);
            let (mut lc, mut rc) = (Aabb::EMPTY, Aabb::EMPTY);
            for p in src {
                if left(p) {
                    lc = lc.grow(p.centroid());
                    l[i].write(*p);
                    i += 1;
                } else {
                    rc = rc.grow(p.centroid());
                    r[j].write(*p);
                    j += 1;
                }
            }
            (lc, rc)
        })
        .reduce(
            || (Aabb::EMPTY, Aabb::EMPTY),
            |a, b| (a.0.union(&b.0), a.1.union(&b.1)),
        );
    (mid, lc, rc)
}

/// The serial build of a subtree (below [`PARALLEL_THRESHOLD`] primitives) into `out`,
/// depth-first; interior offsets are distances from the node to its second child.
pub(super) fn build_into(
    prims: &mut [BuildPrim],
    first: usize,
    depth: usize,
    nb: NodeBounds,
    max_leaf: usize,
    out: &mut Vec<Node>,
) {
    let Some(split) = choose_split(prims, &nb, depth, max_leaf) else {
        out.push(leaf(prims, nb.bounds, first));
        return;
    };
    let me = out.len();
    out.push(interior(&nb.bounds, split.axis));
    let (left, right) = prims.split_at_mut(split.mid);
    build_into(left, first, depth + 1, split.left, max_leaf, out);
    out[me].offset = (out.len() - me) as u32;
    build_into(
        right,
        first + split.mid,
        depth + 1,
        split.right,
        max_leaf,
        out,
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every bit of a reference list and of its root bounds, for exact comparison.
    fn bits(prims: &[BuildPrim], root: &NodeBounds) -> (Vec<[u32; 8]>, [u32; 12]) {
        let v3 = |v: Vec3A| v.to_array().map(f32::to_bits);
        let list = prims
            .iter()
            .map(|p| {
                let [a, b, c] = p.min.map(f32::to_bits);
                let [d, e, f] = p.max.map(f32::to_bits);
                [a, b, c, p.index, d, e, f, p._pad]
            })
            .collect();
        let r = [
            root.bounds.min,
            root.bounds.max,
            root.centroids.min,
            root.centroids.max,
        ]
        .map(v3);
        (list, r.concat().try_into().unwrap())
    }

    fn on_threads<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(f)
    }

    // The references written over the boxes' own storage are exactly those of the copying
    // pass (boxes, indices, order, root bounds), on 1 and 2 threads: with every box usable
    // (no serial pass) and with unusable boxes (empty, NaN, infinite) at the first and last
    // place, at chunk boundaries and in runs, which the serial pass moves the rest over.
    #[test]
    fn references_over_the_boxes_match_the_copy() {
        let mut s = 99u64;
        let mut next = move || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 40) as f32 / (1u64 << 24) as f32
        };
        let n = 3 * CHUNK + 1237;
        let all_usable: Vec<Aabb> = (0..n)
            .map(|_| {
                let p = Vec3A::new(next(), next(), next()) * 50.0 - 25.0;
                Aabb {
                    min: p,
                    max: p + Vec3A::new(next(), next(), next()),
                }
            })
            .collect();
        let mut some_unusable = all_usable.clone();
        let bad = [
            Aabb::EMPTY,
            Aabb {
                min: Vec3A::new(f32::NAN, 0.0, 0.0),
                max: Vec3A::ONE,
            },
            Aabb {
                min: Vec3A::ZERO,
                max: Vec3A::new(1.0, f32::INFINITY, 1.0),
            },
        ];
        let places = [
            0,
            1,
            2,
            CHUNK - 1,
            CHUNK,
            2 * CHUNK + 5,
            2 * CHUNK + 6,
            n - 1,
        ];
        for (k, &i) in places.iter().enumerate() {
            some_unusable[i] = bad[k % bad.len()];
        }
        for i in (CHUNK + 100..CHUNK + 400).step_by(3) {
            some_unusable[i] = bad[i % bad.len()];
        }
        for boxes in [&all_usable, &some_unusable] {
            let (copied, root) = build_prims(boxes);
            let want = bits(&copied, &root);
            for threads in [1, 2] {
                let (owned, root) = on_threads(threads, || build_prims_owned(boxes.clone()));
                assert_eq!(bits(&owned, &root), want, "{threads} thread(s)");
            }
        }
        assert_eq!(build_prims(&some_unusable).0.len(), n - places.len() - 100);
        // And so the same tree, both layouts' node arrays and the leaf order.
        for threads in [1, 2] {
            let (a, b) = on_threads(threads, || {
                (
                    super::super::Bvh::build_with_layout(&some_unusable, Default::default()),
                    super::super::Bvh::build_owned(some_unusable.clone(), Default::default(), true),
                )
            });
            assert_eq!(a.fingerprint(), b.fingerprint());
            assert_eq!(a.order_ref(), b.order_ref());
        }
    }
}

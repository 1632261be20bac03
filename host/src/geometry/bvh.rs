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
//! largest-area interior children until it has eight), as Embree does on AVX machines: a ray
//! then makes one eight-box SIMD test where the binary tree needed up to seven node visits
//! with one scalar box test each. Nodes store their children's boxes as structure-of-arrays
//! (256 bytes, four cache lines) and are laid out depth-first.
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

use std::mem::MaybeUninit;

use glam::{Vec3A, Vec4};
use rayon::prelude::*;

use super::float_error::gamma;
use super::{Aabb, Ray};

/// Number of centroid bins per axis in the SAH build.
pub const BIN_COUNT: usize = 16;
/// Leaves hold at most this many primitives.
pub const MAX_LEAF_SIZE: usize = 4;
/// Cost of visiting a node relative to one primitive test, in the SAH.
const TRAVERSAL_COST: f32 = 1.0;
/// Subtrees with more primitives than this are built in parallel.
const PARALLEL_THRESHOLD: usize = 16 * 1024;
/// Nodes with more primitives than this compute their bounds, bins and partition in parallel
/// (the top levels, where `rayon::join` over subtrees has nothing to split yet).
const PARALLEL_NODE_THRESHOLD: usize = 64 * 1024;
/// Primitives per parallel task in those passes.
const CHUNK: usize = 16 * 1024;
/// Binary tree depth limit; the build keeps the tree shallower than this (see `choose_split`).
const MAX_DEPTH: usize = 64;
/// Traversal stack entries kept on the machine stack: at most seven are pushed per wide level,
/// so 64 cover nine levels even when every box is hit; deeper searches spill into a `Vec`. The
/// array is left uninitialised (zeroing it for every ray cost 4% of traversal).
const STACK_SIZE: usize = 64;

/// One node of the binary build tree (32 bytes), stored depth-first.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
struct Node {
    min: [f32; 3],
    /// Leaf: first primitive (in [`Bvh::order`] order). Interior: index of the second child.
    offset: u32,
    max: [f32; 3],
    /// Number of primitives; 0 for interior nodes.
    count: u16,
    /// Split axis of an interior node.
    axis: u8,
    _pad: u8,
}

/// Child slots per wide node.
const WIDTH: usize = 8;

/// One eight-wide node (256 bytes): the boxes of up to eight children as structure of arrays,
/// so one SIMD operation handles the same coordinate of all eight (each array is 32-byte
/// aligned, one AVX register). An unused slot has an empty box (`min = +∞`, `max = −∞`) that
/// no ray meets.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(64))]
struct WideNode {
    min_x: [f32; WIDTH],
    min_y: [f32; WIDTH],
    min_z: [f32; WIDTH],
    max_x: [f32; WIDTH],
    max_y: [f32; WIDTH],
    max_z: [f32; WIDTH],
    /// Interior child: index of its wide node. Leaf child: its first primitive (leaf order).
    child: [u32; WIDTH],
    /// Leaf child: number of primitives (> 0). Interior child or unused slot: 0.
    count: [u16; WIDTH],
    /// Number of used slots (the first ones).
    slots: u32,
    _pad: [u32; 3],
}

// Four cache lines, as the layout comment says.
const _: () = assert!(std::mem::size_of::<WideNode>() == 256);

impl WideNode {
    const EMPTY: WideNode = WideNode {
        min_x: [f32::INFINITY; WIDTH],
        min_y: [f32::INFINITY; WIDTH],
        min_z: [f32::INFINITY; WIDTH],
        max_x: [f32::NEG_INFINITY; WIDTH],
        max_y: [f32::NEG_INFINITY; WIDTH],
        max_z: [f32::NEG_INFINITY; WIDTH],
        child: [u32::MAX; WIDTH],
        count: [0; WIDTH],
        slots: 0,
        _pad: [0; 3],
    };

    fn set_box(&mut self, slot: usize, n: &Node) {
        self.min_x[slot] = n.min[0];
        self.min_y[slot] = n.min[1];
        self.min_z[slot] = n.min[2];
        self.max_x[slot] = n.max[0];
        self.max_y[slot] = n.max[1];
        self.max_z[slot] = n.max[2];
    }
}

/// Which box-test kernel the traversal runs (see the module documentation).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TraversalKernel {
    /// Two four-wide halves per node (`glam::Vec4`); runs everywhere.
    #[default]
    Portable,
    /// One 256-bit AVX operation per node; only where the CPU has AVX2.
    Avx2,
}

impl TraversalKernel {
    /// The fastest kernel this CPU runs.
    pub fn best_available() -> TraversalKernel {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            return TraversalKernel::Avx2;
        }
        TraversalKernel::Portable
    }
}

/// A BVH over primitives given by their bounds.
#[derive(Clone, Debug, Default)]
pub struct Bvh {
    nodes: Vec<WideNode>,
    /// Primitive indices (into the list given to [`Bvh::build`]) in leaf order.
    order: Vec<u32>,
    /// Bounds of everything in the tree.
    bounds: Option<Aabb>,
    /// The box-test kernel [`Bvh::traverse`] uses; [`TraversalKernel::Avx2`] only where the
    /// CPU has it.
    kernel: TraversalKernel,
}

#[derive(Clone, Copy)]
struct BuildPrim {
    bounds: Aabb,
    centroid: Vec3A,
    index: u32,
}

/// A traversal stack entry: a wide node (`count == 0`) or a leaf's primitives, and the
/// distance at which the ray enters its box.
#[derive(Clone, Copy)]
struct Entry {
    /// Interior: wide node index. Leaf: first primitive in leaf order.
    child: u32,
    /// Leaf: number of primitives; 0 for a wide node.
    count: u32,
    /// Entry distance into the box (units of `ray.dir`).
    near: f32,
}

/// What the box-test kernels need of a ray, computed once per ray.
struct RayBoxes {
    origin: [f32; 3],
    inv_dir: [f32; 3],
}

impl Bvh {
    /// Builds over primitives with the given bounds. Primitives with empty or non-finite bounds
    /// are left out (they can never be hit).
    pub fn build(bounds: &[Aabb]) -> Bvh {
        // In parallel and in order (rayon's collect keeps the input order).
        let mut prims: Vec<BuildPrim> = bounds
            .par_iter()
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
        let binary = build_range(&mut prims, 0, 0);
        let order = prims.par_iter().map(|p| p.index).collect();
        let root = &binary[0];
        let bounds = Some(Aabb {
            min: Vec3A::from(root.min),
            max: Vec3A::from(root.max),
        });
        Bvh {
            nodes: collapse(&binary),
            order,
            bounds,
            kernel: TraversalKernel::best_available(),
        }
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
        self.nodes.len() * std::mem::size_of::<WideNode>() + self.order.len() * 4
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
        t_max: f32,
        any_hit: bool,
        test: F,
    ) -> Option<f32> {
        self.traverse_with_stack::<STACK_SIZE, F>(ray, t_max, any_hit, test)
    }

    /// [`Bvh::traverse`] with `N` fixed stack entries before spilling (tests use a tiny `N`).
    #[inline]
    fn traverse_with_stack<const N: usize, F: FnMut(u32, f32) -> Option<f32>>(
        &self,
        ray: &Ray,
        t_max: f32,
        any_hit: bool,
        test: F,
    ) -> Option<f32> {
        if self.nodes.is_empty() {
            return None;
        }
        #[cfg(target_arch = "x86_64")]
        if self.kernel == TraversalKernel::Avx2 {
            // SAFETY: `kernel` is `Avx2` only when the CPU reports AVX2 (`best_available`,
            // `set_kernel`).
            return unsafe { self.traverse_avx2::<N, F>(ray, t_max, any_hit, test) };
        }
        self.traverse_loop::<N, false, F>(ray, t_max, any_hit, test)
    }

    /// The traversal loop compiled with AVX2 enabled, so the eight-box test is one 256-bit
    /// operation and the loop around it (and the inlined primitive test) is compiled for it.
    ///
    /// # Safety
    /// The CPU must support AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn traverse_avx2<const N: usize, F: FnMut(u32, f32) -> Option<f32>>(
        &self,
        ray: &Ray,
        t_max: f32,
        any_hit: bool,
        test: F,
    ) -> Option<f32> {
        self.traverse_loop::<N, true, F>(ray, t_max, any_hit, test)
    }

    /// The one traversal loop; `AVX2` picks the box-test kernel (true only when called from
    /// [`Bvh::traverse_avx2`]).
    #[inline(always)]
    fn traverse_loop<const N: usize, const AVX2: bool, F: FnMut(u32, f32) -> Option<f32>>(
        &self,
        ray: &Ray,
        mut t_max: f32,
        any_hit: bool,
        mut test: F,
    ) -> Option<f32> {
        let inv_dir = Vec3A::ONE / ray.dir;
        let rb = RayBoxes {
            origin: ray.origin.to_array(),
            inv_dir: inv_dir.to_array(),
        };
        // Uninitialised: only entries below `sp` are ever read.
        let mut stack = [const { MaybeUninit::<Entry>::uninit() }; N];
        let mut sp = 0usize;
        // Older entries moved out when the fixed stack was full (newest last); they lie below
        // everything on the fixed stack. Empty, and so never allocated, for the trees the
        // build makes in practice.
        let mut spill: Vec<Entry> = Vec::new();
        let mut entry = Entry {
            child: 0,
            count: 0,
            near: 0.0,
        };
        let mut found = None;
        loop {
            // Entries pushed before the search shrank may now lie beyond it.
            if entry.near <= t_max {
                if entry.count > 0 {
                    for slot in entry.child..entry.child + entry.count {
                        if let Some(t) = test(slot, t_max) {
                            t_max = t;
                            found = Some(t);
                            if any_hit {
                                return found;
                            }
                        }
                    }
                } else {
                    let n = &self.nodes[entry.child as usize];
                    let mut near = [0.0f32; WIDTH];
                    #[cfg(target_arch = "x86_64")]
                    let mask = if AVX2 {
                        // SAFETY: `AVX2` is true only inside `traverse_avx2`.
                        unsafe { node_hits_avx2(n, &rb, t_max, &mut near) }
                    } else {
                        node_hits_portable(n, &rb, t_max, &mut near)
                    };
                    #[cfg(not(target_arch = "x86_64"))]
                    let mask = node_hits_portable(n, &rb, t_max, &mut near);
                    if mask != 0 {
                        // `i` is a set bit of an eight-bit mask; `& 7` lets the compiler
                        // drop the bounds checks.
                        let at = |i: u32| {
                            let i = i as usize & (WIDTH - 1);
                            Entry {
                                child: n.child[i],
                                count: n.count[i] as u32,
                                near: near[i],
                            }
                        };
                        let first = mask.trailing_zeros();
                        let rest = mask & (mask - 1);
                        if rest == 0 {
                            // One box hit (the common case deep in the tree): no stack.
                            entry = at(first);
                            continue;
                        }
                        if any_hit {
                            // Any hit ends the search, so order does not matter: no sort.
                            let mut m = rest;
                            while m != 0 {
                                push(&mut stack, &mut sp, &mut spill, at(m.trailing_zeros()));
                                m &= m - 1;
                            }
                            entry = at(first);
                            continue;
                        }
                        let second = rest.trailing_zeros();
                        if rest & (rest - 1) == 0 {
                            // Two boxes: visit the nearer (the first slot on a tie).
                            let (a, b) = (at(first), at(second));
                            let (now, later) = if b.near < a.near { (b, a) } else { (a, b) };
                            push(&mut stack, &mut sp, &mut spill, later);
                            entry = now;
                            continue;
                        }
                        // Three or more: insertion sort by entry distance (stable, so ties
                        // keep slot order), visit the nearest, push the others farthest first.
                        let mut hits = [Entry {
                            child: 0,
                            count: 0,
                            near: 0.0,
                        }; WIDTH];
                        let mut k = 0;
                        let mut m = mask;
                        while m != 0 {
                            let e = at(m.trailing_zeros());
                            m &= m - 1;
                            let mut j = k;
                            while j > 0 && hits[j - 1].near > e.near {
                                hits[j] = hits[j - 1];
                                j -= 1;
                            }
                            hits[j] = e;
                            k += 1;
                        }
                        for h in hits[1..k].iter().rev() {
                            push(&mut stack, &mut sp, &mut spill, *h);
                        }
                        entry = hits[0];
                        continue;
                    }
                }
            }
            if sp > 0 {
                sp -= 1;
                // SAFETY: entries below the old `sp` were written by `push`.
                entry = unsafe { stack[sp].assume_init() };
            } else if let Some(e) = spill.pop() {
                entry = e;
            } else {
                return found;
            }
        }
    }
}

/// Pushes `e` on the traversal stack. When the `N` fixed entries are used they move, in order,
/// to the end of `spill` (below every later entry), so a pop looks at `spill` only once the
/// fixed stack is empty and the visiting order is the same as with one unbounded stack.
#[inline(always)]
fn push<const N: usize>(
    stack: &mut [MaybeUninit<Entry>; N],
    sp: &mut usize,
    spill: &mut Vec<Entry>,
    e: Entry,
) {
    if *sp == N {
        spill_stack(stack, spill);
        *sp = 0;
    }
    stack[*sp].write(e);
    *sp += 1;
}

/// Moves the full fixed stack to the end of `spill` (kept out of line: it never runs for the
/// trees the build makes in practice).
#[cold]
#[inline(never)]
fn spill_stack<const N: usize>(stack: &[MaybeUninit<Entry>; N], spill: &mut Vec<Entry>) {
    // SAFETY: called only when all `N` entries were written.
    spill.extend(stack.iter().map(|e| unsafe { e.assume_init() }));
}

/// Slab test of a node's eight boxes with two four-wide halves: the bit mask of the used slots
/// the ray meets before `t_max`, and each box's entry distance in `near`. Operand order matters
/// for NaN (a ray parallel to a slab and starting on its plane): SSE `min`/`max` return their
/// second operand when either is NaN, as `Aabb::hit` relies on too; [`node_hits_avx2`] does
/// exactly the same operations.
#[inline(always)]
fn node_hits_portable(n: &WideNode, r: &RayBoxes, t_max: f32, near: &mut [f32; WIDTH]) -> u32 {
    let (ox, oy, oz) = (
        Vec4::splat(r.origin[0]),
        Vec4::splat(r.origin[1]),
        Vec4::splat(r.origin[2]),
    );
    let (ix, iy, iz) = (
        Vec4::splat(r.inv_dir[0]),
        Vec4::splat(r.inv_dir[1]),
        Vec4::splat(r.inv_dir[2]),
    );
    // Enlarging the far distance by 1 + 2γ₃ keeps the test conservative (see `Aabb::hit`).
    let far_scale = Vec4::splat(1.0 + 2.0 * gamma(3));
    let t_max = Vec4::splat(t_max);
    let mut mask = 0;
    for half in 0..2 {
        let lane = |a: &[f32; WIDTH]| Vec4::from_slice(&a[4 * half..4 * half + 4]);
        let tx0 = (lane(&n.min_x) - ox) * ix;
        let tx1 = (lane(&n.max_x) - ox) * ix;
        let ty0 = (lane(&n.min_y) - oy) * iy;
        let ty1 = (lane(&n.max_y) - oy) * iy;
        let tz0 = (lane(&n.min_z) - oz) * iz;
        let tz1 = (lane(&n.max_z) - oz) * iz;
        let t_near = tx0
            .min(tx1)
            .max(ty0.min(ty1).max(tz0.min(tz1).max(Vec4::ZERO)));
        let t_far = tx0.max(tx1).min(ty0.max(ty1).min(tz0.max(tz1).min(t_max))) * far_scale;
        mask |= t_near.cmple(t_far).bitmask() << (4 * half);
        t_near.write_to_slice(&mut near[4 * half..4 * half + 4]);
    }
    // Unused slots sit at the end; their empty boxes can pass the slab test (±∞ − ±∞
    // orders), so they are masked out by the slot count.
    mask & ((1u32 << n.slots) - 1)
}

/// [`node_hits_portable`] as one 256-bit operation per step: the same IEEE operations with the
/// same operand order on every lane (`_mm256_min_ps(a, b)` returns `b` on NaN like
/// `_mm_min_ps`), so the same mask and the same distances bit for bit.
///
/// # Safety
/// The CPU must support AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn node_hits_avx2(n: &WideNode, r: &RayBoxes, t_max: f32, near: &mut [f32; WIDTH]) -> u32 {
    use std::arch::x86_64::*;
    let (ox, oy, oz) = (
        _mm256_set1_ps(r.origin[0]),
        _mm256_set1_ps(r.origin[1]),
        _mm256_set1_ps(r.origin[2]),
    );
    let (ix, iy, iz) = (
        _mm256_set1_ps(r.inv_dir[0]),
        _mm256_set1_ps(r.inv_dir[1]),
        _mm256_set1_ps(r.inv_dir[2]),
    );
    let far_scale = _mm256_set1_ps(1.0 + 2.0 * gamma(3));
    let t_max = _mm256_set1_ps(t_max);
    // SAFETY: the arrays are 32 bytes each at 32-byte offsets of a 64-byte-aligned node.
    let lane = |a: &[f32; WIDTH]| unsafe { _mm256_load_ps(a.as_ptr()) };
    let tx0 = _mm256_mul_ps(_mm256_sub_ps(lane(&n.min_x), ox), ix);
    let tx1 = _mm256_mul_ps(_mm256_sub_ps(lane(&n.max_x), ox), ix);
    let ty0 = _mm256_mul_ps(_mm256_sub_ps(lane(&n.min_y), oy), iy);
    let ty1 = _mm256_mul_ps(_mm256_sub_ps(lane(&n.max_y), oy), iy);
    let tz0 = _mm256_mul_ps(_mm256_sub_ps(lane(&n.min_z), oz), iz);
    let tz1 = _mm256_mul_ps(_mm256_sub_ps(lane(&n.max_z), oz), iz);
    let t_near = _mm256_max_ps(
        _mm256_min_ps(tx0, tx1),
        _mm256_max_ps(
            _mm256_min_ps(ty0, ty1),
            _mm256_max_ps(_mm256_min_ps(tz0, tz1), _mm256_setzero_ps()),
        ),
    );
    let t_far = _mm256_mul_ps(
        _mm256_min_ps(
            _mm256_max_ps(tx0, tx1),
            _mm256_min_ps(
                _mm256_max_ps(ty0, ty1),
                _mm256_min_ps(_mm256_max_ps(tz0, tz1), t_max),
            ),
        ),
        far_scale,
    );
    // `_CMP_LE_OQ` is false on NaN, like SSE's `cmpleps`.
    let mask = _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(t_near, t_far)) as u32;
    // SAFETY: `near` holds eight f32.
    unsafe { _mm256_storeu_ps(near.as_mut_ptr(), t_near) };
    mask & ((1u32 << n.slots) - 1)
}

/// Collapses the binary tree (depth-first, first child next, `offset` the second) into wide
/// nodes, depth-first. Each wide node takes its binary node's two children and repeatedly
/// replaces the interior one with the largest surface area by its two children, up to eight.
fn collapse(binary: &[Node]) -> Vec<WideNode> {
    let root_children = if binary[0].count > 0 {
        vec![0]
    } else {
        binary_children(binary, 0).to_vec()
    };
    wide_subtree(binary, root_children, 0)
}

fn binary_children(binary: &[Node], i: usize) -> [usize; 2] {
    [i + 1, binary[i].offset as usize]
}

fn node_area(n: &Node) -> f32 {
    Aabb {
        min: Vec3A::from(n.min),
        max: Vec3A::from(n.max),
    }
    .surface_area()
}

/// Wide levels whose subtrees are collapsed in parallel (8² = 64 tasks at most).
const PARALLEL_COLLAPSE_DEPTH: usize = 2;

/// The wide subtree over `children` (binary node indices) with its root at index 0 and child
/// indices relative to it. Near the root the interior children's subtrees are collapsed in
/// parallel and appended in slot order, which is exactly the depth-first layout
/// [`fill_wide`] makes, so the result is the same for any thread count.
fn wide_subtree(binary: &[Node], children: Vec<usize>, depth: usize) -> Vec<WideNode> {
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
fn expand_children(binary: &[Node], mut children: Vec<usize>) -> Vec<usize> {
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
fn fill_wide(binary: &[Node], children: Vec<usize>, me: usize, out: &mut Vec<WideNode>) {
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

/// Primitive counts and bounds per bin along each axis.
struct Bins {
    counts: [[u32; BIN_COUNT]; 3],
    boxes: [[Aabb; BIN_COUNT]; 3],
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
fn bin_all(prims: &[BuildPrim], centroids: &Aabb) -> Bins {
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
fn prim_bounds(prims: &[BuildPrim]) -> Aabb {
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
fn centroid_bounds(prims: &[BuildPrim]) -> Aabb {
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
fn partition_stable_parallel<F: Fn(&BuildPrim) -> bool + Sync>(
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

fn build_into(prims: &mut [BuildPrim], first: usize, depth: usize, out: &mut Vec<Node>) {
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

    /// Uniform numbers in [0, 1) from a 64-bit LCG started at `s` (the tests' shared
    /// deterministic source of boxes and rays).
    fn uniform_stream(mut s: u64) -> impl FnMut() -> f32 {
        move || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 40) as f32 / (1u64 << 24) as f32
        }
    }

    // Determinism: the parallel build must produce the identical tree (same leaf order, same
    // node bounds and offsets) on 1 and on 2 threads; compared exactly.
    #[test]
    fn build_is_independent_of_thread_count() {
        let mut bounds = Vec::new();
        let mut s = 777u64;
        for _ in 0..(PARALLEL_NODE_THRESHOLD * 2 + 1000) {
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
        assert_eq!(a.nodes, b.nodes);
    }

    // The collapse near the root runs its subtrees in parallel and appends them; the layout must
    // be exactly the sequential depth-first one (every node's boxes, children, leaf sizes and
    // slot counts compared exactly), and the parallel stable partition must equal a sequential
    // stable partition.
    #[test]
    fn parallel_collapse_and_partition_match_sequential() {
        let mut next = uniform_stream(4242);
        let mut prims: Vec<BuildPrim> = (0..(PARALLEL_NODE_THRESHOLD + 5000))
            .map(|i| {
                let p = Vec3A::new(next(), next(), next()) * 100.0;
                let b = Aabb {
                    min: p,
                    max: p + Vec3A::splat(0.5),
                };
                BuildPrim {
                    bounds: b,
                    centroid: b.centroid(),
                    index: i as u32,
                }
            })
            .collect();
        let left = |p: &BuildPrim| p.centroid.x < 37.0;
        let mut seq: Vec<u32> = prims.iter().filter(|p| left(p)).map(|p| p.index).collect();
        seq.extend(prims.iter().filter(|p| !left(p)).map(|p| p.index));
        let mut par = prims.clone();
        let mid = partition_stable_parallel(&mut par, left);
        assert_eq!(mid, prims.iter().filter(|p| left(p)).count());
        assert_eq!(par.iter().map(|p| p.index).collect::<Vec<_>>(), seq);

        let binary = build_range(&mut prims, 0, 0);
        let mut sequential = vec![WideNode::EMPTY];
        fill_wide(
            &binary,
            binary_children(&binary, 0).to_vec(),
            0,
            &mut sequential,
        );
        assert_eq!(collapse(&binary), sequential);
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
        let mut leaves = 0;
        for n in &bvh.nodes {
            for slot in 0..WIDTH {
                if n.count[slot] == 0 {
                    continue;
                }
                leaves += n.count[slot] as usize;
                let first = n.child[slot] as usize;
                for &i in &bvh.order[first..first + n.count[slot] as usize] {
                    let b = bounds[i as usize];
                    assert!(
                        n.min_x[slot] <= b.min.x
                            && n.min_y[slot] <= b.min.y
                            && n.min_z[slot] <= b.min.z
                            && n.max_x[slot] >= b.max.x
                            && n.max_y[slot] >= b.max.y
                            && n.max_z[slot] >= b.max.z
                    );
                }
            }
        }
        // Every primitive sits in exactly one leaf slot.
        assert_eq!(leaves, bounds.len());
    }

    // The wide traversal must find exactly the closest hit a brute-force loop finds: primitives
    // are boxes, "hit" is the conservative slab test's entry distance, 2000 random rays over
    // 3000 random boxes (small and large, overlapping); compared exactly, and any-hit must agree
    // on whether anything is hit at all.
    #[test]
    fn wide_traversal_matches_brute_force() {
        let mut next = uniform_stream(99);
        let mut boxes = Vec::new();
        for i in 0..3000 {
            let p = Vec3A::new(next(), next(), next()) * 20.0 - 10.0;
            let size = if i % 100 == 0 { 4.0 } else { 0.3 };
            let e = Vec3A::new(next(), next(), next()) * size + 0.01;
            boxes.push(Aabb {
                min: p - e,
                max: p + e,
            });
        }
        let bvh = Bvh::build(&boxes);
        let entry = |b: &Aabb, ray: &Ray, t_max: f32| -> Option<f32> {
            let inv = Vec3A::ONE / ray.dir;
            if !b.hit(ray.origin, inv, t_max) {
                return None;
            }
            let t0 = (b.min - ray.origin) * inv;
            let t1 = (b.max - ray.origin) * inv;
            let t = t0.min(t1).max_element().max(1e-6);
            (t < t_max).then_some(t)
        };
        let mut hits = 0;
        for _ in 0..2000 {
            let o = Vec3A::new(next(), next(), next()) * 30.0 - 15.0;
            let d = Vec3A::new(next(), next(), next()) * 2.0 - 1.0;
            let ray = Ray::new(o, d);
            let brute = boxes
                .iter()
                .filter_map(|b| entry(b, &ray, f32::INFINITY))
                .fold(None, |m: Option<f32>, t| Some(m.map_or(t, |m| m.min(t))));
            let found = bvh.traverse(&ray, f32::INFINITY, false, |slot, t_max| {
                entry(&boxes[bvh.order[slot as usize] as usize], &ray, t_max)
            });
            assert_eq!(found, brute);
            let any = bvh.traverse(&ray, f32::INFINITY, true, |slot, t_max| {
                entry(&boxes[bvh.order[slot as usize] as usize], &ray, t_max)
            });
            assert_eq!(any.is_some(), brute.is_some());
            hits += brute.is_some() as usize;
        }
        // The test means something only if many rays hit and many miss.
        assert!(hits > 200 && hits < 1800, "{hits} of 2000 rays hit");
    }

    // With a two-entry fixed stack nearly every ray spills into the `Vec`; the search must stay
    // exact: the closest hit equals brute force exactly (same boxes and rays as above, and the
    // any-hit query agrees on whether something is hit), and the primitive tests (slot and
    // `t_max`, bit for bit) come in the same order as with the full-size stack.
    #[test]
    fn spilled_stack_stays_exact() {
        let mut next = uniform_stream(5);
        let boxes: Vec<Aabb> = (0..2000)
            .map(|_| {
                let p = Vec3A::new(next(), next(), next()) * 20.0 - 10.0;
                let e = Vec3A::new(next(), next(), next()) * 0.5 + 0.01;
                Aabb {
                    min: p - e,
                    max: p + e,
                }
            })
            .collect();
        let bvh = Bvh::build(&boxes);
        for _ in 0..500 {
            let o = Vec3A::new(next(), next(), next()) * 30.0 - 15.0;
            let ray = Ray::new(o, Vec3A::new(next(), next(), next()) * 2.0 - 1.0);
            let inv = Vec3A::ONE / ray.dir;
            let entry = |b: &Aabb, t_max: f32| -> Option<f32> {
                if !b.hit(ray.origin, inv, t_max) {
                    return None;
                }
                let t = ((b.min - ray.origin) * inv)
                    .min((b.max - ray.origin) * inv)
                    .max_element()
                    .max(1e-6);
                (t < t_max).then_some(t)
            };
            let brute = boxes
                .iter()
                .filter_map(|b| entry(b, f32::INFINITY))
                .fold(None, |m: Option<f32>, t| Some(m.map_or(t, |m| m.min(t))));
            let mut spilled_log = Vec::new();
            let found = bvh.traverse_with_stack::<2, _>(&ray, f32::INFINITY, false, |slot, t| {
                spilled_log.push((slot, t.to_bits()));
                entry(&boxes[bvh.order[slot as usize] as usize], t)
            });
            assert_eq!(found, brute);
            // And in the same order as with the full-size stack (spilling keeps LIFO order).
            let mut log = Vec::new();
            bvh.traverse(&ray, f32::INFINITY, false, |slot, t| {
                log.push((slot, t.to_bits()));
                entry(&boxes[bvh.order[slot as usize] as usize], t)
            });
            assert_eq!(spilled_log, log);
            let any = bvh.traverse_with_stack::<2, _>(&ray, f32::INFINITY, true, |slot, t| {
                entry(&boxes[bvh.order[slot as usize] as usize], t)
            });
            assert_eq!(any.is_some(), brute.is_some());
        }
    }

    // The AVX2 and the portable kernel must walk the tree identically: for every ray the
    // sequence of primitive tests (leaf slot and the `t_max` handed over, compared bit for bit)
    // and the result must be equal, closest-hit and any-hit. 4000 random boxes on an integer
    // grid and 3000 rays, a third of them axis-parallel (zero direction components) starting
    // on box planes, where the slab test meets NaN (0 · ∞) and operand order decides.
    #[test]
    fn kernels_visit_identically() {
        if TraversalKernel::best_available() != TraversalKernel::Avx2 {
            eprintln!("kernels_visit_identically: this CPU has no AVX2, only one kernel to run");
            return;
        }
        let mut next = uniform_stream(31);
        let boxes: Vec<Aabb> = (0..4000)
            .map(|_| {
                let p = (Vec3A::new(next(), next(), next()) * 40.0 - 20.0).floor();
                let e = (Vec3A::new(next(), next(), next()) * 3.0).floor() + 1.0;
                Aabb { min: p, max: p + e }
            })
            .collect();
        let mut bvh = Bvh::build(&boxes);
        let entry = |b: &Aabb, ray: &Ray, t_max: f32| -> Option<f32> {
            let inv = Vec3A::ONE / ray.dir;
            if !b.hit(ray.origin, inv, t_max) {
                return None;
            }
            let t = ((b.min - ray.origin) * inv)
                .min((b.max - ray.origin) * inv)
                .max_element()
                .max(1e-6);
            (t < t_max).then_some(t)
        };
        let mut visits = 0usize;
        for r in 0..3000 {
            let mut o = Vec3A::new(next(), next(), next()) * 50.0 - 25.0;
            let mut d = Vec3A::new(next(), next(), next()) * 2.0 - 1.0;
            if r % 3 == 0 {
                o = o.floor();
                let axis = r / 3 % 3;
                d[axis] = 0.0;
                d[(axis + 1) % 3] = if r % 2 == 0 { 0.0 } else { -0.0 };
            }
            let ray = Ray::new(o, d);
            for any_hit in [false, true] {
                let mut runs = Vec::new();
                for kernel in [TraversalKernel::Portable, TraversalKernel::Avx2] {
                    bvh.set_kernel(kernel);
                    assert_eq!(bvh.kernel(), kernel);
                    let mut log = Vec::new();
                    let found = bvh.traverse(&ray, f32::INFINITY, any_hit, |slot, t_max| {
                        log.push((slot, t_max.to_bits()));
                        entry(&boxes[bvh.order[slot as usize] as usize], &ray, t_max)
                    });
                    runs.push((found.map(f32::to_bits), log));
                }
                visits += runs[0].1.len();
                assert!(runs[0] == runs[1], "ray {r} (any_hit {any_hit}) differs");
            }
        }
        // The comparison means something only if the rays reach many leaves (5,872 primitive
        // tests in 6,000 walks when written).
        assert!(visits > 4_000, "only {visits} primitive tests");
    }
}

//! Closest-first traversal of the eight-wide tree with two box-test kernels (AVX2 chosen at
//! run time, and a portable four-wide one) that visit the same nodes in the same order.

use std::mem::MaybeUninit;

use glam::{Vec3A, Vec4};

use super::kernel::TraversalKernel;
use super::tree::Bvh;
use super::wide_node::{QuantNode, WideNode, WIDTH};
use crate::geometry::float_error::gamma;
use crate::geometry::prefetch::prefetch_line;
use crate::geometry::Ray;

/// Traversal stack entries kept on the machine stack: at most seven are pushed per wide level,
/// so 64 cover nine levels even when every box is hit; deeper searches spill into a `Vec`. The
/// array is left uninitialised (zeroing it for every ray cost 4% of traversal).
pub(super) const STACK_SIZE: usize = 64;

/// A traversal stack entry: a wide node (`count == 0`) or a leaf's primitives, and the
/// distance at which the ray enters its box.
#[derive(Clone, Copy)]
pub(super) struct Entry {
    /// Interior: wide node index. Leaf: first primitive in leaf order.
    pub(super) child: u32,
    /// Leaf: number of primitives; 0 for a wide node.
    pub(super) count: u32,
    /// Entry distance into the box (units of `ray.dir`).
    pub(super) near: f32,
}

/// What the box-test kernels need of a ray, computed once per ray: its origin, the
/// reciprocal of its direction, and for each axis which of a box's two planes the ray meets
/// first (its octant), so a node test reads the entry and exit planes directly instead of
/// ordering both with a `min` and a `max` per axis.
pub(super) struct RayBoxes {
    pub(super) origin: [f32; 3],
    pub(super) inv_dir: [f32; 3],
    /// Per axis, the plane the ray enters through, as an index into a node's planes
    /// `min_x, min_y, min_z, max_x, max_y, max_z`: `axis` where the reciprocal's sign bit is
    /// clear, `axis + 3` where it is set (so `-0.0` counts as negative, as its reciprocal
    /// `-∞` is).
    pub(super) near: [usize; 3],
    /// Per axis, the plane the ray leaves through (the other one).
    pub(super) far: [usize; 3],
}

impl RayBoxes {
    /// The ray's box-test constants.
    ///
    /// Why the entry plane can be chosen by sign alone: for a used slot (`min <= max`) and a
    /// finite non-zero reciprocal, `(min - o) · inv` and `(max - o) · inv` are ordered as the
    /// sign of `inv` says (subtraction and multiplication round monotonically), so the chosen
    /// plane's distance is exactly what `min`/`max` of the two would give, bit for bit (ties
    /// included: equal distances are equal floats, and the zero's sign cannot reach the
    /// stored entry distance, which is last compared with `max(…, +0)`). Only where a
    /// component of the direction is zero (an infinite reciprocal) and the origin lies on a
    /// plane of that axis, `0 · ∞` makes that axis's distance NaN; SSE's `max`/`min` return
    /// their second operand on NaN, so the slab test passes over that axis (in its balanced
    /// pairs, perhaps over its partner too) and judges the box by the others. Passing over a
    /// bound only widens the interval, so the box is met wherever the ordered test met it,
    /// and sometimes where it missed it (a ray grazing a face): as conservative or more, the
    /// same closest hits (test `octant_planes_match_the_ordered_slab_test`).
    ///
    /// The planes are chosen by the sign of the direction rather than of its reciprocal: the
    /// same bit (`1/x` keeps the sign of `x`, zeros and infinities included, and on x86 a NaN
    /// passes through the division with its sign), but the choice, and so the addresses of
    /// the first node's planes, no longer wait for the division: the loads overlap it instead
    /// of following it on the chain from a ray's direction to its first box test.
    #[inline(always)]
    pub(super) fn new(ray: &Ray) -> RayBoxes {
        let inv_dir = (Vec3A::ONE / ray.dir).to_array();
        let dir = ray.dir.to_array();
        // Three times each component's sign bit: the entry plane is `axis + 3·sign`, the exit
        // plane `axis + 3 − 3·sign`. Integer arithmetic on the sign bit (what
        // `is_sign_negative` reads) instead of a select per axis and a second select for the
        // exit planes: about half the instructions per ray, the same indices.
        let s = dir.map(|c| 3 * (c.to_bits() >> 31) as usize);
        RayBoxes {
            origin: ray.origin.to_array(),
            inv_dir,
            near: [s[0], 1 + s[1], 2 + s[2]],
            far: [3 - s[0], 4 - s[1], 5 - s[2]],
        }
    }
}

impl Bvh {
    /// Visits, near-first, every primitive whose leaf box the ray reaches before `t_max`.
    /// `test(slot, t_max)` gets the primitive's position in leaf order (primitive
    /// `order_ref()[slot]` of the build input; callers usually store their primitives in that
    /// order) and returns the hit distance if the primitive is hit closer than `t_max`;
    /// the search then shrinks to that distance. With `any_hit` the walk stops at the first hit
    /// (and visits the boxes farthest first, which only changes how soon).
    /// Returns the closest distance found (or the first, for `any_hit`).
    #[inline]
    pub fn traverse<F: FnMut(u32, f32) -> Option<f32>>(
        &self,
        ray: &Ray,
        t_max: f32,
        any_hit: bool,
        mut test: F,
    ) -> Option<f32> {
        self.traverse_leaves(
            ray,
            t_max,
            any_hit,
            #[inline(always)]
            |first, count, t_max| for_each_slot(first, count, t_max, any_hit, &mut test),
        )
    }

    /// [`Bvh::traverse`] handing over whole leaves: `test(first, count, t_max)` gets the
    /// leaf's primitives `first..first + count` in leaf order (at most the larger of
    /// [`super::MAX_LEAF_SIZE`] and [`super::MERGE_LEAF_PRIMITIVES`]) and returns the closest hit distance below `t_max`
    /// among them (with `any_hit`, any one), as [`Bvh::traverse`]'s per-slot loop would: a
    /// scene that stores a leaf's triangles together can test them in one SIMD pass.
    #[inline]
    pub fn traverse_leaves<F: FnMut(u32, u32, f32) -> Option<f32>>(
        &self,
        ray: &Ray,
        t_max: f32,
        any_hit: bool,
        test: F,
    ) -> Option<f32> {
        self.traverse_with_stack::<STACK_SIZE, F>(ray, t_max, any_hit, test)
    }

    /// [`Bvh::traverse_leaves`] with `N` fixed stack entries before spilling (tests use a tiny
    /// `N`).
    #[inline]
    pub(super) fn traverse_with_stack<const N: usize, F: FnMut(u32, u32, f32) -> Option<f32>>(
        &self,
        ray: &Ray,
        t_max: f32,
        any_hit: bool,
        test: F,
    ) -> Option<f32> {
        let quantised = !self.qnodes.is_empty();
        if self.nodes.is_empty() && !quantised {
            return None;
        }
        #[cfg(target_arch = "x86_64")]
        if self.kernel == TraversalKernel::Avx2 {
            // SAFETY: `kernel` is `Avx2` only when the CPU reports AVX2, `popcnt` and FMA
            // (`best_available`, `set_kernel`).
            return unsafe {
                if quantised {
                    self.traverse_avx2::<N, true, F>(ray, t_max, any_hit, test)
                } else {
                    self.traverse_avx2::<N, false, F>(ray, t_max, any_hit, test)
                }
            };
        }
        if quantised {
            self.traverse_loop::<N, false, true, F>(ray, t_max, any_hit, test)
        } else {
            self.traverse_loop::<N, false, false, F>(ray, t_max, any_hit, test)
        }
    }

    /// The traversal loop compiled with AVX2 enabled, so the eight-box test is one 256-bit
    /// operation and the loop around it (and the inlined primitive test) is compiled for it.
    ///
    /// # Safety
    /// The CPU must support AVX2, `popcnt` and FMA.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,popcnt,fma")]
    unsafe fn traverse_avx2<
        const N: usize,
        const QUANTISED: bool,
        F: FnMut(u32, u32, f32) -> Option<f32>,
    >(
        &self,
        ray: &Ray,
        t_max: f32,
        any_hit: bool,
        test: F,
    ) -> Option<f32> {
        self.traverse_loop::<N, true, QUANTISED, F>(ray, t_max, any_hit, test)
    }

    /// The one traversal loop; `AVX2` picks the box-test kernel (true only when called from
    /// [`Bvh::traverse_avx2`]), `QUANTISED` the node layout (`qnodes` instead of `nodes`).
    #[inline(always)]
    fn traverse_loop<
        const N: usize,
        const AVX2: bool,
        const QUANTISED: bool,
        F: FnMut(u32, u32, f32) -> Option<f32>,
    >(
        &self,
        ray: &Ray,
        mut t_max: f32,
        any_hit: bool,
        mut test: F,
    ) -> Option<f32> {
        let rb = RayBoxes::new(ray);
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
        let later = |e: Entry| {
            if QUANTISED {
                prefetch(&self.qnodes, &e);
            } else {
                prefetch(&self.nodes, &e);
            }
            e
        };
        loop {
            // Entries pushed before the search shrank may now lie beyond it.
            if entry.near <= t_max {
                if entry.count > 0 {
                    if let Some(t) = test(entry.child, entry.count, t_max) {
                        t_max = t;
                        found = Some(t);
                        if any_hit {
                            return found;
                        }
                    }
                } else {
                    let mut near = [0.0f32; WIDTH];
                    let (mask, child, count) = if QUANTISED {
                        debug_assert!((entry.child as usize) < self.qnodes.len());
                        // SAFETY: an interior entry comes from the root (index 0 of a
                        // non-empty array) or a node's interior child reference, which the
                        // collapse sets to an index of the same array (test
                        // `interior_references_index_the_nodes`); `Bvh`'s fields are private
                        // and only the build writes them.
                        let n = unsafe { self.qnodes.get_unchecked(entry.child as usize) };
                        #[cfg(target_arch = "x86_64")]
                        let mask = if AVX2 {
                            // SAFETY: `AVX2` is true only inside `traverse_avx2`.
                            unsafe { quant_hits_avx2(n, &rb, t_max, &mut near) }
                        } else {
                            quant_hits_portable(n, &rb, t_max, &mut near)
                        };
                        #[cfg(not(target_arch = "x86_64"))]
                        let mask = quant_hits_portable(n, &rb, t_max, &mut near);
                        (mask, &n.child, &n.count)
                    } else {
                        debug_assert!((entry.child as usize) < self.nodes.len());
                        // SAFETY: as for `qnodes` above.
                        let n = unsafe { self.nodes.get_unchecked(entry.child as usize) };
                        #[cfg(target_arch = "x86_64")]
                        let mask = if AVX2 {
                            // SAFETY: `AVX2` is true only inside `traverse_avx2`.
                            unsafe { node_hits_avx2(n, &rb, t_max, &mut near) }
                        } else {
                            node_hits_portable(n, &rb, t_max, &mut near)
                        };
                        #[cfg(not(target_arch = "x86_64"))]
                        let mask = node_hits_portable(n, &rb, t_max, &mut near);
                        (mask, &n.child, &n.count)
                    };
                    if mask != 0 {
                        // `i` is a set bit of an eight-bit mask; `& 7` lets the compiler
                        // drop the bounds checks.
                        let at = |i: u32| {
                            let i = i as usize & (WIDTH - 1);
                            Entry {
                                child: child[i],
                                count: count[i] as u32,
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
                        let second = rest.trailing_zeros();
                        if rest & (rest - 1) == 0 {
                            // Two boxes: visit the nearer (the first slot on a tie); for any
                            // hit the farther (the second slot on a tie), see below.
                            let (a, b) = (at(first), at(second));
                            let (now, after) = if any_hit {
                                if a.near > b.near {
                                    (a, b)
                                } else {
                                    (b, a)
                                }
                            } else if b.near < a.near {
                                (b, a)
                            } else {
                                (a, b)
                            };
                            push(&mut stack, &mut sp, &mut spill, later(after));
                            entry = now;
                            continue;
                        }
                        // Three or more: each hit's place in the order by entry distance, ties
                        // in slot order (what a stable sort gives), is its rank: the number of
                        // hits nearer than it or as near in an earlier slot, counted with two
                        // SIMD comparisons and no data-dependent branch. The nearest is
                        // visited, the others pushed farthest first. Hit lanes have no NaN
                        // distance (the box test's `<=` is false on NaN), so the ranks are
                        // `0..k` once each.
                        //
                        // Any hit ends the search, so there the order changes no result, only
                        // how soon the search ends: the boxes are visited in the reverse
                        // order, farthest first. A shadow ray's box around its origin is
                        // entered at 0 and rarely holds its blocker, while the boxes towards
                        // the light do where the light is shielded (a window, a lamp's
                        // housing): in the window room 9.5% fewer instructions per shadow
                        // ray than visiting in slot order, in the Cornell box 2.2%.
                        let k = mask.count_ones() as usize;
                        let rank = |i: u32| (nearer::<AVX2>(&near, i) & mask).count_ones() as usize;
                        if sp + k <= N {
                            // Rank `r` goes to `top - r`: the farthest at `sp`, rank 1 the new
                            // top of the stack, rank 0 just above it, read back as the entry
                            // (any hit: to `sp + r`, the farthest read back).
                            let top = sp + k - 1;
                            let place = |r: usize| if any_hit { sp + r } else { top - r };
                            #[cfg(debug_assertions)]
                            let mut seen = 0u32;
                            let mut m = mask;
                            while m != 0 {
                                let i = m.trailing_zeros();
                                m &= m - 1;
                                let r = rank(i);
                                #[cfg(debug_assertions)]
                                {
                                    seen |= 1 << r;
                                }
                                // SAFETY: `r < k` (the hits other than `i` are counted), so
                                // `sp <= place(r) <= top < N`.
                                unsafe { stack.get_unchecked_mut(place(r)) }.write(later(at(i)));
                            }
                            #[cfg(debug_assertions)]
                            debug_assert_eq!(seen, (1 << k) - 1, "ranks are not a permutation");
                            sp = top;
                            // SAFETY: slot `top` was written above (rank 0, any hit rank
                            // `k - 1`; the ranks are a permutation of `0..k`).
                            entry = unsafe { stack.get_unchecked(top).assume_init() };
                            continue;
                        }
                        // Too few fixed entries left: the same order through `push`.
                        let mut hits = [Entry {
                            child: 0,
                            count: 0,
                            near: 0.0,
                        }; WIDTH];
                        let mut m = mask;
                        while m != 0 {
                            let i = m.trailing_zeros();
                            m &= m - 1;
                            hits[rank(i) & (WIDTH - 1)] = at(i);
                        }
                        if any_hit {
                            for h in &hits[..k - 1] {
                                push(&mut stack, &mut sp, &mut spill, *h);
                            }
                            entry = hits[k - 1];
                        } else {
                            for h in hits[1..k].iter().rev() {
                                push(&mut stack, &mut sp, &mut spill, *h);
                            }
                            entry = hits[0];
                        }
                        continue;
                    }
                }
            }
            if sp > 0 {
                sp -= 1;
                // SAFETY: `sp` never exceeds `N`, and entries below the old `sp` were written
                // by `push` or the ordering above.
                entry = unsafe { stack.get_unchecked(sp).assume_init() };
            } else if let Some(e) = spill.pop() {
                entry = e;
            } else {
                return found;
            }
        }
    }
}

/// Starts loading the node of an interior entry pushed for later, so that its cache misses
/// overlap the search of the nearer boxes (large scenes, whose nodes are not in the caches).
/// A hint only: it changes no result.
#[inline(always)]
fn prefetch<T>(nodes: &[T], e: &Entry) {
    if e.count == 0 {
        // `wrapping_add` makes no claim about the address, and a prefetch never faults.
        let p = nodes.as_ptr().wrapping_add(e.child as usize).cast::<u8>();
        for line in 0..std::mem::size_of::<T>() / 64 {
            prefetch_line(p.wrapping_add(64 * line));
        }
    }
}

/// [`Bvh::traverse`]'s leaf test: `test(slot, t_max)` for the leaf's slots in order, the
/// search shrinking to each hit; the closest hit (with `any_hit`, the first).
#[inline(always)]
pub(super) fn for_each_slot<F: FnMut(u32, f32) -> Option<f32>>(
    first: u32,
    count: u32,
    mut t_max: f32,
    any_hit: bool,
    test: &mut F,
) -> Option<f32> {
    let mut found = None;
    for slot in first..first + count {
        if let Some(t) = test(slot, t_max) {
            t_max = t;
            found = Some(t);
            if any_hit {
                break;
            }
        }
    }
    found
}

/// Pushes `e` on the traversal stack. When the `N` fixed entries are used they move, in order,
/// to the end of `spill` (below every later entry), so a pop looks at `spill` only once the
/// fixed stack is empty and the visiting order is the same as with one unbounded stack.
#[inline(always)]
pub(super) fn push<const N: usize>(
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
pub(super) fn spill_stack<const N: usize>(stack: &[MaybeUninit<Entry>; N], spill: &mut Vec<Entry>) {
    // SAFETY: called only when all `N` entries were written.
    spill.extend(stack.iter().map(|e| unsafe { e.assume_init() }));
}

/// The hit-ordering comparison of slot `i` (< 8) against all eight: bit `j` set where
/// `near[j] < near[i]`, or `near[j] == near[i]` and `j < i` (ties in slot order). The AVX2
/// and portable versions make the same IEEE comparisons, so they give the same bits.
#[inline(always)]
fn nearer<const AVX2: bool>(near: &[f32; WIDTH], i: u32) -> u32 {
    #[cfg(target_arch = "x86_64")]
    if AVX2 {
        // SAFETY: `AVX2` is true only inside `traverse_avx2`.
        return unsafe { nearer_avx2(near, i) };
    }
    let x = Vec4::splat(near[i as usize & (WIDTH - 1)]);
    let (lo, hi) = (Vec4::from_slice(&near[..4]), Vec4::from_slice(&near[4..]));
    let lt = lo.cmplt(x).bitmask() | hi.cmplt(x).bitmask() << 4;
    let eq = lo.cmpeq(x).bitmask() | hi.cmpeq(x).bitmask() << 4;
    lt | (eq & ((1 << i) - 1))
}

/// [`nearer`] with one 256-bit comparison each.
///
/// # Safety
/// The CPU must support AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn nearer_avx2(near: &[f32; WIDTH], i: u32) -> u32 {
    use std::arch::x86_64::*;
    // SAFETY: `near` holds eight f32.
    let v = unsafe { _mm256_loadu_ps(near.as_ptr()) };
    let x = _mm256_set1_ps(near[i as usize & (WIDTH - 1)]);
    // Ordered comparisons, as `Vec4::cmplt` / `cmpeq` (`cmpltps`, `cmpeqps`).
    let lt = _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LT_OQ>(v, x)) as u32;
    let eq = _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_EQ_OQ>(v, x)) as u32;
    lt | (eq & ((1 << i) - 1))
}

/// Slab test of a node's eight boxes with two four-wide halves: the bit mask of the used slots
/// the ray meets before `t_max`, and each box's entry distance in `near`. Operand order matters
/// for NaN (a ray parallel to a slab and starting on its plane): SSE `min`/`max` return their
/// second operand when either is NaN (see [`RayBoxes::new`]); [`node_hits_avx2`] does exactly
/// the same operations.
#[inline(always)]
pub(super) fn node_hits_portable(
    n: &WideNode,
    r: &RayBoxes,
    t_max: f32,
    near: &mut [f32; WIDTH],
) -> u32 {
    let planes = [&n.min_x, &n.min_y, &n.min_z, &n.max_x, &n.max_y, &n.max_z];
    let mask = slab_halves(
        |plane, half| Vec4::from_slice(&planes[plane][4 * half..4 * half + 4]),
        r,
        t_max,
        near,
    );
    // Unused slots sit at the end; their empty boxes can pass the slab test (±∞ − ±∞
    // orders), so they are masked out.
    mask & n.slot_mask
}

/// [`node_hits_portable`] for a quantised node: each plane decoded as `origin + q · scale`
/// (the same f32 operations as [`QuantNode::from_wide`] and [`quant_hits_avx2`]), then the
/// same slab test.
#[inline(always)]
pub(super) fn quant_hits_portable(
    n: &QuantNode,
    r: &RayBoxes,
    t_max: f32,
    near: &mut [f32; WIDTH],
) -> u32 {
    let mask = slab_halves(
        |plane, half| {
            let axis = plane % 3;
            let q = if plane < 3 { &n.lo[axis] } else { &n.hi[axis] };
            let q = Vec4::new(
                q[4 * half] as f32,
                q[4 * half + 1] as f32,
                q[4 * half + 2] as f32,
                q[4 * half + 3] as f32,
            );
            Vec4::splat(n.origin[axis]) + q * Vec4::splat(n.scale[axis])
        },
        r,
        t_max,
        near,
    );
    mask & n.slot_mask
}

/// The slab test of eight boxes as two four-wide halves; `lane(plane, half)` gives plane
/// `min_x, min_y, min_z, max_x, max_y, max_z` (0..6) of slots `4·half..4·half + 4`. Each axis
/// reads only the ray's entry and exit planes ([`RayBoxes::near`], [`RayBoxes::far`]).
#[inline(always)]
fn slab_halves(
    lane: impl Fn(usize, usize) -> Vec4,
    r: &RayBoxes,
    t_max: f32,
    near: &mut [f32; WIDTH],
) -> u32 {
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
        let tx_near = (lane(r.near[0], half) - ox) * ix;
        let tx_far = (lane(r.far[0], half) - ox) * ix;
        let ty_near = (lane(r.near[1], half) - oy) * iy;
        let ty_far = (lane(r.far[1], half) - oy) * iy;
        let tz_near = (lane(r.near[2], half) - oz) * iz;
        let tz_far = (lane(r.far[2], half) - oz) * iz;
        // The three axes as balanced pairs: two dependent steps instead of three.
        let t_near = tx_near.max(ty_near).max(tz_near.max(Vec4::ZERO));
        let t_far = tx_far.min(ty_far).min(tz_far.min(t_max)) * far_scale;
        mask |= t_near.cmple(t_far).bitmask() << (4 * half);
        t_near.write_to_slice(&mut near[4 * half..4 * half + 4]);
    }
    mask
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
pub(super) unsafe fn node_hits_avx2(
    n: &WideNode,
    r: &RayBoxes,
    t_max: f32,
    near: &mut [f32; WIDTH],
) -> u32 {
    use std::arch::x86_64::*;
    // The six plane arrays are the node's first six fields (`repr(C)`, 32 bytes each), so
    // plane `i` starts at byte 32·i of the 64-byte-aligned node.
    let planes = std::ptr::from_ref(n).cast::<[f32; WIDTH]>();
    // SAFETY: `i < 6` (`RayBoxes` holds plane indices 0..6), so the 32 bytes read lie inside
    // the node and are 32-byte aligned.
    let lane = |i: usize| unsafe { _mm256_load_ps(planes.add(i).cast::<f32>()) };
    let near_planes = [lane(r.near[0]), lane(r.near[1]), lane(r.near[2])];
    let far_planes = [lane(r.far[0]), lane(r.far[1]), lane(r.far[2])];
    slab_avx2(near_planes, far_planes, r, t_max, near) & n.slot_mask
}

// The plane layout `node_hits_avx2` and `quant_hits_avx2` read by index.
const _: () = {
    use std::mem::offset_of;
    assert!(offset_of!(WideNode, min_x) == 0);
    assert!(offset_of!(WideNode, min_y) == 32);
    assert!(offset_of!(WideNode, min_z) == 64);
    assert!(offset_of!(WideNode, max_x) == 96);
    assert!(offset_of!(WideNode, max_y) == 128);
    assert!(offset_of!(WideNode, max_z) == 160);
    assert!(offset_of!(QuantNode, hi) == offset_of!(QuantNode, lo) + 3 * WIDTH);
};

/// [`quant_hits_portable`] with AVX2: the eight steps of a plane widened to 32-bit integers,
/// converted (exactly) and decoded as `origin + q · scale` in one fused multiply-add, then
/// [`slab_avx2`]. The fused result equals the portable kernel's multiply-then-add bit for bit:
/// `q · scale` (an integer below 256 times a power of two, both normal) is exact, so the only
/// rounding either way is that of the sum.
///
/// # Safety
/// The CPU must support AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
#[inline]
pub(super) unsafe fn quant_hits_avx2(
    n: &QuantNode,
    r: &RayBoxes,
    t_max: f32,
    near: &mut [f32; WIDTH],
) -> u32 {
    use std::arch::x86_64::*;
    // `lo` and `hi` are adjacent, so plane `i` (0..6: `lo[0..3]`, then `hi[0..3]`) is the
    // `i`-th eight-byte array from `lo`.
    let steps = std::ptr::from_ref(&n.lo).cast::<[u8; WIDTH]>();
    let plane = |i: usize, axis: usize| {
        // SAFETY: `i < 6`, so the eight bytes read (what `_mm_loadl_epi64` reads) lie inside
        // `lo` and `hi`.
        let bytes = unsafe { _mm_loadl_epi64(steps.add(i).cast::<__m128i>()) };
        let steps = _mm256_cvtepi32_ps(_mm256_cvtepu8_epi32(bytes));
        _mm256_fmadd_ps(
            steps,
            _mm256_set1_ps(n.scale[axis]),
            _mm256_set1_ps(n.origin[axis]),
        )
    };
    let near_planes = [
        plane(r.near[0], 0),
        plane(r.near[1], 1),
        plane(r.near[2], 2),
    ];
    let far_planes = [plane(r.far[0], 0), plane(r.far[1], 1), plane(r.far[2], 2)];
    slab_avx2(near_planes, far_planes, r, t_max, near) & n.slot_mask
}

/// The slab test of eight boxes given as each axis's entry planes (x, y, z) and exit planes
/// ([`RayBoxes::near`], [`RayBoxes::far`]): the same operations in the same order as
/// [`slab_halves`].
///
/// # Safety
/// The CPU must support AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn slab_avx2(
    near_planes: [std::arch::x86_64::__m256; 3],
    far_planes: [std::arch::x86_64::__m256; 3],
    r: &RayBoxes,
    t_max: f32,
    near: &mut [f32; WIDTH],
) -> u32 {
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
    let tx_near = _mm256_mul_ps(_mm256_sub_ps(near_planes[0], ox), ix);
    let tx_far = _mm256_mul_ps(_mm256_sub_ps(far_planes[0], ox), ix);
    let ty_near = _mm256_mul_ps(_mm256_sub_ps(near_planes[1], oy), iy);
    let ty_far = _mm256_mul_ps(_mm256_sub_ps(far_planes[1], oy), iy);
    let tz_near = _mm256_mul_ps(_mm256_sub_ps(near_planes[2], oz), iz);
    let tz_far = _mm256_mul_ps(_mm256_sub_ps(far_planes[2], oz), iz);
    let t_near = _mm256_max_ps(
        _mm256_max_ps(tx_near, ty_near),
        _mm256_max_ps(tz_near, _mm256_setzero_ps()),
    );
    let t_far = _mm256_mul_ps(
        _mm256_min_ps(_mm256_min_ps(tx_far, ty_far), _mm256_min_ps(tz_far, t_max)),
        far_scale,
    );
    // `_CMP_LE_OQ` is false on NaN, like SSE's `cmpleps`.
    let mask = _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(t_near, t_far)) as u32;
    // SAFETY: `near` holds eight f32.
    unsafe { _mm256_storeu_ps(near.as_mut_ptr(), t_near) };
    mask
}

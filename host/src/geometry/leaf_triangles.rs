//! The triangles of the BVH's leaves (mesh triangles, and quads as their two halves), stored
//! leaf by leaf transposed, and the test of a leaf's triangles four at a time.
//!
//! Each leaf slot owns one triangle *lane*, or two for a quad (its halves in the order the
//! scalar quad test tries them, so the lanes in order are that test's triangles in order;
//! a quad's leaf then takes the four-lane pass instead of two scalar tests a quad, which
//! cost the ten-quad window room about half its instructions). Where every slot has one lane
//! (meshes only) lane `s` is slot `s`; otherwise a map gives each slot's first lane and
//! each lane's slot ([`LeafTriangles::lanes`], [`LeafTriangles::slot_of_lane`]).
//!
//! Layout (36 bytes per lane, as the one-record-per-triangle layout before it): lane `s`
//! owns floats `9s..9s + 9`, so the leaf `first..first + n` owns
//! `9·first..9·(first + n)`; inside it coordinate `c` (0..9: x, y, z of p0, then of p1, of
//! p2) of member `j` sits at `9·first + c·n + j`. One unaligned 16-byte load at
//! `9·first + c·n` so gives coordinate `c` of the leaf's (up to) four triangles as four lanes;
//! lanes beyond `n` read the next coordinates and are masked out. A leaf of one triangle is its
//! plain record (x, y, z of p0, p1, p2). A leaf of five to eight triangles (the collapse merges
//! up to [`super::bvh::MERGE_LEAF_PRIMITIVES`]) is stored as consecutive blocks of four and the
//! rest, each laid out as a leaf of its own, and tested block by block in slot order with the
//! search distance carried from one block to the next. Four floats of padding at the end keep every load
//! inside the buffer. A leaf holding a sphere or a quad (scenes with them keep unmerged
//! leaves, which can mix kinds) is all NaN (mesh positions are finite, checked when a mesh is
//! made) and is tested primitive by primitive through its objects.
//!
//! The four-lane pass ([`LeafTriangles::test`]) repeats [`intersect_triangle_axis`]' f32
//! operations in the same order on every lane, so each lane's edge functions, determinant,
//! scaled distance, distance and error bound are bit for bit the scalar test's. Where the
//! scalar test would take a path the lanes do not model, the whole leaf goes through the
//! scalar test instead: an edge function exactly zero (the scalar test recomputes the three
//! in f64) or a NaN among the values whose maxima form the error bound (`f32::max` and SIMD
//! `max` differ on NaN). Lanes pass the checks against the `t_max` the leaf was entered with;
//! the survivors (rarely more than one) are then re-checked in slot order against the search
//! distance as it shrinks, exactly as the scalar test run slot by slot would. So the hits,
//! distances and barycentrics are the scalar test's (test `leaf_pass_matches_scalar_test`),
//! and the watertightness of the scalar test (the edge functions of a shared edge computed
//! with the same operations, the exact-zero rule, the error bound on `t`) holds lane by lane.
//! (Embree's `Triangle4` leaves, Woop et al.'s watertight test, and `docs/performance.md`,
//! "Transposed leaves".)

use glam::{Vec3A, Vec4};
use rayon::prelude::*;

use super::float_error::gamma;
use super::huge_pages::HugePageBuf;
use super::triangle::{intersect_triangle_axis, TriangleHit, WatertightRay};
use super::Ray;

/// Floats per triangle: x, y, z of p0, p1, p2.
const COORDS: usize = 9;
/// Triangles per SIMD pass.
const LANES: usize = 4;
/// Floats after the last leaf, so that the last four-lane load stays inside the buffer.
const PADDING: usize = 4;

/// A triangle hit in a leaf: its lane (the slot in leaf order where every slot has one lane,
/// see [`LeafTriangles::slot_of_lane`]) and the scalar test's result.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct LeafHit {
    pub(super) lane: u32,
    pub(super) hit: TriangleHit,
}

/// What one four-lane pass decided.
enum Pass {
    /// The closest accepted lane, if any: (lane, hit).
    Done(Option<(usize, TriangleHit)>),
    /// A lane needs the scalar test's f64 edge functions or its NaN rules.
    Scalar,
}

/// The triangles one leaf slot contributes to the four-lane test: a mesh triangle one lane, a
/// quad its two halves (`Quad::triangle(0)`, then `(1)`: the order in which
/// the scalar test of a quad tries them), a sphere none (its leaf is tested through the
/// objects).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum SlotTriangles {
    /// One triangle (a mesh's).
    One([Vec3A; 3]),
    /// Two triangles tried in this order (a quad's halves).
    Two([Vec3A; 3], [Vec3A; 3]),
    /// Not triangles: the whole leaf goes through the objects.
    Other,
}

impl SlotTriangles {
    fn lanes(&self) -> u32 {
        match self {
            SlotTriangles::Two(..) => 2,
            _ => 1,
        }
    }
}

/// The triangles of every BVH leaf, transposed per leaf (see the module documentation), one
/// lane per mesh triangle and two per quad.
#[derive(Clone, Debug, Default)]
pub(super) struct LeafTriangles {
    data: HugePageBuf<f32>,
    /// Where some slot has two lanes (a quad): `lane_start[s]` is slot `s`'s first lane
    /// (`slots + 1` entries, the last the lane count). Empty when every slot has one lane
    /// (lane = slot: meshes only, the common case, which then reads no map).
    lane_start: Vec<u32>,
    /// With `lane_start`: the slot of every lane.
    lane_slot: Vec<u32>,
}

impl LeafTriangles {
    /// Lays out `slots` leaf-order slots by `leaves` (`(first, count)`, sorted, partitioning
    /// `0..slots`, as [`super::Bvh::leaves`] gives them); `vertices(slot)` is the slot's
    /// triangle, `None` for a sphere or quad. In parallel, the same for any thread count.
    #[cfg(test)]
    pub(super) fn build(
        slots: usize,
        leaves: &[(u32, u32)],
        vertices: impl Fn(u32) -> Option<[Vec3A; 3]> + Sync,
    ) -> LeafTriangles {
        Self::build_lanes(slots, leaves, false, |s| {
            vertices(s).map_or(SlotTriangles::Other, SlotTriangles::One)
        })
    }

    /// [`LeafTriangles::build`] with slots of one or two triangle lanes (`triangles(slot)`);
    /// `two_lanes` says whether any slot may have two (quads): only then is the lane map
    /// made. A leaf with an [`SlotTriangles::Other`] slot stays NaN (tested through the
    /// objects).
    pub(super) fn build_lanes(
        slots: usize,
        leaves: &[(u32, u32)],
        two_lanes: bool,
        triangles: impl Fn(u32) -> SlotTriangles + Sync,
    ) -> LeafTriangles {
        let (lane_start, lane_slot) = if two_lanes {
            let counts: Vec<u32> = (0..slots as u32)
                .into_par_iter()
                .map(|s| triangles(s).lanes())
                .collect();
            let mut start = Vec::with_capacity(slots + 1);
            let mut at = 0u32;
            let mut lane_slot = Vec::new();
            for (s, &c) in counts.iter().enumerate() {
                start.push(at);
                at += c;
                lane_slot.extend(std::iter::repeat_n(s as u32, c as usize));
            }
            start.push(at);
            (start, lane_slot)
        } else {
            (Vec::new(), Vec::new())
        };
        let lanes = if two_lanes { lane_slot.len() } else { slots };
        let lane_of = |s: usize| {
            if two_lanes {
                lane_start[s] as usize
            } else {
                s
            }
        };
        // On huge pages when large (the traversal's reads spread over all of it), filled in
        // parallel.
        let mut data = HugePageBuf::from_fn_par(lanes * COORDS + PADDING, |_| f32::NAN);
        // Cut the buffer into the leaves' blocks (serial, one split per leaf), then fill them
        // in parallel.
        let mut blocks = Vec::with_capacity(leaves.len());
        let mut rest = &mut data[..lanes * COORDS];
        let mut at = 0usize;
        for &(first, count) in leaves {
            let (first, count) = (first as usize, count as usize);
            debug_assert!(first + count <= slots);
            let (lf, le) = (lane_of(first), lane_of(first + count));
            debug_assert!(lf >= at);
            let tail = std::mem::take(&mut rest);
            let (_, tail) = tail.split_at_mut((lf - at) * COORDS);
            let (block, tail) = tail.split_at_mut((le - lf) * COORDS);
            rest = tail;
            at = le;
            blocks.push((first as u32, count as u32, block));
        }
        blocks.into_par_iter().for_each(|(first, n, block)| {
            let mut tris: Vec<[Vec3A; 3]> = Vec::with_capacity(block.len() / COORDS);
            for s in first..first + n {
                match triangles(s) {
                    SlotTriangles::One(t) => tris.push(t),
                    SlotTriangles::Two(a, b) => tris.extend([a, b]),
                    // A leaf with another kind of primitive stays NaN.
                    SlotTriangles::Other => return,
                }
            }
            debug_assert_eq!(tris.len() * COORDS, block.len());
            // Blocks of four (the last one the rest), each transposed on its own.
            for (tris, block) in tris.chunks(LANES).zip(block.chunks_mut(LANES * COORDS)) {
                let m = tris.len();
                for (j, t) in tris.iter().enumerate() {
                    for (v, p) in t.iter().enumerate() {
                        for axis in 0..3 {
                            block[(3 * v + axis) * m + j] = p[axis];
                        }
                    }
                }
            }
        });
        LeafTriangles {
            data,
            lane_start,
            lane_slot,
        }
    }

    /// The lanes `(first, count)` of the leaf of slots `first..first + count`.
    #[inline(always)]
    pub(super) fn lanes(&self, first: u32, count: u32) -> (u32, u32) {
        if self.lane_start.is_empty() {
            return (first, count);
        }
        let (a, b) = (
            self.lane_start.get(first as usize).copied().unwrap_or(0),
            self.lane_start
                .get((first + count) as usize)
                .copied()
                .unwrap_or(0),
        );
        (a, b.saturating_sub(a))
    }

    /// Whether some slot has two lanes (the scene has quads; otherwise lane = slot).
    #[inline(always)]
    pub(super) fn has_quads(&self) -> bool {
        !self.lane_slot.is_empty()
    }

    /// The slot of `lane` and which of the slot's triangles it is (0, or 1 for a quad's
    /// second half).
    #[inline(always)]
    pub(super) fn slot_of_lane(&self, lane: u32) -> (u32, usize) {
        if self.lane_slot.is_empty() {
            return (lane, 0);
        }
        let slot = self.lane_slot[lane as usize];
        (slot, (lane - self.lane_start[slot as usize]) as usize)
    }

    /// Bytes held.
    pub(super) fn memory_bytes(&self) -> usize {
        self.data.len() * std::mem::size_of::<f32>()
            + (self.lane_start.len() + self.lane_slot.len()) * std::mem::size_of::<u32>()
    }

    /// Whether the leaf starting at lane `first` (see [`LeafTriangles::lanes`]) holds
    /// something other than triangles (it is then tested primitive by primitive through its
    /// objects).
    #[inline(always)]
    pub(super) fn is_other(&self, first: u32) -> bool {
        self.data
            .get(first as usize * COORDS)
            .is_none_or(|v| v.is_nan())
    }

    /// The vertices of member `j` of the leaf `first..first + n` (a one-triangle leaf's by
    /// [`LeafTriangles::record`]'s three loads).
    #[inline(always)]
    pub(super) fn vertices(&self, first: usize, n: usize, j: usize) -> [Vec3A; 3] {
        // The block of four holding member `j` (the leaf itself when it has at most four).
        let (first, n, j) = if n > LANES {
            let k = j & !(LANES - 1);
            (first + k, (n - k).min(LANES), j - k)
        } else {
            (first, n, j)
        };
        if n == 1 {
            return self.record(first);
        }
        self.gather(first, n, j)
    }

    /// [`LeafTriangles::vertices`] float by float.
    #[inline(always)]
    fn gather(&self, first: usize, n: usize, j: usize) -> [Vec3A; 3] {
        // One bounds check for the leaf's block instead of one per float.
        let block = &self.data[first * COORDS..(first + n) * COORDS];
        assert!(j < n);
        // SAFETY: `c · n + j < 9n = block.len()` for `c ≤ 8` and `j < n`.
        let at = |c: usize| unsafe { *block.get_unchecked(c * n + j) };
        [
            Vec3A::new(at(0), at(1), at(2)),
            Vec3A::new(at(3), at(4), at(5)),
            Vec3A::new(at(6), at(7), at(8)),
        ]
    }

    /// The closest hit below `t_max` among the triangles of the leaf's lanes `first..first + n`
    /// ([`LeafTriangles::lanes`]; all triangles: `!is_other(first)`), or with `any_hit` the first in slot order: exactly
    /// what [`LeafTriangles::test_scalar`] gives. `KZ` is `wr.dominant_axis()`.
    #[inline(always)]
    pub(super) fn test<const KZ: usize>(
        &self,
        ray: &Ray,
        wr: &WatertightRay,
        first: u32,
        n: u32,
        t_max: f32,
        any_hit: bool,
    ) -> Option<LeafHit> {
        // Blocks of four in slot order (one for a leaf of at most four), the search shrinking
        // to each hit: what the scalar test does slot by slot. One loop, so that the block test
        // is inlined once.
        let (first, n) = (first as usize, n as usize);
        let (end, mut at, mut t_max, mut best) = (first + n, first, t_max, None);
        loop {
            let m = (end - at).min(LANES);
            if let Some(h) = self.test_block::<KZ>(ray, wr, at, m, t_max, any_hit) {
                t_max = h.hit.t;
                best = Some(h);
                if any_hit {
                    break;
                }
            }
            at += m;
            if at >= end {
                break;
            }
        }
        best
    }

    /// [`LeafTriangles::test`] of one block of at most four triangles, laid out as a leaf of
    /// its own (the whole leaf when it has at most four).
    #[inline(always)]
    fn test_block<const KZ: usize>(
        &self,
        ray: &Ray,
        wr: &WatertightRay,
        first: usize,
        n: usize,
        t_max: f32,
        any_hit: bool,
    ) -> Option<LeafHit> {
        if n == 1 {
            // The plain record: the scalar test is as short as one lane pass.
            let [a, b, c] = self.record(first);
            let hit = intersect_triangle_axis::<KZ>(ray, wr, t_max, a, b, c)?;
            return Some(LeafHit {
                lane: first as u32,
                hit,
            });
        }
        // One bounds check for the whole leaf; the lane loads below stay inside `block`.
        let block = &self.data[first * COORDS..first * COORDS + n * COORDS + PADDING - 1];
        match pass4::<KZ>(ray, wr, block, n, t_max, any_hit) {
            Pass::Done(hit) => hit.map(|(lane, hit)| LeafHit {
                lane: (first + lane) as u32,
                hit,
            }),
            Pass::Scalar => self.scalar::<KZ>(ray, wr, first, n, t_max, any_hit),
        }
    }

    /// The leaf's triangles one by one with [`intersect_triangle_axis`], in slot order, the
    /// search shrinking to each hit (the reference [`LeafTriangles::test`] reproduces).
    #[cfg(test)]
    pub(super) fn test_scalar<const KZ: usize>(
        &self,
        ray: &Ray,
        wr: &WatertightRay,
        first: u32,
        n: u32,
        t_max: f32,
        any_hit: bool,
    ) -> Option<LeafHit> {
        self.scalar::<KZ>(ray, wr, first as usize, n as usize, t_max, any_hit)
    }

    /// [`LeafTriangles::test_scalar`] (out of line: it runs for leaves with an exact-zero
    /// edge function only).
    #[inline(never)]
    fn scalar<const KZ: usize>(
        &self,
        ray: &Ray,
        wr: &WatertightRay,
        first: usize,
        n: usize,
        mut t_max: f32,
        any_hit: bool,
    ) -> Option<LeafHit> {
        let mut best = None;
        for j in 0..n {
            let [a, b, c] = self.vertices(first, n, j);
            if let Some(hit) = intersect_triangle_axis::<KZ>(ray, wr, t_max, a, b, c) {
                t_max = hit.t;
                best = Some(LeafHit {
                    lane: (first + j) as u32,
                    hit,
                });
                if any_hit {
                    break;
                }
            }
        }
        best
    }

    /// The vertices of a one-triangle leaf's record. On x86-64 each is one unaligned 16-byte
    /// load whose fourth lane (the next coordinate) the triangle test never reads: three loads
    /// instead of nine scalar ones and their shuffles.
    #[inline(always)]
    fn record(&self, first: usize) -> [Vec3A; 3] {
        #[cfg(target_arch = "x86_64")]
        {
            use std::arch::x86_64::_mm_loadu_ps;
            let r = &self.data[first * COORDS..first * COORDS + 10];
            let p = r.as_ptr();
            // SAFETY: `r` holds 10 floats (the record and one more, the next record's or the
            // padding); the loads read floats 0..4, 3..7 and 6..10 of it. SSE2 is part of
            // x86-64.
            unsafe {
                [
                    Vec3A::from(_mm_loadu_ps(p)),
                    Vec3A::from(_mm_loadu_ps(p.add(3))),
                    Vec3A::from(_mm_loadu_ps(p.add(6))),
                ]
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            self.gather(first, 1, 0)
        }
    }
}

/// One four-lane pass over the `n` (2..=4) triangles of a leaf's `block`,
/// [`intersect_triangle_axis`]' operations lane by lane; see the module documentation for why
/// it equals the scalar test run slot by slot (with `any_hit`, the first lane hit, where the
/// scalar loop stops).
#[inline(always)]
fn pass4<const KZ: usize>(
    ray: &Ray,
    wr: &WatertightRay,
    block: &[f32],
    n: usize,
    t_max: f32,
    any_hit: bool,
) -> Pass {
    let (kx, ky) = ((KZ + 1) % 3, (KZ + 2) % 3);
    let valid = (1u32 << n) - 1;
    let load = |c: usize| {
        let at = c * n;
        debug_assert!(at + LANES <= block.len());
        // SAFETY: `at + 4 ≤ 8n + 4 ≤ block.len()`: `c ≤ 8`, `n ≥ 1`, and `block` holds the
        // leaf's `9n` floats and 3 more.
        Vec4::from_array(unsafe { block.as_ptr().add(at).cast::<[f32; 4]>().read_unaligned() })
    };
    let zero = Vec4::ZERO;
    let origin = ray.origin.to_array();
    let [sx, sy, sz] = wr.shear().map(Vec4::splat);
    let (ox, oy, oz) = (
        Vec4::splat(origin[kx]),
        Vec4::splat(origin[ky]),
        Vec4::splat(origin[KZ]),
    );
    // Translate to the ray origin, permute so z is the dominant axis, shear onto +z.
    let (az, bz, cz) = (load(KZ) - oz, load(3 + KZ) - oz, load(6 + KZ) - oz);
    let ax = (load(kx) - ox) + sx * az;
    let ay = (load(ky) - oy) + sy * az;
    let bx = (load(3 + kx) - ox) + sx * bz;
    let by = (load(3 + ky) - oy) + sy * bz;
    let cx = (load(6 + kx) - ox) + sx * cz;
    let cy = (load(6 + ky) - oy) + sy * cz;
    let e0 = bx * cy - by * cx;
    let e1 = cx * ay - cy * ax;
    let e2 = ax * by - ay * bx;
    if (e0.cmpeq(zero) | e1.cmpeq(zero) | e2.cmpeq(zero)).bitmask() & valid != 0 {
        return Pass::Scalar;
    }
    let mixed = (e0.cmplt(zero) | e1.cmplt(zero) | e2.cmplt(zero))
        & (e0.cmpgt(zero) | e1.cmpgt(zero) | e2.cmpgt(zero));
    let inside = valid & !mixed.bitmask();
    if inside == 0 {
        return Pass::Done(None);
    }
    let det = e0 + e1 + e2;
    let (azs, bzs, czs) = (az * sz, bz * sz, cz * sz);
    let t_scaled = e0 * azs + e1 * bzs + e2 * czs;
    let t_max4 = Vec4::splat(t_max);
    let limit = t_max4 * det;
    let reject = det.cmpeq(zero)
        | (det.cmplt(zero) & (t_scaled.cmpge(zero) | t_scaled.cmplt(limit)))
        | (det.cmpgt(zero) & (t_scaled.cmple(zero) | t_scaled.cmpgt(limit)));
    let inv_det = Vec4::ONE / det;
    let t = t_scaled * inv_det;
    let candidates = inside & !reject.bitmask() & t.cmplt(t_max4).bitmask();
    if candidates == 0 {
        return Pass::Done(None);
    }
    // The error bound on t. Its maxima see no NaN for a candidate lane (so they are the
    // scalar test's `f32::max`): `t < t_max` makes `t`, so `det` and `t_scaled`, non-NaN; an
    // arithmetic operation with a NaN operand gives NaN, so the three edge functions and the
    // scaled z's are non-NaN, so are the sheared x's and y's (each enters an edge function),
    // and so are the unscaled z's (each enters a sheared x).
    let max_z_world = az.abs().max(bz.abs()).max(cz.abs());
    let max_z = azs.abs().max(bzs.abs()).max(czs.abs());
    let delta_z = Vec4::splat(gamma(3)) * max_z;
    let max_x = ax.abs().max(bx.abs()).max(cx.abs());
    let max_y = ay.abs().max(by.abs()).max(cy.abs());
    let delta_x = Vec4::splat(gamma(5)) * (max_x + max_z_world);
    let delta_y = Vec4::splat(gamma(5)) * (max_y + max_z_world);
    let delta_e = Vec4::splat(2.0)
        * (Vec4::splat(gamma(2)) * max_x * max_y + delta_y * max_x + delta_x * max_y);
    let max_e = e0.abs().max(e1.abs()).max(e2.abs());
    let delta_t = Vec4::splat(3.0)
        * (Vec4::splat(gamma(3)) * max_e * max_z + delta_e * max_z + delta_z * max_e)
        * inv_det.abs();
    let mut accepted = candidates & !t.cmple(delta_t).bitmask();
    // Slot order, the search shrinking to each hit: the checks that involve `t_max` again
    // for the later lanes (the first one passed them against this very `t_max`).
    let (ts, d, tt) = (t_scaled.to_array(), det.to_array(), t.to_array());
    let mut t_max = t_max;
    let mut best = None;
    while accepted != 0 {
        let l = accepted.trailing_zeros() as usize & (LANES - 1);
        accepted &= accepted - 1;
        let limit = t_max * d[l];
        if (d[l] < 0.0 && ts[l] < limit) || (d[l] > 0.0 && ts[l] > limit) || !(tt[l] < t_max) {
            continue;
        }
        t_max = tt[l];
        best = Some(l);
        if any_hit {
            break;
        }
    }
    Pass::Done(best.map(|l| {
        let inv = inv_det.to_array()[l];
        (
            l,
            TriangleHit {
                t: tt[l],
                b0: e0.to_array()[l] * inv,
                b1: e1.to_array()[l] * inv,
                b2: e2.to_array()[l] * inv,
            },
        )
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Uniform numbers in [0, 1) from a 64-bit LCG (deterministic).
    fn uniform_stream(mut s: u64) -> impl FnMut() -> f32 {
        move || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 40) as f32 / (1u64 << 24) as f32
        }
    }

    /// The four-lane test and the scalar one on one leaf, dispatched on the ray's axis.
    fn both(
        tris: &LeafTriangles,
        ray: &Ray,
        first: u32,
        n: u32,
        t_max: f32,
        any_hit: bool,
    ) -> (Option<LeafHit>, Option<LeafHit>) {
        let wr = WatertightRay::new(ray);
        match wr.dominant_axis() {
            0 => (
                tris.test::<0>(ray, &wr, first, n, t_max, any_hit),
                tris.test_scalar::<0>(ray, &wr, first, n, t_max, any_hit),
            ),
            1 => (
                tris.test::<1>(ray, &wr, first, n, t_max, any_hit),
                tris.test_scalar::<1>(ray, &wr, first, n, t_max, any_hit),
            ),
            _ => (
                tris.test::<2>(ray, &wr, first, n, t_max, any_hit),
                tris.test_scalar::<2>(ray, &wr, first, n, t_max, any_hit),
            ),
        }
    }

    /// Bits of a hit, so that equality is exact (sign of zero included).
    fn bits(h: Option<LeafHit>) -> Option<(u32, [u32; 4])> {
        h.map(|h| {
            (
                h.lane,
                [h.hit.t, h.hit.b0, h.hit.b1, h.hit.b2].map(f32::to_bits),
            )
        })
    }

    // The four-lane pass must give exactly the scalar test's result run slot by slot (same
    // slot, same t and barycentrics bit for bit, hit or not; closest hit and any hit) on
    // leaves of 1 to 4 triangles and on merged leaves of 5 to 8 (two blocks): a fan of triangles sharing edges and one vertex on an
    // integer grid, hit through that vertex, through edge midpoints and through grid points
    // (exact-zero edge functions, the scalar test's f64 path) by axis-parallel and oblique
    // rays; duplicated and stacked triangles (equal and nearly equal distances, where the
    // search's shrinking `t_max` decides); and random rays and random `t_max`. Tolerance: none
    // (the pass repeats the scalar test's f32 operations). The counts check that every kind
    // of case was met (hits, misses, edge and vertex hits).
    #[test]
    fn leaf_pass_matches_scalar_test() {
        let v = |x: f32, y: f32, z: f32| Vec3A::new(x, y, z);
        // Leaves: a fan of four around (1, 1, 0) (shared edges), its first three, its first
        // two, a single triangle, two copies of one triangle, four stacked triangles one ULP
        // apart in z, and a tilted pair.
        let fan = [
            [v(1.0, 1.0, 0.0), v(0.0, 0.0, 0.0), v(2.0, 0.0, 0.0)],
            [v(1.0, 1.0, 0.0), v(2.0, 0.0, 0.0), v(2.0, 2.0, 0.0)],
            [v(1.0, 1.0, 0.0), v(2.0, 2.0, 0.0), v(0.0, 2.0, 0.0)],
            [v(1.0, 1.0, 0.0), v(0.0, 2.0, 0.0), v(0.0, 0.0, 0.0)],
        ];
        let z1 = f32::from_bits(1.0f32.to_bits() + 1);
        let z2 = f32::from_bits(1.0f32.to_bits() + 2);
        let stacked: Vec<[Vec3A; 3]> = [z2, 1.0, z1, 1.0]
            .iter()
            .map(|&z| [v(0.0, 0.0, z), v(2.0, 0.0, z), v(0.0, 2.0, z)])
            .collect();
        let tilted = [
            [v(0.0, 0.0, -1.0), v(2.0, 0.0, 1.0), v(0.0, 2.0, 0.5)],
            [v(2.0, 0.0, 1.0), v(2.0, 2.0, -0.5), v(0.0, 2.0, 0.5)],
        ];
        let cat = |a: &[[Vec3A; 3]], b: &[[Vec3A; 3]]| [a, b].concat();
        let mut leaf_tris: Vec<Vec<[Vec3A; 3]>> = vec![
            fan.to_vec(),
            fan[..3].to_vec(),
            fan[..2].to_vec(),
            fan[1..2].to_vec(),
            vec![fan[2], fan[2]],
            stacked.clone(),
            tilted.to_vec(),
            // Two blocks: the second one of one triangle (its plain record), of two, three
            // and four; a hit in the first block and one in the second at equal or nearly
            // equal distances.
            cat(&fan, &fan[2..3]),
            cat(&stacked, &tilted),
            cat(&tilted, &[fan[1], fan[2], fan[3], fan[0]]),
            cat(&fan[1..], &stacked[1..]),
            cat(&stacked, &fan),
        ];
        // The same leaves far from the origin (larger rounding, the error bound at work).
        let far: Vec<Vec<[Vec3A; 3]>> = leaf_tris
            .iter()
            .map(|l| {
                l.iter()
                    .map(|t| t.map(|p| p + v(1.0e4, -3.0e3, 2.0e3)))
                    .collect()
            })
            .collect();
        leaf_tris.extend(far);
        let mut leaves = Vec::new();
        let mut all = Vec::new();
        for l in &leaf_tris {
            leaves.push((all.len() as u32, l.len() as u32));
            all.extend(l.iter().copied());
        }
        let tris = LeafTriangles::build(all.len(), &leaves, |s| Some(all[s as usize]));

        // Targets in the fan's plane: grid points (vertices), edge midpoints, and interior
        // points; directions axis-parallel and oblique, from both sides.
        let mut targets = Vec::new();
        for i in 0..=8 {
            for j in 0..=8 {
                targets.push(v(i as f32 * 0.25, j as f32 * 0.25, 0.0));
            }
        }
        let dirs = [
            v(0.0, 0.0, -1.0),
            v(0.0, 0.0, 1.0),
            v(0.3, -0.2, -1.0),
            v(-1.0, 0.5, 0.25),
            v(0.0, 1.0, -0.5),
            v(1.0, 1.0, 1.0),
        ];
        let mut rays = Vec::new();
        for &offset in &[v(0.0, 0.0, 0.0), v(1.0e4, -3.0e3, 2.0e3)] {
            for &p in &targets {
                for &d in &dirs {
                    rays.push((Ray::new(p + offset - d * 3.0, d), f32::INFINITY));
                    rays.push((Ray::new(p + offset - d * 3.0, d), 3.0));
                }
            }
        }
        let mut next = uniform_stream(99);
        for _ in 0..4000 {
            let o = v(next() * 4.0 - 1.0, next() * 4.0 - 1.0, next() * 6.0 - 3.0);
            let target = v(next() * 2.0, next() * 2.0, next() * 2.0 - 1.0);
            let t_max = if next() < 0.5 {
                f32::INFINITY
            } else {
                next() * 2.0
            };
            rays.push((Ray::new(o, target - o), t_max));
            let far = v(1.0e4, -3.0e3, 2.0e3);
            rays.push((Ray::new(o + far, target - o), t_max));
        }

        let (mut hits, mut misses, mut edge_hits) = (0, 0, 0);
        for (ray, t_max) in &rays {
            for &(first, n) in &leaves {
                for any_hit in [false, true] {
                    let (simd, scalar) = both(&tris, ray, first, n, *t_max, any_hit);
                    assert_eq!(
                        bits(simd),
                        bits(scalar),
                        "ray {ray:?}, t_max {t_max}, leaf {first}+{n}, any hit {any_hit}"
                    );
                    match scalar {
                        Some(h) => {
                            hits += 1;
                            let b = [h.hit.b0, h.hit.b1, h.hit.b2];
                            if b.contains(&0.0) {
                                edge_hits += 1;
                            }
                        }
                        None => misses += 1,
                    }
                }
            }
        }
        assert!(
            hits > 10_000 && misses > 10_000,
            "{hits} hits, {misses} misses"
        );
        assert!(edge_hits > 500, "{edge_hits} edge and vertex hits");
    }

    // The layout: member j's coordinate c of the leaf at `first` of n sits at
    // 9·first + c·n + j, a one-triangle leaf is its plain record, a leaf of more than four is
    // its blocks of four and the rest, each laid out so, and a leaf with another
    // kind of primitive is all NaN (exact comparisons of the stored floats).
    #[test]
    fn leaves_are_stored_transposed() {
        let tri = |k: f32| {
            [
                Vec3A::new(k, k + 0.1, k + 0.2),
                Vec3A::new(k + 0.3, k + 0.4, k + 0.5),
                Vec3A::new(k + 0.6, k + 0.7, k + 0.8),
            ]
        };
        // A leaf of six is a block of four and a block of two.
        let leaves = [(0, 1), (1, 3), (4, 2), (6, 6)];
        let tris = LeafTriangles::build(12, &leaves, |s| (s != 5).then(|| tri(s as f32)));
        assert_eq!(tris.data.len(), 12 * COORDS + PADDING);
        for (first, n) in [(0, 1), (1, 3), (6, 4), (10, 2)] {
            for j in 0..n {
                let t = tri((first + j) as f32);
                for c in 0..COORDS {
                    let want = t[c / 3][c % 3];
                    assert_eq!(tris.data[first * COORDS + c * n + j], want);
                }
            }
        }
        for j in 0..6 {
            assert_eq!(tris.vertices(6, 6, j), tri((6 + j) as f32), "member {j}");
        }
        assert!(!tris.is_other(0) && !tris.is_other(1) && !tris.is_other(6));
        assert!(tris.is_other(4));
        assert!(tris.data[4 * COORDS..6 * COORDS].iter().all(|v| v.is_nan()));
    }
}

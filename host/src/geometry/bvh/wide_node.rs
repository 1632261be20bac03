//! The eight-wide nodes the traversal reads: eight child boxes as structure of arrays, in f32
//! ([`WideNode`]) or quantised to bytes on a per-node grid ([`QuantNode`]).

use super::build::Node;

/// Child slots per wide node.
pub(super) const WIDTH: usize = 8;

/// One eight-wide node (256 bytes): the boxes of up to eight children as structure of arrays,
/// so one SIMD operation handles the same coordinate of all eight (each array is 32-byte
/// aligned, one AVX register). An unused slot has an empty box (`min = +∞`, `max = −∞`) that
/// no ray meets.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(64))]
pub(super) struct WideNode {
    pub(super) min_x: [f32; WIDTH],
    pub(super) min_y: [f32; WIDTH],
    pub(super) min_z: [f32; WIDTH],
    pub(super) max_x: [f32; WIDTH],
    pub(super) max_y: [f32; WIDTH],
    pub(super) max_z: [f32; WIDTH],
    /// Interior child: index of its wide node. Leaf child: its first primitive (leaf order).
    pub(super) child: [u32; WIDTH],
    /// Leaf child: number of primitives (> 0). Interior child or unused slot: 0.
    pub(super) count: [u16; WIDTH],
    /// Number of used slots (the first ones).
    pub(super) slots: u32,
    /// `(1 << slots) - 1`: the used slots as a bit mask, so the box test masks out the
    /// unused ones with one `and` (set with `slots` by [`WideNode::set_slots`]).
    pub(super) slot_mask: u32,
    pub(super) _pad: [u32; 2],
}

// Four cache lines, as the layout comment says.
const _: () = assert!(std::mem::size_of::<WideNode>() == 256);

impl WideNode {
    pub(super) const EMPTY: WideNode = WideNode {
        min_x: [f32::INFINITY; WIDTH],
        min_y: [f32::INFINITY; WIDTH],
        min_z: [f32::INFINITY; WIDTH],
        max_x: [f32::NEG_INFINITY; WIDTH],
        max_y: [f32::NEG_INFINITY; WIDTH],
        max_z: [f32::NEG_INFINITY; WIDTH],
        child: [u32::MAX; WIDTH],
        count: [0; WIDTH],
        slots: 0,
        slot_mask: 0,
        _pad: [0; 2],
    };

    /// Sets the number of used slots (the first `slots`, at most [`WIDTH`]) and their mask.
    pub(super) fn set_slots(&mut self, slots: usize) {
        self.slots = slots as u32;
        self.slot_mask = slot_mask(slots);
    }

    pub(super) fn set_box(&mut self, slot: usize, n: &Node) {
        self.min_x[slot] = n.min[0];
        self.min_y[slot] = n.min[1];
        self.min_z[slot] = n.min[2];
        self.max_x[slot] = n.max[0];
        self.max_y[slot] = n.max[1];
        self.max_z[slot] = n.max[2];
    }
}

/// One eight-wide node with quantised child boxes (128 bytes, two cache lines instead of
/// four): each child coordinate is an 8-bit step on a grid over the node's own box,
/// `origin + q · scale` per axis with `scale` a power of two, so `q · scale` is exact and the
/// decoded coordinate is one rounded addition that the traversal repeats bit for bit. The
/// steps are chosen at build time by evaluating that very expression, lower corners rounded
/// down and upper ones up, so every decoded box contains its child's float box: the box test
/// stays conservative and the tree finds the same closest hits (it may visit a few more
/// nodes, and equal entry distances may order differently). For large scenes, whose float
/// nodes no longer fit in the caches (`docs/performance.md`, "Quantised nodes").
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(64))]
pub(super) struct QuantNode {
    /// Grid origin per axis (x, y, z): the node's box lower corner.
    pub(super) origin: [f32; 3],
    /// Grid step per axis (a power of two).
    pub(super) scale: [f32; 3],
    /// Lower corners' steps, `lo[axis][slot]`.
    pub(super) lo: [[u8; WIDTH]; 3],
    /// Upper corners' steps, `hi[axis][slot]`.
    pub(super) hi: [[u8; WIDTH]; 3],
    /// As [`WideNode::child`].
    pub(super) child: [u32; WIDTH],
    /// As [`WideNode::count`].
    pub(super) count: [u16; WIDTH],
    /// Number of used slots (the first ones).
    pub(super) slots: u32,
    /// As [`WideNode::slot_mask`] (in the four bytes the alignment leaves free).
    pub(super) slot_mask: u32,
}

const _: () = assert!(std::mem::size_of::<QuantNode>() == 128);

/// The bit mask of the first `slots` slots (`slots` ≤ 8, so the shift cannot overflow).
fn slot_mask(slots: usize) -> u32 {
    (1u32 << slots.min(WIDTH)) - 1
}

/// The decoded coordinate `origin + q · scale` (f32, in this order), as the traversal computes
/// it.
#[inline(always)]
pub(super) fn decode(origin: f32, scale: f32, q: u8) -> f32 {
    origin + q as f32 * scale
}

impl QuantNode {
    /// Quantises a float node; `None` where a grid cannot hold its boxes conservatively
    /// (extents beyond the power-of-two range used here, non-finite corners); the caller then
    /// keeps the float nodes.
    pub(super) fn from_wide(n: &WideNode) -> Option<QuantNode> {
        let slots = n.slots as usize;
        if slots == 0 || slots > WIDTH {
            return None;
        }
        let mut q = QuantNode {
            origin: [0.0; 3],
            scale: [1.0; 3],
            // Unused slots decode to an inverted box; they are masked by `slots` anyway.
            lo: [[u8::MAX; WIDTH]; 3],
            hi: [[0; WIDTH]; 3],
            child: n.child,
            count: n.count,
            slots: n.slots,
            slot_mask: slot_mask(slots),
        };
        let mins = [&n.min_x, &n.min_y, &n.min_z];
        let maxs = [&n.max_x, &n.max_y, &n.max_z];
        for axis in 0..3 {
            let (mn, mx) = (&mins[axis][..slots], &maxs[axis][..slots]);
            if !mn.iter().chain(mx).all(|v| v.is_finite()) {
                return None;
            }
            let origin = mn.iter().copied().fold(f32::INFINITY, f32::min);
            let top = mx.iter().copied().fold(f32::NEG_INFINITY, f32::max);
            // The smallest power of two with 255 steps covering the extent (in f64, exact
            // for these magnitudes); 2⁻¹⁰⁰ … 2¹⁰⁰ keeps `q · scale` a normal, exact f32.
            let extent = top as f64 - origin as f64;
            let exp = if extent > 0.0 {
                (extent / 255.0).log2().ceil().clamp(-100.0, 100.0) as i32
            } else {
                0
            };
            let scale = 2f32.powi(exp);
            q.origin[axis] = origin;
            q.scale[axis] = scale;
            for s in 0..slots {
                let (lo, hi) = (mn[s], mx[s]);
                // Start from the nearest step and move outward until the decoded corner
                // (computed exactly as the traversal does) contains the float one.
                let guess = |v: f32| ((v as f64 - origin as f64) / scale as f64).round();
                let mut ql = guess(lo).clamp(0.0, 255.0) as u8;
                while decode(origin, scale, ql) > lo {
                    ql = ql.checked_sub(1)?;
                }
                while ql < u8::MAX && decode(origin, scale, ql + 1) <= lo {
                    ql += 1;
                }
                let mut qh = guess(hi).clamp(0.0, 255.0) as u8;
                while decode(origin, scale, qh) < hi {
                    qh = qh.checked_add(1)?;
                }
                while qh > 0 && decode(origin, scale, qh - 1) >= hi {
                    qh -= 1;
                }
                q.lo[axis][s] = ql;
                q.hi[axis][s] = qh;
            }
        }
        Some(q)
    }

    /// The decoded (conservative) float boxes, as the traversal sees them.
    pub(super) fn decoded(&self) -> WideNode {
        let mut w = WideNode::EMPTY;
        for s in 0..self.slots as usize {
            let d = |axis: usize, q: &[[u8; WIDTH]; 3]| {
                decode(self.origin[axis], self.scale[axis], q[axis][s])
            };
            w.min_x[s] = d(0, &self.lo);
            w.min_y[s] = d(1, &self.lo);
            w.min_z[s] = d(2, &self.lo);
            w.max_x[s] = d(0, &self.hi);
            w.max_y[s] = d(1, &self.hi);
            w.max_z[s] = d(2, &self.hi);
            w.child[s] = self.child[s];
            w.count[s] = self.count[s];
        }
        w.set_slots(self.slots as usize);
        w
    }
}

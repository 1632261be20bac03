//! The eight-wide node the traversal reads: eight child boxes as structure of arrays.

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
    pub(super) _pad: [u32; 3],
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
        _pad: [0; 3],
    };

    pub(super) fn set_box(&mut self, slot: usize, n: &Node) {
        self.min_x[slot] = n.min[0];
        self.min_y[slot] = n.min[1];
        self.min_z[slot] = n.min[2];
        self.max_x[slot] = n.max[0];
        self.max_y[slot] = n.max[1];
        self.max_z[slot] = n.max[2];
    }
}

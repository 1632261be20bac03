//! Tree statistics in Embree's terms (its `verbose=2` build report), and per-ray visit
//! counts, for comparing the tree's quality with Embree's (the scaling bench prints both).

use glam::Vec3A;

use super::traverse::{node_hits_portable, quant_hits_portable, RayBoxes};
use super::tree::Bvh;
use super::wide_node::WIDTH;
use crate::geometry::{Aabb, Ray};

/// Counts and surface-area costs of a tree.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BvhStatistics {
    /// Wide nodes.
    pub nodes: usize,
    /// Used child slots over all nodes (interior and leaf children).
    pub children: usize,
    /// Leaves.
    pub leaves: usize,
    /// Primitives in the leaves.
    pub primitives: usize,
    /// Leaves of 1, 2, … 8 primitives.
    pub leaf_sizes: [usize; WIDTH],
    /// Wide nodes with 1, 2, … 8 used slots.
    pub node_slots: [usize; WIDTH],
    /// Wide nodes whose children are all leaves.
    pub twig_nodes: usize,
    /// Σ over the wide nodes of their box's surface area over the root's: the expected
    /// number of wide-node tests of a ray that crosses the root's box (Embree's node SAH).
    pub node_sah: f64,
    /// Σ over the leaves of their box's area over the root's times their four-triangle
    /// passes (`⌈count / 4⌉`): expected leaf passes per ray (Embree's leaf SAH, which counts
    /// its four-triangle blocks).
    pub leaf_sah: f64,
}

/// What one ray's traversal did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct VisitCounts {
    /// Wide nodes whose boxes were tested.
    pub nodes: u64,
    /// Leaves handed to the primitive test.
    pub leaves: u64,
    /// Primitives in those leaves.
    pub primitives: u64,
}

impl std::ops::AddAssign for VisitCounts {
    fn add_assign(&mut self, o: VisitCounts) {
        self.nodes += o.nodes;
        self.leaves += o.leaves;
        self.primitives += o.primitives;
    }
}

impl Bvh {
    /// The tree's [`BvhStatistics`] (boxes of quantised nodes as decoded, i.e. as the
    /// traversal sees them).
    pub fn statistics(&self) -> BvhStatistics {
        let mut s = BvhStatistics::default();
        let Some(root) = self.bounds else {
            return s;
        };
        let root_area = f64::from(root.surface_area());
        if root_area <= 0.0 {
            return s;
        }
        // (node index, its box's area)
        let mut stack = vec![(0usize, root_area)];
        while let Some((i, area)) = stack.pop() {
            s.nodes += 1;
            s.node_sah += area / root_area;
            let (boxes, child, count, slots) = self.node_boxes(i);
            s.children += slots;
            s.node_slots[slots.clamp(1, WIDTH) - 1] += 1;
            if count[..slots].iter().all(|&c| c > 0) {
                s.twig_nodes += 1;
            }
            for k in 0..slots {
                let a = f64::from(boxes[k].surface_area());
                if count[k] > 0 {
                    let n = usize::from(count[k]);
                    s.leaves += 1;
                    s.primitives += n;
                    s.leaf_sizes[(n - 1).min(WIDTH - 1)] += 1;
                    s.leaf_sah += a / root_area * n.div_ceil(4) as f64;
                } else {
                    stack.push((child[k] as usize, a));
                }
            }
        }
        s
    }

    /// Node `i`'s used child boxes (decoded if quantised), references, counts and slot count.
    fn node_boxes(&self, i: usize) -> ([Aabb; WIDTH], [u32; WIDTH], [u16; WIDTH], usize) {
        let w = if self.qnodes.is_empty() {
            self.nodes[i]
        } else {
            self.qnodes[i].decoded()
        };
        let mut boxes = [Aabb::EMPTY; WIDTH];
        let slots = (w.slots as usize).min(WIDTH);
        for (k, b) in boxes.iter_mut().enumerate().take(slots) {
            *b = Aabb {
                min: Vec3A::new(w.min_x[k], w.min_y[k], w.min_z[k]),
                max: Vec3A::new(w.max_x[k], w.max_y[k], w.max_z[k]),
            };
        }
        (boxes, w.child, w.count, slots)
    }

    /// What [`Bvh::traverse_leaves`] does for this ray (`test` as there): the same box test
    /// and visiting order (closest hit: hit children by entry distance, ties in slot order, as
    /// test `hit_children_visit_in_stable_distance_order` checks against the real loop; any
    /// hit: the reverse of that order), written plainly and counted
    /// (test `visit_counts_match_the_traversal`). For statistics only: slower than the real traversal.
    pub fn count_visits(
        &self,
        ray: &Ray,
        mut t_max: f32,
        any_hit: bool,
        mut test: impl FnMut(u32, u32, f32) -> Option<f32>,
    ) -> VisitCounts {
        let mut c = VisitCounts::default();
        if self.nodes.is_empty() && self.qnodes.is_empty() {
            return c;
        }
        let rb = RayBoxes::new(ray);
        let mut stack = vec![(0u32, 0u32, 0.0f32)];
        while let Some((child, count, near)) = stack.pop() {
            if near > t_max {
                continue;
            }
            if count > 0 {
                c.leaves += 1;
                c.primitives += u64::from(count);
                if let Some(t) = test(child, count, t_max) {
                    t_max = t;
                    if any_hit {
                        break;
                    }
                }
                continue;
            }
            c.nodes += 1;
            let mut d = [0.0; WIDTH];
            let (mask, n_child, n_count) = if self.qnodes.is_empty() {
                let n = &self.nodes[child as usize];
                (node_hits_portable(n, &rb, t_max, &mut d), n.child, n.count)
            } else {
                let n = &self.qnodes[child as usize];
                (quant_hits_portable(n, &rb, t_max, &mut d), n.child, n.count)
            };
            let mut hits: Vec<(u32, u32, f32)> = (0..WIDTH)
                .filter(|&k| mask & (1 << k) != 0)
                .map(|k| (n_child[k], u32::from(n_count[k]), d[k]))
                .collect();
            // Stable: ties stay in slot order (IEEE order, as the loop's comparisons; hit
            // lanes have no NaN distance).
            hits.sort_by(|a, b| a.2.partial_cmp(&b.2).unwrap_or(std::cmp::Ordering::Equal));
            if any_hit {
                // As the loop: farthest first (the later slot on a tie).
                stack.extend(hits.iter());
            } else {
                stack.extend(hits.iter().rev());
            }
        }
        c
    }
}

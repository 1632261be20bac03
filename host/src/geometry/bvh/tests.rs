//! Tests of the build, the collapse and both traversal kernels.

use super::build::*;
use super::collapse::*;
use super::traverse::*;
use super::tree::*;
use super::wide_node::*;
use super::*;
use crate::geometry::{Aabb, Ray};
use glam::Vec3A;

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

// The collapse near the root runs its subtrees in parallel into parts placed afterwards; the
// layout must be exactly the sequential depth-first one (every node's boxes, children, leaf
// sizes and slot counts compared exactly; float and quantised), and the parallel stable
// partition must equal a sequential stable partition.
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
            BuildPrim::new(&b, i as u32)
        })
        .collect();
    let left = |p: &BuildPrim| p.centroid().x < 37.0;
    let mut seq: Vec<u32> = prims.iter().filter(|p| left(p)).map(|p| p.index).collect();
    seq.extend(prims.iter().filter(|p| !left(p)).map(|p| p.index));
    let mut par = prims.clone();
    let mid = partition_stable_parallel(&mut par, left);
    assert_eq!(mid, prims.iter().filter(|p| left(p)).count());
    assert_eq!(par.iter().map(|p| p.index).collect::<Vec<_>>(), seq);

    let binary = build_range(&mut prims, 0, 0);
    let mut sequential: Vec<WideNode> = Vec::new();
    fill_wide(
        &binary,
        Children::of(&binary, 0),
        MERGE_LEAF_PRIMITIVES,
        &mut sequential,
    );
    assert_eq!(
        collapse::<WideNode>(binary.clone(), MERGE_LEAF_PRIMITIVES)
            .ok()
            .as_deref(),
        Some(&sequential[..])
    );
    // The quantised collapse makes each node from its float form on the spot: the same as
    // quantising the sequential float nodes one by one.
    let quantised: Option<Vec<QuantNode>> = sequential.iter().map(QuantNode::from_wide).collect();
    assert!(quantised.is_some());
    assert_eq!(
        collapse::<QuantNode>(binary, MERGE_LEAF_PRIMITIVES)
            .ok()
            .as_deref(),
        quantised.as_deref()
    );
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

// The collapse merges a small binary subtree into one leaf slot only where the surface area
// heuristic accepts it. A hand-made binary tree: four equal overlapping boxes (merging costs
// no extra tests: one leaf of four) and four tiny boxes at the corners of a 100-unit square
// (merged, every ray reaching the square would test all four: four leaves of one). The root
// wide node must hold exactly those five slots (compared exactly).
#[test]
fn collapse_merges_by_surface_area() {
    /// A balanced binary tree over unit-count leaves, depth-first, first child next.
    fn tree(boxes: &[([f32; 3], [f32; 3])], first: u32, out: &mut Vec<Node>) -> usize {
        let me = out.len();
        let mut n = Node {
            min: [f32::INFINITY; 3],
            offset: first,
            max: [f32::NEG_INFINITY; 3],
            count: 1,
            axis: 0,
            _pad: 0,
        };
        for (lo, hi) in boxes {
            for a in 0..3 {
                n.min[a] = n.min[a].min(lo[a]);
                n.max[a] = n.max[a].max(hi[a]);
            }
        }
        out.push(n);
        if boxes.len() > 1 {
            let half = boxes.len() / 2;
            tree(&boxes[..half], first, out);
            let right = tree(&boxes[half..], first + half as u32, out);
            out[me].offset = right as u32;
            out[me].count = 0;
        }
        me
    }
    let unit = ([0.0, 0.0, 0.0], [1.0, 1.0, 1.0]);
    let tiny = |x: f32, y: f32| ([x, y, 5.0], [x + 0.01, y + 0.01, 5.01]);
    let mut boxes = vec![unit; 4];
    boxes.extend([
        tiny(200.0, 0.0),
        tiny(300.0, 0.0),
        tiny(200.0, 100.0),
        tiny(300.0, 100.0),
    ]);
    let mut binary = Vec::new();
    tree(&boxes, 0, &mut binary);
    // Without merging, the eight binary leaves stay apart.
    let apart = collapse_float(binary.clone(), 0);
    assert_eq!(apart[0].count[..apart[0].slots as usize], [1; 8]);
    let wide = collapse_float(binary, MERGE_LEAF_PRIMITIVES);
    let root = &wide[0];
    let mut slots: Vec<(u32, u16)> = (0..root.slots as usize)
        .map(|s| (root.child[s], root.count[s]))
        .collect();
    slots.sort_unstable();
    assert_eq!(slots, vec![(0, 4), (4, 1), (5, 1), (6, 1), (7, 1)]);
    assert_eq!(wide.len(), 1);
    // Past four primitives merges are priced by four-triangle passes: eight unit boxes in one
    // place become one leaf of eight (two passes against eight separate leaves of one); eight
    // tiny boxes, two at each corner of the square, stay apart as the corners' pairs (one leaf
    // of eight would cost two passes per ray reaching the square, the pairs next to nothing).
    let mut boxes = vec![unit; 8];
    for (x, y) in [(200.0, 0.0), (300.0, 0.0), (200.0, 100.0), (300.0, 100.0)] {
        boxes.extend([tiny(x, y); 2]);
    }
    let mut binary = Vec::new();
    tree(&boxes, 0, &mut binary);
    let wide = collapse_float(binary, MERGE_LEAF_PRIMITIVES);
    let root = &wide[0];
    let mut slots: Vec<(u32, u16)> = (0..root.slots as usize)
        .map(|s| (root.child[s], root.count[s]))
        .collect();
    slots.sort_unstable();
    assert_eq!(slots, vec![(0, 8), (8, 2), (10, 2), (12, 2), (14, 2)]);
    assert_eq!(wide.len(), 1);
    // Up to four primitives a merged leaf is one pass, as each of its parts is: four unit
    // boxes in a row become one leaf (its box, area 18, against the parts' 4 × 6 = 24; priced
    // by primitive tests, 4 × 18 > 24 + 1.5 × 18, they stayed apart), and two such rows far
    // apart stay two leaves (the pair's box is 100 times longer than either row).
    let row = |x: f32| -> Vec<([f32; 3], [f32; 3])> {
        (0..4)
            .map(|i| ([x + i as f32, 0.0, 0.0], [x + i as f32 + 1.0, 1.0, 1.0]))
            .collect()
    };
    let mut boxes = row(0.0);
    boxes.extend(row(400.0));
    let mut binary = Vec::new();
    tree(&boxes, 0, &mut binary);
    let wide = collapse_float(binary, 4);
    let root = &wide[0];
    let mut slots: Vec<(u32, u16)> = (0..root.slots as usize)
        .map(|s| (root.child[s], root.count[s]))
        .collect();
    slots.sort_unstable();
    assert_eq!(slots, vec![(0, 4), (4, 4)]);
}

// The wide traversal must find exactly the closest hit a brute-force loop finds, with float
// and with quantised nodes (merged leaves) and with float nodes without merged leaves:
// primitives are boxes, "hit" is the conservative slab test's entry distance, 2000 random rays
// over 3000 random boxes (small and large, overlapping); compared exactly, and any-hit must
// agree on whether anything is hit at all.
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
    let layouts = [NodeLayout::Float, NodeLayout::Quantised];
    let mut bvhs: Vec<Bvh> = layouts
        .iter()
        .map(|&l| Bvh::build_with_layout(&boxes, l))
        .collect();
    for (bvh, layout) in bvhs.iter().zip(layouts) {
        assert_eq!(bvh.layout(), layout);
    }
    // And the tree without merged leaves; the merged one must hold fewer leaf slots, so that
    // merged leaves are part of what is compared.
    let apart = Bvh::build_with_options(&boxes, NodeLayout::Float, false);
    let leaf_slots = |b: &Bvh| -> usize {
        b.nodes
            .iter()
            .map(|n| {
                n.count[..n.slots as usize]
                    .iter()
                    .filter(|&&c| c > 0)
                    .count()
            })
            .sum()
    };
    let (merged, separate) = (leaf_slots(&bvhs[0]), leaf_slots(&apart));
    assert!(
        merged < separate,
        "{merged} merged against {separate} leaf slots"
    );
    bvhs.push(apart);
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
        for bvh in &bvhs {
            let found = bvh.traverse(&ray, f32::INFINITY, false, |slot, t_max| {
                entry(&boxes[bvh.order[slot as usize] as usize], &ray, t_max)
            });
            assert_eq!(found, brute, "{:?} nodes", bvh.layout());
            let any = bvh.traverse(&ray, f32::INFINITY, true, |slot, t_max| {
                entry(&boxes[bvh.order[slot as usize] as usize], &ray, t_max)
            });
            assert_eq!(any.is_some(), brute.is_some(), "{:?} nodes", bvh.layout());
        }
        hits += brute.is_some() as usize;
    }
    // The test means something only if many rays hit and many miss.
    assert!(hits > 200 && hits < 1800, "{hits} of 2000 rays hit");
}

// `Bvh::leaves` must partition the leaf order into the leaves the traversal hands over: sorted,
// contiguous, covering every slot once, at most `MERGE_LEAF_PRIMITIVES` primitives each (two
// passes of four triangle lanes; `MAX_LEAF_SIZE_OTHER` without merging), for float, quantised and
// unmerged trees; and every
// `(first, count)` that `traverse_leaves` gives for 300 random rays is one of them. Exact.
#[test]
fn leaves_partition_the_leaf_order() {
    let mut next = uniform_stream(5);
    let boxes: Vec<Aabb> = (0..3000)
        .map(|_| {
            let p = Vec3A::new(next(), next(), next()) * 20.0 - 10.0;
            let e = Vec3A::new(next(), next(), next()) * 0.3 + 0.01;
            Aabb {
                min: p - e,
                max: p + e,
            }
        })
        .collect();
    for (bvh, largest) in [
        (
            Bvh::build_with_layout(&boxes, NodeLayout::Float),
            MERGE_LEAF_PRIMITIVES,
        ),
        (
            Bvh::build_with_layout(&boxes, NodeLayout::Quantised),
            MERGE_LEAF_PRIMITIVES,
        ),
        (
            Bvh::build_with_options(&boxes, NodeLayout::Float, false),
            MAX_LEAF_SIZE_OTHER,
        ),
    ] {
        let leaves = bvh.leaves();
        let mut at = 0;
        for &(first, count) in &leaves {
            assert_eq!(first, at, "{:?} nodes", bvh.layout());
            assert!((1..=largest as u32).contains(&count));
            at += count;
        }
        assert_eq!(at as usize, bvh.order.len());
        let set: std::collections::HashSet<(u32, u32)> = leaves.iter().copied().collect();
        for _ in 0..300 {
            let o = Vec3A::new(next(), next(), next()) * 30.0 - 15.0;
            let ray = Ray::new(o, Vec3A::new(next(), next(), next()) * 2.0 - 1.0);
            bvh.traverse_leaves(&ray, f32::INFINITY, false, |first, count, _| {
                assert!(set.contains(&(first, count)), "leaf {first}+{count}");
                None
            });
        }
    }
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
        let found = bvh.traverse_with_stack::<2, _>(&ray, f32::INFINITY, false, |first, n, t| {
            for_each_slot(first, n, t, false, &mut |slot, t| {
                spilled_log.push((slot, t.to_bits()));
                entry(&boxes[bvh.order[slot as usize] as usize], t)
            })
        });
        assert_eq!(found, brute);
        // And in the same order as with the full-size stack (spilling keeps LIFO order).
        let mut log = Vec::new();
        bvh.traverse(&ray, f32::INFINITY, false, |slot, t| {
            log.push((slot, t.to_bits()));
            entry(&boxes[bvh.order[slot as usize] as usize], t)
        });
        assert_eq!(spilled_log, log);
        let any = bvh.traverse_with_stack::<2, _>(&ray, f32::INFINITY, true, |first, n, t| {
            for_each_slot(first, n, t, true, &mut |slot, t| {
                entry(&boxes[bvh.order[slot as usize] as usize], t)
            })
        });
        assert_eq!(any.is_some(), brute.is_some());
    }
}

// The AVX2 and the portable kernel must walk the tree identically, with float and with
// quantised nodes: for every ray the
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
    let mut rays = Vec::new();
    for r in 0..3000 {
        let mut o = Vec3A::new(next(), next(), next()) * 50.0 - 25.0;
        let mut d = Vec3A::new(next(), next(), next()) * 2.0 - 1.0;
        if r % 3 == 0 {
            o = o.floor();
            let axis = r / 3 % 3;
            d[axis] = 0.0;
            d[(axis + 1) % 3] = if r % 2 == 0 { 0.0 } else { -0.0 };
        }
        rays.push(Ray::new(o, d));
    }
    for layout in [NodeLayout::Float, NodeLayout::Quantised] {
        let mut bvh = Bvh::build_with_layout(&boxes, layout);
        assert_eq!(bvh.layout(), layout);
        let mut visits = 0usize;
        for (r, ray) in rays.iter().enumerate() {
            let ray = *ray;
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
                assert!(
                    runs[0] == runs[1],
                    "ray {r} (any_hit {any_hit}, {layout:?}) differs"
                );
            }
        }
        // The comparison means something only if the rays reach many leaves (5,872 primitive
        // tests in 6,000 walks with float nodes when written).
        assert!(visits > 4_000, "only {visits} primitive tests ({layout:?})");
    }
}

// Quantised nodes must hold every child box (the box test's conservativeness, hence the
// hits, rests on it) and each step must be the tightest: the next step inward would cut the
// float box. Exact comparisons of the decoded f32 corners (they are what the traversal
// computes). 20,000 boxes far from the origin (offset 10⁴, extents from 10⁻³ down to flat
// zero), so the grids meet rounding in the addition `origin + q · scale`.
#[test]
fn quantised_boxes_contain_and_hug_children() {
    let mut next = uniform_stream(77);
    let boxes: Vec<Aabb> = (0..20_000)
        .map(|i| {
            let p = Vec3A::new(next(), next(), next()) * 50.0 + 1.0e4;
            let mut e = Vec3A::new(next(), next(), next()) * 1.0e-3;
            if i % 7 == 0 {
                e.y = 0.0;
            }
            Aabb { min: p, max: p + e }
        })
        .collect();
    let float = Bvh::build_with_layout(&boxes, NodeLayout::Float);
    let quant = Bvh::build_with_layout(&boxes, NodeLayout::Quantised);
    assert_eq!(quant.layout(), NodeLayout::Quantised);
    assert_eq!(float.nodes.len(), quant.qnodes.len());
    for (f, q) in float.nodes.iter().zip(&quant.qnodes) {
        let d = q.decoded();
        assert_eq!((d.child, d.count, d.slots), (f.child, f.count, f.slots));
        for s in 0..f.slots as usize {
            let fl = [f.min_x[s], f.min_y[s], f.min_z[s]];
            let fh = [f.max_x[s], f.max_y[s], f.max_z[s]];
            let dl = [d.min_x[s], d.min_y[s], d.min_z[s]];
            let dh = [d.max_x[s], d.max_y[s], d.max_z[s]];
            for axis in 0..3 {
                assert!(dl[axis] <= fl[axis] && dh[axis] >= fh[axis]);
                let (o, sc) = (q.origin[axis], q.scale[axis]);
                let (ql, qh) = (q.lo[axis][s], q.hi[axis][s]);
                assert!(ql == u8::MAX || decode(o, sc, ql + 1) > fl[axis]);
                assert!(qh == 0 || decode(o, sc, qh - 1) < fh[axis]);
            }
        }
    }
    // Half the memory per node.
    assert_eq!(
        std::mem::size_of::<QuantNode>() * 2,
        std::mem::size_of::<WideNode>()
    );
}

// Making the build faster must not change the tree. The binary tree of an 81,920-triangle
// icosphere (above both parallel thresholds, so the parallel parts, partitions and bins all
// run) is hashed (FNV-1a over every node's bound bits, offset, count and split axis, then the
// leaf order) and compared exactly with the hash of the build of commit 6234888, the build
// before the single-copy parts, the fused bounds and the ping-pong partition.
#[test]
fn binary_tree_matches_recorded_build() {
    let mesh = crate::geometry::generate::icosphere(6);
    let mut prims: Vec<BuildPrim> = (0..mesh.indices.len())
        .map(|t| {
            let [a, b, c] = mesh.triangle(t);
            let bounds = Aabb::from_point(a).grow(b).grow(c);
            BuildPrim::new(&bounds, t as u32)
        })
        .collect();
    assert!(prims.len() > PARALLEL_NODE_THRESHOLD);
    let nodes = build_range(&mut prims, 0, 0);
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    let mut mix = |w: u32| {
        for b in w.to_le_bytes() {
            h = (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
        }
    };
    for n in &nodes {
        n.min.iter().chain(&n.max).for_each(|v| mix(v.to_bits()));
        mix(n.offset);
        mix(u32::from(n.count));
        mix(u32::from(n.axis));
    }
    prims.iter().for_each(|p| mix(p.index));
    assert_eq!(nodes.len(), 94_889);
    assert_eq!(
        h, 0xdced_d011_1e9b_7875,
        "the tree differs from the recorded build"
    );
}

// Where a node cannot be quantised (here the root's children span ±10³⁸, beyond 255 steps of
// the largest grid step, 2¹⁰⁰), the quantised collapse gives the binary tree back and the
// whole tree is float: exactly the tree of a float build (nodes and leaf order compared
// exactly), on 1 and 2 threads.
#[test]
fn unquantisable_tree_falls_back_to_float() {
    let mut next = uniform_stream(99);
    let mut boxes: Vec<Aabb> = (0..2_000)
        .map(|_| {
            let p = Vec3A::new(next(), next(), next()) * 10.0;
            Aabb {
                min: p,
                max: p + Vec3A::splat(0.1),
            }
        })
        .collect();
    for x in [-1.0e38f32, 1.0e38] {
        let p = Vec3A::new(x, 0.0, 0.0);
        boxes.push(Aabb { min: p, max: p });
    }
    let float = Bvh::build_with_layout(&boxes, NodeLayout::Float);
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let quant = pool.install(|| Bvh::build_with_layout(&boxes, NodeLayout::Quantised));
        assert_eq!(quant.layout(), NodeLayout::Float);
        assert_eq!(quant.nodes, float.nodes);
        assert_eq!(quant.order, float.order);
    }
}

// Every interior child reference must index the node array it lives in (the traversal reads
// nodes without bounds checks on that invariant), for float, quantised and unmerged trees of
// random boxes, exactly.
#[test]
fn interior_references_index_the_nodes() {
    let mut next = uniform_stream(9);
    let boxes: Vec<Aabb> = (0..5000)
        .map(|_| {
            let p = Vec3A::new(next(), next(), next()) * 20.0 - 10.0;
            let e = Vec3A::new(next(), next(), next()) * 0.5 + 0.01;
            Aabb {
                min: p - e,
                max: p + e,
            }
        })
        .collect();
    for bvh in [
        Bvh::build_with_layout(&boxes, NodeLayout::Float),
        Bvh::build_with_layout(&boxes, NodeLayout::Quantised),
        Bvh::build_with_options(&boxes, NodeLayout::Float, false),
    ] {
        let refs: Vec<(u32, u16, u32, u32)> =
            bvh.nodes
                .iter()
                .flat_map(|n| (0..WIDTH).map(|k| (n.child[k], n.count[k], n.slots, n.slot_mask)))
                .chain(bvh.qnodes.iter().flat_map(|n| {
                    (0..WIDTH).map(|k| (n.child[k], n.count[k], n.slots, n.slot_mask))
                }))
                .collect();
        let len = bvh.node_count() as u32;
        assert!(len > 1);
        for (k, &(child, count, slots, mask)) in refs.iter().enumerate() {
            assert_eq!(mask, (1 << slots) - 1);
            if (k % WIDTH) < slots as usize && count == 0 {
                assert!(child < len, "interior reference {child} of {len} nodes");
            }
        }
    }
}

// The closest-first order must be that of a stable sort of each node's hit children by entry
// distance (ties in slot order): the leaves `traverse_leaves` hands over, in order, equal
// those of a plain reference traversal (hits collected in slot order, `sort_by` on the entry
// distance, which is stable, nearest visited first), for 2,000 rays through random boxes in
// which many rays start inside several boxes (entry distance 0 for all: ties) and a third of
// the rays are axis-parallel. Compared exactly, with both kernels and both layouts. Any-hit
// walks (whose order changes no result, only how soon they end) visit each node's hit children
// in the reverse of that order, farthest first: checked the same way with the callback never
// reporting a hit, so that the whole walk is seen.
#[test]
fn hit_children_visit_in_stable_distance_order() {
    let mut next = uniform_stream(21);
    let boxes: Vec<Aabb> = (0..1500)
        .map(|_| {
            let p = Vec3A::new(next(), next(), next()) * 10.0 - 5.0;
            let e = Vec3A::new(next(), next(), next()) * 1.5 + 0.01;
            Aabb {
                min: p - e,
                max: p + e,
            }
        })
        .collect();
    let mut ties = 0;
    for layout in [NodeLayout::Float, NodeLayout::Quantised] {
        let mut bvh = Bvh::build_with_layout(&boxes, layout);
        for kernel in [TraversalKernel::Portable, TraversalKernel::best_available()] {
            bvh.set_kernel(kernel);
            let mut next = uniform_stream(22);
            for r in 0..2000 {
                let o = Vec3A::new(next(), next(), next()) * 12.0 - 6.0;
                let d = if r % 3 == 0 {
                    let mut d = Vec3A::ZERO;
                    d[r % 9 / 3] = if next() < 0.5 { -1.0 } else { 1.0 };
                    d
                } else {
                    Vec3A::new(next(), next(), next()) * 2.0 - 1.0
                };
                let ray = Ray::new(o, d);
                let t_max = if r % 2 == 0 {
                    f32::INFINITY
                } else {
                    next() * 8.0
                };
                let any_hit = r % 4 >= 2;
                let mut got = Vec::new();
                bvh.traverse_leaves(&ray, t_max, any_hit, |first, count, _| {
                    got.push((first, count));
                    None
                });
                // The reference: the same box test, hit children sorted with `sort_by`.
                let rb = RayBoxes::new(&ray);
                let mut want = Vec::new();
                let mut stack = vec![(0u32, 0u32, 0.0f32)];
                while let Some((child, count, near)) = stack.pop() {
                    if near > t_max {
                        continue;
                    }
                    if count > 0 {
                        want.push((child, count));
                        continue;
                    }
                    let mut d = [0.0; WIDTH];
                    let (mask, n_child, n_count) = if bvh.qnodes.is_empty() {
                        let n = &bvh.nodes[child as usize];
                        (node_hits_portable(n, &rb, t_max, &mut d), n.child, n.count)
                    } else {
                        let n = &bvh.qnodes[child as usize];
                        (quant_hits_portable(n, &rb, t_max, &mut d), n.child, n.count)
                    };
                    let mut hits: Vec<(u32, u32, f32)> = (0..WIDTH)
                        .filter(|&k| mask & (1 << k) != 0)
                        .map(|k| (n_child[k], u32::from(n_count[k]), d[k]))
                        .collect();
                    ties += hits.windows(2).filter(|w| w[0].2 == w[1].2).count();
                    hits.sort_by(|a, b| a.2.partial_cmp(&b.2).unwrap());
                    if any_hit {
                        stack.extend(hits.iter());
                    } else {
                        stack.extend(hits.iter().rev());
                    }
                }
                assert_eq!(
                    got, want,
                    "ray {r} (any hit {any_hit}), {layout:?} nodes, {kernel:?} kernel"
                );
            }
        }
    }
    assert!(ties > 1000, "only {ties} equal entry distances");
}

// `count_visits` (statistics) must count what the traversal does: for 1,500 random rays
// through random boxes, closest-hit and any-hit, float and quantised nodes, its leaves and
// primitives equal the leaf calls of `traverse_leaves` with the same primitive test, and the
// statistics' counts add up (every slot a leaf or an interior node but the root). Exact.
#[test]
fn visit_counts_match_the_traversal() {
    let mut next = uniform_stream(41);
    let boxes: Vec<Aabb> = (0..2500)
        .map(|_| {
            let p = Vec3A::new(next(), next(), next()) * 20.0 - 10.0;
            let e = Vec3A::new(next(), next(), next()) * 0.6 + 0.01;
            Aabb {
                min: p - e,
                max: p + e,
            }
        })
        .collect();
    for layout in [NodeLayout::Float, NodeLayout::Quantised] {
        let bvh = Bvh::build_with_layout(&boxes, layout);
        let s = bvh.statistics();
        assert_eq!(s.primitives, boxes.len(), "{layout:?}");
        assert_eq!(s.children, s.leaves + s.nodes - 1, "{layout:?}");
        assert_eq!(s.node_slots.iter().sum::<usize>(), s.nodes, "{layout:?}");
        assert!(s.node_sah >= 1.0 && s.leaf_sah > 0.0, "{layout:?}");
        // Leaf hit: its first primitive's box entered before `t_max`.
        let test = |ray: &Ray, first: u32, t_max: f32| -> Option<f32> {
            let b = &boxes[bvh.order[first as usize] as usize];
            let inv = Vec3A::ONE / ray.dir;
            let t = ((b.min - ray.origin) * inv)
                .min((b.max - ray.origin) * inv)
                .max_element()
                .max(1e-6);
            (b.hit(ray.origin, inv, t_max) && t < t_max).then_some(t)
        };
        let mut leaves = 0;
        for _ in 0..1500 {
            let o = Vec3A::new(next(), next(), next()) * 30.0 - 15.0;
            let d = Vec3A::new(next(), next(), next()) * 2.0 - 1.0;
            let ray = Ray::new(o, d);
            for any_hit in [false, true] {
                let (mut n, mut prims) = (0u64, 0u64);
                bvh.traverse_leaves(&ray, f32::INFINITY, any_hit, |first, count, t_max| {
                    n += 1;
                    prims += u64::from(count);
                    test(&ray, first, t_max)
                });
                let c = bvh.count_visits(&ray, f32::INFINITY, any_hit, |first, _, t_max| {
                    test(&ray, first, t_max)
                });
                assert_eq!((c.leaves, c.primitives), (n, prims), "{layout:?} {any_hit}");
                assert!(c.nodes >= 1);
                leaves += n;
            }
        }
        assert!(leaves > 1000, "only {leaves} leaf visits ({layout:?})");
    }
}

/// The slab test as it was before the entry and exit planes were chosen by the ray's octant:
/// both planes of each axis ordered with SSE's `min`/`max` (`b` on NaN or equality), nested
/// from z outwards. One slot of a float node; `(hit, entry distance)`.
fn ordered_slab(n: &WideNode, slot: usize, rb: &RayBoxes, t_max: f32) -> (bool, f32) {
    let sse_min = |a: f32, b: f32| if a < b { a } else { b };
    let sse_max = |a: f32, b: f32| if a > b { a } else { b };
    let lo = [n.min_x[slot], n.min_y[slot], n.min_z[slot]];
    let hi = [n.max_x[slot], n.max_y[slot], n.max_z[slot]];
    let t0: [f32; 3] = std::array::from_fn(|a| (lo[a] - rb.origin[a]) * rb.inv_dir[a]);
    let t1: [f32; 3] = std::array::from_fn(|a| (hi[a] - rb.origin[a]) * rb.inv_dir[a]);
    let near = sse_max(
        sse_min(t0[0], t1[0]),
        sse_max(sse_min(t0[1], t1[1]), sse_max(sse_min(t0[2], t1[2]), 0.0)),
    );
    let far = sse_min(
        sse_max(t0[0], t1[0]),
        sse_min(sse_max(t0[1], t1[1]), sse_min(sse_max(t0[2], t1[2]), t_max)),
    ) * (1.0 + 2.0 * crate::geometry::float_error::gamma(3));
    (near <= far, near)
}

// The node test reads each axis's entry and exit plane by the ray's octant and takes the
// `max`/`min` of the three axes as a balanced pair (shorter dependency chains), where it used
// to order both planes of every axis and nest the axes. For 200 random nodes (boxes with flat
// sides, slots used 1..8) and 3,000 rays per node (a third with zero or negative-zero
// direction components and origins on the boxes' planes, where `0 · ∞` is NaN), with the
// portable and the AVX2 kernel, float and quantised nodes (the quantised node against the
// ordered test of its decoded boxes): every box the ordered test meets is met (the test stays
// conservative), and where no direction component is zero the masks are equal and the entry
// distances equal bit for bit. The cases where a grazing ray now meets a box the ordered test
// missed must occur, or the test would not exercise the difference.
#[test]
fn octant_planes_match_the_ordered_slab_test() {
    let mut next = uniform_stream(2024);
    let kernels = [TraversalKernel::Portable, TraversalKernel::best_available()];
    let (mut compared, mut grazing_gained) = (0usize, 0usize);
    for _ in 0..200 {
        let mut n = WideNode::EMPTY;
        let slots = 1 + (next() * 8.0) as usize % WIDTH;
        for s in 0..slots {
            let p: [f32; 3] = std::array::from_fn(|_| (next() * 8.0 - 4.0).floor());
            let e: [f32; 3] = std::array::from_fn(|_| (next() * 3.0).floor());
            (n.min_x[s], n.min_y[s], n.min_z[s]) = (p[0], p[1], p[2]);
            (n.max_x[s], n.max_y[s], n.max_z[s]) = (p[0] + e[0], p[1] + e[1], p[2] + e[2]);
        }
        n.set_slots(slots);
        let q = QuantNode::from_wide(&n).expect("small integer boxes quantise");
        // The quantised node's decoded boxes, as a float node for the reference.
        let dq = q.decoded();
        for r in 0..3000 {
            let mut o = Vec3A::new(next(), next(), next()) * 12.0 - 6.0;
            let mut d = Vec3A::new(next(), next(), next()) * 2.0 - 1.0;
            if r % 3 == 0 {
                o = o.floor();
                let axis = r / 3 % 3;
                d[axis] = if r % 2 == 0 { 0.0 } else { -0.0 };
                if r % 5 == 0 {
                    d[(axis + 1) % 3] = -0.0;
                }
            }
            let ray = Ray::new(o, d);
            let rb = RayBoxes::new(&ray);
            let exact = rb.inv_dir.iter().all(|v| v.is_finite());
            let t_max = if r % 4 == 0 {
                f32::INFINITY
            } else {
                next() * 10.0
            };
            for &kernel in &kernels {
                for (node, reference) in [(None, &n), (Some(&q), &dq)] {
                    let mut near = [f32::NAN; WIDTH];
                    let mask = match (kernel, node) {
                        (TraversalKernel::Portable, None) => {
                            node_hits_portable(&n, &rb, t_max, &mut near)
                        }
                        (TraversalKernel::Portable, Some(q)) => {
                            quant_hits_portable(q, &rb, t_max, &mut near)
                        }
                        #[cfg(target_arch = "x86_64")]
                        // SAFETY: `best_available` said this CPU runs the AVX2 kernel.
                        (TraversalKernel::Avx2, None) => unsafe {
                            node_hits_avx2(&n, &rb, t_max, &mut near)
                        },
                        #[cfg(target_arch = "x86_64")]
                        // SAFETY: as above (AVX2 and FMA).
                        (TraversalKernel::Avx2, Some(q)) => unsafe {
                            quant_hits_avx2(q, &rb, t_max, &mut near)
                        },
                        #[allow(unreachable_patterns)]
                        _ => unreachable!("no other kernel"),
                    };
                    for (s, &near) in near.iter().enumerate().take(slots) {
                        let (want, want_near) = ordered_slab(reference, s, &rb, t_max);
                        let got = mask & (1 << s) != 0;
                        compared += 1;
                        assert!(
                            got || !want,
                            "{kernel:?} missed slot {s} the ordered test meets: {ray:?} t_max {t_max}"
                        );
                        if exact {
                            assert_eq!(got, want, "{kernel:?} slot {s}: {ray:?} t_max {t_max}");
                            if got {
                                assert_eq!(
                                    near.to_bits(),
                                    want_near.to_bits(),
                                    "{kernel:?} slot {s} entry distance: {ray:?}"
                                );
                            }
                        } else if got && !want {
                            grazing_gained += 1;
                        }
                    }
                }
            }
        }
    }
    assert!(compared > 1_000_000, "{compared} slot tests");
    assert!(
        grazing_gained > 0,
        "no grazing ray met a box the ordered test missed"
    );
}

// The entry and exit planes per axis are the reciprocal's sign bit as `is_sign_negative`
// reads it (entry `axis + 3` where set), for every sign case a direction component can have:
// ±1, ±0 (reciprocal ±∞), subnormals (reciprocal ±∞ in f32), ±∞ (reciprocal ±0) and NaN of
// either sign. Exact equality of indices.
#[test]
fn ray_octant_planes_follow_the_reciprocal_sign_bit() {
    let values = [
        1.0f32,
        -1.0,
        0.0,
        -0.0,
        1e-40,
        -1e-40,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::NAN,
        -f32::NAN,
    ];
    for &x in &values {
        for &y in &values {
            for &z in &values {
                let ray = Ray::new(Vec3A::ZERO, Vec3A::new(x, y, z));
                let rb = RayBoxes::new(&ray);
                for a in 0..3 {
                    let neg = rb.inv_dir[a].is_sign_negative();
                    let want_near = if neg { a + 3 } else { a };
                    assert_eq!(rb.near[a], want_near, "({x}, {y}, {z}) axis {a}");
                    assert_eq!(rb.far[a], if neg { a } else { a + 3 });
                }
            }
        }
    }
}

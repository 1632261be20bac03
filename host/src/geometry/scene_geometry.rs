//! The scene's geometry as one object: every shape in world space, one BVH over all of them,
//! and per-object area and sampling data for area lights.
//!
//! The scene builder describes each object as a [`ShapeDesc`] (shape in object space plus a
//! [`Transform`]) and calls [`Geometry::build`]. Transforms are baked in at build time (meshes
//! and quads are transformed vertex by vertex, spheres keep their analytic form and therefore
//! need a similarity transform), so rays are traced in world space with no per-object
//! instancing. Object `i` of the input is `object == i` in every [`Hit`] and sampling call.

use glam::{Vec2, Vec3A};
use rayon::prelude::*;
use std::sync::OnceLock;

use super::bvh::{Bvh, BvhStatistics, NodeLayout, TraversalKernel, VisitCounts};
use super::huge_pages::HugePageBuf;
use super::leaf_triangles::{LeafTriangles, SlotTriangles};
use super::prefetch::prefetch_line;
use super::quad::Quad;
use super::sphere::Sphere;
use super::triangle::{
    barycentric_point, dominant_axis, geometric_normal, intersect_triangle_axis,
    sample_uniform_barycentrics, triangle_area, WatertightRay,
};
use super::{Aabb, GeometryError, Ray, Transform, TriangleMesh};

/// A shape in its own (object) space.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// A triangle mesh (e.g. from [`super::load_obj`] or [`super::load_ply`]).
    Mesh(TriangleMesh),
    /// An analytic sphere.
    Sphere {
        /// Centre (object units).
        center: Vec3A,
        /// Radius (object units, > 0).
        radius: f32,
    },
    /// A parallelogram `corner + s·edge0 + t·edge1`, front face along `edge0 × edge1`.
    Quad {
        /// One corner (object units).
        corner: Vec3A,
        /// First edge from the corner.
        edge0: Vec3A,
        /// Second edge from the corner.
        edge1: Vec3A,
    },
}

/// One scene object: a shape and the transform that places it in the world.
#[derive(Clone, Debug, PartialEq)]
pub struct ShapeDesc {
    /// The shape in object space.
    pub shape: Shape,
    /// Object-to-world transform.
    pub transform: Transform,
}

/// A shape after its transform has been applied.
#[derive(Clone, Debug, PartialEq)]
pub enum WorldShape {
    /// World-space mesh (normals transformed by the inverse transpose, winding kept outward).
    Mesh(TriangleMesh),
    /// World-space sphere.
    Sphere(Sphere),
    /// World-space quad.
    Quad(Quad),
}

/// What a ray hit. All vectors are in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Ray parameter (units of `ray.dir`).
    pub t: f32,
    /// Hit point, computed on the surface (not as `o + t·d`).
    pub point: Vec3A,
    /// Conservative per-axis bound on the point's distance from the true surface; pass it to
    /// [`super::spawn_ray`].
    pub point_error: Vec3A,
    /// Unit geometric normal, facing where the winding (meshes, quads) or the outside
    /// (spheres) says, regardless of which side the ray came from.
    pub geometric_normal: Vec3A,
    /// Unit shading normal: interpolated vertex normals if the mesh has them (not flipped to
    /// the geometric side), otherwise the geometric normal.
    pub shading_normal: Vec3A,
    /// Texture coordinates: interpolated from the mesh if it has uvs, else `(b1, b2)`
    /// barycentrics for triangles, `(s, t)` for quads, `(φ/2π, θ/π)` for spheres.
    pub uv: Vec2,
    /// Index of the object (position in the list given to [`Geometry::build`]).
    pub object: u32,
    /// Index of the primitive within its object: triangle index for meshes, 0 otherwise.
    pub primitive: u32,
}

/// A point sampled on a surface for light sampling.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceSample {
    /// The point.
    pub point: Vec3A,
    /// Per-axis error bound of the point (for [`super::spawn_ray_to`]).
    pub point_error: Vec3A,
    /// Unit geometric normal at the point (front side as for [`Hit::geometric_normal`]).
    pub normal: Vec3A,
    /// Texture coordinates as in [`Hit::uv`].
    pub uv: Vec2,
    /// Density of the sample: per unit area (1/units²) from [`Geometry::sample_area`], per
    /// steradian from [`Geometry::sample_solid_angle`].
    pub pdf: f32,
}

/// A point sampled by solid angle ([`Geometry::sample_towards`]) with the way to it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SampleTowards {
    /// The sample, `pdf` per steradian.
    pub sample: SurfaceSample,
    /// `sample.point − reference` (scene units).
    pub d: Vec3A,
    /// `|d|`.
    pub dist: f32,
}

/// Per-object data kept after the build.
#[derive(Clone, Debug)]
struct Object {
    shape: WorldShape,
    area: f32,
    /// Meshes: cumulative triangle areas normalised to end at 1 (for sampling by area).
    cdf: Vec<f32>,
    /// Meshes: each triangle's [`geometric_normal`] (the same values as computing it each
    /// time, which in f64 costs about 45 instructions a hit or light sample). Made with the
    /// BVH for meshes of at most [`CACHED_NORMALS_MAX_TRIANGLES`] (16 bytes a triangle), for a
    /// larger one at its first light sample if it emits; otherwise a hit computes it.
    normals: OnceLock<Vec<Vec3A>>,
}

/// A BVH leaf entry: an object and a primitive inside it.
#[derive(Clone, Copy, Debug)]
struct Primitive {
    object: u32,
    index: u32,
}

impl Primitive {
    /// The primitive at `input` in the BVH's input, where `starts` holds each object's first
    /// input index (objects in order, their primitives one after another; an object without
    /// primitives starts where the next one does).
    fn of(starts: &[u32], input: u32) -> Primitive {
        let object = starts.partition_point(|&s| s <= input) - 1;
        Primitive {
            object: object as u32,
            index: input - starts[object],
        }
    }
}

/// The closest candidate found during traversal; surface data is computed only for the winner.
#[derive(Clone, Copy)]
enum Candidate {
    /// A mesh triangle or quad half found through its leaf's lanes: its lane (see
    /// [`LeafTriangles::slot_of_lane`]) and barycentrics.
    Slot {
        lane: u32,
        /// The leaf's lanes, `first..first + n`, where its vertices are read again.
        first: u32,
        n: u32,
        b: [f32; 3],
    },
    Triangle {
        prim: Primitive,
        b: [f32; 3],
    },
    Quad {
        prim: Primitive,
        half: usize,
        b: [f32; 3],
    },
    Sphere {
        prim: Primitive,
    },
}

/// All scene geometry with its BVH. Immutable after [`Geometry::build`]; `Sync`, so threads
/// share one instance.
#[derive(Clone, Debug)]
pub struct Geometry {
    objects: Vec<Object>,
    /// The leaves' triangles, transposed leaf by leaf for the four-lane test (36 bytes per
    /// triangle; `docs/performance.md`, "Transposed leaves"). Which object and primitive a
    /// slot is lives apart (`prims`), read only for the hit kept.
    tris: LeafTriangles,
    /// Object and primitive of every leaf slot, in BVH leaf order (read once per hit).
    prims: HugePageBuf<Primitive>,
    bvh: Bvh,
}

impl Geometry {
    /// Applies each object's transform, validates the shapes and builds one BVH over every
    /// triangle, sphere and quad. Errors name the object index and what is wrong (invalid
    /// mesh, non-positive radius, sphere under a non-similarity transform, degenerate quad).
    pub fn build(objects: Vec<ShapeDesc>) -> Result<Geometry, GeometryError> {
        Self::build_with_node_layout(objects, NodeLayout::Auto)
    }

    /// [`Geometry::build`] with a chosen BVH node layout (benchmarks compare them; closest
    /// hits are the same, see [`NodeLayout`]).
    pub fn build_with_node_layout(
        objects: Vec<ShapeDesc>,
        layout: NodeLayout,
    ) -> Result<Geometry, GeometryError> {
        let mut built = Vec::with_capacity(objects.len());
        for (i, desc) in objects.into_iter().enumerate() {
            built.push(
                build_object(desc)
                    .map_err(|message| GeometryError::InvalidObject { object: i, message })?,
            );
        }
        if built.len() > u32::MAX as usize {
            return Err(GeometryError::InvalidObject {
                object: built.len(),
                message: "more than 2³² objects".into(),
            });
        }
        // Each object's first index in the BVH's input: a slot's object and primitive follow
        // from its input index (`Primitive::of`), so no per-primitive list is made.
        let mut starts = Vec::with_capacity(built.len());
        let mut bounds = Vec::new();
        for obj in &built {
            starts.push(bounds.len() as u32);
            match &obj.shape {
                WorldShape::Mesh(m) => {
                    // In parallel, in order (the build is the same for any thread count).
                    bounds.par_extend((0..m.indices.len()).into_par_iter().map(|t| {
                        let [a, b, c] = m.triangle(t);
                        Aabb::from_point(a).grow(b).grow(c)
                    }));
                }
                WorldShape::Sphere(s) => {
                    let r = Vec3A::splat(s.radius);
                    // Widen by a relative ULP so the f32 box surely holds the f64 sphere.
                    let slack = (s.center.abs() + r) * super::float_error::gamma(2);
                    bounds.push(Aabb {
                        min: s.center - r - slack,
                        max: s.center + r + slack,
                    });
                }
                WorldShape::Quad(q) => {
                    let v = q.vertices;
                    bounds.push(Aabb::from_point(v[0]).grow(v[1]).grow(v[2]).grow(v[3]));
                }
            }
        }
        // Merged leaves pay only where every primitive is a triangle (see
        // `Bvh::build_with_options`): the caustic's three quads and sphere in one leaf cost its
        // BDPT 7.6% more instructions.
        let triangles_only = built.iter().all(|o| matches!(o.shape, WorldShape::Mesh(_)));
        // The meshes' area CDFs end in a running sum in order (serial): computed beside the
        // BVH build, which keeps the other thread busy meanwhile. The build takes the boxes:
        // its primitive references are written over them (no new buffer to fault in).
        let (bvh, ()) = rayon::join(
            move || Bvh::build_owned(bounds, layout, triangles_only),
            || {
                built.par_iter_mut().for_each(|obj| {
                    if let WorldShape::Mesh(m) = &obj.shape {
                        (obj.area, obj.cdf) = mesh_area_cdf(m);
                        if m.indices.len() <= CACHED_NORMALS_MAX_TRIANGLES {
                            let _ = obj.normals.set(triangle_normals(m));
                        }
                    }
                });
            },
        );
        let order = bvh.order_ref();
        let prims = HugePageBuf::from_fn_par(order.len(), |s| Primitive::of(&starts, order[s]));
        let has_quads = built.iter().any(|o| matches!(o.shape, WorldShape::Quad(_)));
        let tris = LeafTriangles::build_lanes(prims.len(), &bvh.leaves(), has_quads, |slot| {
            let prim = prims[slot as usize];
            match &built[prim.object as usize].shape {
                WorldShape::Mesh(m) => SlotTriangles::One(m.triangle(prim.index as usize)),
                // The halves in the order `test_object` tries them.
                // (A quad with a non-finite corner keeps the scalar test and its NaN rules.)
                WorldShape::Quad(q) if q.vertices.iter().all(|v| v.is_finite()) => {
                    SlotTriangles::Two(q.triangle(0), q.triangle(1))
                }
                WorldShape::Quad(_) => SlotTriangles::Other,
                WorldShape::Sphere(_) => SlotTriangles::Other,
            }
        });
        Ok(Geometry {
            objects: built,
            tris,
            prims,
            bvh,
        })
    }

    /// Number of objects.
    pub fn object_count(&self) -> usize {
        self.objects.len()
    }

    /// Number of BVH primitives (triangles + spheres + quads).
    pub fn primitive_count(&self) -> usize {
        self.prims.len()
    }

    /// The world-space shape of `object`, if it exists.
    pub fn shape(&self, object: u32) -> Option<&WorldShape> {
        self.objects.get(object as usize).map(|o| &o.shape)
    }

    /// Surface area of `object` (world units²; 0 for unknown objects).
    pub fn object_area(&self, object: u32) -> f32 {
        self.objects.get(object as usize).map_or(0.0, |o| o.area)
    }

    /// World bounds of everything.
    pub fn bounds(&self) -> Aabb {
        self.bvh.bounds()
    }

    /// Bytes held by the BVH nodes and the leaf records (with their copies of triangle
    /// vertices, and every slot's object and primitive), not the meshes.
    pub fn bvh_memory_bytes(&self) -> usize {
        self.bvh.memory_bytes()
            + self.tris.memory_bytes()
            + self.prims.len() * std::mem::size_of::<Primitive>()
    }

    /// The BVH's node layout ([`NodeLayout::Float`] or [`NodeLayout::Quantised`]).
    pub fn node_layout(&self) -> NodeLayout {
        self.bvh.layout()
    }

    /// The BVH's box-test kernel (AVX2 where the CPU has it).
    pub fn traversal_kernel(&self) -> TraversalKernel {
        self.bvh.kernel()
    }

    /// Chooses the BVH's box-test kernel (for benchmarks comparing them; hits are identical).
    pub fn set_traversal_kernel(&mut self, kernel: TraversalKernel) {
        self.bvh.set_kernel(kernel);
    }

    /// The BVH's node and leaf counts and surface-area costs (for comparisons with Embree's
    /// build report).
    pub fn bvh_statistics(&self) -> BvhStatistics {
        self.bvh.statistics()
    }

    /// What a closest-hit [`Geometry::intersect`] (or with `any_hit` an
    /// [`Geometry::occluded`]) query of this ray visits: wide nodes, leaves and primitives
    /// (a plain re-run of the traversal with counters; statistics only).
    pub fn count_visits(&self, ray: &Ray, t_max: f32, any_hit: bool) -> VisitCounts {
        let wr = WatertightRay::new(ray);
        self.bvh
            .count_visits(ray, t_max, any_hit, |first, count, t_max| {
                match wr.dominant_axis() {
                    0 => self.test_leaf::<0>(ray, &wr, first, count, t_max, any_hit),
                    1 => self.test_leaf::<1>(ray, &wr, first, count, t_max, any_hit),
                    _ => self.test_leaf::<2>(ray, &wr, first, count, t_max, any_hit),
                }
                .map(|(t, _)| t)
            })
    }

    /// Closest hit with `0 < t < t_max`, or `None`.
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        // One dispatch on the ray's dominant axis, then the shear and every triangle test
        // have it fixed.
        match dominant_axis(ray.dir) {
            0 => self.intersect_axis::<0>(ray, &WatertightRay::for_axis::<0>(ray), t_max),
            1 => self.intersect_axis::<1>(ray, &WatertightRay::for_axis::<1>(ray), t_max),
            _ => self.intersect_axis::<2>(ray, &WatertightRay::for_axis::<2>(ray), t_max),
        }
    }

    /// Whether anything is hit with `0 < t < t_max` (any-hit traversal; for shadow rays).
    pub fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        match dominant_axis(ray.dir) {
            0 => self.occluded_axis::<0>(ray, &WatertightRay::for_axis::<0>(ray), t_max),
            1 => self.occluded_axis::<1>(ray, &WatertightRay::for_axis::<1>(ray), t_max),
            _ => self.occluded_axis::<2>(ray, &WatertightRay::for_axis::<2>(ray), t_max),
        }
    }

    #[inline]
    fn intersect_axis<const KZ: usize>(
        &self,
        ray: &Ray,
        wr: &WatertightRay,
        t_max: f32,
    ) -> Option<Hit> {
        let mut best: Option<Candidate> = None;
        let t = self.bvh.traverse_leaves(
            ray,
            t_max,
            false,
            #[inline(always)]
            |first, count, t_max| {
                let (t, cand) = self.test_leaf::<KZ>(ray, wr, first, count, t_max, false)?;
                if let Candidate::Slot { lane: slot, .. } = cand {
                    // `make_hit` reads the slot's primitive once the search ends; in large
                    // scenes that entry is a cache miss, which now overlaps the rest of the
                    // search. (The lane is the slot in scenes of meshes only; with quads it
                    // is a nearby index, and a prefetch is only a hint.)
                    prefetch_line(self.prims.as_ptr().wrapping_add(slot as usize));
                }
                best = Some(cand);
                Some(t)
            },
        )?;
        Some(self.make_hit(ray, t, best?))
    }

    #[inline]
    fn occluded_axis<const KZ: usize>(&self, ray: &Ray, wr: &WatertightRay, t_max: f32) -> bool {
        self.bvh
            .traverse_leaves(
                ray,
                t_max,
                true,
                #[inline(always)]
                |first, count, t_max| {
                    self.test_leaf::<KZ>(ray, wr, first, count, t_max, true)
                        .map(|(t, _)| t)
                },
            )
            .is_some()
    }

    /// Tests the leaf `first..first + count` (leaf order): its mesh triangles and quad halves
    /// in four-lane passes ([`LeafTriangles::test`], inlined into the traversal loop), a leaf
    /// with a sphere primitive by primitive through a call. `KZ` is the ray's dominant axis (see
    /// [`intersect_triangle_axis`]). The closest hit below `t_max` (with `any_hit`, the first).
    #[inline(always)]
    fn test_leaf<const KZ: usize>(
        &self,
        ray: &Ray,
        wr: &WatertightRay,
        first: u32,
        count: u32,
        t_max: f32,
        any_hit: bool,
    ) -> Option<(f32, Candidate)> {
        let (lane, lanes) = self.tris.lanes(first, count);
        if self.tris.is_other(lane) {
            return self.test_objects::<KZ>(ray, wr, first, count, t_max, any_hit);
        }
        let h = self.tris.test::<KZ>(ray, wr, lane, lanes, t_max, any_hit)?;
        Some((
            h.hit.t,
            Candidate::Slot {
                lane: h.lane,
                first: lane,
                n: lanes,
                b: [h.hit.b0, h.hit.b1, h.hit.b2],
            },
        ))
    }

    /// A leaf holding spheres or quads: each primitive through its object, in slot order,
    /// the search shrinking to each hit.
    #[inline(never)]
    fn test_objects<const KZ: usize>(
        &self,
        ray: &Ray,
        wr: &WatertightRay,
        first: u32,
        count: u32,
        mut t_max: f32,
        any_hit: bool,
    ) -> Option<(f32, Candidate)> {
        let mut best = None;
        for slot in first..first + count {
            let prim = *self.prims.get(slot as usize)?;
            if let Some((t, cand)) = self.test_object::<KZ>(ray, wr, prim, t_max) {
                t_max = t;
                best = Some((t, cand));
                if any_hit {
                    break;
                }
            }
        }
        best
    }

    /// One primitive tested through its object: a sphere, a quad or a mesh triangle (of a
    /// leaf that also holds spheres or quads). Inlined into [`Geometry::test_objects`], the
    /// one call per such leaf.
    #[inline(always)]
    fn test_object<const KZ: usize>(
        &self,
        ray: &Ray,
        wr: &WatertightRay,
        prim: Primitive,
        t_max: f32,
    ) -> Option<(f32, Candidate)> {
        match &self.objects[prim.object as usize].shape {
            WorldShape::Mesh(m) => {
                let [a, b, c] = m.triangle(prim.index as usize);
                let h = intersect_triangle_axis::<KZ>(ray, wr, t_max, a, b, c)?;
                Some((
                    h.t,
                    Candidate::Triangle {
                        prim,
                        b: [h.b0, h.b1, h.b2],
                    },
                ))
            }
            WorldShape::Quad(q) => {
                let mut result = None;
                let mut t_max = t_max;
                for half in 0..2 {
                    let [a, b, c] = q.triangle(half);
                    if let Some(h) = intersect_triangle_axis::<KZ>(ray, wr, t_max, a, b, c) {
                        t_max = h.t;
                        result = Some((
                            h.t,
                            Candidate::Quad {
                                prim,
                                half,
                                b: [h.b0, h.b1, h.b2],
                            },
                        ));
                    }
                }
                result
            }
            WorldShape::Sphere(s) => {
                let t = s.intersect_t(ray, t_max)?;
                Some((t, Candidate::Sphere { prim }))
            }
        }
    }

    fn make_hit(&self, ray: &Ray, t: f32, cand: Candidate) -> Hit {
        match cand {
            Candidate::Slot { lane, first, n, b } => {
                let (slot, half) = self.tris.slot_of_lane(lane);
                let prim = self.prims[slot as usize];
                // Only a scene with quads has two-lane slots (meshes only: no shape read).
                if self.tris.has_quads() {
                    if let WorldShape::Quad(q) = &self.objects[prim.object as usize].shape {
                        return quad_hit(t, prim, q, half, b);
                    }
                }
                // The vertices from the leaf just tested (in cache; the mesh's index triple
                // and positions are three more scattered reads in large scenes), the same
                // floats as the mesh's.
                let p = self
                    .tris
                    .vertices(first as usize, n as usize, (lane - first) as usize);
                self.mesh_hit(t, prim, p, b)
            }
            Candidate::Triangle { prim, b } => {
                let WorldShape::Mesh(m) = &self.objects[prim.object as usize].shape else {
                    unreachable!("triangle candidate always comes from a mesh")
                };
                self.mesh_hit(t, prim, m.triangle(prim.index as usize), b)
            }
            Candidate::Quad { prim, half, b } => {
                let WorldShape::Quad(q) = &self.objects[prim.object as usize].shape else {
                    unreachable!("quad candidate always comes from a quad")
                };
                quad_hit(t, prim, q, half, b)
            }
            Candidate::Sphere { prim } => {
                let WorldShape::Sphere(s) = &self.objects[prim.object as usize].shape else {
                    unreachable!("sphere candidate always comes from a sphere")
                };
                let sp = s.surface_at(ray, t);
                Hit {
                    t,
                    point: sp.point,
                    point_error: sp.error,
                    geometric_normal: sp.normal,
                    shading_normal: sp.normal,
                    uv: sp.uv,
                    object: prim.object,
                    primitive: 0,
                }
            }
        }
    }

    /// The hit on mesh triangle `prim` (vertices `p0, p1, p2`) with barycentrics `b`; the
    /// mesh's index triple is read only for its vertex normals or uvs.
    #[inline]
    fn mesh_hit(&self, t: f32, prim: Primitive, [p0, p1, p2]: [Vec3A; 3], b: [f32; 3]) -> Hit {
        let WorldShape::Mesh(m) = &self.objects[prim.object as usize].shape else {
            unreachable!("triangle candidate always comes from a mesh")
        };
        let ti = prim.index as usize;
        let (point, point_error) = barycentric_point(b[0], b[1], b[2], p0, p1, p2);
        // `p0, p1, p2` are the mesh's own floats, so the kept normal is this triangle's.
        let ng = match self.objects[prim.object as usize].normals.get() {
            Some(ns) => ns[ti],
            None => geometric_normal(p0, p1, p2),
        };
        let ns = m.normals.as_ref().map_or(ng, |ns| {
            let idx = m.indices[ti];
            let n = ns[idx[0] as usize] * b[0]
                + ns[idx[1] as usize] * b[1]
                + ns[idx[2] as usize] * b[2];
            let n = n.normalize_or_zero();
            if n == Vec3A::ZERO {
                ng
            } else {
                n
            }
        });
        let uv = m.uvs.as_ref().map_or(Vec2::new(b[1], b[2]), |uv| {
            let idx = m.indices[ti];
            uv[idx[0] as usize] * b[0] + uv[idx[1] as usize] * b[1] + uv[idx[2] as usize] * b[2]
        });
        Hit {
            t,
            point,
            point_error,
            geometric_normal: ng,
            shading_normal: ns,
            uv,
            object: prim.object,
            primitive: prim.index,
        }
    }

    /// ∂p/∂(u, v) and ∂n/∂(u, v) of the shading normal at `point` on primitive `primitive`
    /// of `object` (as in a [`Hit`]), in the shape's own parameters (see
    /// [`super::SurfaceDerivatives`]). `None` for unknown objects and degenerate triangles.
    pub fn derivatives(
        &self,
        object: u32,
        primitive: u32,
        point: Vec3A,
    ) -> Option<super::SurfaceDerivatives> {
        match self.shape(object)? {
            WorldShape::Sphere(s) => Some(s.derivatives(point)),
            WorldShape::Quad(q) => Some(q.derivatives()),
            WorldShape::Mesh(m) => {
                if primitive as usize >= m.indices.len() {
                    return None;
                }
                m.derivatives(primitive as usize, point)
            }
        }
    }

    /// Samples a point on `object` uniformly by area from `u ∈ [0,1)²` (`u.x` also picks the
    /// triangle of a mesh, in proportion to its area). `pdf` is `1/area` per unit area.
    /// `None` for unknown or zero-area objects.
    pub fn sample_area(&self, object: u32, u: Vec2) -> Option<SurfaceSample> {
        let obj = self.objects.get(object as usize)?;
        if !(obj.area > 0.0) {
            return None;
        }
        let pdf = 1.0 / obj.area;
        match &obj.shape {
            WorldShape::Sphere(s) => {
                let smp = s.sample_area(u);
                Some(SurfaceSample {
                    point: smp.surface.point,
                    point_error: smp.surface.error,
                    normal: smp.surface.normal,
                    uv: smp.surface.uv,
                    pdf,
                })
            }
            WorldShape::Quad(q) => {
                // The parallelogram's chart corner + s·edge0 + t·edge1 at (s, t) = u: uniform
                // by area, and the same u for the same point from every receiver
                // (`Self::sample_coords`).
                let (s, t) = (u.x.clamp(0.0, 1.0), u.y.clamp(0.0, 1.0));
                let (point, point_error) = q.point(s, t);
                Some(SurfaceSample {
                    point,
                    point_error,
                    normal: q.normal,
                    uv: Vec2::new(s, t),
                    pdf,
                })
            }
            WorldShape::Mesh(m) => {
                // First triangle whose cumulative area exceeds u.x; reuse the fraction within it.
                let i = obj
                    .cdf
                    .partition_point(|&c| c <= u.x)
                    .min(obj.cdf.len() - 1);
                let lo = if i == 0 { 0.0 } else { obj.cdf[i - 1] };
                let width = obj.cdf[i] - lo;
                let ux = if width > 0.0 {
                    ((u.x - lo) / width).clamp(0.0, 1.0)
                } else {
                    0.5
                };
                let [p0, p1, p2] = m.triangle(i);
                let (b0, b1, b2) = sample_uniform_barycentrics(Vec2::new(ux, u.y));
                let (point, point_error) = barycentric_point(b0, b1, b2, p0, p1, p2);
                let idx = m.indices[i];
                let uv = m.uvs.as_ref().map_or(Vec2::new(b1, b2), |uv| {
                    uv[idx[0] as usize] * b0 + uv[idx[1] as usize] * b1 + uv[idx[2] as usize] * b2
                });
                let normals = obj.normals.get_or_init(|| triangle_normals(m));
                Some(SurfaceSample {
                    point,
                    point_error,
                    normal: normals[i],
                    uv,
                    pdf,
                })
            }
        }
    }

    /// The numbers `u ∈ [0, 1]²` from which [`Self::sample_area`] (and so
    /// [`Self::sample_towards`], whatever the receiver) turns into the point `p` of `object`:
    /// for quads, the parallelogram's own chart `(s, t)`; for meshes of at most
    /// [`COORDS_MAX_TRIANGLES`] triangles (a lamp's panel, a converted rectangle), the inverse
    /// of the area-CDF choice and the square-root barycentric map, in the triangle nearest
    /// `p` (a search over the triangles, which is why larger meshes answer `None`). `None`
    /// for spheres (sampled by cone from outside).
    pub fn sample_coords(&self, object: u32, p: Vec3A) -> Option<Vec2> {
        let obj = self.objects.get(object as usize)?;
        match &obj.shape {
            WorldShape::Quad(q) => Some(q.coords(p)),
            WorldShape::Mesh(m) if m.indices.len() <= COORDS_MAX_TRIANGLES => {
                let (i, b0, b1) = nearest_triangle(m, p)?;
                let lo = if i == 0 { 0.0 } else { obj.cdf[i - 1] };
                let width = obj.cdf[i] - lo;
                // sample_uniform_barycentrics: b0 = 1 − √x, b1 = y·√x.
                let su = (1.0 - b0).clamp(0.0, 1.0);
                let y = if su > 0.0 {
                    (b1 / su).clamp(0.0, 1.0)
                } else {
                    0.5
                };
                Some(Vec2::new((lo + su * su * width).clamp(0.0, 1.0), y))
            }
            _ => None,
        }
    }

    /// Density per unit area of [`Self::sample_area`] on `object` (`1/area`; 0 if none).
    pub fn pdf_area(&self, object: u32) -> f32 {
        let a = self.object_area(object);
        if a > 0.0 {
            1.0 / a
        } else {
            0.0
        }
    }

    /// Samples a point on `object` as seen from `reference`, with `pdf` per steradian of
    /// direction at `reference`. Spheres seen from outside sample the subtended cone exactly;
    /// everything else samples by area and converts (`pdf_A · d² / |cos θ_light|`). `None` if the
    /// sample is unusable (zero area, point coincides with `reference`, grazing angle).
    pub fn sample_solid_angle(
        &self,
        object: u32,
        reference: Vec3A,
        u: Vec2,
    ) -> Option<SurfaceSample> {
        self.sample_towards(object, reference, u).map(|t| t.sample)
    }

    /// [`Self::sample_solid_angle`] with the vector from `reference` to the sampled point and
    /// its length, which the density's conversion computes anyway (a light sample needs
    /// both for its direction; the same floats as computing them again).
    #[inline]
    pub fn sample_towards(&self, object: u32, reference: Vec3A, u: Vec2) -> Option<SampleTowards> {
        if let Some(WorldShape::Sphere(s)) = self.shape(object) {
            if let Some(smp) = s.sample_solid_angle(reference, u) {
                let d = smp.surface.point - reference;
                return Some(SampleTowards {
                    sample: SurfaceSample {
                        point: smp.surface.point,
                        point_error: smp.surface.error,
                        normal: smp.surface.normal,
                        uv: smp.surface.uv,
                        pdf: smp.pdf,
                    },
                    d,
                    dist: d.length(),
                });
            }
        }
        let mut smp = self.sample_area(object, u)?;
        let (pdf, d, dist) = area_to_solid_angle(smp.pdf, reference, smp.point, smp.normal)?;
        smp.pdf = pdf;
        Some(SampleTowards {
            sample: smp,
            d,
            dist,
        })
    }

    /// Density per steradian with which [`Self::sample_solid_angle`] would pick `point`
    /// (normal `normal`) on `object` from `reference`; for MIS weights when a BSDF-sampled ray
    /// hits an area light. 0 when that sample could not have been produced.
    pub fn pdf_solid_angle(
        &self,
        object: u32,
        reference: Vec3A,
        point: Vec3A,
        normal: Vec3A,
    ) -> f32 {
        if let Some(WorldShape::Sphere(s)) = self.shape(object) {
            if let Some(pdf) = s.pdf_solid_angle(reference) {
                return pdf;
            }
        }
        area_to_solid_angle(self.pdf_area(object), reference, point, normal).map_or(0.0, |c| c.0)
    }
}

/// Largest mesh whose points [`Geometry::sample_coords`] finds (by a search over its
/// triangles).
pub const COORDS_MAX_TRIANGLES: usize = 64;

/// The triangle of `m` nearest `p` (in its plane, inside or nearest the edges) and the
/// barycentrics `(b0, b1)` of `p` projected into it, clamped to the triangle.
fn nearest_triangle(m: &super::TriangleMesh, p: Vec3A) -> Option<(usize, f32, f32)> {
    let mut best: Option<(f32, usize, f32, f32)> = None;
    for i in 0..m.indices.len() {
        let [p0, p1, p2] = m.triangle(i);
        let (e1, e2, r) = (p1 - p0, p2 - p0, p - p0);
        let n = e1.cross(e2);
        let nn = n.length_squared();
        if !(nn > 0.0) || !nn.is_finite() {
            continue;
        }
        let b1 = r.cross(e2).dot(n) / nn;
        let b2 = e1.cross(r).dot(n) / nn;
        let b0 = 1.0 - b1 - b2;
        // Distance off the plane and outside the edges, relative to the triangle's size.
        let outside = (-b0).max(-b1).max(-b2).max(0.0);
        let score = r.dot(n).abs() / nn.sqrt() / (e1.length() + e2.length()) + outside;
        if best.is_none_or(|b| score < b.0) {
            let (b1, b2) = (b1.max(0.0), b2.max(0.0));
            let sum = (b1 + b2).max(1.0);
            best = Some((score, i, 1.0 - (b1 + b2) / sum, b1 / sum));
        }
    }
    best.map(|(_, i, b0, b1)| (i, b0, b1))
}

/// The hit on half `half` of quad `q` (primitive `prim`) with barycentrics `b`.
#[inline(always)]
fn quad_hit(t: f32, prim: Primitive, q: &Quad, half: usize, b: [f32; 3]) -> Hit {
    let [p0, p1, p2] = q.triangle(half);
    let (point, point_error) = barycentric_point(b[0], b[1], b[2], p0, p1, p2);
    Hit {
        t,
        point,
        point_error,
        geometric_normal: q.normal,
        shading_normal: q.normal,
        uv: Quad::uv(half, b[1], b[2]),
        object: prim.object,
        primitive: 0,
    }
}

/// Meshes of at most this many triangles keep their triangles' geometric normals from the
/// build (at most 1 MiB each); larger ones compute a hit's normal (the closest-hit saving is
/// worth less than the memory and cache lines there).
pub const CACHED_NORMALS_MAX_TRIANGLES: usize = 65_536;

/// Each triangle's [`geometric_normal`], in order.
fn triangle_normals(m: &TriangleMesh) -> Vec<Vec3A> {
    (0..m.indices.len())
        .map(|t| {
            let [a, b, c] = m.triangle(t);
            geometric_normal(a, b, c)
        })
        .collect()
}

/// `pdf_area · d² / |cos θ|` (1/sr) with `d = point − reference` and `|d|` (a light sample
/// needs both for its direction), or `None` if the distance or the cosine is zero.
#[inline]
fn area_to_solid_angle(
    pdf_area: f32,
    reference: Vec3A,
    point: Vec3A,
    normal: Vec3A,
) -> Option<(f32, Vec3A, f32)> {
    let d = point - reference;
    let dist2 = d.length_squared();
    if !(dist2 > 0.0) || !(pdf_area > 0.0) {
        return None;
    }
    let dist = dist2.sqrt();
    let cos = normal.dot(d).abs() / dist;
    if !(cos > 0.0) {
        return None;
    }
    Some((pdf_area * dist2 / cos, d, dist))
}

/// A mesh's total area and its triangles' cumulative areas normalised to end at 1 (empty
/// for a mesh of zero area). Areas in parallel (the f64 cross product and square root are the
/// cost), then the running sum in order, so the CDF is the same for any thread count.
fn mesh_area_cdf(mesh: &TriangleMesh) -> (f32, Vec<f32>) {
    let areas: Vec<f32> = (0..mesh.indices.len())
        .into_par_iter()
        .map(|t| {
            let [a, b, c] = mesh.triangle(t);
            triangle_area(a, b, c)
        })
        .collect();
    let mut cdf = Vec::with_capacity(mesh.indices.len());
    let mut total = 0.0f64;
    for &area in &areas {
        total += area as f64;
        cdf.push(total);
    }
    let cdf = if total > 0.0 {
        cdf.par_iter().map(|&c| (c / total) as f32).collect()
    } else {
        Vec::new()
    };
    (total as f32, cdf)
}

fn build_object(desc: ShapeDesc) -> Result<Object, String> {
    let xf = desc.transform;
    match desc.shape {
        Shape::Mesh(mut mesh) => {
            mesh.validate().map_err(|e| e.to_string())?;
            if !xf.is_identity() {
                // In parallel (elementwise, the same values for any thread count).
                mesh.positions
                    .par_iter_mut()
                    .for_each(|p| *p = xf.point(*p));
                if let Some(ns) = &mut mesh.normals {
                    ns.par_iter_mut().for_each(|n| *n = xf.normal(*n));
                }
                if xf.flips_handedness() {
                    // Keep the winding's front side the same physical side after a mirror.
                    mesh.indices.par_iter_mut().for_each(|t| t.swap(1, 2));
                }
                if let Some(i) = mesh.positions.iter().position(|p| !p.is_finite()) {
                    return Err(format!("vertex {i} is not finite after the transform"));
                }
            }
            // The area and its CDF come later, beside the BVH build (`mesh_area_cdf`).
            Ok(Object {
                shape: WorldShape::Mesh(mesh),
                area: 0.0,
                cdf: Vec::new(),
                normals: OnceLock::new(),
            })
        }
        Shape::Sphere { center, radius } => {
            if !(radius > 0.0) || !radius.is_finite() || !center.is_finite() {
                return Err(format!(
                    "sphere needs a finite centre and a positive radius, got {center} and {radius}"
                ));
            }
            let scale = xf.uniform_scale().ok_or_else(|| {
                "a sphere's transform must be rotation, uniform scale and translation only \
                 (use a mesh for ellipsoids)"
                    .to_string()
            })?;
            let sphere = Sphere {
                center: xf.point(center),
                radius: (radius as f64 * scale) as f32,
            };
            if !sphere.center.is_finite() || !(sphere.radius > 0.0) || !sphere.radius.is_finite() {
                return Err("sphere is degenerate after its transform".into());
            }
            Ok(Object {
                area: sphere.area(),
                shape: WorldShape::Sphere(sphere),
                cdf: Vec::new(),
                normals: OnceLock::new(),
            })
        }
        Shape::Quad {
            corner,
            edge0,
            edge1,
        } => {
            let c = xf.point(corner);
            let e0 = xf.vector(edge0);
            let e1 = xf.vector(edge1);
            let quad = Quad::new(c, e0, e1).ok_or_else(|| {
                format!("degenerate quad: edges {edge0} and {edge1} are parallel or zero")
            })?;
            Ok(Object {
                area: quad.area(),
                shape: WorldShape::Quad(quad),
                cdf: Vec::new(),
                normals: OnceLock::new(),
            })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Primitive;

    // A slot's object and primitive from its input index and the objects' starts are what
    // the per-primitive list (objects in order, each primitive's index within its object)
    // held, objects without primitives included.
    #[test]
    fn primitive_of_input_index_matches_the_list() {
        let counts = [0u32, 3, 1, 0, 0, 5, 1, 0, 2];
        let mut starts = Vec::new();
        let mut list = Vec::new();
        for (object, &n) in counts.iter().enumerate() {
            starts.push(list.len() as u32);
            list.extend((0..n).map(|index| (object as u32, index)));
        }
        for (i, &want) in list.iter().enumerate() {
            let p = Primitive::of(&starts, i as u32);
            assert_eq!((p.object, p.index), want, "input {i}");
        }
    }
}

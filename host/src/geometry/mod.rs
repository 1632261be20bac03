//! Geometry: rays, transforms, shapes, the BVH, robust ray offsets and mesh loaders.
//!
//! All geometry is single precision (`glam::Vec3A`) for speed. Robustness comes from error
//! bounds instead of epsilons:
//! - [`intersect_triangle`] is watertight (Woop, Benthin & Wald 2013): rays through shared
//!   edges and vertices of a closed mesh always hit one of the triangles, and a hit is only
//!   reported when its `t` is provably positive.
//! - Every [`Hit`] and [`SurfaceSample`] carries `point_error`, a conservative per-axis bound
//!   on the distance of the f32 point from the true surface (computed from barycentrics for
//!   triangles, by f64 re-projection for spheres).
//! - [`spawn_ray`] / [`spawn_ray_to`] move ray origins along the geometric normal just past
//!   that error box and round one ULP further (pbrt-v4's method). Because the bounds scale
//!   with coordinate magnitude, this holds from 1e-3 to 1e5 units and far from the origin
//!   (see `host/tests/geometry_self_intersection.rs`). See [`spawn`] for details.
//!
//! Entry point for the scene builder: [`Geometry::build`] with one [`ShapeDesc`] per object;
//! then [`Geometry::intersect`], [`Geometry::occluded`], [`Geometry::sample_area`] and
//! [`Geometry::sample_solid_angle`]. Meshes come from [`load_obj`] / [`load_ply`].

// `!(x > 0.0)` is used on purpose throughout: it also rejects NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod aabb;
pub mod bvh;
pub mod derivatives;
pub mod error;
pub mod float_error;
pub mod generate;
mod huge_pages;
mod leaf_triangles;
pub mod mesh;
pub mod obj;
pub mod ply;
pub mod polygon;
mod prefetch;
pub mod quad;
pub mod ray;
pub mod scene_geometry;
pub mod spawn;
pub mod sphere;
pub mod transform;
pub mod triangle;

pub use aabb::Aabb;
pub use bvh::{
    Bvh, BvhStatistics, NodeLayout, TraversalKernel, VisitCounts, QUANTISE_MIN_PRIMITIVES,
    WIDE_MERGE_MIN_PRIMITIVES,
};
pub use derivatives::SurfaceDerivatives;
pub use error::GeometryError;
pub use mesh::TriangleMesh;
pub use obj::{load_obj, parse_obj};
pub use ply::{load_ply, parse_ply};
pub use quad::Quad;
pub use ray::Ray;
pub use scene_geometry::{
    Geometry, Hit, SampleTowards, Shape, ShapeDesc, SurfaceSample, WorldShape, COORDS_MAX_TRIANGLES,
};
pub use spawn::{offset_ray_origin, spawn_ray, spawn_ray_to, CONNECTION_T_MAX};
pub use sphere::Sphere;
pub use transform::Transform;
pub use triangle::{barycentric_point, intersect_triangle, TriangleHit, WatertightRay};

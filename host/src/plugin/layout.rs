//! The host's record of a surface point seen as the plugin interface's, and back, without a
//! copy: extension v5 passes `ShadingContext` to plugins by reference as a `SurfaceF32`
//! (`spectrace_plugin_api::fast::QueryV5`). Both are `#[repr(C)]` with the same fields in the
//! same places (texture coordinates, then position, geometric and shading normal as 16-byte
//! vectors); the assertions below stop the build if either ever changes. Written by hand
//! because it is two pointer casts that a crate would not make safer than these assertions.
//!
//! The vectors' fourth lanes are the host's (glam keeps anything there); the interface says so
//! (`QueryV5`), and readers use `x, y, z` only.

use crate::material::ShadingContext;
use glam::{Vec2, Vec3A};
use spectrace_plugin_api::fast::{SurfaceF32, Vec4f};
use std::mem::{align_of, offset_of, size_of};

const _: () = {
    assert!(size_of::<ShadingContext>() == size_of::<SurfaceF32>());
    assert!(align_of::<ShadingContext>() == align_of::<SurfaceF32>());
    assert!(offset_of!(ShadingContext, uv) == offset_of!(SurfaceF32, uv));
    assert!(offset_of!(ShadingContext, p) == offset_of!(SurfaceF32, position));
    assert!(offset_of!(ShadingContext, ng) == offset_of!(SurfaceF32, geometric_normal));
    assert!(offset_of!(ShadingContext, ns) == offset_of!(SurfaceF32, shading_normal));
    assert!(size_of::<Vec2>() == size_of::<[f32; 2]>() && align_of::<Vec2>() <= 4);
    assert!(size_of::<Vec3A>() == size_of::<Vec4f>());
    assert!(align_of::<Vec3A>() == align_of::<Vec4f>());
};

/// `ctx` as the interface's surface record (the same memory).
#[inline]
pub fn as_surface(ctx: &ShadingContext) -> &SurfaceF32 {
    // SAFETY: same size, alignment and field offsets (asserted above); every field is plain
    // `f32`s (Vec2 is two, Vec3A four in one 16-byte register, all initialised), so every bit
    // pattern of one is a valid value of the other, and the lifetime is carried over.
    unsafe { &*(ctx as *const ShadingContext).cast::<SurfaceF32>() }
}

/// The interface's surface record as the host's (the same memory): what a plugin built from the
/// host's own code (the standard library) hands its materials.
#[inline]
pub fn as_shading_context(s: &SurfaceF32) -> &ShadingContext {
    // SAFETY: as for `as_surface`, the other way round.
    unsafe { &*(s as *const SurfaceF32).cast::<ShadingContext>() }
}

#[cfg(test)]
mod tests {
    use super::*;

    // The cast sees the same numbers in the same fields, both ways.
    #[test]
    fn the_surface_is_the_same_memory() {
        let ctx = ShadingContext::at(
            Vec3A::new(1.0, 2.0, 3.0),
            Vec3A::new(0.0, 1.0, 0.0),
            Vec3A::new(0.0, 0.0, 1.0),
            Vec2::new(0.25, 0.75),
        );
        let s = as_surface(&ctx);
        assert_eq!(s.uv, [0.25, 0.75]);
        assert_eq!([s.position.x, s.position.y, s.position.z], [1.0, 2.0, 3.0]);
        assert_eq!(s.geometric_normal.y, 1.0);
        assert_eq!(s.shading_normal.z, 1.0);
        assert_eq!(*as_shading_context(s), ctx);
    }
}

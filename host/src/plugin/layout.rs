//! The host's records seen as the plugin interface's, and back, without a copy: extension v5
//! passes `ShadingContext` to plugins by reference as a `SurfaceF32`
//! (`spectrace_plugin_api::fast::QueryV5`), extension v6 a light sample's receiver
//! (`LightSampleContext` as `ReceiverF32`) and lets a plugin light write its sample into the
//! host's `LightLiSample` (as `IncidentF32`). Each pair is `#[repr(C)]` with the same fields in
//! the same places (16-byte vectors, four-lane values, `f32`s); the assertions below stop the
//! build if either side ever changes. Written by hand because these are pointer casts that a
//! crate would not make safer than these assertions.
//!
//! The vectors' fourth lanes are the host's (glam keeps anything there); the interface says so
//! (`QueryV5`), and readers use `x, y, z` only.

use crate::light::{LightLiSample, LightSampleContext};
use crate::material::{BsdfSample, MaterialFlags, ShadingContext};
use crate::spectrum::{LaneMask, SampledSpectrum, SampledWavelengths};
use glam::{Vec2, Vec3A};
use spectrace_plugin_api::fast::{
    IncidentF32, LanesF32, ReceiverF32, ScatterF32, SurfaceF32, ValuesF32, Vec4f, WavelengthsF32,
};
use spectrace_plugin_api::Flags;
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

    assert!(size_of::<LightSampleContext>() == size_of::<ReceiverF32>());
    assert!(align_of::<LightSampleContext>() == align_of::<ReceiverF32>());
    assert!(offset_of!(LightSampleContext, p) == offset_of!(ReceiverF32, p));
    assert!(offset_of!(LightSampleContext, p_error) == offset_of!(ReceiverF32, p_error));
    assert!(offset_of!(LightSampleContext, n) == offset_of!(ReceiverF32, n));

    // A one-field tuple struct of four `f32`s: the same size and alignment leave the field at 0.
    assert!(size_of::<SampledSpectrum>() == size_of::<[f32; 4]>());
    assert!(align_of::<SampledSpectrum>() == align_of::<[f32; 4]>());
    assert!(size_of::<LightLiSample>() == size_of::<IncidentF32>());
    assert!(align_of::<LightLiSample>() == align_of::<IncidentF32>());
    assert!(offset_of!(LightLiSample, radiance) == offset_of!(IncidentF32, value));
    assert!(offset_of!(LightLiSample, wi) == offset_of!(IncidentF32, direction));
    assert!(offset_of!(LightLiSample, pdf) == offset_of!(IncidentF32, pdf));
    assert!(offset_of!(LightLiSample, p_light) == offset_of!(IncidentF32, point));
    assert!(offset_of!(LightLiSample, p_light_error) == offset_of!(IncidentF32, point_error));
    assert!(offset_of!(LightLiSample, n_light) == offset_of!(IncidentF32, normal));

    assert!(size_of::<ValuesF32>() == size_of::<glam::Vec4>());
    assert!(size_of::<MaterialFlags>() == size_of::<Flags>());
    assert!(size_of::<BsdfSample>() == size_of::<ScatterF32>());
    assert!(align_of::<BsdfSample>() == align_of::<ScatterF32>());
    assert!(offset_of!(BsdfSample, wi) == offset_of!(ScatterF32, wi));
    assert!(offset_of!(BsdfSample, f) == offset_of!(ScatterF32, value));
    assert!(offset_of!(BsdfSample, pdf) == offset_of!(ScatterF32, pdf));
    assert!(offset_of!(BsdfSample, flags) == offset_of!(ScatterF32, flags));
    assert!(offset_of!(BsdfSample, eta) == offset_of!(ScatterF32, eta));
};

// The wavelengths: `LanesF32`'s `live` is a `u32` whose low byte is the host's `LaneMask` (one
// byte, `#[repr(transparent)]`) on a little-endian machine; the three bytes after it are
// padding in `SampledWavelengths`.
const _: () = {
    assert!(size_of::<SampledWavelengths>() == size_of::<LanesF32>());
    assert!(align_of::<SampledWavelengths>() == align_of::<LanesF32>());
    assert!(offset_of!(SampledWavelengths, lambda) == offset_of!(LanesF32, nm));
    assert!(offset_of!(SampledWavelengths, pdf) == offset_of!(LanesF32, pdf));
    assert!(offset_of!(SampledWavelengths, lanes) == offset_of!(LanesF32, live));
    assert!(size_of::<LaneMask>() == 1);
};

// Extension v7's wavelengths: the host's record itself, the live bits one byte on both sides
// (padding after it on both).
const _: () = {
    assert!(size_of::<SampledWavelengths>() == size_of::<WavelengthsF32>());
    assert!(align_of::<SampledWavelengths>() == align_of::<WavelengthsF32>());
    assert!(offset_of!(SampledWavelengths, lambda) == offset_of!(WavelengthsF32, nm));
    assert!(offset_of!(SampledWavelengths, pdf) == offset_of!(WavelengthsF32, pdf));
    assert!(offset_of!(SampledWavelengths, lanes) == offset_of!(WavelengthsF32, live));
};

/// The host's wavelengths as extension v7's record (the same memory): what the host hands a v7
/// plugin material.
#[inline]
pub fn as_wavelengths_f32(l: &SampledWavelengths) -> &WavelengthsF32 {
    // SAFETY: same size, alignment and field offsets (asserted above); `lambda`/`nm` and `pdf`
    // are `f32`s on both sides, `lanes` (a one-byte `LaneMask`) is `live` (a `u8`), and the
    // padding after it is padding on both sides; the lifetime is carried over.
    unsafe { &*(l as *const SampledWavelengths).cast::<WavelengthsF32>() }
}

/// Extension v7's wavelengths as the host's (the same memory) when `live` holds only lane bits
/// (as every host's does; `None` otherwise, where the caller copies them instead): what the
/// standard library hands its materials.
#[inline]
pub fn as_wavelengths_v7(l: &WavelengthsF32) -> Option<&SampledWavelengths> {
    if l.live <= LaneMask::ALL.bits() {
        // SAFETY: as for `as_wavelengths_f32`, the other way round; `live` holds only lane
        // bits (checked just now), a valid `LaneMask`.
        Some(unsafe { &*(l as *const WavelengthsF32).cast::<SampledWavelengths>() })
    } else {
        None
    }
}

/// The interface's wavelengths as the host's (the same memory), when `live` holds only lane
/// bits (as every host's does; `None` otherwise, and on a big-endian machine, where the caller
/// copies them instead): what the standard library hands its materials and lights.
#[inline]
pub fn as_wavelengths(l: &LanesF32) -> Option<&SampledWavelengths> {
    if cfg!(target_endian = "little") && l.live <= u32::from(LaneMask::ALL.bits()) {
        // SAFETY: same size, alignment and field offsets (asserted above); `lambda` and `pdf`
        // are `f32`s on both sides, and `lanes` is the low byte of `live`, a valid `LaneMask`
        // (only lane bits, checked just now); the bytes after it are padding on the host's side.
        Some(unsafe { &*(l as *const LanesF32).cast::<SampledWavelengths>() })
    } else {
        None
    }
}

/// The host's vector as the interface's (the same memory; its `w` lane whatever the host's is):
/// how extension v8 passes directions.
#[inline]
pub fn as_vec4f(v: &Vec3A) -> &Vec4f {
    // SAFETY: same size and alignment (asserted above); a Vec3A is four initialised `f32`s in
    // one 16-byte register, a Vec4f four `f32`s, so every bit pattern of one is a valid value of
    // the other, and the lifetime is carried over.
    unsafe { &*(v as *const Vec3A).cast::<Vec4f>() }
}

/// The interface's vector as the host's (the same memory): what the standard library hands its
/// materials.
#[inline]
pub fn as_vec3a(v: &Vec4f) -> &Vec3A {
    // SAFETY: as for `as_vec4f`, the other way round.
    unsafe { &*(v as *const Vec4f).cast::<Vec3A>() }
}

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

/// A light sample's receiver as the interface's (the same memory).
#[inline]
pub fn as_receiver(ctx: &LightSampleContext) -> &ReceiverF32 {
    // SAFETY: same size, alignment and field offsets (asserted above); every field is a Vec3A
    // (four initialised `f32`s), so every bit pattern of one is a valid value of the other.
    unsafe { &*(ctx as *const LightSampleContext).cast::<ReceiverF32>() }
}

/// The interface's receiver as the host's (the same memory): what the standard library hands
/// its lights.
#[inline]
pub fn as_light_context(r: &ReceiverF32) -> &LightSampleContext {
    // SAFETY: as for `as_receiver`, the other way round.
    unsafe { &*(r as *const ReceiverF32).cast::<LightSampleContext>() }
}

/// The host's light sample as the interface's record, for a plugin to write in place.
#[inline]
pub fn as_incident_mut(s: &mut LightLiSample) -> &mut IncidentF32 {
    // SAFETY: same size, alignment and field offsets (asserted above), padding included; every
    // field on both sides is plain `f32`s (Vec3A, SampledSpectrum, f32), so whatever the plugin
    // writes is a valid value of the host's record, and the exclusive borrow is carried over.
    unsafe { &mut *(s as *mut LightLiSample).cast::<IncidentF32>() }
}

/// The host's BSDF sample as the interface's record, for a plugin material to write in place.
/// What the plugin writes in `flags` are the interface's bits: the caller translates them before
/// the sample is used.
#[inline]
pub fn as_scatter_mut(s: &mut BsdfSample) -> &mut ScatterF32 {
    // SAFETY: same size, alignment and field offsets (asserted above); every field on both
    // sides is plain `f32`s or one `u32` (Vec3A, SampledSpectrum, f32, MaterialFlags/Flags), so
    // whatever the plugin writes is a valid value of the host's record.
    unsafe { &mut *(s as *mut BsdfSample).cast::<ScatterF32>() }
}

/// The interface's sample record as the host's BSDF sample (the same memory): where the
/// standard library's materials write their samples. What they write in `flags` are the host's
/// bits: the library translates them before it answers.
#[inline]
pub fn as_bsdf_sample_mut(s: &mut ScatterF32) -> &mut BsdfSample {
    // SAFETY: as for `as_scatter_mut`, the other way round.
    unsafe { &mut *(s as *mut ScatterF32).cast::<BsdfSample>() }
}

/// The interface's incident record as the host's light sample (the same memory): where the
/// standard library writes its lights' samples.
#[inline]
pub fn as_light_sample_mut(s: &mut IncidentF32) -> &mut LightLiSample {
    // SAFETY: as for `as_incident_mut`, the other way round.
    unsafe { &mut *(s as *mut IncidentF32).cast::<LightLiSample>() }
}

/// Extension v8's `eval` answer as one SIMD vector: the four lanes as they come back in two
/// registers, joined by one move (through `[f32; 4]`, lane by lane, it took five).
#[inline]
pub fn values_as_vec4(v: ValuesF32) -> glam::Vec4 {
    // SAFETY: four `f32`s on both sides (`ValuesF32` is `#[repr(C)]`, the same size, asserted
    // above), in lane order; every bit pattern is a valid `f32`. By value: alignment is moot.
    unsafe { std::mem::transmute::<ValuesF32, glam::Vec4>(v) }
}

#[cfg(test)]
mod tests {
    use super::*;

    // An `eval` answer joined into one vector keeps each lane in its place, bit for bit (a NaN's
    // payload, −0, a subnormal, the largest finite).
    #[test]
    fn values_join_into_a_vector_lane_by_lane() {
        let v = [
            f32::from_bits(0x7fc0_1234),
            -0.0,
            f32::from_bits(1),
            f32::MAX,
        ];
        for k in 0..4 {
            let mut w = [0.5, 1.5, 2.5, 3.5];
            w[k] = v[k];
            let joined = values_as_vec4(ValuesF32 { v: w }).to_array();
            assert_eq!(joined.map(f32::to_bits), w.map(f32::to_bits), "lane {k}");
        }
        let joined = values_as_vec4(ValuesF32 { v }).to_array();
        assert_eq!(joined.map(f32::to_bits), v.map(f32::to_bits));
    }

    // The host's wavelengths read in place are the ones a copy gives (lanes, densities, mask);
    // a `live` with bits beyond the lanes is not read in place.
    #[test]
    fn wavelengths_read_in_place() {
        let l = LanesF32 {
            nm: [400.0, 500.0, 600.0, 700.0],
            pdf: [0.01, 0.02, 0.0, 0.04],
            live: 0b1011,
        };
        let w = as_wavelengths(&l).expect("lane bits only");
        assert_eq!(w.lambda, l.nm);
        assert_eq!(w.pdf, l.pdf);
        assert_eq!(w.lanes, LaneMask::from_bits(0b1011));
        assert!(as_wavelengths(&LanesF32 { live: 0x100, ..l }).is_none());
        assert!(as_wavelengths(&LanesF32 {
            live: 0b1_0000,
            ..l
        })
        .is_none());
    }

    // Extension v7's wavelengths are the host's record, both ways; a `live` with bits beyond
    // the lanes is not read as the host's.
    #[test]
    fn v7_wavelengths_are_the_same_memory() {
        let w = SampledWavelengths {
            lambda: [400.0, 500.0, 600.0, 700.0],
            pdf: [0.01, 0.02, 0.0, 0.04],
            lanes: LaneMask::from_bits(0b1011),
        };
        let l = as_wavelengths_f32(&w);
        assert_eq!(l.nm, w.lambda);
        assert_eq!(l.pdf, w.pdf);
        assert_eq!(l.live, 0b1011);
        assert_eq!(as_wavelengths_v7(l), Some(&w));
        let bad = WavelengthsF32 {
            live: 0b1_0000,
            ..*l
        };
        assert!(as_wavelengths_v7(&bad).is_none());
    }

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

    // A light's receiver and sample are the same memory as the interface's records.
    #[test]
    fn the_light_records_are_the_same_memory() {
        let ctx = LightSampleContext {
            p: Vec3A::new(1.0, 2.0, 3.0),
            p_error: Vec3A::splat(1e-6),
            n: Vec3A::Y,
        };
        let r = as_receiver(&ctx);
        assert_eq!([r.p.x, r.p.y, r.p.z], [1.0, 2.0, 3.0]);
        assert_eq!(r.p_error.x, 1e-6);
        assert_eq!(r.n.y, 1.0);
        assert_eq!(*as_light_context(r), ctx);
        let mut s = LightLiSample {
            radiance: SampledSpectrum([0.0; 4]),
            wi: Vec3A::ZERO,
            pdf: 0.0,
            p_light: Vec3A::ZERO,
            p_light_error: Vec3A::ZERO,
            n_light: Vec3A::ZERO,
        };
        let out = as_incident_mut(&mut s);
        out.value = [1.0, 2.0, 3.0, 4.0];
        out.direction = Vec4f::new(0.0, 1.0, 0.0);
        out.pdf = 0.5;
        out.point = Vec4f::new(4.0, 5.0, 6.0);
        out.point_error = Vec4f::new(1e-5, 1e-5, 1e-5);
        out.normal = Vec4f::new(0.0, -1.0, 0.0);
        assert_eq!(s.radiance.0, [1.0, 2.0, 3.0, 4.0]);
        assert_eq!(s.wi, Vec3A::Y);
        assert_eq!(s.pdf, 0.5);
        assert_eq!(s.p_light, Vec3A::new(4.0, 5.0, 6.0));
        assert_eq!(s.p_light_error, Vec3A::splat(1e-5));
        assert_eq!(s.n_light, -Vec3A::Y);
    }
}

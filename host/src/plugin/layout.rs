//! The host's records seen as the plugin interface's (`spectrace_plugin_api::lanes`), and back,
//! without a copy: the per-sample calls pass `ShadingContext` as a `Surface`, the wavelengths
//! as `Wavelengths`, a light sample's receiver (`LightSampleContext`) as a `Receiver`, and let a
//! plugin write its answer into the host's `BsdfSample` (as `Scatter`) and `LightLiSample` (as
//! `Incident`). Each pair is `#[repr(C)]` with the same fields in the same places (16-byte
//! vectors, four-lane values, `f32`s); the assertions below stop the build if either side ever
//! changes. Written by hand because these are pointer casts that a crate would not make safer
//! than these assertions.
//!
//! The vectors' fourth lanes are the host's (glam keeps anything there); the interface says so
//! (`lanes`), and readers use `x, y, z` only.

use crate::light::{LightLiSample, LightSampleContext};
use crate::material::{BsdfSample, MaterialFlags, ShadingContext};
use crate::spectrum::{LaneMask, SampledSpectrum, SampledWavelengths};
use glam::{Vec2, Vec3A};
use spectrace_plugin_api::lanes::{
    Incident, Receiver, Scatter, Surface, Values, Vec4f, Wavelengths,
};
use spectrace_plugin_api::Flags;
use std::mem::{align_of, offset_of, size_of};

const _: () = {
    assert!(size_of::<ShadingContext>() == size_of::<Surface>());
    assert!(align_of::<ShadingContext>() == align_of::<Surface>());
    assert!(offset_of!(ShadingContext, uv) == offset_of!(Surface, uv));
    assert!(offset_of!(ShadingContext, p) == offset_of!(Surface, position));
    assert!(offset_of!(ShadingContext, ng) == offset_of!(Surface, geometric_normal));
    assert!(offset_of!(ShadingContext, ns) == offset_of!(Surface, shading_normal));
    assert!(size_of::<Vec2>() == size_of::<[f32; 2]>() && align_of::<Vec2>() <= 4);
    assert!(size_of::<Vec3A>() == size_of::<Vec4f>());
    assert!(align_of::<Vec3A>() == align_of::<Vec4f>());

    assert!(size_of::<LightSampleContext>() == size_of::<Receiver>());
    assert!(align_of::<LightSampleContext>() == align_of::<Receiver>());
    assert!(offset_of!(LightSampleContext, p) == offset_of!(Receiver, p));
    assert!(offset_of!(LightSampleContext, p_error) == offset_of!(Receiver, p_error));
    assert!(offset_of!(LightSampleContext, n) == offset_of!(Receiver, n));

    // A one-field tuple struct of four `f32`s: the same size and alignment leave the field at 0.
    assert!(size_of::<SampledSpectrum>() == size_of::<[f32; 4]>());
    assert!(align_of::<SampledSpectrum>() == align_of::<[f32; 4]>());
    assert!(size_of::<LightLiSample>() == size_of::<Incident>());
    assert!(align_of::<LightLiSample>() == align_of::<Incident>());
    assert!(offset_of!(LightLiSample, radiance) == offset_of!(Incident, value));
    assert!(offset_of!(LightLiSample, wi) == offset_of!(Incident, direction));
    assert!(offset_of!(LightLiSample, pdf) == offset_of!(Incident, pdf));
    assert!(offset_of!(LightLiSample, p_light) == offset_of!(Incident, point));
    assert!(offset_of!(LightLiSample, p_light_error) == offset_of!(Incident, point_error));
    assert!(offset_of!(LightLiSample, n_light) == offset_of!(Incident, normal));

    assert!(size_of::<Values>() == size_of::<glam::Vec4>());
    assert!(size_of::<MaterialFlags>() == size_of::<Flags>());
    assert!(size_of::<BsdfSample>() == size_of::<Scatter>());
    assert!(align_of::<BsdfSample>() == align_of::<Scatter>());
    assert!(offset_of!(BsdfSample, wi) == offset_of!(Scatter, wi));
    assert!(offset_of!(BsdfSample, f) == offset_of!(Scatter, value));
    assert!(offset_of!(BsdfSample, pdf) == offset_of!(Scatter, pdf));
    assert!(offset_of!(BsdfSample, flags) == offset_of!(Scatter, flags));
    assert!(offset_of!(BsdfSample, eta) == offset_of!(Scatter, eta));
};

// The wavelengths: the host's record itself, the live bits one byte on both sides
// (padding after it on both).
const _: () = {
    assert!(size_of::<SampledWavelengths>() == size_of::<Wavelengths>());
    assert!(align_of::<SampledWavelengths>() == align_of::<Wavelengths>());
    assert!(offset_of!(SampledWavelengths, lambda) == offset_of!(Wavelengths, nm));
    assert!(offset_of!(SampledWavelengths, pdf) == offset_of!(Wavelengths, pdf));
    assert!(offset_of!(SampledWavelengths, lanes) == offset_of!(Wavelengths, live));
};

/// The host's wavelengths as the interface's record (the same memory): what the host hands a
/// plugin material.
#[inline]
pub fn as_wavelengths(l: &SampledWavelengths) -> &Wavelengths {
    // SAFETY: same size, alignment and field offsets (asserted above); `lambda`/`nm` and `pdf`
    // are `f32`s on both sides, `lanes` (a one-byte `LaneMask`) is `live` (a `u8`), and the
    // padding after it is padding on both sides; the lifetime is carried over.
    unsafe { &*(l as *const SampledWavelengths).cast::<Wavelengths>() }
}

/// The interface's wavelengths as the host's (the same memory) when `live` holds only lane bits
/// (as every host's does; `None` otherwise, where the caller copies them instead): what the
/// standard library hands its materials.
#[inline]
pub fn as_host_wavelengths(l: &Wavelengths) -> Option<&SampledWavelengths> {
    if l.live <= LaneMask::ALL.bits() {
        // SAFETY: as for `as_wavelengths`, the other way round; `live` holds only lane
        // bits (checked just now), a valid `LaneMask`.
        Some(unsafe { &*(l as *const Wavelengths).cast::<SampledWavelengths>() })
    } else {
        None
    }
}

/// The host's vector as the interface's (the same memory; its `w` lane whatever the host's is):
/// how the per-sample calls pass directions.
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
pub fn as_surface(ctx: &ShadingContext) -> &Surface {
    // SAFETY: same size, alignment and field offsets (asserted above); every field is plain
    // `f32`s (Vec2 is two, Vec3A four in one 16-byte register, all initialised), so every bit
    // pattern of one is a valid value of the other, and the lifetime is carried over.
    unsafe { &*(ctx as *const ShadingContext).cast::<Surface>() }
}

/// The interface's surface record as the host's (the same memory): what a plugin built from the
/// host's own code (the standard library) hands its materials.
#[inline]
pub fn as_shading_context(s: &Surface) -> &ShadingContext {
    // SAFETY: as for `as_surface`, the other way round.
    unsafe { &*(s as *const Surface).cast::<ShadingContext>() }
}

/// A light sample's receiver as the interface's (the same memory).
#[inline]
pub fn as_receiver(ctx: &LightSampleContext) -> &Receiver {
    // SAFETY: same size, alignment and field offsets (asserted above); every field is a Vec3A
    // (four initialised `f32`s), so every bit pattern of one is a valid value of the other.
    unsafe { &*(ctx as *const LightSampleContext).cast::<Receiver>() }
}

/// The interface's receiver as the host's (the same memory): what the standard library hands
/// its lights.
#[inline]
pub fn as_light_context(r: &Receiver) -> &LightSampleContext {
    // SAFETY: as for `as_receiver`, the other way round.
    unsafe { &*(r as *const Receiver).cast::<LightSampleContext>() }
}

/// The host's light sample as the interface's record, for a plugin to write in place.
#[inline]
pub fn as_incident_mut(s: &mut LightLiSample) -> &mut Incident {
    // SAFETY: same size, alignment and field offsets (asserted above), padding included; every
    // field on both sides is plain `f32`s (Vec3A, SampledSpectrum, f32), so whatever the plugin
    // writes is a valid value of the host's record, and the exclusive borrow is carried over.
    unsafe { &mut *(s as *mut LightLiSample).cast::<Incident>() }
}

/// The host's BSDF sample as the interface's record, for a plugin material to write in place.
/// What the plugin writes in `flags` are the interface's bits: the caller translates them before
/// the sample is used.
#[inline]
pub fn as_scatter_mut(s: &mut BsdfSample) -> &mut Scatter {
    // SAFETY: same size, alignment and field offsets (asserted above); every field on both
    // sides is plain `f32`s or one `u32` (Vec3A, SampledSpectrum, f32, MaterialFlags/Flags), so
    // whatever the plugin writes is a valid value of the host's record.
    unsafe { &mut *(s as *mut BsdfSample).cast::<Scatter>() }
}

/// The interface's sample record as the host's BSDF sample (the same memory): where the
/// standard library's materials write their samples. What they write in `flags` are the host's
/// bits: the library translates them before it answers.
#[inline]
pub fn as_bsdf_sample_mut(s: &mut Scatter) -> &mut BsdfSample {
    // SAFETY: as for `as_scatter_mut`, the other way round.
    unsafe { &mut *(s as *mut Scatter).cast::<BsdfSample>() }
}

/// The interface's incident record as the host's light sample (the same memory): where the
/// standard library writes its lights' samples.
#[inline]
pub fn as_light_sample_mut(s: &mut Incident) -> &mut LightLiSample {
    // SAFETY: as for `as_incident_mut`, the other way round.
    unsafe { &mut *(s as *mut Incident).cast::<LightLiSample>() }
}

/// An `eval` answer as one SIMD vector: the four lanes as they come back in two
/// registers, joined by one move (through `[f32; 4]`, lane by lane, it took five).
#[inline]
pub fn values_as_vec4(v: Values) -> glam::Vec4 {
    // SAFETY: four `f32`s on both sides (`Values` is `#[repr(C)]`, the same size, asserted
    // above), in lane order; every bit pattern is a valid `f32`. By value: alignment is moot.
    unsafe { std::mem::transmute::<Values, glam::Vec4>(v) }
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
            let joined = values_as_vec4(Values { v: w }).to_array();
            assert_eq!(joined.map(f32::to_bits), w.map(f32::to_bits), "lane {k}");
        }
        let joined = values_as_vec4(Values { v }).to_array();
        assert_eq!(joined.map(f32::to_bits), v.map(f32::to_bits));
    }

    // The interface's wavelengths are the host's record, both ways; a `live` with bits beyond
    // the lanes is not read as the host's.
    #[test]
    fn the_wavelengths_are_the_same_memory() {
        let w = SampledWavelengths {
            lambda: [400.0, 500.0, 600.0, 700.0],
            pdf: [0.01, 0.02, 0.0, 0.04],
            lanes: LaneMask::from_bits(0b1011),
        };
        let l = as_wavelengths(&w);
        assert_eq!(l.nm, w.lambda);
        assert_eq!(l.pdf, w.pdf);
        assert_eq!(l.live, 0b1011);
        assert_eq!(as_host_wavelengths(l), Some(&w));
        let bad = Wavelengths {
            live: 0b1_0000,
            ..*l
        };
        assert!(as_host_wavelengths(&bad).is_none());
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

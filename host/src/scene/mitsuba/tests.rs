//! Tests of the Mitsuba import: the XML layer's rules and refusals, the conversion of each
//! element kind against values worked out by hand from Mitsuba's documented conventions, and the
//! public scenes in `scenes/mitsuba/` converting and building.

use super::convert::{convert_tree, transform_of, Conversion};
use super::xml::{parse_scene_text, read_scene};
use super::*;
use crate::scene_file::description::TransformStep;
use glam::{DMat4, DVec3};
use ron::Value;
use std::path::PathBuf;

/// A fresh directory under the system's temporary directory.
fn temp_dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("spectrace-mitsuba-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn convert_text(xml: &str) -> Result<Conversion, crate::scene::SceneError> {
    static N: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let dir = temp_dir(&format!(
        "text{}",
        N.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
    ));
    let file = dir.join("scene.xml");
    std::fs::write(&file, xml).unwrap();
    convert_file(&file, &[])
}

fn get<'a>(v: &'a Value, key: &str) -> &'a Value {
    match v {
        Value::Map(m) => m
            .iter()
            .find(|(k, _)| **k == Value::String(key.into()))
            .map(|(_, v)| v)
            .unwrap_or_else(|| panic!("no `{key}` in {v:?}")),
        _ => panic!("not a map: {v:?}"),
    }
}

fn f(v: &Value) -> f64 {
    match v {
        Value::Number(n) => n.into_f64(),
        _ => panic!("not a number: {v:?}"),
    }
}

fn vec3(v: &Value) -> DVec3 {
    match v {
        Value::Seq(s) => DVec3::new(f(&s[0]), f(&s[1]), f(&s[2])),
        _ => panic!("not a sequence: {v:?}"),
    }
}

const CAMERA: &str = r#"<sensor type="perspective"><float name="fov" value="40"/>
    <transform name="to_world"><lookat origin="0,0,4" target="0,0,0" up="0,1,0"/></transform>
    <film type="hdrfilm"><integer name="width" value="64"/><integer name="height" value="32"/></film></sensor>"#;

// `default` sets a parameter, `$name` substitutes it, `-D` wins over the default; an undefined
// `$name` is an error naming file and line.
#[test]
fn defaults_substitution_and_command_line() {
    let dir = temp_dir("defaults");
    let file = dir.join("s.xml");
    std::fs::write(
        &file,
        r#"<scene version="3.0.0"><default name="spp" value="16"/><default name="w" value="40"/>
<sensor type="perspective"><sampler type="independent"><integer name="sample_count" value="$spp"/></sampler>
<film type="hdrfilm"><integer name="width" value="$w"/><integer name="height" value="${w}0"/></film></sensor></scene>"#,
    )
    .unwrap();
    let c = convert_file(&file, &[]);
    // `${w}` is not Mitsuba syntax: `$` followed by `{` is kept, and `{w}0` is not a number.
    assert!(c.is_err());
    std::fs::write(
        &file,
        r#"<scene version="3.0.0"><default name="spp" value="16"/><default name="w" value="40"/>
<sensor type="perspective"><sampler type="independent"><integer name="sample_count" value="$spp"/></sampler>
<film type="hdrfilm"><integer name="width" value="$w"/><integer name="height" value="$w"/></film></sensor></scene>"#,
    )
    .unwrap();
    let c = convert_file(&file, &[]).unwrap();
    assert_eq!(c.desc.output.spp, Some(16));
    let c = convert_file(&file, &[("spp".into(), "128".into())]).unwrap();
    assert_eq!(c.desc.output.spp, Some(128));
    let res = get(&c.desc.cameras[0].params, "resolution");
    assert_eq!(
        res,
        &Value::Seq(vec![convert::num(40.0), convert::num(40.0)])
    );
    std::fs::write(
        &file,
        r#"<scene version="3.0.0">
<integrator type="path"><integer name="max_depth" value="$depth"/></integrator></scene>"#,
    )
    .unwrap();
    let e = convert_file(&file, &[]).unwrap_err().to_string();
    assert!(e.contains("s.xml:2:") && e.contains("$depth"), "{e}");
}

// Includes insert the other file's children; a cycle is refused with the chain named.
#[test]
fn include_and_cycles() {
    let dir = temp_dir("include");
    std::fs::write(
        dir.join("main.xml"),
        r#"<scene version="3.0.0"><include filename="parts/bsdfs.xml"/>
<shape type="sphere"><ref id="red"/></shape></scene>"#,
    )
    .unwrap();
    std::fs::create_dir_all(dir.join("parts")).unwrap();
    std::fs::write(
        dir.join("parts/bsdfs.xml"),
        r#"<scene version="3.0.0"><bsdf type="diffuse" id="red"><rgb name="reflectance" value="0.8, 0.1, 0.1"/></bsdf></scene>"#,
    )
    .unwrap();
    let c = convert_file(&dir.join("main.xml"), &[]).unwrap();
    assert_eq!(c.desc.materials[0].name, "red");
    assert_eq!(c.desc.objects[0].material, "red");

    std::fs::write(
        dir.join("a.xml"),
        r#"<scene version="3.0.0"><include filename="b.xml"/></scene>"#,
    )
    .unwrap();
    std::fs::write(
        dir.join("b.xml"),
        r#"<scene version="3.0.0"><include filename="a.xml"/></scene>"#,
    )
    .unwrap();
    let e = convert_file(&dir.join("a.xml"), &[])
        .unwrap_err()
        .to_string();
    assert!(e.contains("cyclic include") && e.contains("b.xml"), "{e}");
    std::fs::write(
        dir.join("self.xml"),
        r#"<scene version="3.0.0"><include filename="self.xml"/></scene>"#,
    )
    .unwrap();
    let e = convert_file(&dir.join("self.xml"), &[])
        .unwrap_err()
        .to_string();
    assert!(e.contains("cyclic include"), "{e}");
    let e = convert_file(&dir.join("missing.xml"), &[])
        .unwrap_err()
        .to_string();
    assert!(e.contains("missing.xml"), "{e}");
}

// Entity expansion ("billion laughs") and any DTD are refused at once; malformed XML is an error
// with line and column; an unknown element is named.
#[test]
fn hostile_and_malformed_xml() {
    let laughs = r#"<?xml version="1.0"?>
<!DOCTYPE lolz [<!ENTITY lol "lol"><!ENTITY lol2 "&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;">
<!ENTITY lol3 "&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;">]>
<scene version="3.0.0"><string name="x" value="&lol3;"/></scene>"#;
    let e = parse_scene_text(laughs, Path::new("laughs.xml"))
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("laughs.xml:1:1:") && e.contains("DTD"), "{e}");
    let e = parse_scene_text(
        "<scene version=\"3.0.0\">\n  <shape type=\"sphere\">\n</scene>",
        Path::new("bad.xml"),
    )
    .unwrap_err()
    .to_string();
    assert!(e.starts_with("bad.xml:3:"), "{e}");
    let e = parse_scene_text("<mesh/>", Path::new("m.xml"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("<scene>"), "{e}");
    let e = convert_text("<scene version=\"3.0.0\">\n<gizmo/></scene>")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains(":2:") && e.contains("unknown element <gizmo>"),
        "{e}"
    );
    let e = convert_text("<scene version=\"3.0.0\"><shape type=\"obj\"><string name=\"filename\" value=\"nowhere.obj\"/></shape></scene>")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("file not found") && e.contains("nowhere.obj"),
        "{e}"
    );
    let e = convert_text(
        r#"<scene version="3.0.0"><shape type="sphere"><ref id="nope"/></shape></scene>"#,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("no element has id \"nope\""), "{e}");
}

// Mitsuba's operations compose left to right (each applies after the ones before); the matrix is
// row-major; lookat's columns are (up × dir, dir × left, dir, origin).
#[test]
fn transforms_follow_mitsuba() {
    let t = parse_scene_text(
        r#"<scene version="3.0.0"><transform name="to_world"><scale value="2"/>
<rotate y="1" angle="90"/><translate x="1" y="2" z="3"/></transform></scene>"#,
        Path::new("t.xml"),
    )
    .unwrap();
    let m = transform_of(&t.children[0]).unwrap();
    // (1, 0, 0) → scale (2, 0, 0) → rotate 90° about +y (right-handed): (0, 0, −2) → + (1, 2, 3).
    let p = m.transform_point3(DVec3::X);
    assert!((p - DVec3::new(1.0, 2.0, 1.0)).length() < 1e-12, "{p}");
    let t = parse_scene_text(
        r#"<scene version="3.0.0"><transform name="to_world"><matrix value="1 0 0 5  0 1 0 6  0 0 1 7  0 0 0 1"/></transform></scene>"#,
        Path::new("t.xml"),
    )
    .unwrap();
    let m = transform_of(&t.children[0]).unwrap();
    assert_eq!(m.transform_point3(DVec3::ZERO), DVec3::new(5.0, 6.0, 7.0));
    let t = parse_scene_text(
        r#"<scene version="3.0.0"><transform name="to_world"><lookat origin="1,2,3" target="1,2,0" up="0,1,0"/></transform></scene>"#,
        Path::new("t.xml"),
    )
    .unwrap();
    let m = transform_of(&t.children[0]).unwrap();
    assert_eq!(m.transform_point3(DVec3::ZERO), DVec3::new(1.0, 2.0, 3.0));
    assert!((m.transform_vector3(DVec3::Z) - DVec3::NEG_Z).length() < 1e-12);
    // Looking down −z with +y up, Mitsuba's local +x ("left") is world −x.
    assert!((m.transform_vector3(DVec3::X) - DVec3::NEG_X).length() < 1e-12);
    let t = parse_scene_text(
        r#"<scene version="3.0.0"><transform name="to_world"><scale x="0"/></transform></scene>"#,
        Path::new("t.xml"),
    )
    .unwrap();
    assert!(transform_of(&t.children[0]).is_err());
}

// The camera: position, look-at point and up from to_world; fov_axis "smaller" on a wide film is
// the y axis; "diagonal" is converted to x (tan θx = tan θd · a / √(1 + a²)).
#[test]
fn camera_conventions() {
    let c = convert_text(&format!("<scene version=\"3.0.0\">{CAMERA}</scene>")).unwrap();
    let cam = &c.desc.cameras[0];
    assert_eq!(cam.type_name, "pinhole");
    assert_eq!(
        vec3(get(&cam.params, "position")),
        DVec3::new(0.0, 0.0, 4.0)
    );
    assert_eq!(vec3(get(&cam.params, "look_at")), DVec3::new(0.0, 0.0, 3.0));
    assert_eq!(f(get(&cam.params, "fov")), 40.0);
    let wide = CAMERA.replace(
        "<float name=\"fov\" value=\"40\"/>",
        "<float name=\"fov\" value=\"40\"/><string name=\"fov_axis\" value=\"smaller\"/>",
    );
    let c = convert_text(&format!("<scene version=\"3.0.0\">{wide}</scene>")).unwrap();
    assert_eq!(
        get(&c.desc.cameras[0].params, "fov_axis"),
        &Value::String("y".into())
    );
    let diag = CAMERA.replace(
        "<float name=\"fov\" value=\"40\"/>",
        "<float name=\"fov\" value=\"40\"/><string name=\"fov_axis\" value=\"diagonal\"/>",
    );
    let c = convert_text(&format!("<scene version=\"3.0.0\">{diag}</scene>")).unwrap();
    let a: f64 = 2.0;
    let want = 2.0
        * ((20f64.to_radians().tan()) * a / (1.0 + a * a).sqrt())
            .atan()
            .to_degrees();
    assert!((f(get(&c.desc.cameras[0].params, "fov")) - want).abs() < 1e-9);
    let lens = CAMERA.replace("perspective", "thinlens").replace("<float name=\"fov\" value=\"40\"/>", "<float name=\"fov\" value=\"40\"/><float name=\"aperture_radius\" value=\"0.05\"/><float name=\"focus_distance\" value=\"4\"/>");
    let c = convert_text(&format!("<scene version=\"3.0.0\">{lens}</scene>")).unwrap();
    assert_eq!(c.desc.cameras[0].type_name, "perspective");
    assert_eq!(f(get(&c.desc.cameras[0].params, "lens_radius")), 0.05);
    let clipped = CAMERA.replace(
        "<float name=\"fov\" value=\"40\"/>",
        "<float name=\"fov\" value=\"40\"/><float name=\"near_clip\" value=\"1\"/>",
    );
    let c = convert_text(&format!("<scene version=\"3.0.0\">{clipped}</scene>")).unwrap();
    assert!(
        c.notes.iter().any(|n| n.contains("near_clip")),
        "{:?}",
        c.notes
    );
}

// BSDFs: each maps to the documented spectrace material, and what is approximated says so.
#[test]
fn bsdf_mapping() {
    let c = convert_text(r#"<scene version="3.0.0">
<bsdf type="dielectric" id="water"><string name="int_ior" value="water"/><float name="ext_ior" value="1.0"/></bsdf>
<bsdf type="conductor" id="gold"><string name="material" value="Au"/></bsdf>
<bsdf type="conductor" id="mirror"/>
<bsdf type="roughconductor" id="rough"><float name="alpha" value="0.2"/><string name="distribution" value="ggx"/><string name="material" value="Cu"/></bsdf>
<bsdf type="plastic" id="plastic"><rgb name="diffuse_reflectance" value="0.2, 0.4, 0.6"/></bsdf>
<bsdf type="twosided" id="two"><bsdf type="diffuse"><float name="reflectance" value="0.3"/><float name="bogus" value="1"/></bsdf></bsdf>
<bsdf type="weird" id="weird"/>
<bsdf type="thindielectric" id="sheet"/>
<shape type="sphere"><ref id="water"/></shape><shape type="sphere"><ref id="gold"/></shape>
<shape type="sphere"><ref id="mirror"/></shape><shape type="sphere"><ref id="rough"/></shape>
<shape type="sphere"><ref id="plastic"/></shape><shape type="sphere"><ref id="two"/></shape>
<shape type="sphere"><ref id="weird"/></shape><shape type="sphere"><ref id="sheet"/></shape>
</scene>"#).unwrap();
    let m = |n: &str| c.desc.materials.iter().find(|m| m.name == n).unwrap();
    assert_eq!(m("water").type_name, "dielectric");
    assert!((f(get(&m("water").params, "ior")) - 1.333).abs() < 1e-9);
    assert_eq!(
        get(&m("gold").params, "metal"),
        &Value::String("gold".into())
    );
    assert_eq!(m("mirror").type_name, "mirror");
    assert_eq!(f(get(&m("rough").params, "alpha")), 0.2);
    assert_eq!(m("plastic").type_name, "plastic");
    assert_eq!(
        get(&m("plastic").params, "diffuse_reflectance"),
        &Value::Map(
            [(
                Value::String("rgb".into()),
                Value::Seq(vec![
                    Value::Number(0.2.into()),
                    Value::Number(0.4.into()),
                    Value::Number(0.6.into())
                ])
            )]
            .into_iter()
            .collect()
        )
    );
    // Mitsuba's defaults: polypropylene (1.49) in air (1.000277).
    assert_eq!(f(get(&m("plastic").params, "int_ior")), 1.49);
    assert_eq!(f(get(&m("plastic").params, "ext_ior")), 1.000277);
    assert_eq!(f(get(&m("two").params, "reflectance")), 0.3);
    assert_eq!(m("sheet").type_name, "thin_film");
    let notes = c.notes.join("\n");
    for want in [
        "bsdf weird: not supported",
        "parameter `bogus` ignored",
        "thindielectric",
    ] {
        assert!(notes.contains(want), "missing `{want}` in\n{notes}");
    }
    assert!(
        !notes.contains("plastic"),
        "plastic is no longer approximated:\n{notes}"
    );
    // One note per kind, not one per element.
    let c = convert_text(r#"<scene version="3.0.0">
<shape type="sphere"><bsdf type="principled"/></shape><shape type="sphere"><bsdf type="principled"/></shape></scene>"#).unwrap();
    assert_eq!(
        c.notes
            .iter()
            .filter(|n| n.starts_with("principled"))
            .count(),
        1,
        "{:?}",
        c.notes
    );
}

// plastic and roughplastic: every parameter carried over (a bitmap base as a texture, the
// named IORs as numbers, nonlinear, specular_reflectance, α, the distribution), and the
// converted materials build.
#[test]
fn plastic_mapping() {
    let dir = temp_dir("plastic");
    // Only its existence is checked on conversion.
    std::fs::write(dir.join("base.png"), [0u8; 0]).unwrap();
    let xml = r#"<scene version="3.0.0">
<bsdf type="roughplastic" id="rough"><float name="alpha" value="0.3"/><string name="int_ior" value="acrylic glass"/>
  <float name="ext_ior" value="1.0"/><boolean name="nonlinear" value="true"/><float name="specular_reflectance" value="0.5"/>
  <rgb name="diffuse_reflectance" value="0.8, 0.1, 0.1"/></bsdf>
<bsdf type="roughplastic" id="beck"><texture type="bitmap" name="diffuse_reflectance"><string name="filename" value="base.png"/></texture></bsdf>
<bsdf type="twosided" id="two"><bsdf type="plastic"><float name="int_ior" value="1.9"/></bsdf></bsdf>
<shape type="sphere"><ref id="rough"/></shape><shape type="sphere"><ref id="beck"/></shape><shape type="sphere"><ref id="two"/></shape>
</scene>"#;
    std::fs::write(dir.join("s.xml"), xml).unwrap();
    let c = convert_file(&dir.join("s.xml"), &[]).unwrap_or_else(|e| panic!("{e}"));
    let m = |n: &str| c.desc.materials.iter().find(|m| m.name == n).unwrap();
    let rough = &m("rough").params;
    assert_eq!(m("rough").type_name, "rough_plastic");
    assert_eq!(f(get(rough, "alpha")), 0.3);
    assert_eq!(f(get(rough, "int_ior")), 1.49, "acrylic glass");
    assert_eq!(f(get(rough, "ext_ior")), 1.0);
    assert_eq!(get(rough, "nonlinear"), &Value::Bool(true));
    assert_eq!(f(get(rough, "specular_reflectance")), 0.5);
    let beck = &m("beck").params;
    assert_eq!(f(get(beck, "alpha")), 0.1, "Mitsuba's default α");
    assert!(matches!(get(beck, "diffuse_reflectance"), Value::Map(_)));
    let tex = get(get(beck, "diffuse_reflectance"), "texture");
    assert!(matches!(get(tex, "file"), Value::String(s) if s.ends_with("base.png")));
    assert_eq!(m("two").type_name, "plastic");
    assert_eq!(f(get(&m("two").params, "int_ior")), 1.9);
    // Mitsuba's default distribution is Beckmann, which spectrace's rough_plastic has.
    assert_eq!(get(beck, "distribution"), &Value::String("beckmann".into()));
    assert_eq!(
        get(rough, "distribution"),
        &Value::String("beckmann".into())
    );
    let notes = c.notes.join("\n");
    assert!(!notes.contains("distribution"), "{notes}");
    assert!(!notes.contains("ignored"), "{notes}");
    // The untextured ones build as the built-ins.
    use crate::scene::ObjectFactory;
    for n in ["rough", "two"] {
        let item = m(n);
        let ctx = crate::scene::FactoryContext {
            base_dir: dir.clone(),
            item: n.into(),
            representation: Default::default(),
            spd_factories: Default::default(),
        };
        crate::scene::BuiltinFactory
            .material(&item.type_name, &item.params, &ctx)
            .unwrap_or_else(|e| panic!("{n}: {e}"));
    }
}

// Emitters in Mitsuba's spectral units: an area light's rgb radiance becomes the illuminant-
// method table; a point light's intensity I(λ) gives Φ = 4π∫I dλ; constant → environment;
// envmap → the envmap syntax with to_world passed through as `transform`.
#[test]
fn emitters() {
    let dir = temp_dir("emit");
    std::fs::write(dir.join("sky.exr"), b"not read by the converter").unwrap();
    let xml = r#"<scene version="3.0.0">
<shape type="rectangle"><emitter type="area"><rgb name="radiance" value="1, 1, 1"/></emitter></shape>
<emitter type="point"><point name="position" x="0" y="2" z="0"/><spectrum name="intensity" value="2"/></emitter>
<emitter type="constant"><float name="radiance" value="0.5"/></emitter>
<emitter type="envmap"><string name="filename" value="sky.exr"/><float name="scale" value="2"/>
  <transform name="to_world"><rotate y="1" angle="90"/></transform></emitter>
<emitter type="directional"><vector name="direction" x="0" y="-1" z="0"/><spectrum name="irradiance" value="400:1, 700:1"/></emitter>
</scene>"#;
    std::fs::write(dir.join("s.xml"), xml).unwrap();
    let c = convert_file(&dir.join("s.xml"), &[]).unwrap();
    let em = &c.desc.materials[0];
    assert_eq!(em.type_name, "emissive");
    let Value::Seq(t) = get(&em.params, "radiance") else {
        panic!()
    };
    let at = |l: f64| {
        t.iter()
            .find_map(|p| match p {
                Value::Seq(p) if f(&p[0]) == l => Some(f(&p[1])),
                _ => None,
            })
            .unwrap()
    };
    assert!((at(560.0) / 1.01013 - 1.0).abs() < 3e-3);
    let point = c
        .desc
        .lights
        .iter()
        .find(|l| l.type_name == "point")
        .unwrap();
    // ∫ 2 dλ over 360–830 nm = 940 W/sr → Φ = 4π · 940 W.
    assert!(
        (f(get(&point.params, "power")) / (4.0 * std::f64::consts::PI * 940.0) - 1.0).abs() < 1e-12
    );
    assert!(c.desc.lights.iter().any(|l| l.type_name == "environment"));
    let env = c
        .desc
        .lights
        .iter()
        .find(|l| l.type_name == "envmap")
        .unwrap();
    assert_eq!(get(&env.params, "file"), &Value::String("sky.exr".into()));
    assert_eq!(f(get(&env.params, "scale")), 2.0);
    let Value::Seq(rows) = get(&env.params, "transform") else {
        panic!()
    };
    let Value::Seq(r0) = &rows[0] else { panic!() };
    // Row 0 of a 90° rotation about +y: (cos, 0, sin, 0) = (0, 0, 1, 0).
    assert!(f(&r0[0]).abs() < 1e-12 && (f(&r0[2]) - 1.0).abs() < 1e-12);
    let sun = c
        .desc
        .lights
        .iter()
        .find(|l| l.type_name == "directional")
        .unwrap();
    // 1 W/(m²·nm) over 400–700 nm (zero outside, as in Mitsuba) = 300 W/m², within the 5 nm
    // grid's trapezoid error at the two edges (2 × 2.5 W/m²).
    assert!((f(get(&sun.params, "irradiance")) - 300.0).abs() <= 5.0 + 1e-9);
}

// Textures: a bitmap reflectance becomes `(texture: (file: …))` with filter, encoding and the
// to_uv scale and offset.
#[test]
fn textures_in_the_agreed_syntax() {
    let dir = temp_dir("tex");
    std::fs::write(
        dir.join("wood.png"),
        b"png bytes are not read by the converter",
    )
    .unwrap();
    std::fs::write(dir.join("s.xml"), r#"<scene version="3.0.0"><shape type="sphere"><bsdf type="diffuse">
<texture type="bitmap" name="reflectance"><string name="filename" value="wood.png"/><boolean name="raw" value="true"/>
<string name="filter_type" value="nearest"/><transform name="to_uv"><scale x="4" y="2"/><translate x="0.5" y="0.25"/></transform>
</texture></bsdf></shape></scene>"#).unwrap();
    let c = convert_file(&dir.join("s.xml"), &[]).unwrap();
    let tex = get(get(&c.desc.materials[0].params, "reflectance"), "texture");
    assert_eq!(get(tex, "file"), &Value::String("wood.png".into()));
    assert_eq!(get(tex, "encoding"), &Value::String("linear".into()));
    assert_eq!(get(tex, "filter"), &Value::String("nearest".into()));
    let Value::Seq(s) = get(tex, "uv_scale") else {
        panic!()
    };
    assert_eq!((f(&s[0]), f(&s[1])), (4.0, 2.0));
    let Value::Seq(o) = get(tex, "uv_offset") else {
        panic!()
    };
    // Mitsuba's v runs from the image's top row, spectrace's from the bottom row:
    // o_v' = 1 − s_v − o_v = 1 − 2 − 0.25.
    assert_eq!((f(&o[0]), f(&o[1])), (0.5, -1.25));
}

// Regression (texture upside down on imported meshes): Mitsuba's bitmap puts v = 0 at the
// image's top row and reads serialized and PLY uvs as stored (OBJ's it flips); spectrace puts
// v = 0 at the bottom row. A serialized mesh's uvs are written flipped, a PLY gets `flip_v`, an
// OBJ none unless `flip_tex_coords` is false. Without the fix the public floor-tiles scene's
// textured object differed from Mitsuba's by an RMSE of 0.100 against Mitsuba's own 0.014
// (docs/mitsuba-import.md, "Compared against Mitsuba 3").
#[test]
fn mesh_uvs_follow_mitsubas_image_orientation() {
    let dir = temp_dir("uvflip");
    let mesh = crate::geometry::TriangleMesh {
        positions: vec![glam::Vec3A::ZERO, glam::Vec3A::X, glam::Vec3A::Y],
        normals: None,
        uvs: Some(vec![
            glam::Vec2::new(0.0, 0.0),
            glam::Vec2::new(1.0, 0.25),
            glam::Vec2::new(0.5, 1.0),
        ]),
        indices: vec![[0, 1, 2]],
    };
    std::fs::write(
        dir.join("tri.serialized"),
        serialized::write_serialized(&mesh, "tri"),
    )
    .unwrap();
    for n in ["a.ply", "a.obj", "b.obj"] {
        std::fs::write(dir.join(n), b"not read by the converter").unwrap();
    }
    std::fs::write(dir.join("s.xml"), r#"<scene version="3.0.0">
<shape type="serialized" id="m"><string name="filename" value="tri.serialized"/></shape>
<shape type="ply" id="p"><string name="filename" value="a.ply"/></shape>
<shape type="obj" id="o"><string name="filename" value="a.obj"/></shape>
<shape type="obj" id="of"><string name="filename" value="b.obj"/><boolean name="flip_tex_coords" value="false"/></shape>
</scene>"#).unwrap();
    let c = convert_file(&dir.join("s.xml"), &[]).unwrap();
    let o = |n: &str| c.desc.objects.iter().find(|o| o.name == n).unwrap();
    let Value::Seq(uvs) = get(&o("m").params, "uvs") else {
        panic!()
    };
    let v: Vec<f64> = uvs
        .iter()
        .map(|t| match t {
            Value::Seq(p) => f(&p[1]),
            _ => panic!(),
        })
        .collect();
    assert_eq!(v, vec![1.0, 0.75, 0.0]);
    assert_eq!(get(&o("p").params, "flip_v"), &Value::Bool(true));
    assert_eq!(get(&o("of").params, "flip_v"), &Value::Bool(true));
    let Value::Map(obj) = &o("o").params else {
        panic!()
    };
    assert!(!obj.keys().any(|k| k == &Value::String("flip_v".into())));
}

// A checkerboard becomes the mean of its two colours (the surface's mean reflectance), not
// color0; a `<path value>` folder is searched for files (Mitsuba 3's resource path).
#[test]
fn checkerboard_mean_and_resource_path() {
    let dir = temp_dir("pathtag");
    std::fs::create_dir_all(dir.join("common/textures")).unwrap();
    std::fs::create_dir_all(dir.join("docs/scenes")).unwrap();
    std::fs::write(dir.join("common/textures/wood.png"), b"not read").unwrap();
    std::fs::write(
        dir.join("docs/scenes/s.xml"),
        r#"<scene version="3.0.0"><path value="../../common"/>
<shape type="sphere" id="a"><bsdf type="diffuse"><texture type="bitmap" name="reflectance">
<string name="filename" value="textures/wood.png"/></texture></bsdf></shape>
<shape type="sphere" id="b"><bsdf type="diffuse"><texture type="checkerboard" name="reflectance">
<rgb name="color0" value="0.2"/><rgb name="color1" value="0.4"/></texture></bsdf></shape>
<shape type="sphere" id="c"><bsdf type="diffuse"><texture type="checkerboard" name="reflectance">
<rgb name="color0" value="0.2, 0.4, 0.6"/><rgb name="color1" value="0.4"/></texture></bsdf></shape>
</scene>"#,
    )
    .unwrap();
    let c = convert_file(&dir.join("docs/scenes/s.xml"), &[]).unwrap();
    let refl = |i: usize| get(&c.desc.materials[i].params, "reflectance").clone();
    let tex = refl(0);
    let file = get(get(&tex, "texture"), "file");
    let Value::String(file) = file else { panic!() };
    assert!(
        std::path::Path::new(file).ends_with("common/textures/wood.png"),
        "{file}"
    );
    assert!((f(&refl(1)) - 0.3).abs() < 1e-12);
    let r2 = refl(2);
    let Value::Seq(rgb) = get(&r2, "rgb") else {
        panic!()
    };
    let rgb: Vec<f64> = rgb.iter().map(f).collect();
    assert!(
        (rgb[0] - 0.3).abs() < 1e-12
            && (rgb[1] - 0.4).abs() < 1e-12
            && (rgb[2] - 0.5).abs() < 1e-12
    );
    // A missing folder is an error naming it.
    std::fs::write(
        dir.join("docs/scenes/bad.xml"),
        r#"<scene version="3.0.0"><path value="nowhere"/></scene>"#,
    )
    .unwrap();
    let e = convert_file(&dir.join("docs/scenes/bad.xml"), &[])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("folder not found") && e.contains("nowhere"),
        "{e}"
    );
}

// Textured emission: an `area` emitter whose `radiance` is a bitmap becomes an `emissive`
// material with `radiance: (texture: (file: …))` (an emission texture), not a uniform stand-in,
// and no note about textured emission is made.
#[test]
fn textured_area_emitter_becomes_an_emission_texture() {
    let dir = temp_dir("emtex");
    std::fs::write(dir.join("screen.exr"), b"not read by the converter").unwrap();
    std::fs::write(
        dir.join("s.xml"),
        r#"<scene version="3.0.0"><shape type="rectangle"><emitter type="area">
<texture type="bitmap" name="radiance"><string name="filename" value="screen.exr"/></texture>
</emitter></shape></scene>"#,
    )
    .unwrap();
    let c = convert_file(&dir.join("s.xml"), &[]).unwrap();
    let m = &c.desc.materials[0];
    assert_eq!(m.type_name, "emissive");
    let tex = get(get(&m.params, "radiance"), "texture");
    assert_eq!(get(tex, "file"), &Value::String("screen.exr".into()));
    assert!(
        !c.notes
            .iter()
            .any(|n| format!("{n:?}").contains("textured emission")),
        "{:?}",
        c.notes
    );
}

// Shapes: rectangle → quad with normal +z (−z when flipped), cube → 12 outward
// triangles, disk → fan, serialized → inline mesh, instances → copies with composed transforms.
#[test]
fn shapes() {
    let dir = temp_dir("shapes");
    let mesh = crate::geometry::TriangleMesh {
        positions: vec![glam::Vec3A::ZERO, glam::Vec3A::X, glam::Vec3A::Y],
        normals: None,
        uvs: None,
        indices: vec![[0, 1, 2]],
    };
    std::fs::write(
        dir.join("tri.serialized"),
        serialized::write_serialized(&mesh, "tri"),
    )
    .unwrap();
    std::fs::write(dir.join("s.xml"), r#"<scene version="3.0.0">
<shape type="rectangle" id="r"/><shape type="rectangle" id="rf"><boolean name="flip_normals" value="true"/></shape>
<shape type="cube" id="c"/><shape type="disk" id="d"/>
<shape type="serialized" id="m"><string name="filename" value="tri.serialized"/></shape>
<shape type="shapegroup" id="g"><shape type="sphere"><float name="radius" value="0.5"/></shape></shape>
<shape type="instance"><ref id="g"/><transform name="to_world"><translate x="3"/></transform></shape>
<shape type="instance"><ref id="g"/><transform name="to_world"><translate x="-3"/></transform></shape>
<shape type="bsplinecurve" id="hair"/>
</scene>"#).unwrap();
    let c = convert_file(&dir.join("s.xml"), &[]).unwrap();
    let o = |n: &str| {
        c.desc
            .objects
            .iter()
            .find(|o| o.name == n)
            .unwrap_or_else(|| {
                panic!(
                    "{n}: {:?}",
                    c.desc.objects.iter().map(|o| &o.name).collect::<Vec<_>>()
                )
            })
    };
    let e0 = vec3(get(&o("r").params, "edge0"));
    let e1 = vec3(get(&o("r").params, "edge1"));
    assert_eq!(e0.cross(e1).normalize(), DVec3::Z);
    let e0 = vec3(get(&o("rf").params, "edge0"));
    let e1 = vec3(get(&o("rf").params, "edge1"));
    assert_eq!(e0.cross(e1).normalize(), DVec3::NEG_Z);
    let cube = convert::cube_mesh(false);
    assert_eq!(cube.indices.len(), 12);
    for t in &cube.indices {
        let [a, b, cc] = t.map(|i| cube.positions[i as usize]);
        let n = (b - a).cross(cc - a);
        let centre = (a + b + cc) / 3.0;
        assert!(n.dot(centre) > 0.0, "cube face points inwards");
    }
    let disk = convert::disk_mesh(false);
    let area: f32 = disk
        .indices
        .iter()
        .map(|t| {
            let [a, b, cc] = t.map(|i| disk.positions[i as usize]);
            0.5 * (b - a).cross(cc - a).z
        })
        .sum();
    assert!(
        (area as f64 / std::f64::consts::PI - 1.0).abs() < 5e-4,
        "{area}"
    );
    assert_eq!(o("m").type_name, "mesh");
    let instances: Vec<_> = c
        .desc
        .objects
        .iter()
        .filter(|o| o.type_name == "sphere")
        .collect();
    assert_eq!(instances.len(), 2);
    let xs: Vec<f64> = instances
        .iter()
        .map(|o| match &o.transform[0] {
            TransformStep::Matrix(m) => m[0][3],
            s => panic!("{s:?}"),
        })
        .collect();
    assert!(xs.contains(&3.0) && xs.contains(&-3.0));
    assert!(
        c.notes
            .iter()
            .any(|n| n.starts_with("shape bsplinecurve: not supported")),
        "{:?}",
        c.notes
    );
}

// The public scenes convert and build into renderable spectrace scenes with the camera where
// Mitsuba puts it (Bitterli's Cornell box: eye at (0, 1, 6.8) looking down −z).
#[test]
fn public_scenes_build() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/mitsuba");
    let cbox = root.join("cornell-box/scene.xml");
    let c = convert_file(
        &cbox,
        &[("resx".into(), "32".into()), ("resy".into(), "32".into())],
    )
    .unwrap();
    let cam = &c.desc.cameras[0];
    assert!((vec3(get(&cam.params, "position")) - DVec3::new(0.0, 1.0, 6.8)).length() < 1e-9);
    assert!((vec3(get(&cam.params, "look_at")) - DVec3::new(0.0, 1.0, 5.8)).length() < 1e-9);
    assert_eq!(c.desc.output.max_depth, Some(64));
    let scene = crate::scene::build_scene(
        &c.desc,
        cbox.parent().unwrap(),
        &cbox,
        &[&crate::scene::BuiltinFactory],
    )
    .unwrap();
    assert_eq!(scene.lights.lights().len(), 1);
    for s in ["veach-mis/scene.xml", "veach-mis/scene-mitsuba3.xml"] {
        let p = root.join(s);
        let scene = crate::scene::load_scene_file(&p, &[&crate::scene::BuiltinFactory]).unwrap();
        assert_eq!(scene.lights.lights().len(), 3, "{s}");
    }
}

// The camera transform of a Mitsuba file that mirrors the image is noted.
#[test]
fn mirrored_camera_noted() {
    let m = CAMERA.replace("<lookat", "<scale x=\"-1\"/><lookat");
    let c = convert_text(&format!("<scene version=\"3.0.0\">{m}</scene>")).unwrap();
    assert!(
        c.notes.iter().any(|n| n.contains("mirrored")),
        "{:?}",
        c.notes
    );
    let _ = DMat4::IDENTITY;
}

// Reading stays within bounds: an include chain deeper than the limit is refused.
#[test]
fn include_depth_limit() {
    let dir = temp_dir("depth");
    for i in 0..=(xml::MAX_INCLUDE_DEPTH + 1) {
        std::fs::write(
            dir.join(format!("f{i}.xml")),
            format!(
                r#"<scene version="3.0.0"><include filename="f{}.xml"/></scene>"#,
                i + 1
            ),
        )
        .unwrap();
    }
    let e = read_scene(&dir.join("f0.xml"), &[])
        .unwrap_err()
        .to_string();
    assert!(e.contains("nested deeper"), "{e}");
    let _ = convert_tree;
}

// Random edits of a real scene (bytes deleted, duplicated, replaced by XML punctuation) give a
// description or an error, never a panic: 3000 cases of the Cornell box, under a second.
#[test]
fn random_edits_never_panic() {
    let root =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/mitsuba/cornell-box/scene.xml");
    let text = std::fs::read(&root).unwrap();
    let mut state = 0x9E37_79B9_7F4A_7C15u64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    let punct = b"<>/=\"'&$ 0.-e9";
    for _ in 0..3000 {
        let mut t = text.clone();
        for _ in 0..1 + next() % 4 {
            let i = (next() as usize) % t.len();
            match next() % 3 {
                0 => {
                    t.remove(i);
                }
                1 => t[i] = punct[(next() as usize) % punct.len()],
                _ => {
                    let j = (i + (next() as usize) % 40).min(t.len());
                    let piece = t[i..j].to_vec();
                    t.splice(i..i, piece);
                }
            }
        }
        if let Ok(s) = std::str::from_utf8(&t) {
            if let Ok(root_el) = parse_scene_text(s, Path::new("/nonexistent-dir/x.xml")) {
                let _ = convert_tree(&root_el, Path::new("/nonexistent-dir"));
            }
        }
    }
}

// The converted Cornell box renders to Mitsuba 3's image mean. Reference: Mitsuba 3.9.1
// llvm_ad_spectral, the same file at 256×256 and 4096 spp, linear sRGB mean (0.19504, 0.12674,
// 0.03471) (docs/mitsuba-import.md). Here 64×64 at 128 spp with pt (about 1 s): the image mean
// does not depend on the resolution (the same image plane, normalised filter). Its Monte Carlo
// spread, seen here between seeds at 32 spp, was up to 3% in blue (the darkest channel), so about
// 1.5% at 128 spp; with the 0.44% systematic difference in blue at 256×256: tolerance 4%.
#[test]
fn cornell_box_mean_matches_mitsuba() {
    use crate::integrator::{render, PathTracer, RenderSettings, SampleBudget};
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/mitsuba/cornell-box/scene.xml");
    let c = convert_file(
        &p,
        &[("resx".into(), "48".into()), ("resy".into(), "48".into())],
    )
    .unwrap();
    let scene = crate::scene::build_scene(
        &c.desc,
        p.parent().unwrap(),
        &p,
        &[&crate::scene::BuiltinFactory],
    )
    .unwrap();
    let settings = RenderSettings {
        budget: SampleBudget::Spp(128),
        seed: 1,
        tracer: PathTracer {
            max_depth: scene.options.max_depth,
            ..PathTracer::default()
        },
        ..RenderSettings::default()
    };
    let r = render(&scene, &settings, &|_: u64, _: u64| {}, None).unwrap();
    eprintln!(
        "mean of {} pixels",
        r.image.to_rgb(&crate::color::SRGB).len()
    );
    let rgb = r.image.to_rgb(&crate::color::SRGB);
    let n = rgb.len() as f64;
    let mean: Vec<f64> = (0..3)
        .map(|k| rgb.iter().map(|p| p[k]).sum::<f64>() / n)
        .collect();
    let want = [0.19504, 0.12674, 0.03471];
    for k in 0..3 {
        assert!(
            (mean[k] / want[k] - 1.0).abs() < 0.04,
            "channel {k}: {} vs Mitsuba {}",
            mean[k],
            want[k]
        );
    }
}

/// Where on its image a texture on each of Mitsuba's analytic shapes is looked up, against
/// Mitsuba 3.9.1 itself. Quantity: at points on `rectangle` (also with `flip_normals`),
/// `disk`, `sphere` and `cube`, Mitsuba's uv (`si.uv` of rays hitting them, its bitmap's row
/// coordinate counted from the image's top; `scripts/mitsuba_import/uv_probe.py` printed these
/// values) against the converted scene's: the hit's uv through the texture's `uv_scale` and
/// `uv_offset`, the row coordinate being 1 − v (spectrace's v = 0 is the bottom row); both
/// compared modulo 1 (the sphere's and the disk's seams). Tolerance 2e-3: the disk and the
/// textured sphere are tessellated with 128 sectors (chords 3e-4 inside the arcs, the
/// interpolated angles within 1e-3 of the true ones away from the disk's centre and the
/// sphere's poles, where no point is probed); the rectangle and the cube are exact to f32.
#[test]
fn analytic_shapes_show_textures_as_mitsuba_does() {
    // The textured sphere's mesh: outward triangles, area 5e-4 below the sphere's (16 128
    // triangles of 128 sectors × 64 rings).
    let sphere = convert::uv_sphere_mesh(DVec3::new(1.0, 2.0, 3.0), 2.0);
    assert_eq!(sphere.indices.len(), 16_128);
    let mut area = 0.0f64;
    for t in &sphere.indices {
        let [a, b, cc] = t.map(|i| sphere.positions[i as usize].as_dvec3());
        let n = (b - a).cross(cc - a);
        assert!(
            n.dot((a + b + cc) / 3.0 - DVec3::new(1.0, 2.0, 3.0)) > 0.0,
            "inward triangle"
        );
        area += 0.5 * n.length();
    }
    let rel = area / (4.0 * std::f64::consts::PI * 4.0) - 1.0;
    assert!((-1e-3..0.0).contains(&rel), "sphere mesh area off by {rel}");
    let dir = temp_dir("analytic_uvs");
    image::RgbImage::from_fn(4, 4, |x, y| image::Rgb([40 * x as u8, 40 * y as u8, 100]))
        .save(dir.join("t.png"))
        .unwrap();
    let bsdf = r#"<bsdf type="diffuse"><texture type="bitmap" name="reflectance">
        <string name="filename" value="t.png"/></texture></bsdf>"#;
    let at = |x: f64| format!(r#"<transform name="to_world"><translate x="{x}"/></transform>"#);
    let xml = format!(
        r#"<scene version="3.0.0">
<shape type="rectangle" id="rect">{}{bsdf}</shape>
<shape type="rectangle" id="rectf">{}<boolean name="flip_normals" value="true"/>{bsdf}</shape>
<shape type="disk" id="disk">{}{bsdf}</shape>
<shape type="sphere" id="sphere">{}{bsdf}</shape>
<shape type="cube" id="cube">{}{bsdf}</shape>
<sensor type="perspective"><transform name="to_world"><lookat origin="20, 0, 50" target="20, 0, 0" up="0, 1, 0"/></transform></sensor>
</scene>"#,
        at(0.0),
        at(10.0),
        at(20.0),
        at(30.0),
        at(40.0)
    );
    let file = dir.join("s.xml");
    std::fs::write(&file, xml).unwrap();
    let c = convert_file(&file, &[]).unwrap();
    let scene =
        crate::scene::build_scene(&c.desc, &dir, &file, &[&crate::scene::BuiltinFactory]).unwrap();
    assert_eq!(scene.geometry.object_count(), c.desc.objects.len());
    // (shape id, translation, local ray origin, direction, Mitsuba's uv).
    type Probe = (&'static str, f64, [f64; 3], [f64; 3], [f64; 2]);
    let down = [0.0, 0.0, -1.0];
    let mut probes: Vec<Probe> = vec![
        ("rect", 0.0, [-0.9, -0.9, 5.0], down, [0.05, 0.05]),
        ("rect", 0.0, [0.9, -0.9, 5.0], down, [0.95, 0.05]),
        ("rect", 0.0, [-0.9, 0.9, 5.0], down, [0.05, 0.95]),
        ("rect", 0.0, [0.9, 0.9, 5.0], down, [0.95, 0.95]),
        ("rectf", 10.0, [-0.9, -0.9, 5.0], down, [0.05, 0.05]),
        ("rectf", 10.0, [0.9, -0.9, 5.0], down, [0.95, 0.05]),
        ("rectf", 10.0, [-0.9, 0.9, 5.0], down, [0.05, 0.95]),
        ("disk", 20.0, [0.5, 0.0, 5.0], down, [0.5, 0.0]),
        ("disk", 20.0, [0.0, 0.5, 5.0], down, [0.5, 0.25]),
        ("disk", 20.0, [-0.5, 0.0, 5.0], down, [0.5, 0.5]),
        ("disk", 20.0, [0.0, -0.5, 5.0], down, [0.5, 0.75]),
        ("disk", 20.0, [0.9, 0.1, 5.0], down, [0.9055, 0.0176]),
        ("disk", 20.0, [0.1, 0.01, 5.0], down, [0.1005, 0.0159]),
        (
            "sphere",
            30.0,
            [5.0, 0.0, 0.0],
            [-1.0, 0.0, 0.0],
            [0.0, 0.5],
        ),
        (
            "sphere",
            30.0,
            [0.0, 5.0, 0.0],
            [0.0, -1.0, 0.0],
            [0.25, 0.5],
        ),
        (
            "sphere",
            30.0,
            [-5.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.5, 0.5],
        ),
        (
            "sphere",
            30.0,
            [0.0, -5.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.75, 0.5],
        ),
        (
            "sphere",
            30.0,
            [5.0, 0.01, 0.5],
            [-1.0, 0.0, 0.0],
            [0.0018, 0.3333],
        ),
        (
            "sphere",
            30.0,
            [5.0, -0.01, 0.5],
            [-1.0, 0.0, 0.0],
            [0.9982, 0.3333],
        ),
        ("sphere", 30.0, [0.3, 0.4, 5.0], down, [0.1476, 0.1667]),
    ];
    // Mitsuba's cube: three points on each face (rays along the face's inward normal).
    let cube: [([f64; 3], [f64; 2]); 18] = [
        ([-1.0, -0.8, -0.8], [0.1, 0.1]),
        ([-1.0, 0.8, -0.8], [0.9, 0.1]),
        ([-1.0, -0.8, 0.8], [0.1, 0.9]),
        ([1.0, -0.8, -0.8], [0.1, 0.9]),
        ([1.0, 0.8, -0.8], [0.9, 0.9]),
        ([1.0, -0.8, 0.8], [0.1, 0.1]),
        ([-0.8, -1.0, -0.8], [0.1, 0.1]),
        ([-0.8, -1.0, 0.8], [0.9, 0.1]),
        ([0.8, -1.0, -0.8], [0.1, 0.9]),
        ([-0.8, 1.0, -0.8], [0.9, 0.9]),
        ([-0.8, 1.0, 0.8], [0.9, 0.1]),
        ([0.8, 1.0, -0.8], [0.1, 0.9]),
        ([-0.8, -0.8, -1.0], [0.9, 0.1]),
        ([0.8, -0.8, -1.0], [0.9, 0.9]),
        ([-0.8, 0.8, -1.0], [0.1, 0.1]),
        ([-0.8, -0.8, 1.0], [0.1, 0.1]),
        ([0.8, -0.8, 1.0], [0.1, 0.9]),
        ([-0.8, 0.8, 1.0], [0.9, 0.1]),
    ];
    for (p, uv) in cube {
        let a = (0..3).find(|&i| p[i].abs() == 1.0).unwrap();
        let mut o = p;
        o[a] *= 5.0;
        let mut d = [0.0; 3];
        d[a] = -p[a];
        probes.push(("cube", 40.0, o, d, uv));
    }
    let pair = |t: &Value, k: &str, default: f64| -> [f64; 2] {
        match t {
            Value::Map(m) => match m.iter().find(|(key, _)| **key == Value::String(k.into())) {
                Some((_, Value::Seq(p))) => [f(&p[0]), f(&p[1])],
                _ => [default; 2],
            },
            _ => [default; 2],
        }
    };
    for (id, dx, o, d, want) in probes {
        let ray = crate::geometry::Ray::new(
            glam::Vec3A::new((o[0] + dx) as f32, o[1] as f32, o[2] as f32),
            glam::Vec3A::new(d[0] as f32, d[1] as f32, d[2] as f32),
        );
        let hit = scene.geometry.intersect(&ray, f32::INFINITY).unwrap();
        let obj = &c.desc.objects[hit.object as usize];
        assert!(obj.name.starts_with(id), "{id}: hit {}", obj.name);
        let mat = c
            .desc
            .materials
            .iter()
            .find(|m| m.name == obj.material)
            .unwrap();
        let tex = get(get(&mat.params, "reflectance"), "texture");
        let (sc, of) = (pair(tex, "uv_scale", 1.0), pair(tex, "uv_offset", 0.0));
        let u = hit.uv.x as f64 * sc[0] + of[0];
        let row = 1.0 - (hit.uv.y as f64 * sc[1] + of[1]);
        // Modulo 1 (the sphere's u and the disk's v wrap around; the texture repeats).
        let circular = |a: f64, b: f64| {
            let d = (a - b).rem_euclid(1.0);
            d.min(1.0 - d)
        };
        let (du, dv) = (circular(u, want[0]), circular(row, want[1]));
        println!(
            "{id} at {o:?}: Mitsuba {want:?}, spectrace ({:.4}, {row:.4})",
            u.rem_euclid(1.0)
        );
        assert!(
            du < 2e-3 && dv < 2e-3,
            "{id} at {o:?}: Mitsuba's uv {want:?}, the converted scene's ({u}, {row})"
        );
    }
}

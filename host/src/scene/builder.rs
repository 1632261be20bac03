//! From a RON scene file (or a [`SceneDescription`]) to a renderable [`Scene`].

use super::description::{ObjectDescription, SceneDescription, TransformStep};
use super::factory::{FactoryContext, FactoryError, ObjectFactory, SpdFactories};
use super::params::{as_f64_list, Params};
use super::representation::RepresentationOptions;
use super::{Scene, SceneError, SceneObject, SceneObjectManager, SceneOptions};
use crate::camera::manager::NamedCamera;
use crate::camera::{CameraManager, Filter, FovAxis, PerspectiveCamera};
use crate::color::{CieObserverKind, Observer, ResampledObserver, RgbColorSpace};
use crate::geometry::{
    load_obj, load_ply, Geometry, GeometryError, Shape, ShapeDesc, Transform, TriangleMesh,
};
use crate::light::{AreaLight, Light, LightSourceManager};
use crate::material::Material;
use glam::{DVec3, Vec2, Vec3A};
use ron::Value;
use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

/// Parse RON text into a description; syntax errors carry `file:line:column`.
pub fn parse_scene_str(text: &str, file: &Path) -> Result<SceneDescription, SceneError> {
    ron::Options::default()
        .with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME)
        .from_str::<SceneDescription>(text)
        .map_err(|e| SceneError::Syntax {
            file: file.to_path_buf(),
            line: e.position.line,
            column: e.position.col,
            message: e.code.to_string(),
        })
}

/// Read, parse and build a scene file; relative paths inside resolve against its directory.
pub fn load_scene_file(path: &Path, factories: &[&dyn ObjectFactory]) -> Result<Scene, SceneError> {
    load_scene_file_with(path, factories, &RepresentationOptions::default())
}

/// [`load_scene_file`] with the spectral representation switches `representation`.
pub fn load_scene_file_with(
    path: &Path,
    factories: &[&dyn ObjectFactory],
    representation: &RepresentationOptions,
) -> Result<Scene, SceneError> {
    let text =
        crate::limits::read_text_limited(path, crate::limits::SCENE_FILE_MAX_BYTES, "scene file")
            .map_err(|source| SceneError::Io {
            file: path.to_path_buf(),
            source,
        })?;
    let desc = parse_scene_str(&text, path)?;
    let base = path.parent().unwrap_or(Path::new("."));
    build_scene_with(&desc, base, path, factories, representation)
}

/// Ask each factory in turn; the first that knows the type builds it.
fn first_known<T>(
    factories: &[&dyn ObjectFactory],
    kind: &'static str,
    type_name: &str,
    mut f: impl FnMut(&dyn ObjectFactory) -> Result<T, FactoryError>,
) -> Result<T, String> {
    for fac in factories {
        match f(*fac) {
            Ok(v) => return Ok(v),
            Err(FactoryError::UnknownType { .. }) => continue,
            Err(e) => return Err(e.to_string()),
        }
    }
    let known: Vec<String> = factories
        .iter()
        .flat_map(|f| f.known_types())
        .filter(|(k, _)| *k == kind)
        .map(|(_, t)| t)
        .collect();
    Err(format!(
        "unknown {kind} type `{type_name}`; known {kind} types: {}",
        known.join(", ")
    ))
}

/// Build a scene from a description. `file` is only used in messages; `base_dir` resolves
/// relative paths.
pub fn build_scene(
    desc: &SceneDescription,
    base_dir: &Path,
    file: &Path,
    factories: &[&dyn ObjectFactory],
) -> Result<Scene, SceneError> {
    build_scene_with(
        desc,
        base_dir,
        file,
        factories,
        &RepresentationOptions::default(),
    )
}

/// [`build_scene`] with the spectral representation switches `representation`: they reach
/// every item through [`FactoryContext::representation`], and a coarser observer step replaces
/// the scene's observer by its [`ResampledObserver`].
pub fn build_scene_with(
    desc: &SceneDescription,
    base_dir: &Path,
    file: &Path,
    factories: &[&dyn ObjectFactory],
    representation: &RepresentationOptions,
) -> Result<Scene, SceneError> {
    let item_err = |item: String, message: String| SceneError::Item {
        file: file.to_path_buf(),
        item,
        message,
    };
    let spd_factories = SpdFactories(
        factories
            .iter()
            .filter_map(|f| f.shared_spd_factory())
            .collect(),
    );
    let ctx_for = |item: &str| FactoryContext {
        base_dir: base_dir.to_path_buf(),
        item: item.to_string(),
        representation: *representation,
        spd_factories: spd_factories.clone(),
    };

    // Observer and options.
    let obs_name = desc.observer.as_deref().unwrap_or("cie1931-2");
    let observer: Arc<dyn Observer> = match CieObserverKind::from_name(obs_name) {
        Some(kind) => Arc::new(kind.get().clone()),
        // Not a CIE name: an observer type from a factory (a plugin), with default parameters.
        None => first_known(factories, "observer", obs_name, |f| {
            f.observer(obs_name, &ron::Value::Unit, &ctx_for("observer"))
        })
        .map_err(|e| {
            let names: Vec<&str> = CieObserverKind::ALL.iter().map(|k| k.name()).collect();
            item_err(
                "observer".into(),
                format!("{e} (built-in observers: {})", names.join(", ")),
            )
        })?,
    };
    let observer = ResampledObserver::wrap(observer, representation.observer_step_nm)
        .map_err(|e| item_err("observer".into(), e.to_string()))?;
    let mut options = SceneOptions::default();
    if let Some(s) = desc.output.spp {
        options.spp = s.max(1);
    }
    if let Some(d) = desc.output.max_depth {
        options.max_depth = d;
    }
    if let Some(e) = desc.output.png_exposure {
        options.png_exposure = e;
    }
    if let Some(name) = &desc.output.rgb_space {
        options.rgb_space = RgbColorSpace::by_name(name).ok_or_else(|| {
            item_err(
                "output".into(),
                format!("parameter `rgb_space`: unknown RGB space `{name}`; known: srgb, rec2020, display-p3, aces2065-1"),
            )
        })?;
        options.rgb_space_name = name.clone();
    }

    // Materials.
    let mut materials: HashMap<&str, Arc<dyn Material>> = HashMap::new();
    for m in &desc.materials {
        let item = format!("material {:?}", m.name);
        if materials.contains_key(m.name.as_str()) {
            return Err(item_err(item, "duplicate material name".into()));
        }
        let ctx = ctx_for(&item);
        let mat = first_known(factories, "material", &m.type_name, |f| {
            f.material(&m.type_name, &m.params, &ctx)
        })
        .map_err(|e| item_err(item.clone(), e))?;
        materials.insert(m.name.as_str(), mat);
    }

    // Objects and geometry.
    let mut shapes = Vec::with_capacity(desc.objects.len());
    let mut objects = Vec::with_capacity(desc.objects.len());
    let mut names = HashMap::new();
    for o in &desc.objects {
        let item = format!("object {:?}", o.name);
        if names.insert(o.name.as_str(), ()).is_some() {
            return Err(item_err(item, "duplicate object name".into()));
        }
        let material = materials.get(o.material.as_str()).cloned().ok_or_else(|| {
            item_err(
                item.clone(),
                format!("material `{}` is not defined in `materials`", o.material),
            )
        })?;
        let shape = build_shape(o, &ctx_for(&item)).map_err(|e| item_err(item.clone(), e))?;
        let transform = build_transform(&o.transform)
            .map_err(|e| item_err(item.clone(), format!("transform: {e}")))?;
        shapes.push(ShapeDesc { shape, transform });
        objects.push(SceneObject {
            name: o.name.clone(),
            material,
        });
    }
    if shapes.is_empty() {
        return Err(SceneError::Scene {
            file: file.to_path_buf(),
            message: "the scene has no objects".into(),
        });
    }
    let geometry = Arc::new(Geometry::build(shapes).map_err(|e| match e {
        GeometryError::InvalidObject { object, message } => {
            item_err(format!("object {:?}", desc.objects[object].name), message)
        }
        other => SceneError::Scene {
            file: file.to_path_buf(),
            message: other.to_string(),
        },
    })?);

    // Lights: area lights from emissive objects, then the listed lights.
    let mut lights: Vec<Arc<dyn Light>> = Vec::new();
    for (i, o) in objects.iter().enumerate() {
        if let Some(profile) = o.material.emission() {
            if geometry.object_area(i as u32) > 0.0 {
                lights.push(Arc::new(AreaLight::new(
                    geometry.clone(),
                    i as u32,
                    profile,
                )));
            }
        }
    }
    for l in &desc.lights {
        let item = format!("light {:?}", l.name);
        let ctx = ctx_for(&item);
        let light = first_known(factories, "light", &l.type_name, |f| {
            f.light(&l.type_name, &l.params, &ctx)
        })
        .map_err(|e| item_err(item.clone(), e))?;
        lights.push(light);
    }
    let bounds = geometry.bounds();
    for l in &lights {
        l.preprocess(&bounds);
    }
    let lights = LightSourceManager::new(lights, objects.len());

    // Cameras.
    let mut cameras = CameraManager::new();
    for c in &desc.cameras {
        let item = format!("camera {:?}", c.name);
        let cam = build_camera(&c.type_name, &c.params).map_err(|e| item_err(item.clone(), e))?;
        cameras
            .add(NamedCamera {
                name: c.name.clone(),
                camera: Arc::new(cam.0),
                filter: cam.1,
            })
            .map_err(|e| item_err(item, e))?;
    }
    if cameras.cameras().is_empty() {
        return Err(SceneError::Scene {
            file: file.to_path_buf(),
            message: "the scene has no camera".into(),
        });
    }

    Ok(Scene {
        geometry,
        objects: SceneObjectManager::new(objects),
        cameras,
        lights,
        observer,
        options,
    })
}

fn build_transform(steps: &[TransformStep]) -> Result<Transform, String> {
    let mut t = Transform::IDENTITY;
    for s in steps {
        let next = match s {
            TransformStep::Translate(v) => Ok(Transform::translate(DVec3::from_array(*v))),
            TransformStep::Scale(v) => Transform::scale(DVec3::from_array(*v)),
            TransformStep::Rotate { axis, degrees } => {
                Transform::rotate(DVec3::from_array(*axis), *degrees)
            }
            TransformStep::Matrix(m) => Transform::from_rows(*m),
        }
        .map_err(|e| e.to_string())?;
        t = t.then(&next);
    }
    Ok(t)
}

fn vec3_list(v: Option<&Value>, param: &str) -> Result<Vec<Vec3A>, String> {
    let Some(Value::Seq(items)) = v else {
        return Err(format!("parameter `{param}`: expected a list of (x, y, z)"));
    };
    items
        .iter()
        .enumerate()
        .map(|(i, it)| {
            as_f64_list(it)
                .filter(|l| l.len() == 3)
                .map(|l| Vec3A::new(l[0] as f32, l[1] as f32, l[2] as f32))
                .ok_or_else(|| format!("parameter `{param}`: entry {i} is not (x, y, z)"))
        })
        .collect()
}

fn build_shape(o: &ObjectDescription, ctx: &FactoryContext) -> Result<Shape, String> {
    let p = Params::new(&o.params);
    let pe = |e: super::params::ParamError| e.to_string();
    match o.type_name.as_str() {
        "sphere" => {
            p.expect_only(&["center", "radius"]).map_err(pe)?;
            let radius = p.f32("radius").map_err(pe)?;
            if !(radius > 0.0) {
                return Err("parameter `radius`: must be > 0".into());
            }
            Ok(Shape::Sphere {
                center: p.vec3_or("center", Vec3A::ZERO).map_err(pe)?,
                radius,
            })
        }
        "quad" => {
            p.expect_only(&["corner", "edge0", "edge1"]).map_err(pe)?;
            Ok(Shape::Quad {
                corner: p.vec3("corner").map_err(pe)?,
                edge0: p.vec3("edge0").map_err(pe)?,
                edge1: p.vec3("edge1").map_err(pe)?,
            })
        }
        "mesh" => {
            p.expect_only(&["positions", "indices", "normals", "uvs"])
                .map_err(pe)?;
            let positions = vec3_list(p.get("positions"), "positions")?;
            let Some(Value::Seq(idx)) = p.get("indices") else {
                return Err("parameter `indices`: expected a list of (a, b, c)".into());
            };
            let indices = idx
                .iter()
                .enumerate()
                .map(|(i, it)| {
                    as_f64_list(it)
                        .filter(|l| l.len() == 3 && l.iter().all(|x| *x >= 0.0 && x.fract() == 0.0))
                        .map(|l| [l[0] as u32, l[1] as u32, l[2] as u32])
                        .ok_or_else(|| {
                            format!("parameter `indices`: entry {i} is not three vertex indices")
                        })
                })
                .collect::<Result<Vec<_>, _>>()?;
            let normals = match p.get("normals") {
                Some(v) => Some(vec3_list(Some(v), "normals")?),
                None => None,
            };
            let uvs = match p.get("uvs") {
                Some(Value::Seq(items)) => Some(
                    items
                        .iter()
                        .enumerate()
                        .map(|(i, it)| {
                            as_f64_list(it)
                                .filter(|l| l.len() == 2)
                                .map(|l| Vec2::new(l[0] as f32, l[1] as f32))
                                .ok_or_else(|| format!("parameter `uvs`: entry {i} is not (u, v)"))
                        })
                        .collect::<Result<Vec<_>, _>>()?,
                ),
                Some(_) => return Err("parameter `uvs`: expected a list of (u, v)".into()),
                None => None,
            };
            let mesh = TriangleMesh {
                positions,
                normals,
                uvs,
                indices,
            };
            mesh.validate().map_err(|e| e.to_string())?;
            Ok(Shape::Mesh(mesh))
        }
        "obj" | "ply" => {
            p.expect_only(&["file"]).map_err(pe)?;
            let path = ctx.resolve(p.string("file").map_err(pe)?);
            let mesh = if o.type_name == "obj" {
                load_obj(&path)
            } else {
                load_ply(&path)
            }
            .map_err(|e| e.to_string())?;
            Ok(Shape::Mesh(mesh))
        }
        other => Err(format!(
            "unknown object type `{other}`; known: mesh, obj, ply, sphere, quad"
        )),
    }
}

fn build_camera(type_name: &str, params: &Value) -> Result<(PerspectiveCamera, Filter), String> {
    let p = Params::new(params);
    let pe = |e: super::params::ParamError| e.to_string();
    match type_name {
        "perspective" | "pinhole" | "thin_lens" => {}
        other => {
            return Err(format!(
                "unknown camera type `{other}`; known: perspective, pinhole, thin_lens"
            ))
        }
    }
    p.expect_only(&[
        "position",
        "look_at",
        "up",
        "fov",
        "fov_axis",
        "resolution",
        "lens_radius",
        "focus_distance",
        "filter",
    ])
    .map_err(pe)?;
    let res = p
        .get("resolution")
        .and_then(as_f64_list)
        .filter(|l| {
            l.len() == 2
                && l.iter()
                    .all(|v| *v >= 1.0 && *v <= 65536.0 && v.fract() == 0.0)
        })
        .ok_or("parameter `resolution`: expected (width, height) in pixels, 1..65536")?;
    crate::limits::check_image_size(res[0] as u64, res[1] as u64)
        .map_err(|e| format!("parameter `resolution`: {e}"))?;
    let fov_axis = match p.string_opt("fov_axis").map_err(pe)?.unwrap_or("x") {
        "x" => FovAxis::X,
        "y" => FovAxis::Y,
        other => {
            return Err(format!(
                "parameter `fov_axis`: expected \"x\" or \"y\", got {other:?}"
            ))
        }
    };
    let lens_radius = if type_name == "pinhole" {
        0.0
    } else {
        p.f32_or("lens_radius", 0.0).map_err(pe)?
    };
    let filter = match p.get("filter") {
        None => Filter::default(),
        Some(Value::String(s)) if s == "box" => Filter::default(),
        Some(Value::String(s)) if s == "gaussian" => Filter::Gaussian {
            sigma: 0.5,
            radius: 1.5,
        },
        Some(v @ Value::Map(_)) => {
            let f = Params::new(v);
            match f.string("type").map_err(pe)? {
                "box" => Filter::Box {
                    radius: f.f32_or("radius", 0.5).map_err(pe)?,
                },
                "gaussian" => Filter::Gaussian {
                    sigma: f.f32_or("sigma", 0.5).map_err(pe)?,
                    radius: f.f32_or("radius", 1.5).map_err(pe)?,
                },
                other => {
                    return Err(format!(
                        "parameter `filter.type`: unknown filter `{other}`; known: box, gaussian"
                    ))
                }
            }
        }
        Some(_) => {
            return Err(
                "parameter `filter`: expected \"box\", \"gaussian\" or (type: .., ...)".into(),
            )
        }
    };
    if !(filter.radius() > 0.0) {
        return Err("parameter `filter`: radius must be > 0".into());
    }
    let cam = PerspectiveCamera::new(
        p.vec3("position").map_err(pe)?,
        p.vec3("look_at").map_err(pe)?,
        p.vec3_or("up", Vec3A::Y).map_err(pe)?,
        p.f32_or("fov", 40.0).map_err(pe)?,
        fov_axis,
        (res[0] as u32, res[1] as u32),
        lens_radius,
        p.f32_or("focus_distance", 1.0).map_err(pe)?,
    )?;
    Ok((cam, filter))
}

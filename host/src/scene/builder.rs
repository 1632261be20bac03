//! From a RON scene file (or a [`SceneDescription`]) to a renderable [`Scene`].

use super::{Scene, SceneError, SceneObject, SceneObjectManager, SceneOptions};
use crate::camera::manager::NamedCamera;
use crate::camera::CameraManager;
use crate::color::{Observer, ResampledObserver, RgbColorSpace};
use crate::geometry::{Geometry, GeometryError, ShapeDesc, Transform};
use crate::light::{AreaLight, Light, LightFlags, LightSourceManager};
use crate::material::Material;
use crate::scene_file::description::{SceneDescription, TransformStep};
use crate::scene_file::factory::{FactoryContext, FactoryError, ObjectFactory, SpdFactories};
use crate::scene_file::representation::RepresentationOptions;
use crate::scene_file::units::{params_in_metres, LengthUnit};
use glam::DVec3;
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
    let desc = read_scene_file(path)?;
    let base = path.parent().unwrap_or(Path::new("."));
    build_scene_with(&desc, base, path, factories, representation)
}

/// Read and parse a scene file (within the scene-file size limit) without building it, for
/// callers that change the description first (e.g. `render --resolution`); build it with
/// [`build_scene_with`] and the file's directory as base.
pub fn read_scene_file(path: &Path) -> Result<SceneDescription, SceneError> {
    if super::mitsuba::is_mitsuba_file(path) {
        return super::mitsuba::read_description(path, &[]);
    }
    let text =
        crate::limits::read_text_limited(path, crate::limits::SCENE_FILE_MAX_BYTES, "scene file")
            .map_err(|source| SceneError::Io {
            file: path.to_path_buf(),
            source,
        })?;
    parse_scene_str(&text, path)
}

/// Read any scene file's description: a Mitsuba XML file with `defines` (`-D name=value`), a
/// RON file as [`read_scene_file`] does (then `defines` must be empty).
pub fn read_scene_file_defined(
    path: &Path,
    defines: &[(String, String)],
) -> Result<SceneDescription, SceneError> {
    if super::mitsuba::is_mitsuba_file(path) {
        super::mitsuba::read_description(path, defines)
    } else if defines.is_empty() {
        read_scene_file(path)
    } else {
        Err(SceneError::Scene {
            file: path.to_path_buf(),
            message: "-D name=value sets parameters of Mitsuba XML scenes only".into(),
        })
    }
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
    // Sorted and once each: a type offered by several factories (the registry and the
    // built-in table both list the built-ins) is named once.
    let known: std::collections::BTreeSet<String> = factories
        .iter()
        .flat_map(|f| f.known_types())
        .filter(|(k, _)| *k == kind)
        .map(|(_, t)| t)
        .collect();
    Err(format!(
        "unknown {kind} type `{type_name}`; known {kind} types: {}",
        known.into_iter().collect::<Vec<_>>().join(", ")
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
    // The scene's factories that share their SPD types, then the built-in table (so a nested
    // `(type: "table", ..)` is found however the scene was built).
    let builtin: Arc<dyn ObjectFactory> = Arc::new(crate::builtin::BuiltinFactory);
    let spd_factories = SpdFactories(
        factories
            .iter()
            .filter_map(|f| f.shared_spd_factory())
            .chain([builtin])
            .collect(),
    );
    let ctx_for = |item: &str| FactoryContext {
        base_dir: base_dir.to_path_buf(),
        item: item.to_string(),
        representation: *representation,
        spd_factories: spd_factories.clone(),
    };

    // Observer and options.
    let (obs_name, obs_params) = desc
        .observer
        .as_ref()
        .map(|o| o.type_and_params())
        .unwrap_or(("cie1931-2", ron::Value::Unit));
    // Every observer, the CIE tables included, is a registered type built with default
    // parameters.
    let observer: Arc<dyn Observer> = first_known(factories, "observer", obs_name, |f| {
        f.observer(obs_name, &obs_params, &ctx_for("observer"))
    })
    .map_err(|e| item_err("observer".into(), e))?;
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
        if !(e.is_finite() && e > 0.0) {
            return Err(item_err(
                "output".into(),
                format!("parameter `png_exposure`: a linear multiplier, finite and > 0, got {e}"),
            ));
        }
        options.png_exposure = e;
        options.png_exposure_given = true;
    }
    if let Some(u) = &desc.units {
        options.length_unit = LengthUnit::parse(u).map_err(|e| item_err("units".into(), e))?;
    }
    let metres = options.length_unit.metres();
    options.relative_emission = match desc.emission_units.as_deref() {
        None | Some("absolute") => false,
        Some("relative") => true,
        Some(other) => {
            return Err(item_err(
                "emission_units".into(),
                format!("unknown value `{other}`; expected \"absolute\" or \"relative\""),
            ))
        }
    };
    // Lengths of lights and cameras in metres: the parameters their type documents in scene
    // units (see `units`).
    let in_metres = |kind: &'static str, type_name: &str, params: &ron::Value| match factories
        .iter()
        .find_map(|f| f.param_docs(kind, type_name))
    {
        Some(docs) => params_in_metres(params, &docs, metres),
        None => params.clone(),
    };
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
        let ctx = ctx_for(&item);
        let shape = first_known(factories, "shape", &o.type_name, |f| {
            f.shape(&o.type_name, &o.params, &ctx)
        })
        .map_err(|e| item_err(item.clone(), e))?;
        let mut transform = build_transform(&o.transform)
            .map_err(|e| item_err(item.clone(), format!("transform: {e}")))?;
        if metres != 1.0 {
            // Last step: the object in metres.
            transform = transform.then(
                &Transform::scale(DVec3::splat(metres))
                    .map_err(|e| item_err(item.clone(), e.to_string()))?,
            );
        }
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
    let mut warnings = Vec::new();
    let mut lights: Vec<Arc<dyn Light>> = Vec::new();
    // The scene item each light came from, for messages.
    let mut light_items: Vec<String> = Vec::new();
    for (i, o) in objects.iter().enumerate() {
        if let Some(profile) = o.material.emission() {
            if geometry.object_area(i as u32) > 0.0 {
                match o.material.emission_texture() {
                    Some(texture) => {
                        let texels = texture.texels_shown();
                        lights.push(Arc::new(crate::light::TexturedAreaLight::new(
                            geometry.clone(),
                            i as u32,
                            profile,
                            texture,
                            texels,
                        )))
                    }
                    None => lights.push(Arc::new(AreaLight::new(
                        geometry.clone(),
                        i as u32,
                        profile,
                    ))),
                }
                light_items.push(format!("object {:?}", o.name));
            } else {
                warnings.push(format!(
                    "object {:?} has an emissive material but zero area: it emits nothing",
                    o.name
                ));
            }
        }
    }
    for l in &desc.lights {
        let item = format!("light {:?}", l.name);
        let ctx = ctx_for(&item);
        let params = in_metres("light", &l.type_name, &l.params);
        let light = first_known(factories, "light", &l.type_name, |f| {
            f.light(&l.type_name, &params, &ctx)
        })
        .map_err(|e| item_err(item.clone(), e))?;
        lights.push(light);
        light_items.push(item);
    }
    // Cameras.
    let mut cameras = CameraManager::new();
    for c in &desc.cameras {
        let item = format!("camera {:?}", c.name);
        let ctx = ctx_for(&item);
        let params = in_metres("camera", &c.type_name, &c.params);
        let cam = first_known(factories, "camera", &c.type_name, |f| {
            f.camera(&c.type_name, &params, &ctx)
        })
        .map_err(|e| item_err(item.clone(), e))?;
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

    // Lights learn the scene's extent; an environment light wraps every camera too.
    let environments: Vec<usize> = (0..lights.len())
        .filter(|&i| lights[i].flags().contains(LightFlags::ENVIRONMENT))
        .collect();
    if environments.len() > 1 {
        let named = |i: usize| match i.checked_sub(lights.len() - desc.lights.len()) {
            Some(k) => format!("light {:?}", desc.lights[k].name),
            None => format!("light {i}"),
        };
        return Err(SceneError::Scene {
            file: file.to_path_buf(),
            message: format!(
                "a scene can have one environment light, but {} and {} both are one",
                named(environments[0]),
                named(environments[1])
            ),
        });
    }
    let bounds = geometry.bounds();
    let view_bounds = cameras
        .cameras()
        .iter()
        .fold(bounds, |b, c| b.grow(c.camera.position()));
    for l in &lights {
        l.preprocess(&bounds);
        l.preprocess_view(&view_bounds);
    }
    // Total powers (known once the lights know the scene's extent): finite or refused, and
    // what makes a light or the whole scene contribute nothing is a warning.
    let mut powers = Vec::with_capacity(lights.len());
    for (l, item) in lights.iter().zip(&light_items) {
        let power = l.power();
        super::warnings::light_power(item, power, &mut warnings)
            .map_err(|e| item_err(item.clone(), e))?;
        if let Some(w) = l.build_warning() {
            warnings.push(format!("{item}: {w}"));
        }
        powers.push(power);
    }
    warnings.extend(crate::scene_file::units::undeclared_unit_warning(
        desc.units.is_some(),
        f64::from((bounds.max - bounds.min).max_element()),
    ));
    warnings.extend(super::warnings::no_light(&powers));
    warnings.extend(super::warnings::all_black(&objects));
    let names: Vec<&str> = objects.iter().map(|o| o.name.as_str()).collect();
    warnings.extend(super::warnings::coordinate_precision(&geometry, &names));
    warnings.extend(super::warnings::fluorescence_without_data(&objects));
    warnings.extend(super::warnings::blind_cameras(
        &geometry,
        cameras.cameras(),
        !environments.is_empty(),
    ));
    let lights = LightSourceManager::new(lights, objects.len());
    options.light_items = light_items;
    let sensors = crate::builtin::sensor::grid::build_sensors(&desc.sensors, metres)
        .map_err(|(item, e)| item_err(item, e))?;
    let glare =
        crate::builtin::sensor::glare_observer::build_glare_observers(&desc.sensors, metres)
            .map_err(|(item, e)| item_err(item, e))?;

    Ok(Scene {
        geometry,
        objects: SceneObjectManager::new(objects),
        cameras,
        lights,
        observer,
        options,
        warnings,
        sensors,
        glare,
    })
}

fn build_transform(steps: &[TransformStep]) -> Result<Transform, String> {
    let mut t = Transform::IDENTITY;
    for s in steps {
        let next = match s {
            TransformStep::Translate(v) if !v.iter().all(|x| x.is_finite()) => {
                return Err(format!("translation must be finite, got {v:?}"))
            }
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

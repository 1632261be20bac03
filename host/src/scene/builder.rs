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
    let b = SceneBuilder::new(desc, base_dir, file, factories, representation);
    let observer = b.observer()?;
    let mut options = b.options()?;
    let metres = options.length_unit.metres();
    let materials = b.materials()?;
    let (shapes, objects) = b.objects(&materials, metres)?;
    let geometry = b.geometry(shapes)?;

    // Lights: area lights from emissive objects, then the listed lights.
    let mut warnings = Vec::new();
    let mut lights = area_lights(&geometry, &objects, &mut warnings);
    b.listed_lights(metres, &mut lights)?;
    let cameras = b.cameras(metres)?;
    let has_environment = b.prepare_lights(&lights, &geometry, &cameras)?;
    let powers = b.light_powers(&lights, &mut warnings)?;
    let bounds = geometry.bounds();
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
        has_environment,
    ));
    let (lights, light_items): (Vec<_>, Vec<_>) = lights.into_iter().unzip();
    let lights = LightSourceManager::new(lights, objects.len());
    options.light_items = light_items;
    let sensors = crate::builtin::sensor::grid::build_sensors(&desc.sensors, metres)
        .map_err(|(item, e)| b.item_err(item, e))?;
    let glare =
        crate::builtin::sensor::glare_observer::build_glare_observers(&desc.sensors, metres)
            .map_err(|(item, e)| b.item_err(item, e))?;

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

/// A light and the scene item it came from (`object "lamp"`, `light "sun"`), for messages.
type ItemLight = (Arc<dyn Light>, String);

/// What every step of [`build_scene_with`] shares: the description, where it came from and the
/// factories that build its items.
struct SceneBuilder<'a> {
    desc: &'a SceneDescription,
    base_dir: &'a Path,
    file: &'a Path,
    factories: &'a [&'a dyn ObjectFactory],
    representation: RepresentationOptions,
    /// The scene's factories that share their SPD types, then the built-in table (so a nested
    /// `(type: "table", ..)` is found however the scene was built).
    spd_factories: SpdFactories,
}

impl<'a> SceneBuilder<'a> {
    fn new(
        desc: &'a SceneDescription,
        base_dir: &'a Path,
        file: &'a Path,
        factories: &'a [&'a dyn ObjectFactory],
        representation: &RepresentationOptions,
    ) -> Self {
        let builtin: Arc<dyn ObjectFactory> = Arc::new(crate::builtin::BuiltinFactory);
        let spd_factories = SpdFactories(
            factories
                .iter()
                .filter_map(|f| f.shared_spd_factory())
                .chain([builtin])
                .collect(),
        );
        Self {
            desc,
            base_dir,
            file,
            factories,
            representation: *representation,
            spd_factories,
        }
    }

    /// An error in scene item `item` (e.g. `material "red"`).
    fn item_err(&self, item: String, message: String) -> SceneError {
        SceneError::Item {
            file: self.file.to_path_buf(),
            item,
            message,
        }
    }

    /// An error about the scene as a whole.
    fn scene_err(&self, message: String) -> SceneError {
        SceneError::Scene {
            file: self.file.to_path_buf(),
            message,
        }
    }

    /// What a factory is told while it builds `item`.
    fn ctx_for(&self, item: &str) -> FactoryContext {
        FactoryContext {
            base_dir: self.base_dir.to_path_buf(),
            item: item.to_string(),
            representation: self.representation,
            spd_factories: self.spd_factories.clone(),
        }
    }

    /// Lengths of lights and cameras in metres: the parameters their type documents in scene
    /// units (see `units`).
    fn in_metres(
        &self,
        kind: &'static str,
        type_name: &str,
        params: &ron::Value,
        metres: f64,
    ) -> ron::Value {
        match self
            .factories
            .iter()
            .find_map(|f| f.param_docs(kind, type_name))
        {
            Some(docs) => params_in_metres(params, &docs, metres),
            None => params.clone(),
        }
    }

    /// The observer (CIE 1931 2° unless the scene names one), resampled to the representation's
    /// step. Every observer, the CIE tables included, is a registered type built with default
    /// parameters.
    fn observer(&self) -> Result<Arc<dyn Observer>, SceneError> {
        let (obs_name, obs_params) = self
            .desc
            .observer
            .as_ref()
            .map(|o| o.type_and_params())
            .unwrap_or(("cie1931-2", ron::Value::Unit));
        let observer: Arc<dyn Observer> = first_known(self.factories, "observer", obs_name, |f| {
            f.observer(obs_name, &obs_params, &self.ctx_for("observer"))
        })
        .map_err(|e| self.item_err("observer".into(), e))?;
        ResampledObserver::wrap(observer, self.representation.observer_step_nm)
            .map_err(|e| self.item_err("observer".into(), e.to_string()))
    }

    /// The render options the scene file sets: `output`, `units`, `emission_units`.
    fn options(&self) -> Result<SceneOptions, SceneError> {
        let desc = self.desc;
        let mut options = SceneOptions::default();
        if let Some(s) = desc.output.spp {
            options.spp = s.max(1);
        }
        if let Some(d) = desc.output.max_depth {
            options.max_depth = d;
        }
        if let Some(e) = desc.output.png_exposure {
            if !(e.is_finite() && e > 0.0) {
                return Err(self.item_err(
                    "output".into(),
                    format!(
                        "parameter `png_exposure`: a linear multiplier, finite and > 0, got {e}"
                    ),
                ));
            }
            options.png_exposure = e;
            options.png_exposure_given = true;
        }
        if let Some(u) = &desc.units {
            options.length_unit =
                LengthUnit::parse(u).map_err(|e| self.item_err("units".into(), e))?;
        }
        options.relative_emission = match desc.emission_units.as_deref() {
            None | Some("absolute") => false,
            Some("relative") => true,
            Some(other) => {
                return Err(self.item_err(
                    "emission_units".into(),
                    format!("unknown value `{other}`; expected \"absolute\" or \"relative\""),
                ))
            }
        };
        if let Some(name) = &desc.output.rgb_space {
            options.rgb_space = RgbColorSpace::by_name(name).ok_or_else(|| {
                self.item_err(
                    "output".into(),
                    format!("parameter `rgb_space`: unknown RGB space `{name}`; known: srgb, rec2020, display-p3, aces2065-1"),
                )
            })?;
            options.rgb_space_name = name.clone();
        }
        Ok(options)
    }

    /// The named materials (names unique).
    fn materials(&self) -> Result<HashMap<&'a str, Arc<dyn Material>>, SceneError> {
        let desc: &'a SceneDescription = self.desc;
        let mut materials: HashMap<&'a str, Arc<dyn Material>> = HashMap::new();
        for m in &desc.materials {
            let item = format!("material {:?}", m.name);
            if materials.contains_key(m.name.as_str()) {
                return Err(self.item_err(item, "duplicate material name".into()));
            }
            let ctx = self.ctx_for(&item);
            let mat = first_known(self.factories, "material", &m.type_name, |f| {
                f.material(&m.type_name, &m.params, &ctx)
            })
            .map_err(|e| self.item_err(item.clone(), e))?;
            materials.insert(m.name.as_str(), mat);
        }
        Ok(materials)
    }

    /// Each object's shape with its transform (ending in metres) and its material; at least one.
    fn objects(
        &self,
        materials: &HashMap<&str, Arc<dyn Material>>,
        metres: f64,
    ) -> Result<(Vec<ShapeDesc>, Vec<SceneObject>), SceneError> {
        let desc = self.desc;
        let mut shapes = Vec::with_capacity(desc.objects.len());
        let mut objects = Vec::with_capacity(desc.objects.len());
        let mut names = HashMap::new();
        for o in &desc.objects {
            let item = format!("object {:?}", o.name);
            if names.insert(o.name.as_str(), ()).is_some() {
                return Err(self.item_err(item, "duplicate object name".into()));
            }
            let material = materials.get(o.material.as_str()).cloned().ok_or_else(|| {
                self.item_err(
                    item.clone(),
                    format!("material `{}` is not defined in `materials`", o.material),
                )
            })?;
            let ctx = self.ctx_for(&item);
            let shape = first_known(self.factories, "shape", &o.type_name, |f| {
                f.shape(&o.type_name, &o.params, &ctx)
            })
            .map_err(|e| self.item_err(item.clone(), e))?;
            let mut transform = build_transform(&o.transform)
                .map_err(|e| self.item_err(item.clone(), format!("transform: {e}")))?;
            if metres != 1.0 {
                // Last step: the object in metres.
                transform = transform.then(
                    &Transform::scale(DVec3::splat(metres))
                        .map_err(|e| self.item_err(item.clone(), e.to_string()))?,
                );
            }
            shapes.push(ShapeDesc { shape, transform });
            objects.push(SceneObject {
                name: o.name.clone(),
                material,
            });
        }
        if shapes.is_empty() {
            return Err(self.scene_err("the scene has no objects".into()));
        }
        Ok((shapes, objects))
    }

    /// The geometry of `shapes` (an object refused by it is named).
    fn geometry(&self, shapes: Vec<ShapeDesc>) -> Result<Arc<Geometry>, SceneError> {
        let geometry = Geometry::build(shapes).map_err(|e| match e {
            GeometryError::InvalidObject { object, message } => self.item_err(
                format!("object {:?}", self.desc.objects[object].name),
                message,
            ),
            other => self.scene_err(other.to_string()),
        })?;
        Ok(Arc::new(geometry))
    }

    /// The scene's `lights`, appended to `lights`.
    fn listed_lights(&self, metres: f64, lights: &mut Vec<ItemLight>) -> Result<(), SceneError> {
        for l in &self.desc.lights {
            let item = format!("light {:?}", l.name);
            let ctx = self.ctx_for(&item);
            let params = self.in_metres("light", &l.type_name, &l.params, metres);
            let light = first_known(self.factories, "light", &l.type_name, |f| {
                f.light(&l.type_name, &params, &ctx)
            })
            .map_err(|e| self.item_err(item.clone(), e))?;
            lights.push((light, item));
        }
        Ok(())
    }

    /// The scene's cameras (at least one, names unique).
    fn cameras(&self, metres: f64) -> Result<CameraManager, SceneError> {
        let mut cameras = CameraManager::new();
        for c in &self.desc.cameras {
            let item = format!("camera {:?}", c.name);
            let ctx = self.ctx_for(&item);
            let params = self.in_metres("camera", &c.type_name, &c.params, metres);
            let cam = first_known(self.factories, "camera", &c.type_name, |f| {
                f.camera(&c.type_name, &params, &ctx)
            })
            .map_err(|e| self.item_err(item.clone(), e))?;
            cameras
                .add(NamedCamera {
                    name: c.name.clone(),
                    camera: Arc::new(cam.0),
                    filter: cam.1,
                })
                .map_err(|e| self.item_err(item, e))?;
        }
        if cameras.cameras().is_empty() {
            return Err(self.scene_err("the scene has no camera".into()));
        }
        Ok(cameras)
    }

    /// Lights learn the scene's extent; an environment light wraps every camera too. At most
    /// one environment light; returns whether there is one.
    fn prepare_lights(
        &self,
        lights: &[ItemLight],
        geometry: &Geometry,
        cameras: &CameraManager,
    ) -> Result<bool, SceneError> {
        let environments: Vec<usize> = (0..lights.len())
            .filter(|&i| lights[i].0.flags().contains(LightFlags::ENVIRONMENT))
            .collect();
        if environments.len() > 1 {
            let listed = &self.desc.lights;
            let named = |i: usize| match i.checked_sub(lights.len() - listed.len()) {
                Some(k) => format!("light {:?}", listed[k].name),
                None => format!("light {i}"),
            };
            return Err(self.scene_err(format!(
                "a scene can have one environment light, but {} and {} both are one",
                named(environments[0]),
                named(environments[1])
            )));
        }
        let bounds = geometry.bounds();
        let view_bounds = cameras
            .cameras()
            .iter()
            .fold(bounds, |b, c| b.grow(c.camera.position()));
        for (l, _) in lights {
            l.preprocess(&bounds);
            l.preprocess_view(&view_bounds);
        }
        Ok(!environments.is_empty())
    }

    /// Total powers (known once the lights know the scene's extent): finite or refused, and
    /// what makes a light contribute nothing is a warning.
    fn light_powers(
        &self,
        lights: &[ItemLight],
        warnings: &mut Vec<String>,
    ) -> Result<Vec<f64>, SceneError> {
        let mut powers = Vec::with_capacity(lights.len());
        for (l, item) in lights {
            let power = l.power();
            super::warnings::light_power(item, power, warnings)
                .map_err(|e| self.item_err(item.clone(), e))?;
            if let Some(w) = l.build_warning() {
                warnings.push(format!("{item}: {w}"));
            }
            powers.push(power);
        }
        Ok(powers)
    }
}

/// An area light for each emissive object of nonzero area (textured when its emission is); an
/// emissive object of zero area is a warning.
fn area_lights(
    geometry: &Arc<Geometry>,
    objects: &[SceneObject],
    warnings: &mut Vec<String>,
) -> Vec<ItemLight> {
    let mut lights: Vec<ItemLight> = Vec::new();
    for (i, o) in objects.iter().enumerate() {
        let Some(profile) = o.material.emission() else {
            continue;
        };
        if geometry.object_area(i as u32) > 0.0 {
            let light: Arc<dyn Light> = match o.material.emission_texture() {
                Some(texture) => {
                    let texels = texture.texels_shown();
                    Arc::new(crate::light::TexturedAreaLight::new(
                        geometry.clone(),
                        i as u32,
                        profile,
                        texture,
                        texels,
                    ))
                }
                None => Arc::new(AreaLight::new(geometry.clone(), i as u32, profile)),
            };
            lights.push((light, format!("object {:?}", o.name)));
        } else {
            warnings.push(format!(
                "object {:?} has an emissive material but zero area: it emits nothing",
                o.name
            ));
        }
    }
    lights
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

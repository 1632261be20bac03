//! `perspective` (alias `thin_lens`): a perspective camera with an optional thin lens; and
//! `pinhole`, the same camera with the lens radius forced to 0. Two types in one file because
//! `pinhole` is `perspective` with one parameter fixed.
//!
//! | parameter        | unit        | default   | meaning                                             |
//! |------------------|-------------|-----------|-----------------------------------------------------|
//! | `position`       | scene units | —         | eye position                                        |
//! | `look_at`        | scene units | —         | point looked at                                     |
//! | `up`             | —           | `(0, 1, 0)` | up direction                                      |
//! | `fov`            | degrees     | `40`      | full field of view along `fov_axis`                 |
//! | `fov_axis`       | —           | `"x"`     | `"x"` (width) or `"y"` (height)                     |
//! | `resolution`     | pixels      | —         | (width, height), 1..65536                           |
//! | `lens_radius`    | scene units | `0`       | thin-lens aperture radius (ignored by `pinhole`)    |
//! | `focus_distance` | scene units | `1`       | distance of the plane in focus                      |
//! | `filter`         | pixels      | `"box"`   | `"box"`, `"gaussian"`, `(type: "box", radius: r)` or `(type: "gaussian", sigma: s, radius: r)` |

use crate::builtin::{finite, finite3, from_value, Build, BuiltinType};
use crate::camera::{Filter, FovAxis, PerspectiveCamera};
use crate::scene_file::params::Params;
use crate::scene_file::type_doc::Param;
use crate::scene_file::{FactoryContext, FactoryError};
use glam::Vec3A;
use ron::Value;
use serde::{Deserialize, Serialize};

const PARAMS: &[Param] = &[
    Param::required("position", "scene units", "eye position, (x, y, z)"),
    Param::required("look_at", "scene units", "point looked at"),
    Param::optional("up", "", "(0, 1, 0)", "up direction"),
    Param::optional("fov", "degrees", "40", "full field of view along `fov_axis`"),
    Param::optional("fov_axis", "", "\"x\"", "\"x\" (image width) or \"y\" (height)"),
    Param::required("resolution", "pixels", "(width, height), each 1..65536"),
    Param::optional("lens_radius", "scene units", "0", "thin-lens aperture radius (ignored by `pinhole`)"),
    Param::optional("focus_distance", "scene units", "1", "distance of the plane in focus"),
    Param::optional("filter", "pixels", "\"box\"", "\"box\", \"gaussian\", (type: \"box\", radius: r) or (type: \"gaussian\", sigma: s, radius: r)"),
];

/// The perspective camera.
pub const TYPE: BuiltinType = BuiltinType {
    name: "perspective",
    aliases: &["thin_lens"],
    version: 1,
    description: "perspective camera with an optional thin lens",
    params: PARAMS,
    build: Build::Camera(|v, ctx| build(&from_value(v)?, false, ctx)),
    state: None,
};

/// The pinhole camera.
pub const PINHOLE: BuiltinType = BuiltinType {
    name: "pinhole",
    aliases: &[],
    version: 1,
    description: "perspective camera without a lens (lens_radius is ignored)",
    params: PARAMS,
    build: Build::Camera(|v, ctx| build(&from_value(v)?, true, ctx)),
    state: None,
};

/// Parameters of [`TYPE`] and [`PINHOLE`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PerspectiveParams {
    /// Eye.
    pub position: [f64; 3],
    /// Target.
    pub look_at: [f64; 3],
    /// Up.
    #[serde(default)]
    pub up: Option<[f64; 3]>,
    /// Field of view, degrees.
    #[serde(default)]
    pub fov: Option<f64>,
    /// `x` or `y`.
    #[serde(default)]
    pub fov_axis: Option<String>,
    /// Pixels.
    pub resolution: Value,
    /// Aperture radius.
    #[serde(default)]
    pub lens_radius: Option<f64>,
    /// Focus distance.
    #[serde(default)]
    pub focus_distance: Option<f64>,
    /// Pixel filter.
    #[serde(default)]
    pub filter: Option<Value>,
}

fn err(message: impl Into<String>) -> FactoryError {
    FactoryError::Param(message.into())
}

fn filter(v: &Option<Value>) -> Result<Filter, FactoryError> {
    let pe = |e: crate::scene_file::params::ParamError| {
        err(format!("parameter `filter.{}`: {}", e.param, e.message))
    };
    let f = match v {
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
                    return Err(err(format!(
                        "parameter `filter.type`: unknown filter `{other}`; known: box, gaussian"
                    )))
                }
            }
        }
        Some(_) => {
            return Err(err(
                "parameter `filter`: expected \"box\", \"gaussian\" or (type: .., ...)",
            ))
        }
    };
    if !(f.radius() > 0.0) {
        return Err(err("parameter `filter`: radius must be > 0"));
    }
    Ok(f)
}

/// Build the camera and its filter.
pub fn build(
    p: &PerspectiveParams,
    pinhole: bool,
    _ctx: &FactoryContext,
) -> Result<(PerspectiveCamera, Filter), FactoryError> {
    let res = crate::scene_file::params::as_f64_list(&p.resolution)
        .filter(|l| {
            l.len() == 2
                && l.iter()
                    .all(|v| *v >= 1.0 && *v <= 65536.0 && v.fract() == 0.0)
        })
        .ok_or_else(|| {
            err("parameter `resolution`: expected (width, height) in pixels, 1..65536")
        })?;
    crate::limits::check_image_size(res[0] as u64, res[1] as u64)
        .map_err(|e| err(format!("parameter `resolution`: {e}")))?;
    let fov_axis = match p.fov_axis.as_deref().unwrap_or("x") {
        "x" => FovAxis::X,
        "y" => FovAxis::Y,
        other => {
            return Err(err(format!(
                "parameter `fov_axis`: expected \"x\" or \"y\", got {other:?}"
            )))
        }
    };
    let lens_radius = if pinhole {
        0.0
    } else {
        finite("lens_radius", p.lens_radius.unwrap_or(0.0))? as f32
    };
    let filter = filter(&p.filter)?;
    let cam = PerspectiveCamera::new(
        finite3("position", p.position)?,
        finite3("look_at", p.look_at)?,
        match p.up {
            Some(u) => finite3("up", u)?,
            None => Vec3A::Y,
        },
        finite("fov", p.fov.unwrap_or(40.0))? as f32,
        fov_axis,
        (res[0] as u32, res[1] as u32),
        lens_radius,
        finite("focus_distance", p.focus_distance.unwrap_or(1.0))? as f32,
    )
    .map_err(err)?;
    Ok((cam, filter))
}

//! `luminaire`: a measured luminaire (IES LM-63 or EULUMDAT candela table) as a point light.
//!
//! | parameter    | unit        | default      | meaning                                                        |
//! |--------------|-------------|--------------|----------------------------------------------------------------|
//! | `file`       | —           | —            | `.ies` or `.ldt` file, relative to the scene file (or `table`) |
//! | `table`      | —           | —            | the candela table inline ([`CandelaTable`]; blobs and baked lights store it so) |
//! | `position`   | scene units | —            | where the luminaire is (its photometric centre)                |
//! | `aim`        | —           | `(0, -1, 0)` | world direction of the photometric axis (nadir, γ = 0)         |
//! | `c0`         | —           | `(1, 0, 0)`  | world direction of the C0 half-plane (types A, B: of h = +90°), made perpendicular to `aim` |
//! | `spd`        | —           | `"a"`        | emission spectrum (SPD spectral value)                         |
//! | `flux_lm`    | lm          | the table's  | total luminous flux: the table is scaled to give it            |
//! | `multiplier` | —           | `1`          | factor on every candela value (after `flux_lm`)                |
//! | `tilt_deg`   | degrees     | from `aim`   | lamp tilt angle for the file's TILT table                      |
//!
//! The table gives luminous intensity (cd); with the SPD's luminous efficacy K (lm/W, 683·∫Sȳ,
//! CIE 1931 2°) the radiant intensity is cd/K · S(λ) W/(sr·nm). The default SPD is CIE
//! illuminant A (2856 K), the reference lamp of incandescent photometry: the files give no
//! spectrum, so give the lamp's own SPD when it is known (a bundled lamp such as
//! `phosphor_led_yag` or `blackbody:3000`).
//!
//! Lamp tilt (LM-63 `TILT=INCLUDE` or a tilt file): every candela value is multiplied by the
//! table's factor at the lamp's tilt angle, linear between the table's angles and the end value
//! beyond them. The angle is `tilt_deg` when given, else taken from the orientation, per the
//! file's lamp-to-luminaire geometry: 1 (vertical lamp) the angle between `aim` and straight
//! down; 2 (horizontal lamp along the C0–C180 plane) the elevation of the `c0` axis above the
//! horizontal; 3 (horizontal lamp along C90–C270) that of the C90 axis. The scene's up is +y.

use super::light_spd;
use crate::builtin::spectral::Spectrum;
use crate::builtin::{check, from_value, param_err, state_fns, Build, BuiltinType, Embed};
use crate::light::{Light, LuminaireLight};
use crate::photometry::efficacy::luminous_efficacy_lm_per_w;
use crate::photometry::{load_luminaire, CandelaTable, Luminaire};
use crate::scene_file::type_doc::Param;
use crate::scene_file::{FactoryContext, FactoryError};
use crate::spectrum::parse_spd_spec;
use glam::Vec3A;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// The type.
pub const TYPE: BuiltinType = BuiltinType {
    name: "luminaire",
    aliases: &[],
    version: 1,
    description: "measured luminaire: IES LM-63 or EULUMDAT candela table with an SPD",
    params: &[
        Param::optional(
            "file",
            "",
            "—",
            ".ies or .ldt file, relative to the scene file (give `file` or `table`)",
        ),
        Param::optional(
            "table",
            "cd",
            "—",
            "candela table inline: (photometric_type, symmetry, h_deg, v_deg, candela, ..)",
        ),
        Param::required("position", "scene units", "photometric centre, (x, y, z)"),
        Param::optional(
            "aim",
            "",
            "(0, -1, 0)",
            "world direction of the photometric axis (nadir, gamma = 0)",
        ),
        Param::optional(
            "c0",
            "",
            "(1, 0, 0)",
            "world direction of the C0 half-plane (types A, B: h = +90), made perpendicular to aim",
        ),
        Param::optional(
            "spd",
            "",
            "\"a\"",
            "emission spectrum: spec string, (nm, value) list or (type: .., params: ..)",
        ),
        Param::optional(
            "flux_lm",
            "lm",
            "the table's",
            "total luminous flux; the table is scaled to give it",
        ),
        Param::optional("multiplier", "", "1", "factor on every candela value"),
        Param::optional(
            "tilt_deg",
            "degrees",
            "from aim",
            "lamp tilt angle looked up in the file's TILT table",
        ),
    ],
    build: Build::Light(|v, ctx| build(&from_value(v)?, ctx)),
    state: Some(state_fns::<LuminaireParams>()),
};

/// Parameters of [`TYPE`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LuminaireParams {
    /// Luminaire file, relative to the scene file.
    #[serde(default)]
    pub file: Option<String>,
    /// Inline candela table.
    #[serde(default)]
    pub table: Option<CandelaTable>,
    /// Photometric centre, scene units.
    pub position: [f64; 3],
    /// Photometric axis (nadir) direction.
    #[serde(default)]
    pub aim: Option<[f64; 3]>,
    /// C0 half-plane direction.
    #[serde(default)]
    pub c0: Option<[f64; 3]>,
    /// Emission spectrum.
    #[serde(default)]
    pub spd: Option<Spectrum>,
    /// Total luminous flux override, lm.
    #[serde(default)]
    pub flux_lm: Option<f64>,
    /// Candela multiplier.
    #[serde(default)]
    pub multiplier: Option<f64>,
    /// Lamp tilt angle, degrees.
    #[serde(default)]
    pub tilt_deg: Option<f64>,
}

impl Embed for LuminaireParams {
    /// The file becomes its table, so a blob does not need it.
    fn embed(&mut self, ctx: &FactoryContext) -> Result<(), FactoryError> {
        if let Some(file) = self.file.take() {
            let lum = read_file(&file, ctx)?;
            self.table = Some(CandelaTable::from_luminaire(&lum, &file));
        }
        self.spd.embed(ctx)
    }
}

fn read_file(file: &str, ctx: &FactoryContext) -> Result<Luminaire, FactoryError> {
    load_luminaire(&ctx.resolve(file)).map_err(|e| param_err("file", e))
}

/// The luminaire of `p` (file or table), unscaled.
pub fn luminaire_of(p: &LuminaireParams, ctx: &FactoryContext) -> Result<Luminaire, FactoryError> {
    match (&p.file, &p.table) {
        (Some(f), None) => read_file(f, ctx),
        (None, Some(t)) => t.to_luminaire().map_err(|e| param_err("table", e)),
        (Some(_), Some(_)) => Err(param_err("file", "give `file` or `table`, not both")),
        (None, None) => Err(param_err(
            "file",
            "missing: give an .ies or .ldt `file` (or an inline `table`)",
        )),
    }
}

/// World directions of the luminaire frame's x, y, z axes for `aim` (−y of the frame) and
/// `c0` (+x of the frame, made perpendicular to `aim`).
pub fn frame_axes(aim: Option<[f64; 3]>, c0: Option<[f64; 3]>) -> Result<[Vec3A; 3], FactoryError> {
    let aim = match aim {
        Some(a) => check::direction("aim", a)?.normalize(),
        None => Vec3A::NEG_Y,
    };
    let y = -aim;
    let c0_given = c0.is_some();
    let c0 = match c0 {
        Some(c) => check::direction("c0", c)?.normalize(),
        None if aim.x.abs() < 0.9 => Vec3A::X,
        None => Vec3A::NEG_Z,
    };
    let x = c0 - y * c0.dot(y);
    if !(x.length() > 1e-4) {
        let why = if c0_given {
            "is parallel to `aim`; it must point across the photometric axis"
        } else {
            "cannot be chosen"
        };
        return Err(param_err("c0", why));
    }
    let x = x.normalize();
    Ok([x, y, x.cross(y)])
}

/// The lamp tilt angle in degrees for `geometry` (LM-63 1, 2, 3) with frame `axes` (module docs).
pub fn tilt_angle_deg(geometry: i64, axes: &[Vec3A; 3]) -> f64 {
    let up = Vec3A::Y;
    match geometry {
        // Vertical lamp: angle between the photometric axis (−y of the frame) and straight down.
        1 => (axes[1].dot(up) as f64)
            .clamp(-1.0, 1.0)
            .acos()
            .to_degrees(),
        // Horizontal lamp along C0–C180 (x) or C90–C270 (−z): its elevation.
        2 => (axes[0].dot(up).abs() as f64)
            .clamp(0.0, 1.0)
            .asin()
            .to_degrees(),
        _ => (axes[2].dot(up).abs() as f64)
            .clamp(0.0, 1.0)
            .asin()
            .to_degrees(),
    }
}

/// Build the light.
pub fn build(p: &LuminaireParams, ctx: &FactoryContext) -> Result<Arc<dyn Light>, FactoryError> {
    Ok(Arc::new(build_luminaire(p, ctx)?))
}

/// The factor `flux_lm` and `multiplier` put on the table (tilt not included).
fn user_factor(p: &LuminaireParams, lum: &Luminaire, tilt: f64) -> Result<f64, FactoryError> {
    let mut factor = 1.0;
    if let Some(flux) = p.flux_lm {
        let flux = check::radiometric("flux_lm", flux, "lm")? as f64;
        let table = lum.flux_lm() * tilt;
        if !(table > 0.0) {
            return Err(param_err(
                "flux_lm",
                "the table is all zero, so no scale gives it a flux",
            ));
        }
        // The override fixes the flux the luminaire emits as installed (tilt included).
        factor = flux / table;
    }
    if let Some(m) = p.multiplier {
        factor *= check::radiometric("multiplier", m, "")? as f64;
    }
    Ok(factor)
}

/// The lamp tilt factor of `lum` for `p`'s orientation or `tilt_deg`.
fn tilt_factor(
    p: &LuminaireParams,
    lum: &Luminaire,
    axes: &[Vec3A; 3],
) -> Result<f64, FactoryError> {
    match (&lum.tilt, p.tilt_deg) {
        (Some(t), Some(a)) if a.is_finite() => Ok(t.factor_at(a)),
        (Some(_), Some(a)) => Err(param_err("tilt_deg", format!("{a} is not finite"))),
        (Some(t), None) => Ok(t.factor_at(tilt_angle_deg(t.geometry, axes))),
        (None, Some(_)) => Err(param_err(
            "tilt_deg",
            "the luminaire has no TILT table (TILT=NONE), so a tilt angle changes nothing",
        )),
        (None, None) => Ok(1.0),
    }
}

/// The luminaire as a file would describe it: the table with `flux_lm` and `multiplier`
/// applied, the lamp tilt table kept (not applied), for export.
pub fn exported_luminaire(
    p: &LuminaireParams,
    ctx: &FactoryContext,
) -> Result<Luminaire, FactoryError> {
    let axes = frame_axes(p.aim, p.c0)?;
    let lum = luminaire_of(p, ctx)?;
    let tilt = tilt_factor(p, &lum, &axes)?;
    let factor = user_factor(p, &lum, tilt)?;
    Ok(if factor == 1.0 {
        lum
    } else {
        lum.scaled(factor)
    })
}

/// Build the light as its own type (for callers that need its table or flux).
pub fn build_luminaire(
    p: &LuminaireParams,
    ctx: &FactoryContext,
) -> Result<LuminaireLight, FactoryError> {
    let position = check::position("position", p.position)?;
    let axes = frame_axes(p.aim, p.c0)?;
    let mut lum = luminaire_of(p, ctx)?;
    let tilt = tilt_factor(p, &lum, &axes)?;
    let factor = tilt * user_factor(p, &lum, tilt)?;
    if factor != 1.0 {
        lum = lum.scaled(factor);
    }
    let spd = match &p.spd {
        Some(_) => light_spd(&p.spd, ctx)?,
        None => Arc::new(parse_spd_spec("a").map_err(|e| param_err("spd", e))?),
    };
    let k = luminous_efficacy_lm_per_w(spd.as_ref());
    if !(k > 0.0) {
        return Err(param_err(
            "spd",
            "the spectrum has no visible light (luminous efficacy 0 lm/W), so candela cannot be converted to watts",
        ));
    }
    Ok(LuminaireLight::new(position, axes, lum, spd, k))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The default frame is the identity; `aim` and `c0` give an orthonormal right-handed frame
    /// whose −y is `aim` (1e-6: f32 arithmetic).
    #[test]
    fn frame_from_aim_and_c0() {
        let a = frame_axes(None, None).unwrap();
        assert_eq!(a, [Vec3A::X, Vec3A::Y, Vec3A::Z]);
        let a = frame_axes(Some([1.0, -1.0, 0.0]), Some([0.0, 0.0, 1.0])).unwrap();
        let aim = Vec3A::new(1.0, -1.0, 0.0).normalize();
        assert!((-a[1] - aim).length() < 1e-6);
        assert!((a[0].cross(a[1]) - a[2]).length() < 1e-6);
        assert!(a[0].dot(a[1]).abs() < 1e-6);
        assert!(frame_axes(Some([1.0, 0.0, 0.0]), Some([2.0, 0.0, 0.0])).is_err());
        // Aimed along x with no c0: still a frame.
        assert!(frame_axes(Some([1.0, 0.0, 0.0]), None).is_ok());
    }

    /// Tilt angles by geometry: a luminaire aimed 30° off the nadir about z has a vertical lamp
    /// tilted 30° (geometry 1), its C0 axis raised 30° (geometry 2), its C90 axis level (3).
    #[test]
    fn tilt_angles_by_geometry() {
        let t = 30f64.to_radians();
        let axes = frame_axes(Some([t.sin(), -t.cos(), 0.0]), None).unwrap();
        assert!((tilt_angle_deg(1, &axes) - 30.0).abs() < 1e-3);
        assert!((tilt_angle_deg(2, &axes) - 30.0).abs() < 1e-3);
        assert!(tilt_angle_deg(3, &axes).abs() < 1e-3);
    }
}

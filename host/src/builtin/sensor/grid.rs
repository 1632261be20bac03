//! `illuminance_grid`: a rectangular grid of illuminance measurement points, as a lighting
//! designer lays one over a floor or a desk (EN 12464-1, CIE 171:2006 §2). The points are the
//! centres of the `nx × ny` cells of the parallelogram `corner + s·edge0 + t·edge1`, s, t ∈ [0, 1];
//! each measures the illuminance on the side `edge0 × edge1` points to (the same normal as the
//! `quad` shape), from the whole hemisphere on that side. The sensor is not geometry: it blocks
//! no light and is seen by no ray, so a grid laid on a floor measures what lands on the floor.
//!
//! ```ron
//! sensors: [(name: "floor", type: "illuminance_grid",
//!            params: (corner: (-2, 0, 2), edge0: (4, 0, 0), edge1: (0, 0, -4), resolution: (20, 20)))]
//! ```
//!
//! | parameter    | unit          | default               | meaning                                        |
//! |--------------|---------------|-----------------------|------------------------------------------------|
//! | `corner`     | scene units   | —                     | one corner of the grid, (x, y, z)              |
//! | `edge0`      | scene units   | —                     | first edge; `nx` cells along it                |
//! | `edge1`      | scene units   | —                     | second edge; `ny` cells; normal edge0 × edge1  |
//! | `resolution` | points        | —                     | (nx, ny), each ≥ 1, nx·ny ≤ 1 000 000          |
//! | `samples`    | per point     | the render's spp      | estimator samples per point (≥ 1)              |
//!
//! Results are in lux (lm/m²) with their standard error; see [`crate::sensor::estimate`].

use serde::Deserialize;

/// The scene item type name.
pub const TYPE_NAME: &str = "illuminance_grid";

/// Most points one grid may have (each costs `samples` paths).
pub const MAX_POINTS: u64 = 1_000_000;

pub use super::limits::MAX_SAMPLES;

/// Parameters of an `illuminance_grid`, as written in the scene.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GridParams {
    /// A corner (scene length units).
    pub corner: [f64; 3],
    /// First edge.
    pub edge0: [f64; 3],
    /// Second edge.
    pub edge1: [f64; 3],
    /// Points along edge0 and edge1.
    pub resolution: [u32; 2],
    /// Samples per point (default: the render's samples per pixel).
    #[serde(default)]
    pub samples: Option<u32>,
}

/// A built illuminance grid: its name and geometry in metres (converted from the scene's units
/// by [`build_sensors`]).
#[derive(Clone, Debug, PartialEq)]
pub struct IlluminanceGrid {
    /// Unique name (the output file stem).
    pub name: String,
    /// One corner.
    pub corner: glam::DVec3,
    /// First edge (nx cells along it).
    pub edge0: glam::DVec3,
    /// Second edge (ny cells along it).
    pub edge1: glam::DVec3,
    /// Points along edge0.
    pub nx: u32,
    /// Points along edge1.
    pub ny: u32,
    /// Samples per point, when the scene fixes it.
    pub samples: Option<u32>,
}

impl IlluminanceGrid {
    /// Check and build a grid from its parameters (a RON struct). Errors name the parameter.
    pub fn from_params(name: &str, params: &ron::Value) -> Result<Self, String> {
        let p: GridParams =
            crate::builtin::from_value(params).map_err(|e| format!("parameters: {e}"))?;
        for (key, v) in [("corner", p.corner), ("edge0", p.edge0), ("edge1", p.edge1)] {
            if !v.iter().all(|x| x.is_finite()) {
                return Err(format!("parameter `{key}` must be finite, got {v:?}"));
            }
        }
        let (corner, edge0, edge1) = (
            glam::DVec3::from_array(p.corner),
            glam::DVec3::from_array(p.edge0),
            glam::DVec3::from_array(p.edge1),
        );
        let cross = edge0.cross(edge1);
        if !(cross.length() > 1e-12 * edge0.length() * edge1.length()) || cross.length() == 0.0 {
            return Err(format!(
                "parameters `edge0` {:?} and `edge1` {:?} must be non-zero and not parallel \
                 (their cross product is the grid's normal)",
                p.edge0, p.edge1
            ));
        }
        let [nx, ny] = p.resolution;
        if nx == 0 || ny == 0 || nx as u64 * ny as u64 > MAX_POINTS {
            return Err(format!(
                "parameter `resolution` ({nx}, {ny}): each must be ≥ 1 and nx·ny ≤ {MAX_POINTS}"
            ));
        }
        if let Some(s) = p.samples {
            if s == 0 || s > MAX_SAMPLES {
                return Err(format!(
                    "parameter `samples` {s}: must be between 1 and {MAX_SAMPLES}"
                ));
            }
        }
        Ok(Self {
            name: name.to_string(),
            corner,
            edge0,
            edge1,
            nx,
            ny,
            samples: p.samples,
        })
    }

    /// Unit normal `edge0 × edge1`: the side whose illuminance is measured.
    pub fn normal(&self) -> glam::DVec3 {
        self.edge0.cross(self.edge1).normalize()
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.nx as usize * self.ny as usize
    }

    /// True when the grid has no points (never, once built).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Point `k` (row-major: `k = j·nx + i`, i along edge0), the centre of its cell.
    pub fn point(&self, k: usize) -> glam::DVec3 {
        let (i, j) = (k % self.nx as usize, k / self.nx as usize);
        let s = (i as f64 + 0.5) / self.nx as f64;
        let t = (j as f64 + 0.5) / self.ny as f64;
        self.corner + self.edge0 * s + self.edge1 * t
    }

    /// Every point, row-major.
    pub fn points(&self) -> Vec<glam::DVec3> {
        (0..self.len()).map(|k| self.point(k)).collect()
    }
}

/// Build the scene's `sensors` items, their lengths converted to metres (`metres` per scene
/// unit, see the scene's `units`); an error names the item and what is wrong.
pub fn build_sensors(
    items: &[crate::scene_file::description::ItemDescription],
    metres: f64,
) -> Result<Vec<IlluminanceGrid>, (String, String)> {
    let mut out: Vec<IlluminanceGrid> = Vec::with_capacity(items.len());
    for it in items {
        let item = format!("sensor {:?}", it.name);
        if it.type_name == super::glare_observer::TYPE_NAME {
            continue;
        }
        if it.type_name != TYPE_NAME {
            return Err((
                item,
                format!(
                    "unknown sensor type `{}`; known: {TYPE_NAME}, {}",
                    it.type_name,
                    super::glare_observer::TYPE_NAME
                ),
            ));
        }
        if it.name.is_empty()
            || it
                .name
                .chars()
                .any(|c| !(c.is_alphanumeric() || c == '_' || c == '-' || c == '.'))
        {
            return Err((
                item,
                "a sensor name is also its output file name: use letters, digits, `_`, `-` and `.` \
                 only"
                    .into(),
            ));
        }
        if out.iter().any(|g| g.name == it.name) {
            return Err((item, "duplicate sensor name".into()));
        }
        let mut g = IlluminanceGrid::from_params(&it.name, &it.params).map_err(|e| (item, e))?;
        g.corner *= metres;
        g.edge0 *= metres;
        g.edge1 *= metres;
        out.push(g);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(params: &str) -> Result<IlluminanceGrid, String> {
        IlluminanceGrid::from_params("g", &ron::from_str(params).unwrap())
    }

    /// Points are the cell centres, row-major along edge0, and the normal is edge0 × edge1
    /// (exact arithmetic on these values: tolerance 1e-12).
    #[test]
    fn points_are_cell_centres() {
        let g =
            grid("(corner: (0, 0, 0), edge0: (2, 0, 0), edge1: (0, 0, -4), resolution: (2, 4))")
                .unwrap();
        assert_eq!(g.len(), 8);
        assert!((g.point(0) - glam::DVec3::new(0.5, 0.0, -0.5)).length() < 1e-12);
        assert!((g.point(1) - glam::DVec3::new(1.5, 0.0, -0.5)).length() < 1e-12);
        assert!((g.point(7) - glam::DVec3::new(1.5, 0.0, -3.5)).length() < 1e-12);
        assert!((g.normal() - glam::DVec3::Y).length() < 1e-12);
    }

    /// Bad parameters are refused with the parameter named.
    #[test]
    fn bad_parameters_name_the_parameter() {
        let e = grid("(corner: (0, 0, 0), edge0: (1, 0, 0), edge1: (2, 0, 0), resolution: (2, 2))")
            .unwrap_err();
        assert!(e.contains("edge0") && e.contains("parallel"), "{e}");
        let e = grid("(corner: (0, 0, 0), edge0: (1, 0, 0), edge1: (0, 1, 0), resolution: (0, 2))")
            .unwrap_err();
        assert!(e.contains("resolution"), "{e}");
        let e = grid(
            "(corner: (0, 0, 0), edge0: (1, 0, 0), edge1: (0, 1, 0), resolution: (2, 2), samples: 0)",
        )
        .unwrap_err();
        assert!(e.contains("samples"), "{e}");
        let e = grid(
            "(corner: (0, 0, 0), edge0: (1, 0, 0), edge1: (0, 1, 0), resolution: (2, 2), size: 3)",
        )
        .unwrap_err();
        assert!(e.contains("size"), "{e}");
    }
}

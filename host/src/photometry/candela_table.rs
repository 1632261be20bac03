//! A candela table written out as data (scene syntax or bincode): what a luminaire file holds,
//! without the file. A scene can give a luminaire light its table inline, a blob stores it this
//! way (the file is read at pack time), and a baked light ([`crate::light::measure::goniometer`]) is one.
//!
//! | field              | unit    | meaning                                                          |
//! |--------------------|---------|------------------------------------------------------------------|
//! | `source`           | —       | where the table came from (a file name, "baked from …")          |
//! | `photometric_type` | —       | `"A"`, `"B"` or `"C"` (see [`super::luminaire`] for the angles)  |
//! | `symmetry`         | —       | `none`, `axial`, `quadrant`, `bilateral_c0_c180`, `bilateral_c90_c270`, `lateral_h` |
//! | `h_deg`, `v_deg`   | degrees | the stored angles, ascending                                     |
//! | `candela`          | cd      | `candela[ih * v_deg.len() + iv]`, every multiplier applied        |
//! | `size_m`           | m       | luminous opening width, length, height (0 for a point)            |
//! | `tilt`             | —       | optional lamp tilt table: `(geometry, angles_deg, factors)`       |
//! | `rated_lamp_lumens`| lm      | the lamps' rated flux for relative photometry, else absent        |

use super::luminaire::{Luminaire, PhotometricType, SourceFormat, Symmetry, TiltTable};
use serde::{Deserialize, Serialize};

/// A lamp tilt table as data.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TiltData {
    /// Lamp-to-luminaire geometry 1, 2 or 3 (LM-63).
    pub geometry: i64,
    /// Tilt angles, degrees.
    pub angles_deg: Vec<f64>,
    /// Multiplying factors at those angles.
    pub factors: Vec<f64>,
}

/// A candela table as data (see the module docs).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CandelaTable {
    /// Where the table came from.
    #[serde(default)]
    pub source: String,
    /// `"A"`, `"B"` or `"C"`.
    pub photometric_type: String,
    /// Symmetry key (module docs).
    pub symmetry: String,
    /// Stored `h` angles, degrees.
    pub h_deg: Vec<f64>,
    /// Stored `v` angles, degrees.
    pub v_deg: Vec<f64>,
    /// Candela, row-major by `h`.
    pub candela: Vec<f64>,
    /// Luminous opening size, m.
    #[serde(default)]
    pub size_m: [f64; 3],
    /// Lamp tilt table.
    #[serde(default)]
    pub tilt: Option<TiltData>,
    /// Rated lamp lumens (relative photometry).
    #[serde(default)]
    pub rated_lamp_lumens: Option<f64>,
}

impl TiltData {
    /// The tilt table, checked.
    fn to_tilt_table(&self) -> Result<TiltTable, String> {
        let t = self;
        if !(1..=3).contains(&t.geometry) {
            return Err(format!(
                "`tilt`: geometry {}; expected 1, 2 or 3",
                t.geometry
            ));
        }
        if t.angles_deg.is_empty() || t.angles_deg.len() != t.factors.len() {
            return Err(format!(
                "`tilt`: {} angles and {} factors (expected as many, at least one)",
                t.angles_deg.len(),
                t.factors.len()
            ));
        }
        if !t.angles_deg.iter().chain(&t.factors).all(|x| x.is_finite())
            || t.factors.iter().any(|f| *f < 0.0)
        {
            return Err("`tilt`: angles and factors must be finite, factors ≥ 0".into());
        }
        Ok(TiltTable {
            geometry: t.geometry,
            angles_deg: t.angles_deg.clone(),
            factors: t.factors.clone(),
            source: "table".into(),
        })
    }
}

const SYMMETRIES: [(Symmetry, &str); 6] = [
    (Symmetry::None, "none"),
    (Symmetry::Axial, "axial"),
    (Symmetry::Quadrant, "quadrant"),
    (Symmetry::BilateralC0C180, "bilateral_c0_c180"),
    (Symmetry::BilateralC90C270, "bilateral_c90_c270"),
    (Symmetry::LateralH, "lateral_h"),
];

impl CandelaTable {
    /// The table of a luminaire (its file's header facts other than these are dropped).
    pub fn from_luminaire(lum: &Luminaire, source: &str) -> Self {
        let ptype = match lum.photometric_type {
            PhotometricType::A => "A",
            PhotometricType::B => "B",
            PhotometricType::C => "C",
        };
        let symmetry = SYMMETRIES
            .iter()
            .find(|(s, _)| *s == lum.symmetry)
            .map_or("none", |(_, k)| k);
        CandelaTable {
            source: source.to_string(),
            photometric_type: ptype.to_string(),
            symmetry: symmetry.to_string(),
            h_deg: lum.h_deg.clone(),
            v_deg: lum.v_deg.clone(),
            candela: lum.candela.clone(),
            size_m: lum.size_m,
            tilt: lum.tilt.as_ref().map(|t| TiltData {
                geometry: t.geometry,
                angles_deg: t.angles_deg.clone(),
                factors: t.factors.clone(),
            }),
            rated_lamp_lumens: if lum.absolute {
                None
            } else {
                lum.rated_lamp_lumens
            },
        }
    }

    /// The luminaire this table describes, or what is wrong with it (the message names the
    /// field).
    pub fn to_luminaire(&self) -> Result<Luminaire, String> {
        let (photometric_type, symmetry) = self.type_and_symmetry()?;
        self.check_grid(symmetry)?;
        let tilt = self
            .tilt
            .as_ref()
            .map(TiltData::to_tilt_table)
            .transpose()?;
        if let Some(r) = self.rated_lamp_lumens {
            if !(r.is_finite() && r > 0.0) {
                return Err(format!(
                    "`rated_lamp_lumens`: {r} is not a finite number > 0"
                ));
            }
        }
        Ok(Luminaire {
            format: SourceFormat::Table,
            photometric_type,
            symmetry,
            h_deg: self.h_deg.clone(),
            v_deg: self.v_deg.clone(),
            candela: self.candela.clone(),
            lamps: Vec::new(),
            multipliers: Vec::new(),
            absolute: self.rated_lamp_lumens.is_none(),
            rated_lamp_lumens: self.rated_lamp_lumens,
            size_m: self.size_m,
            tilt,
            header: if self.source.is_empty() {
                Vec::new()
            } else {
                vec![format!("SOURCE {}", self.source)]
            },
            warnings: Vec::new(),
        })
    }

    /// The photometric type and the symmetry, which must suit each other.
    fn type_and_symmetry(&self) -> Result<(PhotometricType, Symmetry), String> {
        let photometric_type = match self.photometric_type.trim().to_ascii_uppercase().as_str() {
            "A" => PhotometricType::A,
            "B" => PhotometricType::B,
            "C" => PhotometricType::C,
            other => {
                return Err(format!(
                    "`photometric_type`: `{other}`; expected \"A\", \"B\" or \"C\""
                ))
            }
        };
        let symmetry = SYMMETRIES
            .iter()
            .find(|(_, k)| k.eq_ignore_ascii_case(self.symmetry.trim()))
            .map(|(s, _)| *s)
            .ok_or_else(|| {
                let keys: Vec<&str> = SYMMETRIES.iter().map(|(_, k)| *k).collect();
                format!(
                    "`symmetry`: `{}`; expected one of {}",
                    self.symmetry,
                    keys.join(", ")
                )
            })?;
        let c_only = matches!(
            symmetry,
            Symmetry::Axial
                | Symmetry::Quadrant
                | Symmetry::BilateralC0C180
                | Symmetry::BilateralC90C270
        );
        if c_only && photometric_type != PhotometricType::C {
            return Err(format!(
                "`symmetry`: `{}` is a type C symmetry, the table is type {}",
                self.symmetry, self.photometric_type
            ));
        }
        if symmetry == Symmetry::LateralH && photometric_type == PhotometricType::C {
            return Err("`symmetry`: `lateral_h` is for types A and B, the table is type C".into());
        }
        Ok((photometric_type, symmetry))
    }

    /// The angles ascending, as many values as angles, each finite and ≥ 0, a finite size.
    fn check_grid(&self, symmetry: Symmetry) -> Result<(), String> {
        ascending("h_deg", &self.h_deg)?;
        ascending("v_deg", &self.v_deg)?;
        if symmetry == Symmetry::Axial && self.h_deg.len() != 1 {
            return Err(format!(
                "`h_deg`: an axial table stores one plane, this one {}",
                self.h_deg.len()
            ));
        }
        let want = self.h_deg.len() * self.v_deg.len();
        if self.candela.len() != want {
            return Err(format!(
                "`candela`: {} values for {} × {} angles (expected {want})",
                self.candela.len(),
                self.h_deg.len(),
                self.v_deg.len()
            ));
        }
        if let Some(i) = self
            .candela
            .iter()
            .position(|c| !(c.is_finite() && *c >= 0.0))
        {
            return Err(format!(
                "`candela`: value {} ({}) is not a finite number ≥ 0",
                i + 1,
                self.candela[i]
            ));
        }
        if !self.size_m.iter().all(|s| s.is_finite()) {
            return Err(format!("`size_m`: {:?} is not finite", self.size_m));
        }
        Ok(())
    }
}

fn ascending(name: &str, xs: &[f64]) -> Result<(), String> {
    if xs.is_empty() {
        return Err(format!("`{name}`: no angles"));
    }
    if let Some(i) = xs.iter().position(|x| !x.is_finite()) {
        return Err(format!("`{name}`: angle {} is not finite", i + 1));
    }
    if let Some(i) = xs.windows(2).position(|w| w[1] <= w[0]) {
        return Err(format!(
            "`{name}`: angles must ascend, but angle {} ({}) follows {}",
            i + 2,
            xs[i + 1],
            xs[i]
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::photometry::load_luminaire;
    use std::path::Path;

    /// A real file's table survives the round trip through data: same angles, candela, flux and
    /// tilt (exact: nothing is computed).
    #[test]
    fn a_file_round_trips_through_the_table() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
        for f in [
            "data/photometry/erco_par38_lm63-1986_quadrant.ies",
            "tests/data/photometry/tilt_include_lm63_1995.ies",
            "tests/data/photometry/type_b_absolute_lm63_2002.ies",
        ] {
            let lum = load_luminaire(&dir.join(f)).unwrap();
            let back = CandelaTable::from_luminaire(&lum, f)
                .to_luminaire()
                .unwrap();
            assert_eq!(back.h_deg, lum.h_deg);
            assert_eq!(back.v_deg, lum.v_deg);
            assert_eq!(back.candela, lum.candela);
            assert_eq!(back.symmetry, lum.symmetry);
            assert_eq!(back.tilt.is_some(), lum.tilt.is_some());
            assert_eq!(back.flux_lm(), lum.flux_lm());
        }
    }

    /// Bad tables are refused naming the field.
    #[test]
    fn bad_tables_name_the_field() {
        let good = CandelaTable {
            source: String::new(),
            photometric_type: "C".into(),
            symmetry: "axial".into(),
            h_deg: vec![0.0],
            v_deg: vec![0.0, 90.0],
            candela: vec![100.0, 0.0],
            size_m: [0.0; 3],
            tilt: None,
            rated_lamp_lumens: None,
        };
        assert!(good.to_luminaire().is_ok());
        type Mutation = fn(&mut CandelaTable);
        let cases: [(Mutation, &str); 5] = [
            (|t| t.photometric_type = "D".into(), "photometric_type"),
            (|t| t.symmetry = "radial".into(), "symmetry"),
            (|t| t.v_deg = vec![90.0, 0.0], "v_deg"),
            (|t| t.candela = vec![1.0], "candela"),
            (|t| t.candela = vec![1.0, f64::NAN], "candela"),
        ];
        for (mutate, field) in cases {
            let mut t = good.clone();
            mutate(&mut t);
            let e = t.to_luminaire().unwrap_err();
            assert!(e.contains(field), "{e}");
        }
    }
}

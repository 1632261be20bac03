//! EULUMDAT writer: a type C [`Luminaire`] as an `.ldt` file that reads back to the same table.
//!
//! | field | written as |
//! |---|---|
//! | Ityp | 1 for axial symmetry, 2 for a bilateral distribution, 3 otherwise |
//! | Isym | from the symmetry: none 0, axial 1, C0–C180 2, C90–C270 3, quadrant 4 |
//! | Mc, Dc, Ng, Dg | plane and angle counts; Dc and Dg the step when it is even, else 0 |
//! | sizes | the luminaire size in mm (width, length, height as read) |
//! | DFF, LORL | computed from the table: flux below the horizontal / total, total / rated lamp lumens |
//! | lamp sets | as read; absolute photometry: −1 lamps and the table's flux |
//! | direct ratios | 0: not computed (they need the utilisation-factor method of CIE 52) |
//! | intensities | cd per 1000 lm of lamp set 1, shortest round-trip form |

use super::luminaire::{Luminaire, PhotometricType, Symmetry};

/// The EULUMDAT text of `lum`, or why it cannot be one (types A and B, a plane set that is
/// not the regular one the symmetry indicator implies).
pub fn write_eulumdat(lum: &Luminaire, source: &str) -> Result<String, String> {
    if lum.photometric_type != PhotometricType::C {
        return Err("EULUMDAT holds type C photometry only; this luminaire is type A or B".into());
    }
    let planes = c_planes(lum)?;
    let flux = lum.flux_lm();
    let (set_flux, absolute) = match lum.rated_lamp_lumens {
        Some(r) if !lum.absolute && r > 0.0 => (r, false),
        _ => (flux, true),
    };
    if !(set_flux > 0.0) {
        return Err("the luminaire emits nothing; EULUMDAT needs a positive flux".into());
    }
    let dff = if flux > 0.0 {
        100.0 * downward_flux_lm(lum) / flux
    } else {
        0.0
    };
    let lorl = 100.0 * flux / set_flux;
    let mm = lum.size_m.map(|m| m * 1000.0);
    let mut s = Lines::default();
    s.line(format!("exported by spectrace from {source}"));
    s.line(planes.ityp);
    s.line(planes.isym);
    s.line(planes.all.len());
    s.line(even_step(&planes.all));
    s.line(lum.v_deg.len());
    s.line(even_step(&lum.v_deg));
    for _ in 0..5 {
        s.line("");
    }
    s.line(mm[1]);
    s.line(mm[0]);
    s.line(mm[2]);
    for _ in 0..6 {
        s.line("0");
    }
    s.line(dff);
    s.line(lorl);
    s.line("1");
    s.line("0");
    write_lamp_sets(&mut s, lum, set_flux, absolute);
    for _ in 0..10 {
        s.line("0");
    }
    for c in &planes.all {
        s.line(c);
    }
    for g in &lum.v_deg {
        s.line(g);
    }
    let per_klm = 1000.0 / set_flux;
    for ih in 0..planes.stored_n {
        for iv in 0..lum.v_deg.len() {
            s.line(lum.stored_cd(ih, iv) * per_klm);
        }
    }
    Ok(s.0)
}

/// The file's text, one field a line (CRLF).
#[derive(Default)]
struct Lines(String);

impl Lines {
    fn line(&mut self, t: impl std::fmt::Display) {
        use std::fmt::Write;
        let _ = write!(self.0, "{t}\r\n");
    }
}

/// The C-planes as EULUMDAT stores them.
struct Planes {
    /// Symmetry indicator Isym.
    isym: u8,
    /// Type indicator Ityp.
    ityp: u8,
    /// Every C-plane of the full circle (Mc of them).
    all: Vec<f64>,
    /// How many stored planes are written.
    stored_n: usize,
}

/// Isym, Ityp and the C-planes of `lum`, which must be the regular set Isym implies.
fn c_planes(lum: &Luminaire) -> Result<Planes, String> {
    let stored = &lum.h_deg;
    let n = stored.len();
    // The full list of C-planes, and where the stored ones sit in it.
    let mut all = lum.expanded_h_deg();
    let (isym, ityp) = match lum.symmetry {
        Symmetry::None => (0, 3),
        Symmetry::Axial => (1, 1),
        Symmetry::BilateralC0C180 => (2, 2),
        Symmetry::BilateralC90C270 => (3, 2),
        Symmetry::Quadrant => (4, 3),
        Symmetry::LateralH => unreachable!("type C has no lateral symmetry"),
    };
    if isym == 1 {
        all = vec![0.0];
    }
    let mc = all.len();
    let expected_stored = match isym {
        0 => mc,
        1 => 1,
        2 | 3 => mc / 2 + 1,
        _ => mc / 4 + 1,
    };
    let first = if isym == 3 { mc / 4 } else { 0 };
    // A 0..360 table may hold C360 as a copy of C0; EULUMDAT stores [0, 360).
    let stored_n = if isym == 0 && (stored[n - 1] - 360.0).abs() < 1e-9 {
        n - 1
    } else {
        n
    };
    let fits = stored_n == expected_stored
        && (0..stored_n).all(|i| (all[(first + i) % mc] - stored[i]).abs() < 1e-9);
    if !fits {
        return Err(format!(
            "the stored C-planes {:?} are not the regular set EULUMDAT Isym {isym} needs",
            stored
        ));
    }
    Ok(Planes {
        isym,
        ityp,
        all,
        stored_n,
    })
}

/// The step of `xs` when it is even (Dc, Dg), else 0.
fn even_step(xs: &[f64]) -> f64 {
    if xs.len() < 2 {
        return 0.0;
    }
    let d = xs[1] - xs[0];
    if xs.windows(2).all(|w| ((w[1] - w[0]) - d).abs() < 1e-9) {
        d
    } else {
        0.0
    }
}

/// The flux below the horizontal: the table with everything above it cut.
fn downward_flux_lm(lum: &Luminaire) -> f64 {
    let mut lower = lum.clone();
    for (ih, _) in lum.h_deg.iter().enumerate() {
        for (iv, &v) in lum.v_deg.iter().enumerate() {
            if v > 90.0 {
                lower.candela[ih * lum.v_deg.len() + iv] = 0.0;
            }
        }
    }
    lower.flux_lm()
}

/// Line 26 and the lamp sets; set 1 carries `set_flux`, the flux the table refers to (−1
/// lamps for absolute photometry).
fn write_lamp_sets(s: &mut Lines, lum: &Luminaire, set_flux: f64, absolute: bool) {
    // A table without lamp data (measured from a light, or written inline) gets one set.
    let unnamed = [super::luminaire::LampSet {
        count: 1,
        lumens: None,
        description: String::new(),
        watts: None,
    }];
    let lamps: &[super::luminaire::LampSet] = if lum.lamps.is_empty() {
        &unnamed
    } else {
        &lum.lamps
    };
    s.line(lamps.len());
    for (i, l) in lamps.iter().enumerate() {
        let count = if absolute { -1 } else { l.count };
        let set_lm = if i == 0 {
            set_flux
        } else {
            // Only EULUMDAT sources have more sets, and there `lumens` is the set's total.
            l.lumens.unwrap_or(0.0)
        };
        s.line(count);
        s.line(&l.description);
        s.line(set_lm);
        s.line("");
        s.line("");
        s.line(l.watts.unwrap_or(0.0));
    }
}

//! The CIEDE2000 colour difference ΔE00 (CIE 142-2001), with the parametric factors
//! kL = kC = kH = 1, implemented from the formulas as written out by Sharma, Wu & Dalal,
//! "The CIEDE2000 color-difference formula: implementation notes, supplementary test data, and
//! mathematical observations", Color Res. Appl. 30(1), 2005. A ΔE00 of about 1 is a just
//! noticeable difference.

use super::cielab::Lab;

/// 25⁷, the constant of the chroma terms.
const POW25_7: f64 = 6_103_515_625.0;

/// Hue angle in degrees in [0, 360); 0 for a neutral colour (a = b = 0).
#[inline]
fn hue_deg(b: f64, a: f64) -> f64 {
    if a == 0.0 && b == 0.0 {
        return 0.0;
    }
    let h = b.atan2(a).to_degrees();
    if h < 0.0 {
        h + 360.0
    } else {
        h
    }
}

/// ΔE00 between two CIELAB colours (symmetric; 0 for equal colours).
pub fn delta_e_2000(lab1: Lab, lab2: Lab) -> f64 {
    let [l1, a1, b1] = lab1;
    let [l2, a2, b2] = lab2;
    // Chroma-dependent stretch of a* that makes near-neutral hues behave.
    let c_mean = 0.5 * ((a1 * a1 + b1 * b1).sqrt() + (a2 * a2 + b2 * b2).sqrt());
    let c7 = c_mean.powi(7);
    let g = 0.5 * (1.0 - (c7 / (c7 + POW25_7)).sqrt());
    let a1p = (1.0 + g) * a1;
    let a2p = (1.0 + g) * a2;
    let c1p = (a1p * a1p + b1 * b1).sqrt();
    let c2p = (a2p * a2p + b2 * b2).sqrt();
    let h1p = hue_deg(b1, a1p);
    let h2p = hue_deg(b2, a2p);

    let dl = l2 - l1;
    let dc = c2p - c1p;
    let chroma_product = c1p * c2p;
    let dh_angle = if chroma_product == 0.0 {
        0.0
    } else {
        let d = h2p - h1p;
        if d > 180.0 {
            d - 360.0
        } else if d < -180.0 {
            d + 360.0
        } else {
            d
        }
    };
    let dh = 2.0 * chroma_product.sqrt() * (0.5 * dh_angle).to_radians().sin();

    let l_mean = 0.5 * (l1 + l2);
    let cp_mean = 0.5 * (c1p + c2p);
    let h_mean = if chroma_product == 0.0 {
        h1p + h2p
    } else if (h1p - h2p).abs() <= 180.0 {
        0.5 * (h1p + h2p)
    } else if h1p + h2p < 360.0 {
        0.5 * (h1p + h2p + 360.0)
    } else {
        0.5 * (h1p + h2p - 360.0)
    };
    let cosd = |deg: f64| deg.to_radians().cos();
    let t = 1.0 - 0.17 * cosd(h_mean - 30.0)
        + 0.24 * cosd(2.0 * h_mean)
        + 0.32 * cosd(3.0 * h_mean + 6.0)
        - 0.20 * cosd(4.0 * h_mean - 63.0);
    let d_theta = 30.0 * (-((h_mean - 275.0) / 25.0).powi(2)).exp();
    let cp7 = cp_mean.powi(7);
    let r_c = 2.0 * (cp7 / (cp7 + POW25_7)).sqrt();
    let l50 = (l_mean - 50.0).powi(2);
    let s_l = 1.0 + 0.015 * l50 / (20.0 + l50).sqrt();
    let s_c = 1.0 + 0.045 * cp_mean;
    let s_h = 1.0 + 0.015 * cp_mean * t;
    let r_t = -(2.0 * d_theta).to_radians().sin() * r_c;
    let (tl, tc, th) = (dl / s_l, dc / s_c, dh / s_h);
    (tl * tl + tc * tc + th * th + r_t * tc * th)
        .max(0.0)
        .sqrt()
}

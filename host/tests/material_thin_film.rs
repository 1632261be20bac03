//! Thin-film interference (`material/thin_film.rs`) against an independent formulation, the
//! characteristic (transfer) matrix method of Abelès in Macleod's convention (complex index
//! n − i·k, time dependence e^{+iωt}, p admittance ñ/cos θ), the opposite conventions of the
//! Airy sum under test; energy conservation; the zero-thickness limit; and the material's
//! sampling weights.
//! Run: `cargo test --release -p spectrace --test material_thin_film`.

use spectrace::material::complex::Complex;
use spectrace::material::thin_film::{film_response, ThinFilm, ThinFilmBase};
use spectrace::material::{fresnel, Material, ShadingContext, SpectralIor, TransportMode};
use spectrace::spectrum::{SampledWavelengths, LANES};

/// (name, film index, base index as n + i·k).
const STACKS: [(&str, f64, (f64, f64)); 5] = [
    ("soap film in air", 1.33, (1.0, 0.0)),
    ("MgF2 on glass", 1.38, (1.52, 0.0)),
    ("TiO2 on glass", 2.4, (1.52, 0.0)),
    ("oxide on gold (550 nm)", 1.6, (0.43, 2.45)),
    ("alumina on aluminium (550 nm)", 1.76, (0.96, 6.69)),
];
const THICKNESSES_NM: [f64; 6] = [0.0, 40.0, 120.0, 275.0, 600.0, 1500.0];
const ANGLES_DEG: [f64; 5] = [0.0, 25.0, 45.0, 70.0, 85.0];
const WAVELENGTHS_NM: [f64; 3] = [420.0, 550.0, 680.0];

/// cos θ in medium `n` (Macleod convention: decaying root has Im(n cos θ) ≤ 0).
fn cos_macleod(n: Complex, sin0: f64) -> Complex {
    let s = Complex::real(sin0 * sin0) / (n * n);
    let c = (Complex::real(1.0) - s).sqrt();
    let nc = n * c;
    if nc.im > 0.0 {
        -c
    } else {
        c
    }
}

/// Unpolarised (R, T) of air | film | base by the characteristic matrix.
fn tmm(n1: f64, base: (f64, f64), d: f64, theta_deg: f64, lambda: f64) -> (f64, f64) {
    let th = theta_deg.to_radians();
    let (sin0, cos0) = (th.sin(), th.cos());
    let nf = Complex::real(n1);
    let ns = Complex::new(base.0, -base.1); // n − i·k
    let cf = cos_macleod(nf, sin0);
    let cs = cos_macleod(ns, sin0);
    let i = Complex::new(0.0, 1.0);
    let delta = nf * cf * (2.0 * std::f64::consts::PI * d / lambda);
    // cos and sin of a complex δ: (e^{iδ} ± e^{−iδ}) / 2(i).
    let e_p = (i * delta).exp();
    let e_m = (-(i * delta)).exp();
    let cosd = (e_p + e_m) * 0.5;
    let sind = (e_p - e_m) / (i * 2.0);
    let mut r_sum = 0.0;
    let mut t_sum = 0.0;
    for p_pol in [false, true] {
        let (eta0, etaf, etas) = if p_pol {
            (Complex::real(1.0 / cos0), nf / cf, ns / cs)
        } else {
            (Complex::real(cos0), nf * cf, ns * cs)
        };
        let b = cosd + i * sind * etas / etaf;
        let c = i * etaf * sind + cosd * etas;
        let denom = eta0 * b + c;
        let r = (eta0 * b - c) / denom;
        r_sum += r.norm_sqr();
        t_sum += 4.0 * eta0.re * etas.re / denom.norm_sqr();
    }
    (0.5 * r_sum, 0.5 * t_sum)
}

/// Quantity: unpolarised reflectance of 5 stacks × 6 thicknesses × 5 angles × 3 wavelengths
/// (450 cases, from normal to grazing 85°, dielectric and metal bases). Tolerance 1e-6 (the
/// brief's); both are closed forms in f64, so only rounding (~1e-15) separates correct ones,
/// while a wrong phase sign or a missing interface phase shift changes R by 1e-2 or more.
#[test]
fn airy_sum_matches_the_transfer_matrix() {
    let mut worst = 0.0f64;
    for (name, n1, base) in STACKS {
        for d in THICKNESSES_NM {
            for a in ANGLES_DEG {
                for l in WAVELENGTHS_NM {
                    let want = tmm(n1, base, d, a, l).0;
                    let got = film_response(
                        1.0,
                        Complex::real(n1),
                        Complex::new(base.0, base.1),
                        d,
                        a.to_radians().cos(),
                        l,
                    )
                    .reflectance;
                    assert!(
                        (got - want).abs() < 1e-6,
                        "{name}, d {d} nm, {a}°, {l} nm: Airy {got} vs TMM {want}"
                    );
                    worst = worst.max((got - want).abs());
                }
            }
        }
    }
    assert!(worst < 1e-6);
}

/// Quantity: R + T for the lossless (all-dielectric) stacks over the same grid, from the
/// ambient side, and from inside the base (base | film | air) below and beyond the critical
/// angle. Tolerance 1e-9: energy conservation holds exactly for real indices, T is computed
/// from the transmitted amplitude (not as 1 − R), and the TMM's T agrees to 1e-6 as well.
#[test]
fn lossless_film_conserves_energy() {
    for (name, n1, base) in STACKS.iter().filter(|s| s.2 .1 == 0.0) {
        for d in THICKNESSES_NM {
            for a in ANGLES_DEG {
                for l in WAVELENGTHS_NM {
                    let cos = a.to_radians().cos();
                    let f =
                        film_response(1.0, Complex::real(*n1), Complex::real(base.0), d, cos, l);
                    let sum = f.reflectance + f.transmittance;
                    assert!((sum - 1.0).abs() < 1e-9, "{name} d {d} {a}° {l}: R+T {sum}");
                    let t_tmm = tmm(*n1, *base, d, a, l).1;
                    assert!(
                        (f.transmittance - t_tmm).abs() < 1e-6,
                        "{name}: T {} vs {t_tmm}",
                        f.transmittance
                    );
                    let g =
                        film_response(base.0, Complex::real(*n1), Complex::real(1.0), d, cos, l);
                    let sum = g.reflectance + g.transmittance;
                    assert!(
                        (sum - 1.0).abs() < 1e-9,
                        "{name} from inside, {a}°: R+T {sum}"
                    );
                }
            }
        }
    }
}

/// Quantity: R at zero thickness against the project's bare-interface Fresnel functions
/// (`fresnel::dielectric`, `fresnel::conductor`, both f32). Tolerance 1e-5: the f32
/// conductor formula loses digits to cancellation at grazing incidence on a strongly
/// absorbing metal (measured 4.1e-6 for aluminium at 85°, where the f64 Airy value agrees with
/// the transfer matrix to 1e-6); dielectric cases agree to about 1e-7.
#[test]
fn zero_thickness_is_the_bare_interface() {
    for (name, n1, base) in STACKS {
        for a in ANGLES_DEG {
            let cos = a.to_radians().cos();
            let got = film_response(
                1.0,
                Complex::real(n1),
                Complex::new(base.0, base.1),
                0.0,
                cos,
                550.0,
            )
            .reflectance;
            let want = if base.1 == 0.0 {
                fresnel::dielectric(cos as f32, base.0 as f32)
            } else {
                fresnel::conductor(cos as f32, base.0 as f32, base.1 as f32)
            } as f64;
            assert!((got - want).abs() < 1e-5, "{name}, {a}°: {got} vs {want}");
        }
    }
}

/// Quantity: the material's expected per-lane throughput of each lobe, f·|cos|/pdf averaged
/// over 20 000 stratified lobe choices, equals that lane's R (reflection) and T (transmission)
/// from `film_response`, for a 300 nm MgF2-like film on glass at 30° and four wavelengths that
/// interfere differently. Tolerance 1e-3 relative: stratification leaves at most one sample of
/// 20 000 misassigned (5e-5 of the lobe count) and the material works in f32.
#[test]
fn material_weights_each_lane_by_its_own_film_response() {
    let m = ThinFilm::new(
        300.0,
        SpectralIor::Constant(1.38),
        ThinFilmBase::Dielectric(SpectralIor::Constant(1.52)),
    )
    .unwrap();
    let lambda = SampledWavelengths {
        lambda: [420.0, 500.0, 580.0, 660.0],
        pdf: [1.0; LANES],
        lanes: spectrace::spectrum::LaneMask::ALL,
    };
    let th = 30f32.to_radians();
    let wo = glam::Vec3A::new(th.sin(), 0.0, th.cos());
    let n = 20_000;
    let (mut refl, mut trans) = ([0.0f64; LANES], [0.0f64; LANES]);
    for k in 0..n {
        let u = (k as f32 + 0.5) / n as f32;
        let s = m
            .sample(
                wo,
                &ShadingContext::default(),
                &lambda,
                u,
                glam::Vec2::ZERO,
                TransportMode::Importance,
            )
            .unwrap();
        let w = s.f * (s.wi.z.abs() / s.pdf);
        let acc = if s.wi.z > 0.0 { &mut refl } else { &mut trans };
        for i in 0..LANES {
            acc[i] += w[i] as f64 / n as f64;
        }
    }
    for i in 0..LANES {
        let f = film_response(
            1.0,
            Complex::real(1.38),
            Complex::real(1.52),
            300.0,
            th.cos() as f64,
            lambda.lambda[i] as f64,
        );
        assert!(
            (refl[i] / f.reflectance - 1.0).abs() < 1e-3,
            "lane {i}: R {} vs {}",
            refl[i],
            f.reflectance
        );
        assert!(
            (trans[i] / f.transmittance - 1.0).abs() < 1e-3,
            "lane {i}: T {} vs {}",
            trans[i],
            f.transmittance
        );
    }
    // The lanes really differ (interference colours), or the test would not check much.
    assert!(
        refl.iter().cloned().fold(0.0, f64::max) > 1.5 * refl.iter().cloned().fold(1.0, f64::min)
    );
    assert!(ThinFilm::new(
        -1.0,
        SpectralIor::Constant(1.3),
        ThinFilmBase::Dielectric(SpectralIor::Constant(1.5))
    )
    .is_err());
}

/// Construction from scene-style values: a glass name, a number, a metal; bad values are
/// errors naming them (exact string checks).
#[test]
fn constructor_from_specs() {
    assert!(ThinFilm::from_specs(300.0, "1.33", "1.0").is_ok());
    assert!(ThinFilm::from_specs(80.0, "1.6", "au").is_ok());
    assert!(ThinFilm::from_specs(80.0, "N-BK7", "N-SF11").is_ok());
    let e = ThinFilm::from_specs(80.0, "0.5", "au").unwrap_err();
    assert!(e.contains("film") && e.contains("0.5"), "{e}");
    let e = ThinFilm::from_specs(80.0, "1.5", "unobtainium").unwrap_err();
    assert!(e.contains("unobtainium"), "{e}");
}

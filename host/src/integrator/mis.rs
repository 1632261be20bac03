//! Multiple importance sampling shared by the integrators: the power heuristic of two
//! strategies (Veach 1997, §9.2). BDPT's weights over all its strategies are in
//! [`super::bdpt::mis`].

/// Power heuristic with β = 2 for one sample from each of two strategies.
#[inline]
pub fn power_heuristic(pdf_a: f32, pdf_b: f32) -> f32 {
    let a = pdf_a * pdf_a;
    let b = pdf_b * pdf_b;
    if a.is_infinite() {
        return 1.0;
    }
    if a + b == 0.0 {
        return 0.0;
    }
    a / (a + b)
}

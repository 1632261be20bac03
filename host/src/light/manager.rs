//! The scene's lights (the seed's LightSourceManager): chooses a light in proportion to its
//! power with an exact pmf, and maps scene objects to their area lights.

use super::Light;
use crate::spectrum::spd::is_line_lane;
use crate::spectrum::{DeltaLine, SampledSpectrum, SampledWavelengths, LANES};
use std::sync::Arc;

/// All lights plus a power-proportional discrete distribution over them.
#[derive(Debug, Clone, Default)]
pub struct LightSourceManager {
    lights: Vec<Arc<dyn Light>>,
    /// Normalised cumulative power; `cdf[i]` = P(index ≤ i).
    cdf: Vec<f64>,
    pmf: Vec<f32>,
    /// `object_light[object]` = index of the area light on that object.
    object_light: Vec<Option<u32>>,
    /// The environment light (rays leaving the scene see it); a scene has at most one.
    environment: Option<u32>,
    /// Every delta line of every evaluable light, weight = light pmf × the line's share of
    /// that light's power: what a fluorescent surface may draw its excitation from (a
    /// continuous draw never lands on a line).
    delta_lines: Vec<DeltaLine>,
}

impl LightSourceManager {
    /// Build from `lights` (and the number of scene objects, to map area lights back). Lights
    /// with zero or non-finite power get probability 0; if all do, the choice is uniform.
    pub fn new(lights: Vec<Arc<dyn Light>>, object_count: usize) -> Self {
        let mut power: Vec<f64> = lights
            .iter()
            .map(|l| {
                let p = l.power();
                if p.is_finite() && p > 0.0 {
                    p
                } else {
                    0.0
                }
            })
            .collect();
        let total: f64 = power.iter().sum();
        if !(total > 0.0) {
            power.iter_mut().for_each(|p| *p = 1.0);
        }
        let total: f64 = power.iter().sum();
        let mut acc = 0.0;
        let mut cdf = Vec::with_capacity(power.len());
        for p in &power {
            acc += p / total;
            cdf.push(acc);
        }
        if let Some(last) = cdf.last_mut() {
            *last = 1.0;
        }
        let pmf: Vec<f32> = power.iter().map(|p| (p / total) as f32).collect();
        let mut object_light = vec![None; object_count];
        for (i, l) in lights.iter().enumerate() {
            if let Some(o) = l.object() {
                if let Some(slot) = object_light.get_mut(o as usize) {
                    *slot = Some(i as u32);
                }
            }
        }
        let environment = lights
            .iter()
            .position(|l| l.flags().contains(super::LightFlags::ENVIRONMENT))
            .map(|i| i as u32);
        let mut delta_lines: Vec<DeltaLine> = Vec::new();
        for (l, &p) in lights.iter().zip(&pmf) {
            if l.flags().contains(super::LightFlags::BEAMS_ONLY) || !(p > 0.0) {
                continue;
            }
            for line in l.spd().delta_lines() {
                let weight = line.weight * p as f64;
                match delta_lines.iter_mut().find(|d| d.lambda == line.lambda) {
                    Some(d) => d.weight += weight,
                    None => delta_lines.push(DeltaLine {
                        lambda: line.lambda,
                        weight,
                    }),
                }
            }
        }
        Self {
            lights,
            cdf,
            pmf,
            object_light,
            environment,
            delta_lines,
        }
    }

    /// The delta lines of the evaluable lights (nm), each weighted by its light's pmf × its
    /// share of that light's power; empty when no light has a line.
    #[inline]
    pub fn delta_lines(&self) -> &[DeltaLine] {
        &self.delta_lines
    }

    /// Keep only line power on lanes that are discrete draws of a line: a lane whose f32
    /// wavelength sits exactly on one of the scene's [`delta_lines`](Self::delta_lines) was
    /// drawn with that line's discrete probability (the pair's mixture, or a camera path's
    /// excitation draw onto a line lamp), so only power that is itself a line there belongs
    /// to it. Light `light`'s radiance `l` at `lambda` is set to 0 on such lanes where this
    /// light has no line of its own: its continuous density (W/(m²·sr·nm)) there is estimated
    /// by the continuous draws, and divided by a discrete probability it would add a term
    /// that is not in the integral (a bias of the continuous light's density × 1 nm). Nothing
    /// happens in scenes without lines.
    pub fn keep_line_power_only(
        &self,
        light: usize,
        lambda: &SampledWavelengths,
        l: &mut SampledSpectrum,
    ) {
        if self.delta_lines.is_empty() {
            return;
        }
        let mut own: Option<Vec<DeltaLine>> = None;
        for k in 0..LANES {
            let lk = lambda.lambda[k];
            if l[k] != 0.0 && is_line_lane(&self.delta_lines, lk) {
                let own = own.get_or_insert_with(|| self.lights[light].spd().delta_lines());
                if !is_line_lane(own, lk) {
                    l[k] = 0.0;
                }
            }
        }
    }

    /// All lights.
    pub fn lights(&self) -> &[Arc<dyn Light>] {
        &self.lights
    }

    /// True when there are no lights.
    pub fn is_empty(&self) -> bool {
        self.lights.is_empty()
    }

    /// Pick a light with `u ∈ [0,1)`: `(index, probability)`.
    #[inline]
    pub fn sample(&self, u: f32) -> Option<(usize, f32)> {
        if self.lights.is_empty() {
            return None;
        }
        let u = u as f64;
        let i = self
            .cdf
            .partition_point(|&c| c <= u)
            .min(self.lights.len() - 1);
        let p = self.pmf[i];
        if p > 0.0 {
            Some((i, p))
        } else {
            None
        }
    }

    /// Probability of choosing light `index`.
    #[inline]
    pub fn pmf(&self, index: usize) -> f32 {
        self.pmf.get(index).copied().unwrap_or(0.0)
    }

    /// The environment light, if the scene has one.
    #[inline]
    pub fn environment(&self) -> Option<u32> {
        self.environment
    }

    /// The area light on scene object `object`, if it emits.
    #[inline]
    pub fn light_of_object(&self, object: u32) -> Option<u32> {
        self.object_light.get(object as usize).copied().flatten()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::light::PointLight;
    use crate::spectrum::{BuiltinSpd, Spd};
    use glam::Vec3A;

    /// Lights of power 1, 3, 0 and 4 W are chosen with probability 1/8, 3/8, 0, 1/2: exact pmf
    /// (1e-7, f32), and the sampling frequencies over a fine uniform grid of u match it to 1e-3.
    #[test]
    fn chooses_in_proportion_to_power() {
        let spd: Arc<dyn Spd> = Arc::new(BuiltinSpd::blackbody(5000.0).unwrap());
        let lights: Vec<Arc<dyn Light>> = [1.0, 3.0, 0.0, 4.0]
            .iter()
            .map(|&p| Arc::new(PointLight::new(Vec3A::ZERO, spd.clone(), p)) as Arc<dyn Light>)
            .collect();
        let m = LightSourceManager::new(lights, 0);
        let want = [0.125, 0.375, 0.0, 0.5];
        for (i, w) in want.iter().enumerate() {
            assert!((m.pmf(i) - w).abs() < 1e-7);
        }
        let n = 10_000;
        let mut counts = [0usize; 4];
        for k in 0..n {
            let (i, p) = m.sample((k as f32 + 0.5) / n as f32).unwrap();
            assert_eq!(p, m.pmf(i));
            counts[i] += 1;
        }
        for (i, w) in want.iter().enumerate() {
            assert!((counts[i] as f32 / n as f32 - w).abs() < 1e-3);
        }
    }
}

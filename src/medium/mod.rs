//! Participating media: homogeneous volumes that absorb, scatter and emit light along the rays
//! that cross them (`docs/language.md`, Media). A medium fills an object's interior (`medium`
//! in a material; POV-Ray's `interior { fade_distance media }`) or the whole scene
//! (`atmosphere`; POV-Ray's `fog` and scene-wide `media`). `integrator::Path` samples them by
//! free-flight sampling (pbrt-v3's `HomogeneousMedium`, Mitsuba's `volpath`).

mod density;
mod phase;

pub use density::Density;
pub use phase::HenyeyGreenstein;

use glam::Vec3;

use crate::ray::Ray;

/// A medium; coefficients per unit length of scene space at density 1, per channel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Medium {
    /// sigma_a: the fraction of radiance absorbed per unit length.
    pub absorption: Vec3,
    /// sigma_s: the fraction of radiance scattered out (and, from other directions, in) per
    /// unit length.
    pub scattering: Vec3,
    /// Radiance added per unit length (POV-Ray's media `emission`): a segment of length d of a
    /// medium that does not extinguish adds emission × d.
    pub emission: Vec3,
    pub phase: HenyeyGreenstein,
    pub density: Density,
}

/// What free-flight sampling finds along a segment of a medium.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Flight {
    /// The path scatters at distance `t`; `weight` (sigma_s T(t) / pdf(t)) multiplies its
    /// throughput.
    Scattered { t: f32, weight: Vec3 },
    /// The path crosses the whole segment; `weight` (T / the probability of crossing)
    /// multiplies its throughput.
    Crossed { weight: Vec3 },
}

impl Medium {
    /// sigma_t = sigma_a + sigma_s.
    #[inline]
    pub fn extinction(&self) -> Vec3 {
        self.absorption + self.scattering
    }

    /// Whether light is scattered in it (else it only absorbs and emits: no sampling needed).
    #[inline]
    pub fn scatters(&self) -> bool {
        self.scattering.max_element() > 0.0
    }

    /// Beer–Lambert: the fraction of radiance that crosses the ray's first `distance` (which
    /// may be infinite), exp(-sigma_t D) per channel, D the density-weighted length.
    pub fn transmittance(&self, ray: &Ray, distance: f32) -> Vec3 {
        self.transmittance_over(self.density.depth(ray, distance))
    }

    fn transmittance_over(&self, depth: f32) -> Vec3 {
        self.extinction().map(|sigma| if sigma > 0.0 { (-sigma * depth).exp() } else { 1.0 })
    }

    /// Radiance the medium emits along the ray's first `distance` towards its origin: the
    /// integral of emission × density × T(t), emission (1 - exp(-sigma_t D)) / sigma_t per
    /// channel over a density-weighted length D (and emission × D where nothing extinguishes).
    pub fn emitted(&self, ray: &Ray, distance: f32) -> Vec3 {
        if self.emission == Vec3::ZERO {
            return Vec3::ZERO;
        }
        let distance = self.density.depth(ray, distance);
        let sigma = self.extinction();
        Vec3::from_array(std::array::from_fn(|c| {
            let (e, s) = (self.emission[c], sigma[c]);
            if e == 0.0 {
                0.0
            } else if s > 0.0 {
                -e * (-s * distance).exp_m1() / s
            } else {
                e * distance
            }
        }))
    }

    /// Free-flight sampling over the ray's first `length` (infinite where it leaves the
    /// scene): a density-weighted length drawn with density sigma_t exp(-sigma_t D) in one
    /// channel chosen uniformly by `u_channel`, weighed by the density averaged over the
    /// channels (the one-sample MIS of chromatic media, pbrt-v3 15.2.1); the density at the
    /// point cancels from the weight. A medium that does not scatter is crossed with its
    /// transmittance, nothing drawn.
    pub fn sample_flight(&self, ray: &Ray, length: f32, u_channel: f32, u: f32) -> Flight {
        if !self.scatters() {
            return Flight::Crossed { weight: self.transmittance(ray, length) };
        }
        let sigma = self.extinction();
        let total = self.density.depth(ray, length);
        let channel = ((u_channel * 3.0) as usize).min(2);
        let depth =
            if sigma[channel] > 0.0 { -(-u).ln_1p() / sigma[channel] } else { f32::INFINITY };
        if depth < total {
            let transmittance = self.transmittance_over(depth);
            let pdf = (sigma * transmittance).element_sum() / 3.0;
            let t = self.density.distance(ray, depth).min(length);
            return Flight::Scattered { t, weight: self.scattering * transmittance / pdf };
        }
        let transmittance = self.transmittance_over(total);
        let crossing = transmittance.element_sum() / 3.0;
        let weight = if crossing > 0.0 { transmittance / crossing } else { Vec3::ZERO };
        Flight::Crossed { weight }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn medium(absorption: Vec3, scattering: Vec3) -> Medium {
        let (emission, phase) = (Vec3::ZERO, HenyeyGreenstein { g: 0.0 });
        Medium { absorption, scattering, emission, phase, density: Density::Uniform }
    }

    const ALONG_X: Ray = Ray { origin: glam::Vec3A::ZERO, dir: glam::Vec3A::X };

    /// Beer–Lambert's law, and what crosses an infinite medium.
    #[test]
    fn transmittance_is_exponential_in_extinction() {
        let m = medium(Vec3::new(0.5, 1.0, 0.0), Vec3::new(0.5, 0.0, 0.0));
        let t = m.transmittance(&ALONG_X, 2.0);
        assert!((t - Vec3::new((-2.0f32).exp(), (-2.0f32).exp(), 1.0)).abs().max_element() < 1e-6);
        assert_eq!(m.transmittance(&ALONG_X, f32::INFINITY), Vec3::new(0.0, 0.0, 1.0));
    }

    /// A medium that only absorbs and emits with sigma_a = 1 / D and emission c / D is
    /// POV-Ray's fog: c (1 - exp(-d / D)); without extinction, emission × d.
    #[test]
    fn emission_integrates_against_transmittance() {
        let mut m = medium(Vec3::splat(0.25), Vec3::ZERO);
        m.emission = Vec3::new(0.25, 0.5, 0.0);
        let e = m.emitted(&ALONG_X, 3.0);
        let fade = 1.0 - (-0.75f32).exp();
        assert!((e - Vec3::new(1.0, 2.0, 0.0) * fade).abs().max_element() < 1e-6, "{e}");
        assert_eq!(m.emitted(&ALONG_X, f32::INFINITY), Vec3::new(1.0, 2.0, 0.0));
        let clear = Medium { absorption: Vec3::ZERO, ..m };
        assert_eq!(clear.emitted(&ALONG_X, 2.0), Vec3::new(0.5, 1.0, 0.0));
    }

    /// Free-flight sampling is unbiased for the transmittance to a surface: the mean of the
    /// crossing weights (zero for scattered paths) is T(d), per channel, in a chromatic medium,
    /// evenly dense and as ground fog along a rising ray.
    #[test]
    fn free_flight_crossing_weights_average_to_transmittance() {
        let even = medium(Vec3::new(0.2, 0.5, 0.1), Vec3::new(0.3, 0.5, 1.5));
        let ground = Density::Ground { up: Vec3::Y, offset: 0.3, falloff: 0.5 };
        let rising = Ray::new(Vec3::ZERO, Vec3::new(1.0, 1.0, 0.0).normalize());
        for (m, ray) in [(even, ALONG_X), (Medium { density: ground, ..even }, rising)] {
            crossing_weights_average_to_transmittance(&m, &ray);
        }
    }

    fn crossing_weights_average_to_transmittance(m: &Medium, ray: &Ray) {
        let (d, n) = (1.3, 400_000);
        let mut sum = Vec3::ZERO;
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 40) as f32 / (1u64 << 24) as f32
        };
        for _ in 0..n {
            if let Flight::Crossed { weight } = m.sample_flight(ray, d, next(), next()) {
                sum += weight;
            }
        }
        let mean = sum / n as f32;
        let expected = m.transmittance(ray, d);
        assert!((mean - expected).abs().max_element() < 0.01, "{mean} vs {expected}");
    }
}

//! The Henyey–Greenstein phase function (isotropic where g = 0): the angular distribution of
//! light scattered in a medium, sampled exactly (pbrt-v3 15.2.3).

use std::f32::consts::PI;

use glam::{Vec2, Vec3};

use crate::geometry::Frame;

/// p(theta) = (1 - g²) / (4 pi (1 + g² - 2 g cos theta)^(3/2)), theta the angle between the
/// direction light travelled and the one it goes on in: g > 0 scatters forwards, g < 0
/// backwards, g = 0 evenly. g in (-1, 1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HenyeyGreenstein {
    pub g: f32,
}

impl HenyeyGreenstein {
    /// The density of scattering light that arrives from `wi` towards `wo` (pbrt's directions:
    /// both point away from the scattering point), per steradian; it is also the density of
    /// `sample`.
    #[inline]
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.of_cosine(-wo.dot(wi))
    }

    /// p of the cosine between the directions of travel.
    fn of_cosine(&self, cos_theta: f32) -> f32 {
        let g = self.g;
        let denominator = 1.0 + g * g - 2.0 * g * cos_theta;
        (1.0 - g * g) / (4.0 * PI * denominator * denominator.sqrt())
    }

    /// A direction `wi` drawn with density `eval(wo, wi)`, and that density.
    pub fn sample(&self, wo: Vec3, u: Vec2) -> (Vec3, f32) {
        let g = self.g;
        let cos_theta = if g.abs() < 1e-3 {
            1.0 - 2.0 * u.x
        } else {
            let ratio = (1.0 - g * g) / (1.0 - g + 2.0 * g * u.x);
            ((1.0 + g * g - ratio * ratio) / (2.0 * g)).clamp(-1.0, 1.0)
        };
        let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
        let phi = 2.0 * PI * u.y;
        let local = Vec3::new(sin_theta * phi.cos(), sin_theta * phi.sin(), cos_theta);
        // Around the direction of travel, -wo.
        let wi = Frame::from_normal(-wo).to_world(local).normalize();
        (wi, self.of_cosine(cos_theta))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The phase function integrates to one over the sphere (midpoint rule in cos theta).
    #[test]
    fn integrates_to_one() {
        for g in [-0.9, -0.3, 0.0, 0.5, 0.95] {
            let p = HenyeyGreenstein { g };
            let n = 200_000;
            let sum: f64 = (0..n)
                .map(|i| f64::from(p.of_cosine(-1.0 + 2.0 * (i as f32 + 0.5) / n as f32)))
                .sum();
            let integral = sum * 2.0 / f64::from(n) * 2.0 * std::f64::consts::PI;
            assert!((integral - 1.0).abs() < 1e-3, "g {g}: {integral}");
        }
    }

    /// Forward scattering sends light on along its travel, away from `wo`'s side.
    #[test]
    fn positive_g_scatters_forwards() {
        let p = HenyeyGreenstein { g: 0.8 };
        let wo = Vec3::Z;
        assert!(p.eval(wo, -Vec3::Z) > 10.0 * p.eval(wo, Vec3::Z));
        let (wi, pdf) = p.sample(wo, Vec2::new(0.5, 0.3));
        assert!(wi.z < 0.0 && (pdf - p.eval(wo, wi)).abs() < 1e-4 * pdf);
    }
}

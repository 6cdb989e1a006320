//! A spotlight's beam: POV-Ray's angular profile about an axis (full inside `radius`, a smooth
//! falloff to zero at `falloff`, narrowed by `tightness`), tabulated once so that photons leave
//! in proportion to it; a point spotlight sends it from a point, an area spotlight from every
//! point of an emitter (`light::emitted`).

use std::f32::consts::PI;

use glam::{Vec2, Vec3};

use crate::geometry::Frame;

/// Bins of the tabulated profile over cos(theta) in [0, 1].
const BINS: usize = 512;

/// Midpoints integrating the profile over each bin (the spline and cos^tightness are smooth but
/// for a hard edge where `falloff` = `radius`; no endpoint is taken, so a cone of zero width,
/// lit only exactly on its axis, has no power).
const MIDPOINTS: usize = 8;

/// POV-Ray's spotlight profile as a function of cos(theta), theta from the axis:
/// cos^tightness theta times the cubic spline from 0 at `falloff` to 1 at `radius`
/// (POV-Ray 3.7's `Attenuate_Light`), zero behind the light.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpotProfile {
    pub cos_radius: f32,
    pub cos_falloff: f32,
    pub tightness: f32,
}

impl SpotProfile {
    /// From angles in degrees, not negative (past 90 they are read as POV-Ray reads them:
    /// through their cosines).
    pub fn from_degrees(radius: f32, falloff: f32, tightness: f32) -> Self {
        SpotProfile {
            cos_radius: radius.to_radians().cos(),
            cos_falloff: falloff.to_radians().cos(),
            tightness,
        }
    }

    /// The fraction of the axis's intensity sent at cos(theta) = `mu`.
    pub fn eval(&self, mu: f32) -> f32 {
        if mu <= 0.0 {
            return 0.0;
        }
        let narrowed = if self.tightness == 0.0 { 1.0 } else { mu.powf(self.tightness) };
        // POV-Ray applies the spline only for radius < 90 degrees.
        let spline = if self.cos_radius > 0.0 {
            cubic_spline(self.cos_falloff, self.cos_radius, mu)
        } else {
            1.0
        };
        narrowed * spline
    }
}

/// 0 below `low`, 1 from `high`, 3t^2 - 2t^3 between (t from 0 at `low` to 1 at `high`).
fn cubic_spline(low: f32, high: f32, x: f32) -> f32 {
    if x < low {
        0.0
    } else if x >= high {
        1.0
    } else {
        let t = (x - low) / (high - low);
        t * t * (3.0 - 2.0 * t)
    }
}

/// A spotlight's profile aimed along the unit `axis`: the fraction of the axis's intensity sent
/// each way. A point spotlight's and an area spotlight's (`light::emitted`) beam.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Beam {
    pub axis: Vec3,
    pub profile: SpotProfile,
}

impl Beam {
    /// The fraction of the axis's intensity sent towards unit `direction`.
    #[inline]
    pub fn towards(&self, direction: Vec3) -> f32 {
        self.profile.eval(direction.dot(self.axis))
    }
}

/// A beam with its profile tabulated once, so that directions leave in proportion to it
/// (photons) and its solid-angle integral is known (power).
#[derive(Debug, Clone)]
pub struct BeamSampler {
    pub beam: Beam,
    /// Cumulative share of the profile's integral up to the end of each bin of cos(theta).
    cdf: Vec<f32>,
    /// The integral of the profile over cos(theta) in [0, 1].
    integral: f32,
}

/// A direction leaving a spotlight and its solid-angle density.
#[derive(Debug, Clone, Copy)]
pub struct SpotDirection {
    pub direction: Vec3,
    pub pdf: f32,
}

impl BeamSampler {
    pub fn new(beam: Beam) -> Self {
        let h = 1.0 / (BINS * MIDPOINTS) as f64;
        let p = |mu: f64| f64::from(beam.profile.eval(mu as f32));
        let mut cdf = Vec::with_capacity(BINS);
        let mut sum = 0.0;
        for bin in 0..BINS {
            let first = bin * MIDPOINTS;
            sum += (first..first + MIDPOINTS).map(|k| h * p((k as f64 + 0.5) * h)).sum::<f64>();
            cdf.push(sum);
        }
        let cdf = cdf.iter().map(|c| if sum > 0.0 { (c / sum) as f32 } else { 0.0 }).collect();
        BeamSampler { beam, cdf, integral: sum as f32 }
    }

    /// The profile integrated over the sphere of directions, 2 pi ∫ P(mu) dmu: the power of a
    /// unit intensity on the axis.
    pub fn solid_angle(&self) -> f32 {
        2.0 * PI * self.integral
    }

    /// A direction with density proportional to the tabulated profile (within a bin of
    /// cos(theta), uniform); `None` if the profile is zero everywhere.
    pub fn sample(&self, u: Vec2) -> Option<SpotDirection> {
        if self.integral <= 0.0 {
            return None;
        }
        let bin = self.cdf.partition_point(|&c| c <= u.x).min(BINS - 1);
        let below = if bin == 0 { 0.0 } else { self.cdf[bin - 1] };
        let share = self.cdf[bin] - below;
        if share <= 0.0 {
            return None;
        }
        let within = ((u.x - below) / share).clamp(0.0, 1.0);
        let mu = (bin as f32 + within) / BINS as f32;
        let sin = (1.0 - mu * mu).max(0.0).sqrt();
        let phi = 2.0 * PI * u.y;
        let local = Vec3::new(sin * phi.cos(), sin * phi.sin(), mu);
        let direction = Frame::from_normal(self.beam.axis).to_world(local);
        // Density over cos(theta) is share / bin width; phi is uniform over 2 pi.
        let pdf = share * BINS as f32 / (2.0 * PI);
        Some(SpotDirection { direction, pdf })
    }
}

/// A spotlight at `position` with radiant `intensity` on the axis of its beam.
#[derive(Debug, Clone)]
pub struct Spot {
    pub position: Vec3,
    pub intensity: Vec3,
    pub beam: BeamSampler,
}

impl Spot {
    pub fn new(position: Vec3, axis: Vec3, intensity: Vec3, profile: SpotProfile) -> Self {
        Spot { position, intensity, beam: BeamSampler::new(Beam { axis, profile }) }
    }

    /// Radiant intensity towards unit `direction` (leaving the light).
    pub fn intensity_towards(&self, direction: Vec3) -> Vec3 {
        self.intensity * self.beam.beam.towards(direction)
    }

    /// Emitted power per channel: the intensity integrated over the sphere, 2 pi I ∫ P(mu) dmu.
    pub fn power_rgb(&self) -> Vec3 {
        self.beam.solid_angle() * self.intensity
    }

    /// A direction leaving the light with density proportional to its profile.
    pub fn sample_direction(&self, u: Vec2) -> Option<SpotDirection> {
        self.beam.sample(u)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spot(radius: f32, falloff: f32, tightness: f32) -> Spot {
        let profile = SpotProfile::from_degrees(radius, falloff, tightness);
        Spot::new(Vec3::ZERO, Vec3::Z, Vec3::ONE, profile)
    }

    #[test]
    fn the_profile_is_full_inside_the_radius_and_zero_beyond_the_falloff() {
        let p = SpotProfile::from_degrees(20.0, 40.0, 0.0);
        assert_eq!(p.eval(10f32.to_radians().cos()), 1.0);
        assert_eq!(p.eval(41f32.to_radians().cos()), 0.0);
        assert_eq!(p.eval(-1.0), 0.0);
        // Halfway between the cosines the spline is 1/2.
        let mid = 0.5 * (20f32.to_radians().cos() + 40f32.to_radians().cos());
        assert!((p.eval(mid) - 0.5).abs() < 1e-6);
        let tight = SpotProfile::from_degrees(20.0, 40.0, 10.0);
        assert!((tight.eval(0.99) - 0.99f32.powi(10)).abs() < 1e-6);
    }

    #[test]
    fn a_hard_edged_cone_has_the_power_of_its_solid_angle() {
        // radius = falloff: intensity I inside the cone, 2 pi (1 - cos r) I in all.
        let s = spot(30.0, 30.0, 0.0);
        let expected = 2.0 * PI * (1.0 - 30f32.to_radians().cos());
        assert!((s.power_rgb().x - expected).abs() < 1e-3 * expected, "{}", s.power_rgb().x);
    }

    #[test]
    fn tightness_alone_integrates_in_closed_form() {
        // radius 90: P = mu^t, whose integral over [0, 1] is 1 / (t + 1).
        let s = spot(90.0, 90.0, 3.0);
        let expected = 2.0 * PI / 4.0;
        assert!((s.power_rgb().x - expected).abs() < 1e-4 * expected);
    }

    #[test]
    fn sampled_directions_weighted_by_intensity_over_pdf_give_the_power() {
        // Each sample's I P / pdf has mean the power; a density not proportional to what the
        // table says, or a wrong table, moves the mean.
        let s = spot(15.0, 35.0, 5.0);
        let n = 256;
        let mut sum = 0.0f64;
        let mut inside_falloff = true;
        for i in 0..n {
            for j in 0..n {
                let u = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                let d = s.sample_direction(u).expect("a profile with power");
                inside_falloff &= d.direction.dot(Vec3::Z) >= 35f32.to_radians().cos() - 1e-3;
                sum += f64::from(s.intensity_towards(d.direction).x / d.pdf);
            }
        }
        let mean = sum / f64::from(n * n);
        let power = f64::from(s.power_rgb().x);
        assert!(inside_falloff, "a photon left outside the falloff");
        assert!((mean - power).abs() < 2e-3 * power, "{mean} vs {power}");
    }

    #[test]
    fn a_zero_falloff_spot_emits_nothing() {
        let s = spot(0.0, 0.0, 0.0);
        assert_eq!(s.power_rgb(), Vec3::ZERO);
        assert!(s.sample_direction(Vec2::splat(0.5)).is_none());
    }
}

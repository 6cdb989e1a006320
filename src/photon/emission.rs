//! How the photons of a pass are shared out among the lights: in proportion to power, at least
//! one for every light that has power, so that a light's photons carry exactly its power; and
//! how each leaves its light (aimed at the casters of caustics, for a caustic pass).

use super::Projection;
use crate::light::{EmissionSample, Light};
use crate::sampling::Sampler;

/// The most photons a pass (`photon`) or iteration (`sppm`) may emit: 20 million. (`photon`'s
/// stored photons are counted against `--max-memory` too: `pipeline::check_render_memory`.)
pub const MAX_PHOTONS: u32 = 20_000_000;

/// Photons `0..total` of a pass by light: light `l` emits photons `first[l]..first[l + 1]`.
#[derive(Debug, Clone)]
pub struct Emission {
    first: Vec<u32>,
    /// Where a caustic pass aims its photons; `None` for a pass of every photon.
    projection: Option<Projection>,
}

impl Emission {
    /// A pass of every photon: `photons` shared out by the lights' powers (`shared`).
    pub fn new(lights: &[Light], photons: u32) -> Self {
        Self::shared(lights.iter().map(Light::power).collect(), photons, None)
    }

    /// A caustic pass: `photons` photons aimed by `projection`, shared out by the power each
    /// light sends into it (`Projection::share_of`).
    pub fn aimed(lights: &[Light], projection: Projection, photons: u32) -> Self {
        let powers = lights.iter().map(|l| l.power() * projection.share_of(l)).collect();
        Self::shared(powers, photons, Some(projection))
    }

    /// `photons` photons by `powers` (or one per light with power, if that is more), light `l` taking
    /// 1 + floor(m C_l / C) - floor(m C_(l-1) / C) of them, where C_l sums `powers` of the
    /// lights up to l and m is the photons left after the first of each: the counts add up to
    /// the total and follow the powers within one photon.
    fn shared(powers: Vec<f32>, photons: u32, projection: Option<Projection>) -> Self {
        let powers: Vec<f64> = powers.into_iter().map(|p| f64::from(p.max(0.0))).collect();
        let total: f64 = powers.iter().sum();
        let powered = powers.iter().filter(|&&p| p > 0.0).count() as u32;
        let shared = f64::from(photons.saturating_sub(powered));
        let last_powered = powers.iter().rposition(|&p| p > 0.0);
        let mut first = vec![0];
        let (mut below, mut emitted, mut before) = (0.0, 0u32, 0.0);
        for (l, power) in powers.into_iter().enumerate() {
            if power > 0.0 {
                below += power;
                // The last light takes what is left: rounding must not lose a photon.
                let upto = if Some(l) == last_powered {
                    shared
                } else {
                    (shared * below / total).floor().min(shared)
                };
                emitted += 1 + (upto - before) as u32;
                before = upto;
            }
            first.push(emitted);
        }
        Emission { first, projection }
    }

    /// Where one of `photons` photons of `light` starts, from `sampler`'s next numbers.
    pub fn start(
        &self,
        light: &Light,
        photons: u32,
        sampler: &mut Sampler,
    ) -> Option<EmissionSample> {
        let (u_point, u_direction) = (sampler.next_2d(), sampler.next_2d());
        match &self.projection {
            None => light.sample_emission(photons, u_point, u_direction),
            Some(aim) => {
                aim.sample_emission(light, photons, sampler.next_1d(), u_point, u_direction)
            }
        }
    }

    /// Photons emitted in one pass, by all lights.
    pub fn total(&self) -> u32 {
        *self.first.last().expect("one entry more than lights")
    }

    /// The light that emits photon `index` (< `total`), and how many photons it emits.
    pub fn light_of(&self, index: u32) -> (usize, u32) {
        let light = self.first.partition_point(|&f| f <= index) - 1;
        (light, self.first[light + 1] - self.first[light])
    }

    /// Photons light `light` emits per pass.
    pub fn photons_of(&self, light: usize) -> u32 {
        self.first[light + 1] - self.first[light]
    }
}

//! POV-Ray's surface at a point (`docs/povray.md`): how a finish shares the light with the
//! pigment's colour, filter and transmit there. Written once for the solid pigments the
//! language reads and the patterned ones a scene evaluates at each hit.

use glam::Vec3;

use crate::graph::PovFinish;

/// The lobes' shares at a point: the Lambertian albedo, the mirror, the transmission and the
/// coat (`Material`'s fields of the same names).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shares {
    pub diffuse: Vec3,
    pub specular: Vec3,
    pub transmission: Vec3,
    pub coat: f32,
}

/// The shares of `finish` over a pigment of `colour`, `filter` and `through` (filter +
/// transmit): the opaque part 1 - through × `diffuse` × colour is the albedo; the sum of
/// filter × colour and transmit passes through (POV-Ray's filter is tinted by the colour,
/// transmit is not); the reflection is tinted by the colour when `metallic`. The coat lies over
/// them all (`Covers::Everything`) and takes its reflection from what reaches them, so it
/// shares nothing with them; where they sum to more than 1, they are scaled down together, so
/// no point scatters more than it receives.
pub fn pov_shares(finish: &PovFinish, colour: Vec3, filter: f32, through: f32) -> Shares {
    let through = through.clamp(0.0, 1.0);
    let filter = filter.clamp(0.0, through);
    let mut diffuse = finish.diffuse.max(0.0) * (1.0 - through);
    let mut specular = finish.reflection.max(Vec3::ZERO);
    if finish.metallic {
        specular *= colour;
    }
    let mut transmission = filter * colour + Vec3::splat(through - filter);
    let total = (diffuse * colour + specular + transmission).max_element();
    if total > 1.0 {
        diffuse /= total;
        specular /= total;
        transmission /= total;
    }
    Shares { diffuse: diffuse * colour, specular, transmission, coat: finish.coat.clamp(0.0, 1.0) }
}

#[cfg(test)]
mod tests {
    use super::*;

    const PLAIN: PovFinish =
        PovFinish { diffuse: 0.6, reflection: Vec3::ZERO, metallic: false, coat: 0.0 };

    #[test]
    fn filter_is_tinted_by_the_colour_and_transmit_is_not() {
        let red = Vec3::new(1.0, 0.2, 0.2);
        let s = pov_shares(&PLAIN, red, 0.5, 0.5);
        assert!((s.transmission - 0.5 * red).abs().max_element() < 1e-6, "{s:?}");
        assert!((s.diffuse - 0.3 * red).abs().max_element() < 1e-6, "opaque half × 0.6");
        let s = pov_shares(&PLAIN, red, 0.0, 0.25);
        assert!((s.transmission - Vec3::splat(0.25)).abs().max_element() < 1e-6, "{s:?}");
        assert!((s.diffuse - 0.45 * red).abs().max_element() < 1e-6, "{s:?}");
    }

    #[test]
    fn a_clear_point_lets_all_through_and_reflects_nothing_diffusely() {
        let s = pov_shares(&PLAIN, Vec3::ONE, 1.0, 1.0);
        assert_eq!((s.diffuse, s.transmission), (Vec3::ZERO, Vec3::ONE));
    }

    /// Energy: at no point do the shares beneath the coat scatter more than 1, whatever the
    /// finish asks; the coat keeps its strength (it takes its light from theirs).
    #[test]
    fn no_point_scatters_more_than_it_receives() {
        let greedy =
            PovFinish { diffuse: 1.0, reflection: Vec3::splat(0.7), metallic: false, coat: 0.9 };
        for (c, f, t) in [(1.0, 0.0, 0.0), (1.0, 1.0, 1.0), (0.8, 0.3, 0.6), (0.5, 0.0, 0.4)] {
            let s = pov_shares(&greedy, Vec3::splat(c), f, t);
            let total = (s.diffuse + s.specular + s.transmission).max_element();
            assert!(total <= 1.0 + 1e-6, "c {c} f {f} through {t}: {total}");
            assert!(total > 0.99, "scaled down only to 1: {total}");
            assert_eq!(s.coat, 0.9);
        }
    }

    /// A clear pigment under a full highlight passes all its light to the coat's care: the
    /// highlight takes none of the transmission's share (issue 33: it took half).
    #[test]
    fn a_highlight_takes_nothing_from_a_clear_pigment() {
        let shiny = PovFinish { coat: 1.0, ..PLAIN };
        let s = pov_shares(&shiny, Vec3::ONE, 1.0, 1.0);
        assert_eq!((s.transmission, s.coat), (Vec3::ONE, 1.0));
    }
}

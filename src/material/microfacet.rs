//! The GGX / Trowbridge–Reitz distribution of microfacet normals with parameter alpha (Walter
//! et al. 2007), Smith's masking, and sampling of the normals visible from a direction (Heitz
//! 2018). Directions are in a local frame whose +z is the macro-surface normal.

use std::f32::consts::PI;

use glam::{Vec2, Vec3};

#[derive(Debug, Clone, Copy)]
pub struct Ggx {
    pub alpha: f32,
}

impl Ggx {
    /// D(m) = alpha^2 / (pi (sin^2 + alpha^2 cos^2)^2) for unit m above the surface, 0 below
    /// (Walter 2007, eq. 33, with the tangent written out so that alpha near 0 keeps its bits).
    pub fn d(&self, m: Vec3) -> f32 {
        if m.z <= 0.0 {
            return 0.0;
        }
        let a2 = self.alpha * self.alpha;
        let t = m.x * m.x + m.y * m.y + a2 * m.z * m.z;
        a2 / (PI * t * t)
    }

    /// Smith's masking G1(w) = 1 / (1 + Lambda(w)), Lambda = (sqrt(1 + alpha^2 tan^2) - 1) / 2
    /// (Walter 2007, eq. 34): the fraction of the microfacets facing w that w sees.
    pub fn g1(&self, w: Vec3) -> f32 {
        let cos2 = w.z * w.z;
        if cos2 == 0.0 {
            return 0.0;
        }
        let tan2 = (w.x * w.x + w.y * w.y) / cos2;
        let lambda = ((1.0 + self.alpha * self.alpha * tan2).sqrt() - 1.0) * 0.5;
        1.0 / (1.0 + lambda)
    }

    /// Density of the normals visible from `w` (w.z > 0): D_w(m) = G1(w) max(0, w.m) D(m) / w.z
    /// (Heitz 2018, eq. 2); it integrates to 1 over the hemisphere of m.
    pub fn visible_pdf(&self, w: Vec3, m: Vec3) -> f32 {
        let cos = w.dot(m);
        if cos <= 0.0 || w.z <= 0.0 {
            return 0.0;
        }
        self.g1(w) * cos * self.d(m) / w.z
    }

    /// A normal drawn from `visible_pdf(w, ·)` (w.z > 0): stretch w to the hemisphere
    /// configuration, sample a point on the projected half disk, lift it, unstretch (Heitz
    /// 2018, listing 1).
    pub fn sample_visible(&self, w: Vec3, u: Vec2) -> Vec3 {
        let a = self.alpha;
        let wh = Vec3::new(a * w.x, a * w.y, w.z).normalize();
        let len2 = wh.x * wh.x + wh.y * wh.y;
        let t1 = if len2 > 0.0 { Vec3::new(-wh.y, wh.x, 0.0) / len2.sqrt() } else { Vec3::X };
        let t2 = wh.cross(t1);
        let r = u.x.sqrt();
        let phi = 2.0 * PI * u.y;
        let (p1, p2) = (r * phi.cos(), r * phi.sin());
        let s = 0.5 * (1.0 + wh.z);
        let p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * p2;
        let nh = p1 * t1 + p2 * t2 + (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt() * wh;
        Vec3::new(a * nh.x, a * nh.y, nh.z.max(0.0)).normalize()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Midpoint rule over (cos theta, phi) of the upper hemisphere.
    fn hemisphere_integral(f: impl Fn(Vec3) -> f64) -> f64 {
        let (nc, np) = (4000, 64);
        let mut sum = 0.0;
        for i in 0..nc {
            let cos = (i as f64 + 0.5) / nc as f64;
            let sin = (1.0 - cos * cos).sqrt();
            for j in 0..np {
                let phi = (j as f64 + 0.5) / np as f64 * 2.0 * std::f64::consts::PI;
                let m = Vec3::new((sin * phi.cos()) as f32, (sin * phi.sin()) as f32, cos as f32);
                sum += f(m);
            }
        }
        sum * 2.0 * std::f64::consts::PI / (nc * np) as f64
    }

    #[test]
    fn d_integrates_to_one_over_projected_area() {
        // ∫ D(m) cos(theta_m) dm = 1 (Walter 2007, eq. 4).
        for alpha in [0.1, 0.3, 0.5, 1.0] {
            let ggx = Ggx { alpha };
            let total = hemisphere_integral(|m| f64::from(ggx.d(m) * m.z));
            assert!((total - 1.0).abs() < 2e-3, "alpha {alpha}: {total}");
        }
    }

    #[test]
    fn visible_normals_integrate_to_one() {
        // ∫ G1(w) max(0, w.m) D(m) / w.z dm = 1 (Heitz 2018, eq. 2): G1 is Smith's for GGX.
        for alpha in [0.1, 0.5, 1.0] {
            let ggx = Ggx { alpha };
            for theta in [0.0f32, 0.7, 1.3, 1.55] {
                let w = Vec3::new(theta.sin(), 0.0, theta.cos());
                let total = hemisphere_integral(|m| f64::from(ggx.visible_pdf(w, m)));
                assert!((total - 1.0).abs() < 3e-3, "alpha {alpha}, theta {theta}: {total}");
            }
        }
    }

    #[test]
    fn alpha_one_is_the_uniform_hemisphere_in_projected_area() {
        // alpha = 1: D = 1 / pi for every m above, and no masking seen straight on.
        let ggx = Ggx { alpha: 1.0 };
        let m = Vec3::new(0.6, 0.0, 0.8);
        assert!((ggx.d(m) - 1.0 / PI).abs() < 1e-6);
        assert_eq!(ggx.g1(Vec3::Z), 1.0);
    }
}

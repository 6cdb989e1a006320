//! Fresnel reflectance and Snell refraction for smooth dielectrics, and how a boundary shares
//! what arrives between reflection and transmission.

use glam::Vec3;

/// How a boundary divides what arrives between reflection and transmission.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Split {
    /// Fresnel's equations: `total` times F reflected, times 1 - F transmitted.
    Fresnel { total: Vec3 },
    /// The course's fixed reflectance `reflect` (ks) and transmittance `transmit` (kt), whatever
    /// the angle; beyond the critical angle everything reflects.
    Fixed { reflect: Vec3, transmit: Vec3 },
}

impl Split {
    /// Reflectance and transmittance for light arriving at cosine `cos_i` (>= 0) onto a boundary
    /// of relative index `eta` = eta_t / eta_i; transmittance 0 where it reflects totally.
    #[inline]
    pub fn at(&self, cos_i: f32, eta: f32) -> (Vec3, Vec3) {
        match *self {
            Split::Fresnel { total } => {
                let f = fresnel_dielectric(cos_i, eta);
                (f * total, (1.0 - f) * total)
            }
            Split::Fixed { reflect, transmit } if reflects_totally(cos_i, eta) => {
                (reflect + transmit, Vec3::ZERO)
            }
            Split::Fixed { reflect, transmit } => (reflect, transmit),
        }
    }

    /// The energy shared, reflected and transmitted together (mean over RGB): what the lobe is
    /// chosen by.
    #[inline]
    pub fn total(&self) -> Vec3 {
        match *self {
            Split::Fresnel { total } => total,
            Split::Fixed { reflect, transmit } => reflect + transmit,
        }
    }
}

/// Unpolarised Fresnel reflectance for light arriving at cosine `cos_i` (>= 0) onto a boundary
/// of relative index `eta` = eta_t / eta_i; 1 under total internal reflection (pbrt-v4, 9.3).
pub fn fresnel_dielectric(cos_i: f32, eta: f32) -> f32 {
    let cos_i = cos_i.clamp(0.0, 1.0);
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let r_parallel = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let r_perpendicular = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    0.5 * (r_parallel * r_parallel + r_perpendicular * r_perpendicular)
}

/// Whether light arriving at cosine `cos_i` onto a boundary of relative index `eta` reflects
/// totally (Snell: sin^2 of the refracted angle would reach 1).
pub fn reflects_totally(cos_i: f32, eta: f32) -> bool {
    (1.0 - cos_i * cos_i).max(0.0) / (eta * eta) >= 1.0
}

/// The direction refracted from `wo` through a boundary with normal `n` on wo's side and
/// relative index `eta` = eta_t / eta_i (Snell's law); `None` under total internal reflection.
pub fn refract(wo: Vec3, n: Vec3, eta: f32) -> Option<Vec3> {
    let cos_i = n.dot(wo);
    let sin2_t = (1.0 - cos_i * cos_i).max(0.0) / (eta * eta);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some(-wo / eta + (cos_i / eta - cos_t) * n)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normal_incidence_on_glass_reflects_four_percent() {
        // ((n - 1) / (n + 1))^2 = (0.5 / 2.5)^2 = 0.04
        assert!((fresnel_dielectric(1.0, 1.5) - 0.04).abs() < 1e-6);
        assert!((fresnel_dielectric(1.0, 1.0 / 1.5) - 0.04).abs() < 1e-6);
    }

    #[test]
    fn total_internal_reflection_beyond_the_critical_angle() {
        let critical = (1.0f32 / 1.5).asin();
        let eta = 1.0 / 1.5; // leaving glass
        let just_below = (critical - 1e-3).cos();
        let just_above = (critical + 1e-3).cos();
        assert!(fresnel_dielectric(just_below, eta) < 1.0);
        assert_eq!(fresnel_dielectric(just_above, eta), 1.0);
        let wo_beyond = Vec3::new((critical + 1e-3).sin(), 0.0, (critical + 1e-3).cos());
        assert!(refract(wo_beyond, Vec3::Z, eta).is_none());
    }

    #[test]
    fn refraction_obeys_snell() {
        let theta_i = 0.6f32;
        let wo = Vec3::new(theta_i.sin(), 0.0, theta_i.cos());
        let wi = refract(wo, Vec3::Z, 1.5).unwrap();
        assert!((wi.length() - 1.0).abs() < 1e-6);
        assert!(wi.z < 0.0 && wi.x < 0.0, "passes through, on the other side of the normal");
        // sin(theta_i) = 1.5 sin(theta_t)
        assert!((theta_i.sin() - 1.5 * wi.x.abs()).abs() < 1e-6);
    }
}

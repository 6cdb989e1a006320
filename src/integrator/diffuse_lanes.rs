//! Path vertices on a lone Lambertian lobe (`Material::lone_lambertian`) under multiple importance
//! sampling, computed for all lanes at once: the light sample of a point or planar light
//! (`LanesLight`), the lobe's f and pdf there, the power heuristic and the shadow ray, then the
//! shading frame, the cosine-weighted direction and its density, and the next ray. Each lane is
//! set with what these read, as its bounce leaves it (`Path::bounce_by`), and computes by the
//! kernels one path runs (`Light::sample`, `Lambertian`, `Frame`, `power_heuristic`,
//! `offset_origin`), so a lane's vertex is that path's, bit for bit.

use glam::{Vec2, Vec3};

use super::{ShadowLanes, power_heuristic_of};
use crate::geometry::{Frame, Hit, Ray};
use crate::lanes::{Floats, Lane, Mask, MaskLanes, Real, Vec3Lanes, offset_point};
use crate::material::lobe::Lambertian;
use crate::scene::Scene;

/// The lanes' vertices, coordinate by coordinate, and which lanes have one.
pub(super) struct DiffuseLanes {
    set: Mask,
    point: Vec3Lanes,
    normal: Vec3Lanes,
    error: Floats,
    shading_normal: Vec3Lanes,
    wo: Vec3Lanes,
    kd: Vec3Lanes,
    /// The throughput before this vertex.
    beta: Vec3Lanes,
    /// The light chosen (its index in `Scene::lights`, exact in an `f32`; -1 for none) and the
    /// probability of that choice.
    light: Floats,
    probability: Floats,
    u_light: (Floats, Floats),
    u: (Floats, Floats),
}

/// A lane's vertex, as its bounce leaves it.
pub(super) struct DiffuseVertex<'a> {
    pub(super) hit: &'a Hit,
    pub(super) wo: Vec3,
    pub(super) kd: Vec3,
    pub(super) beta: Vec3,
    /// The light chosen for next-event estimation, the probability of that choice and the
    /// point that samples it (`Path::choose_light`).
    pub(super) light: Option<(usize, f32, Vec2)>,
    pub(super) u: Vec2,
}

/// The lanes' BSDF samples: where a lane's path goes on (`continues`), its next ray, and the
/// vertex and the direction's density (`PathState::previous`).
pub(super) struct DiffuseSamples {
    continues: Mask,
    point: Vec3Lanes,
    origin: Vec3Lanes,
    wi: Vec3Lanes,
    pdf: Floats,
}

impl DiffuseLanes {
    pub(super) fn new() -> Self {
        let zero = (Floats::ZERO, Floats::ZERO);
        DiffuseLanes {
            set: Mask::none(),
            point: Vec3Lanes::ZERO,
            normal: Vec3Lanes::ZERO,
            error: Floats::ZERO,
            shading_normal: Vec3Lanes::splat(Vec3::Z),
            wo: Vec3Lanes::splat(Vec3::Z),
            kd: Vec3Lanes::ZERO,
            beta: Vec3Lanes::ZERO,
            light: -Floats::ONE,
            probability: Floats::ONE,
            u_light: zero,
            u: zero,
        }
    }

    /// Sets `lane`'s vertex, if the lanes sample its light: none, or one that `Light::in_lanes`
    /// takes (and none where that light never lights the surface hit). Whether it did.
    #[inline(always)]
    pub(super) fn set_lane(&mut self, scene: &Scene, lane: usize, vertex: DiffuseVertex) -> bool {
        let DiffuseVertex { hit, wo, kd, beta, light, u } = vertex;
        let (light, probability, u_light) = match light {
            Some((index, probability, u_light)) => {
                let light = &scene.lights[index];
                if light.in_lanes().is_none() {
                    return false;
                }
                let index = if light.never_lights(hit.primitive) { -1.0 } else { index as f32 };
                (index, probability, u_light)
            }
            None => (-1.0, 1.0, Vec2::ZERO),
        };
        self.set.set_lane(lane, true);
        self.point.set_lane(lane, hit.point);
        self.normal.set_lane(lane, hit.normal);
        self.error.set_lane(lane, hit.error);
        self.shading_normal.set_lane(lane, hit.shading_normal);
        self.wo.set_lane(lane, wo);
        self.kd.set_lane(lane, kd);
        self.beta.set_lane(lane, beta);
        self.light.set_lane(lane, light);
        self.probability.set_lane(lane, probability);
        self.u_light.0.set_lane(lane, u_light.x);
        self.u_light.1.set_lane(lane, u_light.y);
        self.u.0.set_lane(lane, u.x);
        self.u.1.set_lane(lane, u.y);
        true
    }

    /// The lanes set.
    #[inline(always)]
    pub(super) fn set(&self) -> u32 {
        self.set.bitmask()
    }

    /// Every set lane's vertex: its shadow ray and the radiance it brings put in `shadows`
    /// (`Path::next_event`), and its BSDF sample (`Bsdf::sample`).
    #[inline(always)]
    pub(super) fn scatter(&self, scene: &Scene, shadows: &mut ShadowLanes) -> DiffuseSamples {
        let frame = Frame::around(self.shading_normal);
        let wo_z = frame.local(self.wo).z;
        // The lanes of each light in turn (most scenes have one).
        let mut left = self.set & self.light.ge(Floats::ZERO);
        while left.any() {
            let index = self.light.lane(left.bitmask().trailing_zeros() as usize);
            let same = left & self.light.eq(Floats::splat(index));
            left = left & !same;
            let Some(light) = scene.lights[index as usize].in_lanes() else { continue };
            let sample = light.sample(self.point, self.normal, self.error, self.u_light);
            let wi_z = frame.local(sample.wi).z;
            let f = Lambertian::eval_of(self.kd, wo_z, wi_z);
            let light_pdf = self.probability * sample.pdf;
            let weight = if sample.is_delta {
                Floats::ONE
            } else {
                power_heuristic_of(light_pdf, Lambertian::pdf_of(wo_z, wi_z))
            };
            let cos = self.shading_normal.dot(sample.wi).abs();
            let radiance = self.beta * (f * sample.li * cos * weight / light_pdf);
            let found = same & sample.found & !f.is_zero();
            shadows.set_lanes(found, (sample.origin, sample.dir, sample.t_max), radiance);
        }
        let (local, pdf) = Lambertian::direction(wo_z, self.u.0, self.u.1);
        let wi = frame.world(local);
        let origin = offset_point(self.point, self.normal, self.error, wi);
        let continues = pdf.gt(Floats::ZERO);
        DiffuseSamples { continues, point: self.point, origin, wi, pdf }
    }
}

impl DiffuseSamples {
    /// Whether `lane`'s path goes on.
    #[inline(always)]
    pub(super) fn continues(&self, lane: usize) -> bool {
        self.continues.lane(lane)
    }

    /// `lane`'s next ray, and its vertex and the ray's density.
    #[inline(always)]
    pub(super) fn lane(&self, lane: usize) -> (Ray, (Vec3, f32)) {
        let ray = Ray::new(self.origin.lane(lane), self.wi.lane(lane));
        (ray, (self.point.lane(lane), self.pdf.lane(lane)))
    }
}

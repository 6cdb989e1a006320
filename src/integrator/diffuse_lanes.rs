//! Path vertices on a lone Lambertian lobe (`Material::lone_lambertian`) under multiple importance
//! sampling, computed for all lanes at once: the light sample of a point or planar light
//! (`LanesLight`), the lobe's f and pdf there, the power heuristic and the shadow ray, then the
//! shading frame, the cosine-weighted direction and its density, and the next ray. The hit and
//! `wo` are read where the lanes' rays met the scene (such a vertex leaves its hit as found);
//! the rest each lane is set with as its bounce leaves it (`Path::bounce_by`). Each computes by
//! the kernels one path runs (`Light::sample`, `Lambertian`, `Frame`, `power_heuristic`,
//! `offset_origin`), so a lane's vertex is that path's, bit for bit.

use glam::{Vec2, Vec3};

use super::{ShadowLanes, power_heuristic_of};
use crate::geometry::{Frame, Ray};
use crate::lanes::{Floats, HitLanes, Lane, Mask, MaskLanes, Real, Vec3Lanes, offset_point};
use crate::material::lobe::Lambertian;
use crate::scene::Scene;

/// The lanes' vertices, coordinate by coordinate, and which lanes have one (their hits are the
/// lanes' hit records).
pub(super) struct DiffuseLanes {
    set: Mask,
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

/// A lane's vertex, as its bounce leaves it, at the hit its ray found.
pub(super) struct DiffuseVertex {
    /// The primitive hit.
    pub(super) primitive: u32,
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
        let DiffuseVertex { primitive, kd, beta, light, u } = vertex;
        let (light, probability, u_light) = match light {
            Some((index, probability, u_light)) => {
                let light = &scene.lights[index];
                if light.in_lanes().is_none() {
                    return false;
                }
                let index = if light.never_lights(primitive) { -1.0 } else { index as f32 };
                (index, probability, u_light)
            }
            None => (-1.0, 1.0, Vec2::ZERO),
        };
        self.set.set_lane(lane, true);
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

    /// Every set lane's vertex, at its lane of `hits` and seen from its lane of `wo`: its shadow
    /// ray and the radiance it brings put in `shadows` (`Path::next_event`), and its BSDF
    /// sample (`Bsdf::sample`). (Read from the hit records, not set lane by lane: set, they were
    /// half of what setting a lane cost, perf of S3.)
    #[inline(always)]
    pub(super) fn scatter(
        &self,
        scene: &Scene,
        hits: &HitLanes,
        wo: Vec3Lanes,
        shadows: &mut ShadowLanes,
    ) -> DiffuseSamples {
        let HitLanes { point, normal, shading_normal, error } = *hits;
        let frame = Frame::around(shading_normal);
        let wo_z = frame.local(wo).z;
        // The lanes of each light in turn (most scenes have one).
        let mut left = self.set & self.light.ge(Floats::ZERO);
        while left.any() {
            let index = self.light.lane(left.bitmask().trailing_zeros() as usize);
            let same = left & self.light.eq(Floats::splat(index));
            left = left & !same;
            let Some(light) = scene.lights[index as usize].in_lanes() else { continue };
            let sample = light.sample(point, normal, error, self.u_light);
            let wi_z = frame.local(sample.wi).z;
            let f = Lambertian::eval_of(self.kd, wo_z, wi_z);
            let light_pdf = self.probability * sample.pdf;
            let weight = if sample.is_delta {
                Floats::ONE
            } else {
                power_heuristic_of(light_pdf, Lambertian::pdf_of(wo_z, wi_z))
            };
            let cos = shading_normal.dot(sample.wi).abs();
            let radiance = self.beta * (f * sample.li * cos * weight / light_pdf);
            let found = same & sample.found & !f.is_zero();
            shadows.set_lanes(found, (sample.origin, sample.dir, sample.t_max), radiance);
        }
        let (local, pdf) = Lambertian::direction(wo_z, self.u.0, self.u.1);
        let wi = frame.world(local);
        let origin = offset_point(point, normal, error, wi);
        let continues = pdf.gt(Floats::ZERO);
        DiffuseSamples { continues, point, origin, wi, pdf }
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

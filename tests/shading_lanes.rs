//! Light and BSDF samples computed four lanes at a time (as the path integrator computes them)
//! are exactly those computed one at a time: the same operations in the same order.

mod common;

use common::{LAB_BOX, scene};
use glam::{BVec4A, Vec2, Vec3, Vec4};
use raydiance::geometry::{Hit, HitLanes, LANES, Lane, Ray, Vec2x4, Vec3x4};
use raydiance::light::sample_lanes;
use raydiance::material::{
    LobeFlags, Material, TransportMode, eval_diffuse_lanes, sample_lambertian_lanes,
};
use raydiance::sampling::{Sampler, uniform_sphere};

#[test]
fn lights_sampled_in_lanes_agree_with_one_at_a_time() {
    // Each planar kind, facing down or up, a point light, and a sphere light (sampled one at a
    // time by the integrator, so not handled here).
    let scene = scene(&format!(
        "{LAB_BOX}
        quad {{ <-0.25, 0.99, -0.25>, <0.5, 0, 0>, <0, 0, 0.5>  material {{ emission rgb 10 }} }}
        disk {{ <0.5, 0.2, 0.5>, <0, 1, 0>, 0.3  material {{ emission rgb <1, 2, 3> }} }}
        triangle {{ <-0.9, -0.5, 0.9>, <0.9, -0.5, 0.9>, <0, 0.5, 0.5>  material {{ emission rgb 4 }} }}
        sphere {{ <-0.5, -0.7, 0.25>, 0.2  material {{ emission rgb 1 }} }}
        light_source {{ <0, 0.5, -0.5>  power rgb 2 }}"
    ));
    let mut sampler = Sampler::new(7, 8, 9);
    let (mut found, mut own, mut points) = (0, 0, 0);
    for round in 0..3000 {
        let hits: [Option<Hit>; LANES] = std::array::from_fn(|_| {
            let origin = 1.8 * Vec3::new(sampler.next_1d(), sampler.next_1d(), sampler.next_1d());
            scene.intersect(&Ray::new(origin - 0.9, uniform_sphere(sampler.next_2d())))
        });
        let lights: [Option<(usize, Vec2)>; LANES] = std::array::from_fn(|lane| {
            let light = (sampler.next_1d() * scene.lights.len() as f32) as usize;
            let u = sampler.next_2d();
            (hits[lane].is_some() && (round + lane) % 5 != 0).then_some((light, u))
        });
        let primitives = hits.map(|h| h.map_or(u32::MAX, |h| h.primitive));
        let mut hit_lanes = HitLanes::default();
        for (lane, hit) in hits.iter().enumerate().filter_map(|(l, h)| Some((l, h.as_ref()?))) {
            hit_lanes.set_lane(lane, hit);
        }
        let u = Vec2x4::from_lanes(lights.map(|l| l.map_or(Vec2::ZERO, |(_, u)| u)));
        let lanes = sample_lanes(&scene, &hit_lanes, primitives, lights.map(|l| Some(l?.0)), u);
        for lane in 0..LANES {
            let (Some(hit), Some((light, u))) = (hits[lane], lights[lane]) else {
                assert!(lanes.is_none_or(|l| !l.handled.test(lane)), "an idle lane is not handled");
                continue;
            };
            if scene.lights_in_lanes[light].is_none() {
                assert!(
                    lanes.is_none_or(|l| !l.handled.test(lane)),
                    "light {light} is sampled one at a time"
                );
                continue;
            }
            let lanes = lanes.expect("a light sampled in lanes makes lanes");
            assert!(lanes.handled.test(lane));
            let alone = scene.lights[light].sample(&hit, u);
            assert_eq!(lanes.found.test(lane), alone.is_some(), "light {light} from {hit:?}");
            let in_lanes = scene.lights[light].in_lanes().unwrap();
            own += usize::from(in_lanes.planar.is_some_and(|(p, _)| p == hit.primitive));
            points += usize::from(in_lanes.planar.is_none());
            let Some(alone) = alone else { continue };
            found += 1;
            assert_eq!(lanes.wi.lane(lane), alone.wi);
            assert_eq!(lanes.li.lane(lane), alone.li);
            assert_eq!(lanes.pdf[lane], alone.pdf);
            assert_eq!(lanes.is_delta.test(lane), alone.is_delta);
            let shadow = (lanes.shadow_origin.lane(lane), lanes.shadow_dir.lane(lane));
            assert_eq!(shadow, (alone.shadow.ray.origin.into(), alone.shadow.ray.dir.into()));
            assert_eq!(lanes.shadow_t_max[lane], alone.shadow.t_max);
        }
    }
    assert!(
        found > 2000 && own > 50 && points > 500,
        "samples found {found}, from a light's own surface {own}, of the point light {points}"
    );
}

/// Unit normals of every orientation, including the poles where the tangent frame changes sign.
fn normals(sampler: &mut Sampler) -> [Vec3; LANES] {
    std::array::from_fn(|lane| match sampler.next_1d() {
        u if u < 0.1 => Vec3::Z,
        u if u < 0.2 => -Vec3::Z,
        u if u < 0.3 => [Vec3::X, -Vec3::Y, Vec3::new(0.6, 0.0, -0.8)][lane % 3],
        _ => uniform_sphere(sampler.next_2d()),
    })
}

fn diffuse(sampler: &mut Sampler) -> Material {
    Material { diffuse: Vec3::new(sampler.next_1d(), 0.5, 0.9), ..Material::default() }
}

#[test]
fn lambertian_samples_in_lanes_agree_with_one_at_a_time() {
    let mut sampler = Sampler::new(1, 2, 3);
    let key = |s: Option<raydiance::material::BsdfSample>| {
        s.map(|s| (s.wi, s.weight, s.pdf, s.is_delta(), s.eta))
    };
    for round in 0..5000 {
        let n = normals(&mut sampler);
        let wo: [Vec3; LANES] = std::array::from_fn(|_| uniform_sphere(sampler.next_2d()));
        // The disk's centre and edges as well as inner points.
        let u: [Vec2; LANES] = std::array::from_fn(|lane| match (round + lane) % 9 {
            0 => Vec2::splat(0.5),
            1 => Vec2::new(0.0, sampler.next_1d()),
            _ => sampler.next_2d(),
        });
        let materials: [Material; LANES] = std::array::from_fn(|_| diffuse(&mut sampler));
        let present: [bool; LANES] = std::array::from_fn(|lane| (round + lane) % 6 != 0);
        let lanes = sample_lambertian_lanes(
            BVec4A::from_array(present),
            Vec3x4::from_lanes(materials.each_ref().map(|m| m.diffuse)),
            Vec3x4::from_lanes(n),
            Vec3x4::from_lanes(wo),
            Vec2x4::from_lanes(u),
        );
        for lane in 0..LANES {
            let bsdf = materials[lane].bsdf(n[lane], TransportMode::Radiance);
            let alone =
                bsdf.sample(wo[lane], 0.0, u[lane], LobeFlags::ALL).filter(|_| present[lane]);
            let in_lanes = lanes.found.test(lane).then(|| {
                let (wi, weight) = (lanes.wi.lane(lane), lanes.weight.lane(lane));
                (wi, weight, lanes.pdf[lane], lanes.delta.test(lane), lanes.eta[lane])
            });
            assert_eq!(in_lanes, key(alone), "n {} wo {} u {}", n[lane], wo[lane], u[lane]);
        }
    }
}

#[test]
fn diffuse_lobes_evaluated_in_lanes_agree_with_eval_and_pdf() {
    let mut sampler = Sampler::new(4, 5, 6);
    for round in 0..5000 {
        let n = normals(&mut sampler);
        let [wo, wi]: [[Vec3; LANES]; 2] =
            std::array::from_fn(|_| std::array::from_fn(|_| uniform_sphere(sampler.next_2d())));
        // Lambertian, and mixtures whose diffuse lobe is chosen with a probability below 1.
        let materials: [Material; LANES] = std::array::from_fn(|lane| match (round + lane) % 3 {
            0 => diffuse(&mut sampler),
            1 => Material { specular: Vec3::splat(0.3), ..diffuse(&mut sampler) },
            _ => Material {
                transmission: Vec3::ONE,
                ior: 1.5,
                fresnel: true,
                ..diffuse(&mut sampler)
            },
        });
        let bsdfs: [_; LANES] =
            std::array::from_fn(|lane| materials[lane].bsdf(n[lane], TransportMode::Radiance));
        let p_diffuse: [f32; LANES] =
            std::array::from_fn(|lane| bsdfs[lane].diffuse_probability(wo[lane]));
        let (f, pdf) = eval_diffuse_lanes(
            Vec3x4::from_lanes(n),
            Vec3x4::from_lanes(wo),
            Vec3x4::from_lanes(wi),
            Vec3x4::from_lanes(materials.each_ref().map(|m| m.diffuse)),
            Vec4::from_array(p_diffuse),
        );
        for (lane, bsdf) in bsdfs.iter().enumerate() {
            assert_eq!(f.lane(lane), bsdf.eval(wo[lane], wi[lane]));
            assert_eq!(pdf[lane], bsdf.pdf(wo[lane], wi[lane], LobeFlags::ALL));
        }
    }
}

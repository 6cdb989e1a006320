//! Rays traced in lanes (`Scene::intersect_lanes`, `Scene::occluded_lanes`) meet the scene
//! where each meets it alone (`Scene::intersect`, `Scene::occluded`), whether the lanes test
//! every shape (a scene of few simple shapes), test the simple ones beside a lone other under its
//! own BVH, or traverse the BVH (a scene of many).

use crate::common;

use common::{LAB_BOX, scene};
use glam::Vec3;
use raydiance::geometry::{Hit, Ray};
use raydiance::lanes::{Floats, LANES, Lane, RayLanes, Wide};
use raydiance::sampling::{Sampler, uniform_sphere};
use raydiance::scene::Scene;

fn assert_lanes_agree_with_single_rays(scene: &Scene) {
    let mut sampler = Sampler::new(1, 2, 3);
    let mut hits = 0;
    for round in 0..2000 {
        let rays: [Ray; LANES] = std::array::from_fn(|_| {
            let origin = 1.8 * Vec3::new(sampler.next_1d(), sampler.next_1d(), sampler.next_1d());
            Ray::new(origin - 0.9, uniform_sphere(sampler.next_2d()))
        });
        // Some lanes idle, as at the end of a row.
        let active: [bool; LANES] = std::array::from_fn(|lane| (round + lane) % 7 != 0);
        let lanes = RayLanes::new(&rays);
        let found = scene.intersect_lanes(&lanes, active);
        let t_max: [f32; LANES] =
            std::array::from_fn(|lane| if active[lane] { 2.0 * sampler.next_1d() } else { 0.0 });
        let occluded = scene.occluded_lanes(&lanes, Floats::from_fn(|lane| t_max[lane]));
        for (lane, ray) in rays.iter().enumerate() {
            let alone = scene.intersect(ray).filter(|_| active[lane]);
            // The whole hit record, made in lanes or one at a time, bit for bit.
            let key = |hit: Option<Hit>| {
                hit.map(|h| (h.primitive, h.t, h.point, h.normal, h.shading_normal, h.error))
            };
            assert_eq!(key(found.hits()[lane]), key(alone), "ray {ray:?}");
            let blocked = active[lane] && scene.occluded(ray, t_max[lane]);
            assert_eq!(occluded.lane(lane), blocked, "ray {ray:?} to {}", t_max[lane]);
            let bounded = |h: &Hit| scene.primitives[h.primitive as usize].shape.bounds().is_some();
            hits += usize::from(alone.as_ref().is_some_and(bounded));
        }
    }
    assert!(hits > 1000, "the bounded shapes are hit often: {hits}");
}

#[test]
fn lanes_that_test_every_shape_agree_with_single_rays() {
    assert_lanes_agree_with_single_rays(&scene(&format!(
        "{LAB_BOX}
        sphere {{ <-0.5, -0.7, 0.25>, 0.3 }}
        sphere {{ <0.5, -0.7, -0.25>, 0.3 }}
        quad {{ <-0.25, 0.99, -0.25>, <0.5, 0, 0>, <0, 0, 0.5> }}
        triangle {{ <-0.9, 0, 0.9>, <0.9, 0, 0.9>, <0, 0.9, 0.5> }}
        disk {{ <0, 0.3, 0>, <0, 1, 0>, 0.4 }}"
    )));
}

#[test]
fn lanes_that_test_simple_shapes_beside_a_lone_other_agree_with_single_rays() {
    // A cylinder is not simple: each lane meets it under a BVH of its own (as S5's mesh), the
    // simple shapes in lanes.
    assert_lanes_agree_with_single_rays(&scene(&format!(
        "{LAB_BOX}
        sphere {{ <-0.5, -0.7, 0.25>, 0.3 }}
        quad {{ <-0.25, 0.99, -0.25>, <0.5, 0, 0>, <0, 0, 0.5> }}
        cylinder {{ <0.5, -1, -0.25>, <0.5, 0.2, -0.25>, 0.3 }}"
    )));
}

#[test]
fn lanes_that_traverse_the_bvh_agree_with_single_rays() {
    // More bounded shapes than the lanes test one by one: they go through the BVH.
    let spheres: String = (0..20)
        .map(|i| {
            let (x, y) = ((i % 5) as f32 * 0.4 - 0.8, (i / 5) as f32 * 0.4 - 0.6);
            format!("sphere {{ <{x}, {y}, 0.2>, 0.15 }}\n")
        })
        .collect();
    assert_lanes_agree_with_single_rays(&scene(&format!("{LAB_BOX}{spheres}")));
}

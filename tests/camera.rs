//! The camera's two forms, its orientation (left-handed, red wall on the left) and thin lens.

use crate::common;

use common::{render_image, scene};
use glam::{Vec2, Vec3, Vec3A};

fn camera_of(camera: &str, resolution: &str) -> raydiance::camera::Camera {
    scene(&format!("settings {{ resolution {resolution} }} {camera}")).camera
}

#[test]
fn lab_form_and_look_at_form_give_the_same_rays() {
    let lab = camera_of(
        "camera { origin <0, 0, -3.5>  left <-1, 0, 0>  up <0, 1, 0>  forward <0, 0, 3> }",
        "64, 64",
    );
    // Horizontal field of view 2 atan(1/3), written as an expression.
    let look_at = camera_of(
        "camera { location <0, 0, -3.5>  look_at <0, 0, 0>  angle degrees(2 * atan(1 / 3)) }",
        "64, 64",
    );
    for i in 0..=10 {
        for j in 0..=10 {
            let (x, y) = (i as f32 / 10.0, j as f32 / 10.0);
            let (a, b) = (lab.ray(x, y, Vec2::ZERO), look_at.ray(x, y, Vec2::ZERO));
            assert!((a.origin - b.origin).length() < 1e-6);
            assert!((a.dir - b.dir).length() < 1e-5, "at ({x}, {y}): {} vs {}", a.dir, b.dir);
        }
    }
}

#[test]
fn look_at_form_follows_the_image_aspect_ratio() {
    let wide = camera_of("camera { location <0, 0, -5>  look_at <0, 0, 0>  angle 60 }", "200, 100");
    assert!((wide.left.length() / wide.up.length() - 2.0).abs() < 1e-5);
    let top_left = wide.ray(0.0, 0.0, Vec2::ZERO).dir;
    assert!(
        top_left.x < 0.0 && top_left.y > 0.0,
        "row 0 is the top, column 0 the left: {top_left}"
    );
}

#[test]
fn centre_ray_is_parallel_to_forward() {
    let camera = camera_of(
        "camera { origin <1, 2, 3>  left <0, 0, 1>  up <0, 1, 0>  forward <2, 0, 0> }",
        "32, 32",
    );
    assert!((camera.ray(0.5, 0.5, Vec2::ZERO).dir - Vec3A::X).length() < 1e-6);
}

#[test]
fn red_wall_is_on_the_left_of_the_image() {
    let mut s = common::scene_file("scenes/lab4-direct.scn");
    s.settings.width = 16;
    s.settings.height = 16;
    s.settings.samples = 1;
    let image = render_image(&s);
    // Middle row: the left quarter is the red wall, the right quarter the green one.
    let y = 8;
    let left: Vec3 = (0..3).map(|x| image.get(x, y)).sum();
    let right: Vec3 = (13..16).map(|x| image.get(x, y)).sum();
    assert!(left.x > 3.0 * left.y, "left is red: {left}");
    assert!(right.y > 3.0 * right.x, "right is green: {right}");
}

#[test]
fn thin_lens_keeps_the_focal_plane_sharp() {
    let lens = camera_of(
        "camera { origin <0, 0, -3.5>  left <-1, 0, 0>  up <0, 1, 0>  forward <0, 0, 3>
                  aperture 0.2  focal_distance 4.5 }",
        "32, 32",
    );
    // Rays through the same image point from different lens points meet at the focal plane.
    let (x, y) = (0.3, 0.8);
    let focus = |u: Vec2| {
        let ray = lens.ray(x, y, u);
        ray.origin + ray.dir * ((1.0 - ray.origin.z) / ray.dir.z)
    };
    let a = focus(Vec2::new(0.1, 0.2));
    let b = focus(Vec2::new(0.9, 0.7));
    assert!((a - b).length() < 1e-5, "{a} vs {b}");
    assert!(
        (lens.ray(x, y, Vec2::new(0.1, 0.2)).origin - lens.ray(x, y, Vec2::new(0.9, 0.7)).origin)
            .length()
            > 0.05
    );
}

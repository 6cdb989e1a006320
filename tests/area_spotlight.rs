//! The area spotlight (`docs/povray.md`, Lights: an `area_light` that is also a `spotlight`):
//! each bit of its area a point spotlight, so its irradiance is a closed-form integral over the
//! emitter and becomes the point spotlight's as the area shrinks; its light samples, BSDF-sampled
//! hits and MIS agree; its photons carry its power inside the cone; nothing outside the cone is
//! lit.

use crate::common;

use std::f64::consts::PI;
use std::path::Path;

use glam::{DVec3, Vec2, Vec3};
use raydiance::geometry::Hit;
use raydiance::graph::IntegratorKind;
use raydiance::lang::parse_scene;
use raydiance::light::Light;
use raydiance::progress::Silent;
use raydiance::render::render;
use raydiance::scene::{Scene, build};

/// The light at <0, 3, 0> aimed at <0.5, 0, 0>; the camera looks at the origin, d = 3.
const LIGHT: DVec3 = DVec3::new(0.0, 3.0, 0.0);
const POINT_AT: DVec3 = DVec3::new(0.5, 0.0, 0.0);
const CONE: (f64, f64, f64) = (15.0, 30.0, 2.0);

/// A `.pov` scene: a floor and the spotlight, given `area` (`area_light ...`, or nothing for the
/// point spotlight).
fn scene(area: &str, extra: &str) -> Scene {
    let (radius, falloff, tightness) = CONE;
    let text = format!(
        "camera {{ location <0, 6, -6> look_at <0, 0, 0> }}\n\
         light_source {{ <0, 3, 0> color rgb 1 spotlight point_at <0.5, 0, 0> \
         radius {radius} falloff {falloff} tightness {tightness} {area} }}\n\
         plane {{ y, 0 pigment {{ rgb 0.5 }} finish {{ diffuse 1 }} }}\n{extra}"
    );
    let graph = parse_scene(Path::new("tests/inline.pov"), &text).unwrap_or_else(|e| panic!("{e}"));
    build(&graph).unwrap_or_else(|e| panic!("{e}"))
}

/// POV-Ray's spotlight profile written out again from its definition: cos^t θ times the cubic
/// spline from 0 at cos(falloff) to 1 at cos(radius), nothing behind the light.
fn profile(mu: f64) -> f64 {
    let (radius, falloff, tightness) = CONE;
    if mu <= 0.0 {
        return 0.0;
    }
    let (low, high) = (falloff.to_radians().cos(), radius.to_radians().cos());
    let t = ((mu - low) / (high - low)).clamp(0.0, 1.0);
    mu.powf(tightness) * t * t * (3.0 - 2.0 * t)
}

/// A hit on the floor at `point`, facing up, on no primitive of the scene's.
fn floor_hit(point: Vec3) -> Hit {
    Hit { t: 1.0, point, normal: Vec3::Y, shading_normal: Vec3::Y, error: 0.0, primitive: u32::MAX }
}

/// The irradiance at `point` on the floor by the light's own samples (stratified, n × n).
fn sampled_irradiance(light: &Light, point: Vec3, n: u32) -> f64 {
    let hit = floor_hit(point);
    let mut sum = 0.0;
    for k in 0..n * n {
        let u = Vec2::new(((k % n) as f32 + 0.5) / n as f32, ((k / n) as f32 + 0.5) / n as f32);
        if let Some(s) = light.sample(&hit, u) {
            sum += f64::from(s.li.x * s.wi.y.max(0.0) / s.pdf);
        }
    }
    sum / f64::from(n * n)
}

/// The one light of `scene` (the emitter's, for an area light).
fn only_light(scene: &Scene) -> &Light {
    assert_eq!(scene.lights.len(), 1, "{:?}", scene.lights);
    &scene.lights[0]
}

/// Intensity π · C · d² on the axis, d = 3 (`docs/povray.md`).
const INTENSITY: f64 = PI * 9.0;

/// The irradiance the area spotlight's definition gives at `y`: a horizontal square of side `side`
/// centred on the light, each dA a point spotlight of intensity I dA / A, by the midpoint rule.
fn closed_form(y: DVec3, side: f64) -> f64 {
    let axis = (POINT_AT - LIGHT).normalize();
    let steps = 200;
    let mut sum = 0.0;
    for k in 0..steps * steps {
        let a = ((k % steps) as f64 + 0.5) / steps as f64 - 0.5;
        let b = ((k / steps) as f64 + 0.5) / steps as f64 - 0.5;
        let x = LIGHT + DVec3::new(a * side, 0.0, b * side);
        let to = y - x;
        let r2 = to.length_squared();
        let w = to / r2.sqrt();
        sum += INTENSITY * profile(w.dot(axis)) * (-w.y).max(0.0) / r2;
    }
    sum / f64::from(steps * steps)
}

/// Floor points across the lit spot and its falloff ring, and one outside.
fn floor_points() -> impl Iterator<Item = Vec3> {
    (-8..=12).flat_map(|i| (-6..=6).map(move |j| Vec3::new(0.2 * i as f32, 0.0, 0.2 * j as f32)))
}

#[test]
fn an_area_spotlight_lights_the_floor_as_its_closed_form_and_shrinks_to_the_point_spotlight() {
    let point = scene("", "");
    let peak = closed_form(POINT_AT, 1e-6);
    let mut worst_point = 0.0f64;
    for p in floor_points() {
        let got = sampled_irradiance(only_light(&point), p, 1);
        worst_point = worst_point.max((got - closed_form(DVec3::from(p), 1e-6)).abs() / peak);
    }
    assert!(worst_point < 1e-3, "the point spotlight and the closed form: {worst_point} of peak");
    for side in [0.001, 0.8] {
        let area = scene(&format!("area_light <{side}, 0, 0>, <0, 0, {side}>, 5, 5"), "");
        let (mut worst, mut lit) = (0.0f64, 0);
        for p in floor_points() {
            let got = sampled_irradiance(only_light(&area), p, 24);
            let expected = closed_form(DVec3::from(p), side);
            worst = worst.max((got - expected).abs() / peak);
            lit += usize::from(expected > 0.05 * peak && expected < 0.95 * peak);
            if side < 0.01 {
                let point_light = sampled_irradiance(only_light(&point), p, 1);
                let off = (got - point_light).abs() / peak;
                assert!(
                    off < 2e-3,
                    "side {side} at {p}: {got} vs the point spotlight's {point_light}"
                );
            }
        }
        assert!(lit > 20, "the falloff ring is among the points ({lit})");
        assert!(worst < 0.01, "side {side}: {worst} of the peak from the closed form");
    }
}

#[test]
fn nothing_outside_the_cone_is_lit() {
    // Straight down from a 1 × 1 quad at height 3, falloff 30°: no point of the quad (within
    // √2/2 of its centre) sees a floor point farther than √2/2 + 3 tan 30° ≈ 2.44 from below it
    // inside the cone.
    let text = "camera { location <0, 8, -8> look_at <0, 0, 0> angle 50 }\n\
         light_source { <0, 3, 0> color rgb 1 spotlight point_at <0, 0, 0> radius 15 falloff 30 \
         area_light <1, 0, 0>, <0, 0, 1>, 5, 5 }\n\
         plane { y, 0 pigment { rgb 1 } finish { diffuse 1 } }";
    let mut graph =
        parse_scene(Path::new("tests/inline.pov"), text).unwrap_or_else(|e| panic!("{e}"));
    graph.settings.integrator = IntegratorKind::Direct;
    (graph.settings.width, graph.settings.height, graph.settings.samples) = (32, 32, 4);
    let scene = build(&graph).unwrap_or_else(|e| panic!("{e}"));
    let reach = 0.5f32.sqrt() + 3.0 * 30f32.to_radians().tan();
    let light = only_light(&scene);
    for i in -20..=20 {
        for j in -20..=20 {
            let p = Vec3::new(0.2 * i as f32, 0.0, 0.2 * j as f32);
            let e = sampled_irradiance(light, p, 8);
            if p.length() > reach {
                assert_eq!(e, 0.0, "lit outside the cone at {p}");
            }
        }
    }
    let image = render(&scene, &Silent).0.image();
    let (mut dark, mut lit) = (0, 0);
    for j in 0..32 {
        for i in 0..32 {
            // Where the pixel's corners meet the floor: outside the cone's reach, black.
            // (and whether it passes by the emitter, which is black seen from above).
            let corners = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)].map(|(a, b)| {
                let ray =
                    scene.camera.ray((i as f32 + a) / 32.0, (j as f32 + b) / 32.0, Vec2::ZERO);
                let (o, d) = (Vec3::from(ray.origin), Vec3::from(ray.dir));
                let by_light = o + d * ((3.0 - o.y) / d.y);
                ((o + d * (-o.y / d.y)).length(), by_light.x.abs().max(by_light.z.abs()) > 0.6)
            });
            let value = image.pixels[(j * 32 + i) as usize];
            if corners.iter().all(|&(r, _)| r > reach) {
                assert_eq!(value, Vec3::ZERO, "pixel ({i}, {j}) is lit outside the cone");
                dark += 1;
            } else if corners.iter().all(|&(r, clear)| r < 1.5 && clear) {
                assert!(value.x > 0.0, "pixel ({i}, {j}) inside the cone is dark");
                lit += 1;
            }
        }
    }
    assert!(dark > 100 && lit > 20, "{dark} pixels outside the cone, {lit} inside");
}

/// Photons leave the emitter inside the cone and carry the light's power: their mean power
/// times their number is `power_rgb`, which is the point spotlight's.
#[test]
fn an_area_spotlight_s_photons_carry_its_power_inside_the_cone() {
    let area = scene("area_light <0.8, 0, 0>, <0, 0, 0.8>, 5, 5", "");
    let point = scene("", "");
    let light = only_light(&area);
    let power = f64::from(light.power_rgb().x);
    let point_power = f64::from(only_light(&point).power_rgb().x);
    assert!((power / point_power - 1.0).abs() < 1e-4, "{power} vs {point_power}");
    let axis = (POINT_AT - LIGHT).normalize().as_vec3();
    let n = 128u32;
    let photons = n * n;
    let mut sum = 0.0f64;
    for k in 0..photons {
        let u_direction =
            Vec2::new(((k % n) as f32 + 0.5) / n as f32, ((k / n) as f32 + 0.5) / n as f32);
        // The point: a second, unrelated stratification (golden-ratio steps).
        let u_point = Vec2::new((k as f32 * 0.618_034).fract(), (k as f32 * 0.754_877).fract());
        let s = light.sample_emission(photons, u_point, u_direction).expect("a photon");
        let origin = Vec3::from(s.ray.origin);
        let dir = Vec3::from(s.ray.dir);
        assert!((origin.y - 3.0).abs() < 1e-3 && origin.x.abs() <= 0.4001, "{origin}");
        assert!(dir.dot(axis) >= 30f32.to_radians().cos() - 1e-3, "a photon left the cone: {dir}");
        sum += f64::from(s.power.x);
    }
    assert!((sum / power - 1.0).abs() < 2e-3, "photons carry {sum}, the light {power}");
}

/// Light samples alone and BSDF-sampled hits alone estimate the same image (a ball on the floor
/// under a wide area spotlight), and MIS agrees with both.
#[test]
fn area_spotlight_sampling_agrees_with_bsdf_sampling() {
    let mut s = scene(
        "area_light <2, 0, 0>, <0, 0, 2>, 5, 5",
        "sphere { <0.5, 0.6, 0>, 0.6 pigment { rgb <0.8, 0.5, 0.3> } finish { diffuse 1 } }",
    );
    (s.settings.width, s.settings.height, s.settings.samples, s.settings.max_depth) =
        (32, 24, 128, 2);
    common::assert_light_and_bsdf_sampling_agree_with_mis(&s, "area spotlight");
}

/// An area spotlight is read as an emitter carrying the spotlight's beam, of intensity π C d² / A
/// per unit area on its axis; `circular orient` is a disk facing along the beam; a shadowless one
/// stays a point spotlight, with a warning.
#[test]
fn area_spotlights_are_read_as_beamed_emitters() {
    let text = "camera { location <0, 2, -4> look_at 0 }\n\
         light_source { <0, 4, 0> rgb 2 spotlight point_at <0, 0, 3> area_light x, 2*z, 3, 3 }\n\
         light_source { <0, 4, 0> rgb 1 spotlight point_at <0, 0, 3> \
         area_light 2*x, 2*z, 3, 3 circular orient }\n\
         light_source { <0, 4, 0> rgb 1 spotlight area_light x, z, 3, 3 shadowless }";
    let g = parse_scene(Path::new("tests/inline.pov"), text).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(g.objects.len(), 2);
    let axis = Vec3::new(0.0, -4.0, 3.0) / 5.0;
    let quad = g.objects[0].material.as_ref().expect("the emitter's material");
    let beam = quad.beam.expect("a beam");
    assert!((beam.axis - axis).length() < 1e-6, "{:?}", beam.axis);
    assert_eq!((beam.cone.radius, beam.cone.falloff, beam.cone.tightness), (30.0, 45.0, 0.0));
    let expected = (std::f32::consts::PI * 16.0 * 2.0) / 2.0;
    assert!((quad.emission.x / expected - 1.0).abs() < 1e-5, "{}", quad.emission.x);
    match &g.objects[1].shape {
        raydiance::graph::ShapeNode::Disk { normal, .. } => {
            assert!((*normal - axis).length() < 1e-6, "{normal}")
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(g.lights.len(), 1);
    assert!(g.warnings.iter().any(|w| w.contains(":4:") && w.contains("read as a spotlight")));
}

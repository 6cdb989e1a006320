//! Solids, built from scene graphs made in Rust (the language does not have them yet): cone
//! and torus hits against a brute-force march along the ray with the point-inside test.

mod common;

use std::path::Path;
use std::sync::Arc;

use glam::{Vec2, Vec3};
use raydiance::geometry::{Ray, Shape};
use raydiance::scene::build;
use raydiance::scene::graph::{
    MaterialDesc, ObjectNode, SceneGraph, ShapeNode, TextureNode, Transform,
};

/// A small deterministic generator (SplitMix64).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f32 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
    }

    fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.next()
    }

    fn vec(&mut self, lo: f32, hi: f32) -> Vec3 {
        Vec3::new(self.range(lo, hi), self.range(lo, hi), self.range(lo, hi))
    }

    fn direction(&mut self) -> Vec3 {
        loop {
            let v = self.vec(-1.0, 1.0);
            if v.length_squared() > 0.01 && v.length_squared() <= 1.0 {
                return v.normalize();
            }
        }
    }
}

/// An empty scene graph (camera looking at the origin), for objects to be added to.
fn empty_graph() -> SceneGraph {
    let text = "camera { location <0, 0, -5>  look_at <0, 0, 0>  angle 40  up <0, 1, 0> }";
    raydiance::lang::parse_scene(Path::new("tests/solids.scn"), text).expect("camera parses")
}

fn node(graph: &SceneGraph, shape: ShapeNode, transforms: Vec<Transform>) -> ObjectNode {
    ObjectNode { shape, material: None, transforms, depth: 1, span: graph.camera.span.clone() }
}

fn material(graph: &SceneGraph, diffuse: Vec3, emission: Vec3) -> Arc<MaterialDesc> {
    let mut m = MaterialDesc::new(graph.camera.span.clone());
    m.diffuse = TextureNode::solid(diffuse);
    m.emission = emission;
    Arc::new(m)
}

/// The one bounded shape a graph of one object builds to.
fn built_shape(graph: &SceneGraph, object: ObjectNode) -> Shape {
    let mut graph = graph.clone();
    graph.objects = vec![object];
    let scene = build(&graph).unwrap_or_else(|e| panic!("{e}"));
    scene.primitives[0].shape.clone()
}

fn random_transforms(rng: &mut Rng, far: bool) -> Vec<Transform> {
    let mut transforms = vec![
        Transform::Scale(Vec3::new(rng.range(0.5, 1.5), rng.range(0.5, 1.5), rng.range(0.5, 1.5))),
        Transform::Rotate(rng.vec(-180.0, 180.0)),
        Transform::Translate(rng.vec(-0.5, 0.5)),
    ];
    if far {
        transforms.push(Transform::Translate(Vec3::new(1000.0, -700.0, 600.0)));
    }
    transforms
}

/// The first point along `ray` in (0, t_end) where `inside` changes from its value at the
/// origin, by marching `steps` steps and bisecting; `None` if no sample differs.
fn march(
    inside: impl Fn(Vec3) -> bool,
    ray: &Ray,
    t_start: f32,
    t_end: f32,
    steps: usize,
) -> Option<f32> {
    let start = inside(ray.at(t_start));
    let h = (t_end - t_start) / steps as f32;
    let mut previous = t_start;
    for i in 1..=steps {
        let t = t_start + h * i as f32;
        if inside(ray.at(t)) != start {
            let (mut a, mut b) = (previous, t);
            for _ in 0..40 {
                let m = 0.5 * (a + b);
                if inside(ray.at(m)) != start { b = m } else { a = m }
            }
            return Some(0.5 * (a + b));
        }
        previous = t;
    }
    None
}

/// The segment of the ray's line inside the box (slab test), if any.
fn clip(ray: &Ray, min: Vec3, max: Vec3) -> Option<(f32, f32)> {
    let (o, d) = (Vec3::from(ray.origin), Vec3::from(ray.dir));
    let (t0, t1) = ((min - o) / d, (max - o) / d);
    let (near, far) = (t0.min(t1).max_element(), t0.max(t1).min_element());
    (near <= far && far > 0.0).then_some((near.max(0.0), far))
}

#[derive(Default, Debug)]
struct Tally {
    rays: usize,
    hits: usize,
    slivers: usize,
}

/// The shape's first hit against the march: they agree within `tolerance`, or the analytic
/// hit is on an interval thinner than a march step (a sliver the march steps over). A march
/// crossing that the analytic test misses or finds late is a hole: that fails.
fn check_ray(shape: &Shape, ray: &Ray, steps: usize, tolerance: f32, tally: &mut Tally) {
    tally.rays += 1;
    let bounds = shape.bounds().expect("bounded");
    let pad = 1e-3 * bounds.extent().max_element();
    let Some((t0, t1)) = clip(ray, bounds.min - pad, bounds.max + pad) else {
        assert!(shape.intersection(ray, f32::INFINITY).is_none(), "hit outside the bounds");
        return;
    };
    let h = (t1 - t0) / steps as f32;
    let analytic = shape.intersection(ray, f32::INFINITY).map(|i| i.t);
    let marched = march(|p| shape.contains(p), ray, t0, t1, steps);
    let crossings = shape.crossings(ray, f32::INFINITY);
    // The analytic first interval is thinner than a step, or its middle is within a hair of
    // the inside (a ray along a cone's side line dips in by a rounding over a long stretch).
    let hair = 1e-4 * bounds.extent().max_element();
    let sliver = || {
        let l = &crossings.list;
        // (No crossing at all where the hit is a touch: a tangent, or the apex of a cone.)
        let thin = l.is_empty() || l.len() >= 2 && l[1].at.t - l[0].at.t <= 2.0 * h;
        let near = l.len() >= 2 && {
            let middle = ray.at(0.5 * (l[0].at.t + l[1].at.t));
            let axes = [Vec3::X, Vec3::Y, Vec3::Z, -Vec3::X, -Vec3::Y, -Vec3::Z];
            axes.iter().any(|&a| shape.contains(middle + a * hair))
        };
        !crossings.inside_at_start && (thin || near)
    };
    // The march's first interval is thinner than a step (its sample of the inside may be a
    // rounding of the inside test at a tangent, or a sliver the analytic test calls a touch).
    let marched_sliver = |m: f32| (1..=16).any(|k| !shape.contains(ray.at(m + k as f32 * h / 8.0)));
    // At a grazing hit a rounding of either test moves the crossing along the ray by as much
    // as it moves it across the surface, divided by the cosine.
    let cosine = shape
        .intersection(ray, f32::INFINITY)
        .map_or(1.0, |at| shape.hit(ray, &at).normal.dot(Vec3::from(ray.dir)).abs().max(1e-2));
    let tolerance = tolerance / cosine;
    match (analytic, marched) {
        (None, None) => {}
        (Some(a), Some(m)) if (a - m).abs() <= tolerance => tally.hits += 1,
        (Some(a), Some(m)) if a < m && sliver() => tally.slivers += 1,
        (Some(_), None) if sliver() => tally.slivers += 1,
        (Some(a), Some(m)) if a > m && marched_sliver(m) => tally.slivers += 1,
        (None, Some(m)) if marched_sliver(m) => tally.slivers += 1,
        _ => panic!(
            "{shape:?}\nray {ray:?}: analytic {analytic:?}, march {marched:?} (step {h}), \
             crossings {crossings:?}"
        ),
    }
}

/// Rays through the shape's bounds from outside, and rays grazing its surface (a sampled
/// point, a direction along the tangent plane tilted by a hair).
fn check_shape(shape: &Shape, rng: &mut Rng, rays: usize, tally: &mut Tally) {
    let bounds = shape.bounds().expect("bounded");
    let (center, size) = (bounds.centroid(), bounds.extent().max_element());
    let tolerance = 2e-4 * size + 1e-5 * center.abs().max_element();
    for i in 0..rays {
        let ray = if i % 2 == 0 || shape.area().is_none() {
            let origin = center + rng.direction() * 2.0 * size;
            let target = bounds.min + rng.vec(0.0, 1.0) * bounds.extent();
            Ray::new(origin, (target - origin).normalize())
        } else {
            let s = shape.sample_area(Vec2::new(rng.next(), rng.next())).expect("sampled");
            let tangent = s.normal.cross(rng.direction()).normalize();
            let dir = (tangent + s.normal * rng.range(-1e-3, 1e-3)).normalize();
            Ray::new(s.point - dir * 2.0 * size, dir)
        };
        check_ray(shape, &ray, 200, tolerance, tally);
    }
}

#[test]
fn cone_and_torus_hits_match_a_march_on_100000_rays() {
    let graph = empty_graph();
    let mut rng = Rng(17);
    let mut tally = Tally::default();
    for k in 0..20 {
        let far = k % 5 == 4;
        let transforms = random_transforms(&mut rng, far);
        let torus = ShapeNode::Torus { major: rng.range(0.5, 1.0), minor: rng.range(0.05, 0.45) };
        // Similarity transforms for half of them, so that grazing rays from area samples run.
        let transforms = if k % 2 == 0 {
            vec![Transform::Rotate(rng.vec(-180.0, 180.0)), Transform::Scale(Vec3::splat(0.8))]
                .into_iter()
                .chain(far.then_some(Transform::Translate(Vec3::new(1000.0, -700.0, 600.0))))
                .collect()
        } else {
            transforms
        };
        let shape = built_shape(&graph, node(&graph, torus, transforms.clone()));
        check_shape(&shape, &mut rng, 3000, &mut tally);
        let radii = [rng.range(0.0, 0.6), rng.range(0.1, 0.6)];
        let radii = if k % 3 == 0 { [0.0, radii[1]] } else { radii };
        let cone = ShapeNode::Cone {
            base: rng.vec(-0.5, 0.5),
            base_radius: radii[k % 2],
            cap: rng.vec(-0.5, 0.5) + Vec3::Y,
            cap_radius: radii[(k + 1) % 2],
            open: false,
        };
        // (Cones, like cylinders and ellipsoids, are intersected in f32 in their own space, so
        // far from the origin they lose precision to the translation: tested near it.)
        let near: Vec<_> = transforms
            .into_iter()
            .filter(|t| !far || !matches!(t, Transform::Translate(v) if v.x == 1000.0))
            .collect();
        let shape = built_shape(&graph, node(&graph, cone, near));
        check_shape(&shape, &mut rng, 2000, &mut tally);
    }
    assert!(tally.rays >= 100_000, "{tally:?}");
    // Half the rays graze on purpose: many meet a sliver thinner than the march's step.
    assert!(tally.hits > tally.rays / 4 && tally.slivers < tally.rays / 6, "{tally:?}");
}

#[test]
fn torus_and_cone_area_samples_lie_on_them_and_lit_tori_render() {
    let mut graph = empty_graph();
    let torus = node(
        &graph,
        ShapeNode::Torus { major: 1.0, minor: 0.25 },
        vec![Transform::Rotate(Vec3::new(60.0, 0.0, 0.0))],
    );
    let cone = ShapeNode::Cone {
        base: Vec3::ZERO,
        base_radius: 0.5,
        cap: Vec3::Y,
        cap_radius: 0.0,
        open: false,
    };
    let cone = node(&graph, cone, vec![Transform::Scale(Vec3::splat(2.0))]);
    for object in [torus.clone(), cone] {
        let shape = built_shape(&graph, object);
        let area = shape.area().expect("a similarity: area known");
        let mut rng = Rng(9);
        for _ in 0..2000 {
            let s = shape.sample_area(Vec2::new(rng.next(), rng.next())).unwrap();
            let ray = Ray::new(s.point + s.normal * 1e-3, -s.normal);
            let hit = shape.intersect(&ray, 1.0).expect("a sample is on the surface");
            assert!((hit.point - s.point).length() < 1e-3 && hit.normal.dot(s.normal) > 0.99);
        }
        assert!(area > 0.0);
    }
    // A torus light over nothing but itself: it lights its own inner side; renders finite.
    let mut lit = torus;
    lit.material = Some(material(&graph, Vec3::splat(0.5), Vec3::ONE));
    graph.objects = vec![lit];
    graph.settings.width = 16;
    graph.settings.height = 16;
    graph.settings.samples = 4;
    let scene = build(&graph).unwrap();
    assert_eq!(scene.lights.len(), 1);
    let image = common::render_image(&scene);
    assert!(image.pixels.iter().all(|p| p.is_finite()) && common::mean(&image).x > 0.1);
}

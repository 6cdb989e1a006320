//! Solids and CSG, built from scene graphs made in Rust (the language does not have them yet):
//! cone, torus, algebraic surface, blob, prism, superellipsoid, julia fractal, lathe, sor, ovus, lemon and CSG hits,
//! and POV-Ray's parametric surface against the analytic torus it traces, against a brute-force march along the ray with the point-inside
//! test, inside tests against the operands', an emission-only render against the analytic
//! silhouette, and build errors.

use crate::common;

use std::path::Path;
use std::sync::Arc;

use glam::{Vec2, Vec3};
use raydiance::geometry::{
    Algebra, BlobComponent, ComponentShape, JuliaDesc, JuliaFunction, Ray, Shape, SplineKind,
    Sweep, Term, lemon_min_inner_radius, open_spline_segments, sor_pieces, spline_segments,
};
use raydiance::graph::{
    CsgOp, IntegratorKind, MaterialDesc, ObjectNode, SceneGraph, ShapeNode, TextureNode, Transform,
    compose,
};
use raydiance::scene::{Scene, build};

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
    // A mirror one time in four.
    let mirror = if rng.next() < 0.25 { -1.0 } else { 1.0 };
    let mut transforms = vec![
        Transform::Scale(Vec3::new(
            mirror * rng.range(0.5, 1.5),
            rng.range(0.5, 1.5),
            rng.range(0.5, 1.5),
        )),
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

#[derive(Default, Debug)]
struct Tally {
    rays: usize,
    hits: usize,
    slivers: usize,
    /// Rays aimed from outside the bounds at a point in them, and those whose point is inside.
    aimed: usize,
    aimed_inside: usize,
}

/// The shape's first hit against the march: they agree within `tolerance`, or the analytic
/// hit is on an interval thinner than a march step (a sliver the march steps over). A march
/// crossing that the analytic test misses or finds late is a hole: that fails.
fn check_ray(shape: &Shape, ray: &Ray, steps: usize, tolerance: f32, tally: &mut Tally) {
    tally.rays += 1;
    let bounds = shape.bounds().expect("bounded");
    let pad = 1e-3 * bounds.extent().max_element();
    let Some((t0, t1)) = common::clip(ray, bounds.min - pad, bounds.max + pad) else {
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
            [Vec3::X, Vec3::Y, Vec3::Z, -Vec3::X, -Vec3::Y, -Vec3::Z]
                .iter()
                .any(|&a| shape.contains(middle + a * hair))
        };
        !crossings.inside_at_start && (thin || near)
    };
    // The march's first interval is thinner than a step (its sample of the inside may be a
    // rounding of the inside test at a tangent, or a sliver the analytic test calls a touch).
    // Or it runs within a hair of the surface (a ray along a flat cap, in its plane).
    let axes = [Vec3::X, Vec3::Y, Vec3::Z, -Vec3::X, -Vec3::Y, -Vec3::Z];
    let shell = |p: Vec3| axes.iter().any(|&a| !shape.contains(p + a * hair));
    let marched_sliver = |m: f32| {
        (1..=16).any(|k| !shape.contains(ray.at(m + k as f32 * h / 8.0)))
            || (1..=4).all(|k| shell(ray.at(m + k as f32 * h / 2.0)))
    };
    // At a grazing hit a rounding of either test moves the crossing along the ray by as much
    // as it moves it across the surface, divided by the cosine.
    // (The smaller cosine of the hit's and of the first crossing's: a ray that grazes a flat
    // cap lies in its plane, and which of cap and side comes first is a rounding.)
    let cosine_at = |at| shape.hit(ray, &at).normal.dot(Vec3::from(ray.dir)).abs();
    let hit = shape.intersection(ray, f32::INFINITY).map(cosine_at);
    let first = crossings.list.first().map(|c| cosine_at(c.at));
    let cosine = hit.unwrap_or(1.0).min(first.unwrap_or(1.0)).max(1e-3);
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

/// A ray from outside the bounds aimed at `target`, a point in them: where the target is inside
/// the solid (`target_inside`, by an inside test), the ray meets the solid no later than there.
fn check_aimed(
    shape: &Shape,
    ray: &Ray,
    target: Vec3,
    target_inside: bool,
    tolerance: f32,
    tally: &mut Tally,
) {
    tally.aimed += 1;
    if target_inside {
        tally.aimed_inside += 1;
        let distance = (target - Vec3::from(ray.origin)).length();
        let hit = shape.intersection(ray, f32::INFINITY).map(|i| i.t);
        assert!(
            hit.is_some_and(|t| t <= distance + tolerance),
            "{ray:?} aimed at {target}, inside: hit at {hit:?}, target at {distance}"
        );
    }
}

/// The floor of a march test. The targets of the aimed rays are uniform in the bounds, so the
/// count of those inside the solid is binomial, of mean `aimed` times the solids' mean share of
/// their bounds, at least `share` (each test derives its own from its solids' volumes). A
/// quarter of `aimed * share` is at least 3 standard deviations (at most the square root of
/// the mean) below the mean once `aimed * share >= 16`. Each of those rays met the solid first
/// (`check_aimed`), so it is a hit or a sliver: a shape that returned no hits fails there.
fn assert_aimed_floor(tally: &Tally, share: f32) {
    let expected = tally.aimed as f32 * share;
    assert!(expected >= 16.0, "too few aimed rays for the margin: {tally:?}");
    assert!(tally.aimed_inside as f32 > 0.25 * expected, "{tally:?}");
    assert!(tally.hits + tally.slivers >= tally.aimed_inside, "{tally:?}");
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
        let shape = built_shape(&graph, node(&graph, cone, transforms));
        check_shape(&shape, &mut rng, 2000, &mut tally);
    }
    assert!(tally.rays >= 100_000, "{tally:?}");
    // Half the rays graze on purpose: many meet a sliver thinner than the march's step.
    assert!(tally.hits > tally.rays / 4 && tally.slivers < tally.rays / 6, "{tally:?}");
}

/// The surface P = 0 of the polynomial with these (coefficient, powers of x, y, z) terms.
fn algebraic(terms: &[(f64, [u32; 3])]) -> ShapeNode {
    let terms = terms.iter().map(|&(coefficient, powers)| Term { coefficient, powers }).collect();
    ShapeNode::Algebraic { terms }
}

/// Closed algebraic surfaces within the unit ball, and a cubic that is not (the ball cuts it).
fn algebraic_surfaces() -> [(ShapeNode, bool); 4] {
    // The torus (|p|^2 + R^2 - r^2)^2 - 4 R^2 (x^2 + z^2), R = 0.6, r = 0.25.
    let (r2, k) = (0.36, 0.36 - 0.0625);
    let torus = algebraic(&[
        (1.0, [4, 0, 0]),
        (1.0, [0, 4, 0]),
        (1.0, [0, 0, 4]),
        (2.0, [2, 2, 0]),
        (2.0, [2, 0, 2]),
        (2.0, [0, 2, 2]),
        (2.0 * k - 4.0 * r2, [2, 0, 0]),
        (2.0 * k, [0, 2, 0]),
        (2.0 * k - 4.0 * r2, [0, 0, 2]),
        (k * k, [0, 0, 0]),
    ]);
    let ellipsoid = algebraic(&[
        (1.5, [2, 0, 0]),
        (2.0, [0, 2, 0]),
        (3.0, [0, 0, 2]),
        (0.8, [1, 1, 0]),
        (0.2, [1, 0, 0]),
        (-0.5, [0, 0, 0]),
    ]);
    let rounded_cube =
        algebraic(&[(1.0, [4, 0, 0]), (1.0, [0, 4, 0]), (1.0, [0, 0, 4]), (-0.2, [0, 0, 0])]);
    let cubic = algebraic(&[
        (1.0, [2, 0, 0]),
        (1.0, [0, 2, 0]),
        (1.0, [0, 0, 2]),
        (0.9, [3, 0, 0]),
        (-0.6, [0, 1, 2]),
        (-0.3, [0, 0, 0]),
    ]);
    [(torus, true), (ellipsoid, true), (rounded_cube, true), (cubic, false)]
}

/// The ray turned to graze the shape where it meets it (along the tangent plane, tilted by a
/// hair), from as far back; `None` where it misses.
fn grazing(shape: &Shape, ray: &Ray, rng: &mut Rng, size: f32) -> Option<Ray> {
    let hit = shape.intersect(ray, f32::INFINITY)?;
    let tangent = hit.normal.cross(rng.direction()).normalize();
    let dir = (tangent + hit.normal * rng.range(-1e-3, 1e-3)).normalize();
    Some(Ray::new(hit.point - dir * 2.0 * size, dir))
}

/// Asserts that the shape's inside test agrees with its crossings up to `t_end`: at the start,
/// and between each two that are further apart than `tolerance`; the latter counted.
fn check_inside_between_crossings(shape: &Shape, ray: &Ray, t_end: f32, tolerance: f32) -> usize {
    let crossings = shape.crossings(ray, t_end);
    let mut inside = crossings.inside_at_start;
    assert_eq!(inside, shape.contains(ray.at(0.0)), "{ray:?}");
    let mut ends: Vec<f32> = crossings.list.iter().map(|c| c.at.t).collect();
    ends.push(t_end);
    let mut checked = 0;
    for (c, pair) in crossings.list.iter().zip(ends.windows(2)) {
        inside = !inside;
        assert_eq!(c.entering, inside);
        // Between crossings close together (a ray grazing the surface) the solid is thinner
        // than the inside test's rounding.
        if pair[1] - pair[0] > 50.0 * tolerance {
            let t = 0.5 * (pair[0] + pair[1]);
            let middle = ray.at(t);
            // `ray.at` rounds each coordinate twice in f32 (a product and a sum): off the ray
            // by up to f32::EPSILON (|origin| + t) along each axis, sqrt(3) times that in all,
            // while the crossings are the exact ray's. A probe along an axis that far again
            // times sqrt(3) reaches any surface within that rounding: where one does, the
            // middle is a touch (a grazing ray inside the concave side of a pinched shape
            // comes within 1e-7 of it over a long stretch) and only the side within reach
            // is asserted.
            let reach = 3.0 * f32::EPSILON * (Vec3::from(ray.origin).abs().max_element() + t);
            let touch = [Vec3::X, Vec3::Y, Vec3::Z, -Vec3::X, -Vec3::Y, -Vec3::Z]
                .iter()
                .any(|&a| shape.contains(middle + a * reach) == inside);
            assert!(shape.contains(middle) == inside || touch, "{ray:?} {crossings:?}");
            checked += 1;
        }
    }
    checked
}

#[test]
fn algebraic_surfaces_match_a_march_and_their_crossings_agree_with_inside() {
    let graph = empty_graph();
    let mut rng = Rng(23);
    let mut tally = Tally::default();
    let (mut grazed, mut toggles) = (0, 0);
    for k in 0..12 {
        let (surface, closed) = algebraic_surfaces()[k % 4].clone();
        let transforms = random_transforms(&mut rng, k % 6 == 5);
        let alone = built_shape(&graph, node(&graph, surface.clone(), transforms.clone()));
        assert!(alone.bounds().is_none(), "unbounded as POV-Ray's polynomials are");
        // Bounded by the unit ball, as a scene bounds them, for the march.
        let ball = ShapeNode::Sphere { center: Vec3::ZERO, radius: 1.0 };
        let operands = vec![node(&graph, surface, vec![]), node(&graph, ball, vec![])];
        let csg = ShapeNode::Csg { op: CsgOp::Intersection, operands };
        let shape = built_shape(&graph, node(&graph, csg, transforms));
        let bounds = shape.bounds().expect("bounded by the ball");
        let (center, size) = (bounds.centroid(), bounds.extent().max_element());
        let tolerance = 2e-4 * size + 1e-5 * center.abs().max_element();
        for i in 0..600 {
            let origin = center + rng.direction() * 2.0 * size;
            let target = bounds.min + rng.vec(0.0, 1.0) * bounds.extent();
            let aimed_in = shape.contains(target);
            let mut ray = Ray::new(origin, (target - origin).normalize());
            // Every other ray grazes the surface where the one before met it.
            if i % 2 == 1
                && let Some(graze) = grazing(&shape, &ray, &mut rng, size)
            {
                ray = graze;
                grazed += 1;
            } else {
                check_aimed(&shape, &ray, target, aimed_in, tolerance, &mut tally);
            }
            check_ray(&shape, &ray, 200, tolerance, &mut tally);
            // Alone, a closed surface is met first where the bounded one is.
            if closed {
                let first = alone.intersection(&ray, f32::INFINITY).map(|i| i.t);
                let bounded = shape.intersection(&ray, f32::INFINITY).map(|i| i.t);
                assert_eq!(first.is_some(), bounded.is_some(), "{ray:?}");
                if let (Some(a), Some(b)) = (first, bounded) {
                    assert!((a - b).abs() <= tolerance, "{a} {b}");
                }
            }
            toggles += check_inside_between_crossings(&alone, &ray, 4.0 * size, tolerance);
        }
    }
    assert!(grazed > 500 && toggles > 2000, "{grazed} {toggles}");
    // The surfaces fill 6 to 24% of their ball's own cube (the torus 2 pi^2 R r^2 / 8 = 9%,
    // the rounded cube 24%, the ellipsoid 6.5%), and the world box of that cube turned at random
    // holds 2 to 5 times its volume: more than 1/100 of the bounds.
    assert_aimed_floor(&tally, 0.01);
    assert!(tally.slivers < tally.rays / 6, "{tally:?}");
}

/// A blob of two to four spheres and capsules, each under its own transforms, one of them
/// perhaps of negative strength.
fn random_blob(rng: &mut Rng) -> ShapeNode {
    let count = 2 + (rng.next() * 3.0) as usize;
    let components = (0..count)
        .map(|i| {
            let shape = if rng.next() < 0.5 {
                ComponentShape::Sphere { center: rng.vec(-0.4, 0.4) }
            } else {
                ComponentShape::Capsule { a: rng.vec(-0.5, 0.0), b: rng.vec(0.0, 0.5) }
            };
            let strength = if i == 2 { rng.range(-1.5, 1.5) } else { rng.range(0.8, 2.0) };
            let to_blob = compose(&[
                Transform::Scale(rng.vec(0.6, 1.3)),
                Transform::Rotate(rng.vec(-180.0, 180.0)),
            ]);
            let strength = if strength.abs() < 0.1 { 1.0 } else { strength };
            BlobComponent { shape, radius: rng.range(0.3, 0.7), strength, to_blob }
        })
        .collect();
    ShapeNode::Blob { threshold: rng.range(0.2, 0.7), components }
}

#[test]
fn blobs_match_a_march_and_their_crossings_agree_with_inside() {
    let graph = empty_graph();
    let mut rng = Rng(31);
    let mut tally = Tally::default();
    let (mut grazed, mut toggles) = (0, 0);
    for k in 0..16 {
        let transforms = random_transforms(&mut rng, k % 8 == 7);
        let shape = built_shape(&graph, node(&graph, random_blob(&mut rng), transforms));
        let bounds = shape.bounds().expect("bounded by its components");
        let (center, size) = (bounds.centroid(), bounds.extent().max_element());
        let tolerance = 2e-4 * size + 1e-5 * center.abs().max_element();
        for i in 0..500 {
            let origin = center + rng.direction() * 2.0 * size;
            let target = bounds.min + rng.vec(0.0, 1.0) * bounds.extent();
            let aimed_in = shape.contains(target);
            let mut ray = Ray::new(origin, (target - origin).normalize());
            if i % 2 == 1
                && let Some(graze) = grazing(&shape, &ray, &mut rng, size)
            {
                ray = graze;
                grazed += 1;
            } else {
                check_aimed(&shape, &ray, target, aimed_in, tolerance, &mut tally);
            }
            check_ray(&shape, &ray, 200, tolerance, &mut tally);
            toggles += check_inside_between_crossings(&shape, &ray, 4.0 * size, tolerance);
            // From inside too: a ray starting at a point of the solid.
            let p = bounds.min + rng.vec(0.0, 1.0) * bounds.extent();
            let from_inside = Ray::new(p, rng.direction());
            toggles += check_inside_between_crossings(&shape, &from_inside, 2.0 * size, tolerance);
        }
    }
    assert!(grazed > 500 && toggles > 4000, "{grazed} {toggles}");
    // A component of strength s meets the threshold t at r sqrt(1 - sqrt(t / s)), 2/3 of its
    // radius r for the middle values (t 0.45, s 1.4): 15% of its box. The boxes of the
    // components, turned, and of the blob, turned again, hold 3 to 5 times that each, and a
    // negative component carves: more than 1/100 of the bounds.
    assert_aimed_floor(&tally, 0.01);
    assert!(tally.slivers < tally.rays / 6, "{tally:?}");
}

#[test]
fn csg_with_blob_operands_matches_a_march_and_the_operands_inside_tests() {
    let graph = empty_graph();
    let mut rng = Rng(37);
    let mut tally = Tally::default();
    for k in 0..12 {
        let blob = node(&graph, random_blob(&mut rng), random_transforms(&mut rng, false));
        let other = random_tree(&graph, &mut rng, 0);
        let op = [CsgOp::Difference, CsgOp::Intersection, CsgOp::Merge][k % 3];
        let other = if op == CsgOp::Merge && matches!(other.shape, ShapeNode::Plane { .. }) {
            node(&graph, ShapeNode::Sphere { center: Vec3::ZERO, radius: 0.5 }, vec![])
        } else {
            other
        };
        let tree = ShapeNode::Csg { op, operands: vec![blob, other] };
        check_csg_against_the_march(&graph, tree, 300, &mut rng, &mut tally);
    }
    // The blobs fill more than 1/100 of their bounds (blobs_match_a_march_...); a merge only
    // adds, and the other operand, a solid of half its box or more, keeps or takes away half
    // of that or less on average: more than 1/200 of the bounds, which are the blob's.
    assert_aimed_floor(&tally, 0.005);
    assert!(tally.slivers < tally.rays / 50, "{tally:?}");
}

#[test]
fn csg_with_algebraic_operands_matches_a_march_and_the_operands_inside_tests() {
    let graph = empty_graph();
    let mut rng = Rng(29);
    let mut tally = Tally::default();
    for k in 0..16 {
        let (surface, _) = algebraic_surfaces()[k % 4].clone();
        let other = random_tree(&graph, &mut rng, 0);
        let surface = node(&graph, surface, random_transforms(&mut rng, false));
        let ball = node(&graph, ShapeNode::Sphere { center: Vec3::ZERO, radius: 1.2 }, vec![]);
        let op = [CsgOp::Difference, CsgOp::Intersection][k % 2];
        // A bounded first operand: the surface in the ball, and the other operand taken away
        // from it or kept where both are.
        let bounded = ShapeNode::Csg { op: CsgOp::Intersection, operands: vec![ball, surface] };
        let tree = ShapeNode::Csg { op, operands: vec![node(&graph, bounded, vec![]), other] };
        let tree = node(&graph, tree, random_transforms(&mut rng, false));
        let shape = built_shape(&graph, tree.clone());
        let bounds = shape.bounds().expect("bounded by the ball");
        let (center, size) = (bounds.centroid(), bounds.extent().max_element());
        for _ in 0..100 {
            let p = bounds.min + rng.vec(0.0, 1.0) * bounds.extent();
            assert_eq!(shape.contains(p), inside_by_operands(&graph, &tree, &[], p), "at {p}");
        }
        for _ in 0..300 {
            let origin = center + rng.direction() * 2.0 * size;
            let target = bounds.min + rng.vec(0.0, 1.0) * bounds.extent();
            let aimed_in = inside_by_operands(&graph, &tree, &[], target);
            let ray = Ray::new(origin, (target - origin).normalize());
            check_aimed(&shape, &ray, target, aimed_in, 1e-4 * size, &mut tally);
            check_ray(&shape, &ray, 400, 1e-4 * size, &mut tally);
        }
    }
    // The surfaces fill more than 1/100 of their ball's bounds (algebraic_surfaces_match_...);
    // the other operand, a solid of half its box or more, keeps or takes away half of that or
    // less on average: more than 1/200 of the bounds.
    assert_aimed_floor(&tally, 0.005);
    assert!(tally.slivers < tally.rays / 50, "{tally:?}");
}

/// The points of a star-shaped curve of `k` points about the origin, radii in [lo, hi].
fn star(rng: &mut Rng, k: usize, lo: f32, hi: f32) -> Vec<Vec2> {
    let turn = std::f32::consts::TAU / k as f32;
    (0..k).map(|i| Vec2::from_angle(turn * i as f32) * rng.range(lo, hi)).collect()
}

/// A prism of each spline kind in turn: a star with a star-shaped hole, swept either way.
fn random_prism(rng: &mut Rng, kind: SplineKind, sweep: Sweep) -> ShapeNode {
    let mut points = Vec::new();
    for (lo, hi) in [(0.6, 1.0), (0.15, 0.35)] {
        let k = 5 + (rng.next() * 4.0) as usize;
        let p = star(rng, k, lo, hi);
        let k = p.len();
        match kind {
            SplineKind::Linear => points.extend(p.iter().chain([&p[0]])),
            SplineKind::Quadratic => {
                points.extend([p[k - 1]].iter().chain(&p).chain([&p[0]]));
            }
            SplineKind::Cubic => {
                points.extend([p[k - 1]].iter().chain(&p).chain([&p[0], &p[1]]));
            }
            SplineKind::Bezier => {
                for i in 0..k {
                    let (a, b) = (p[i], p[(i + 1) % k]);
                    let bulge = Vec2::new(a.y - b.y, b.x - a.x) * rng.range(-0.3, 0.3);
                    points.extend([a, a + (b - a) / 3.0 + bulge, b - (b - a) / 3.0 + bulge, b]);
                }
            }
        }
    }
    let segments = spline_segments(kind, &points).expect("closed curves");
    let heights = match sweep {
        Sweep::Linear => [rng.range(-0.6, -0.1), rng.range(0.1, 0.6)],
        Sweep::Conic => [rng.range(0.2, 0.5), rng.range(0.7, 1.0)],
    };
    ShapeNode::Prism { segments, sweep, heights, open: false }
}

const SPLINES: [SplineKind; 4] =
    [SplineKind::Linear, SplineKind::Quadratic, SplineKind::Cubic, SplineKind::Bezier];

#[test]
fn prisms_match_a_march_and_their_crossings_agree_with_inside() {
    let graph = empty_graph();
    let mut rng = Rng(41);
    let mut tally = Tally::default();
    let (mut grazed, mut toggles) = (0, 0);
    for k in 0..16 {
        let sweep = if k % 2 == 0 { Sweep::Linear } else { Sweep::Conic };
        let prism = random_prism(&mut rng, SPLINES[(k / 2) % 4], sweep);
        let transforms = random_transforms(&mut rng, k % 8 == 7);
        let shape = built_shape(&graph, node(&graph, prism, transforms));
        let bounds = shape.bounds().expect("bounded");
        let (center, size) = (bounds.centroid(), bounds.extent().max_element());
        let tolerance = 2e-4 * size + 1e-5 * center.abs().max_element();
        for i in 0..400 {
            let origin = center + rng.direction() * 2.0 * size;
            let target = bounds.min + rng.vec(0.0, 1.0) * bounds.extent();
            let aimed_in = shape.contains(target);
            let mut ray = Ray::new(origin, (target - origin).normalize());
            if i % 2 == 1
                && let Some(graze) = grazing(&shape, &ray, &mut rng, size)
            {
                ray = graze;
                grazed += 1;
            } else {
                check_aimed(&shape, &ray, target, aimed_in, tolerance, &mut tally);
            }
            check_ray(&shape, &ray, 300, tolerance, &mut tally);
            toggles += check_inside_between_crossings(&shape, &ray, 4.0 * size, tolerance);
            // Normals point out of the solid.
            if let Some(hit) = shape.intersect(&ray, f32::INFINITY) {
                let (out, back) = (hit.point + hit.normal * 1e-3, hit.point - hit.normal * 1e-3);
                if shape.contains(out) != shape.contains(back) {
                    assert!(shape.contains(back), "{hit:?}");
                }
            }
        }
    }
    assert!(grazed > 1000 && toggles > 3000, "{grazed} {toggles}");
    // A star of 5 to 8 points at radii 0.6 to 1 covers 0.86 or more of its square of side 2
    // or less, a hole at most pi 0.35^2 = 0.38 of it: 12% of the box and more; a conic sweep
    // keeps a third of its box, and the world box of the box turned at random holds 2 to 5
    // times its volume: more than 1/50 of the bounds.
    assert_aimed_floor(&tally, 0.02);
    assert!(tally.slivers < tally.rays / 6, "{tally:?}");
}

/// `csg` turned and moved at random: its `contains` agrees with its operands' inside tests at
/// 100 points of its bounds, and `rays` rays aimed into its bounds from outside meet it as a
/// march along them does (`check_aimed`, `check_ray`).
fn check_csg_against_the_march(
    graph: &SceneGraph,
    csg: ShapeNode,
    rays: usize,
    rng: &mut Rng,
    tally: &mut Tally,
) {
    let tree = node(graph, csg, random_transforms(rng, false));
    let shape = built_shape(graph, tree.clone());
    let bounds = shape.bounds().expect("a bounded first operand");
    let (center, size) = (bounds.centroid(), bounds.extent().max_element());
    for _ in 0..100 {
        let p = bounds.min + rng.vec(0.0, 1.0) * bounds.extent();
        assert_eq!(shape.contains(p), inside_by_operands(graph, &tree, &[], p), "at {p}");
    }
    for _ in 0..rays {
        let origin = center + rng.direction() * 2.0 * size;
        let target = bounds.min + rng.vec(0.0, 1.0) * bounds.extent();
        let aimed_in = inside_by_operands(graph, &tree, &[], target);
        let ray = Ray::new(origin, (target - origin).normalize());
        check_aimed(&shape, &ray, target, aimed_in, 1e-4 * size, tally);
        check_ray(&shape, &ray, 400, 1e-4 * size, tally);
    }
}

#[test]
fn csg_with_prism_operands_matches_a_march_and_the_operands_inside_tests() {
    let graph = empty_graph();
    let mut rng = Rng(43);
    let mut tally = Tally::default();
    for k in 0..12 {
        let sweep = if k % 2 == 0 { Sweep::Linear } else { Sweep::Conic };
        let prism = random_prism(&mut rng, SPLINES[k % 4], sweep);
        let prism = node(&graph, prism, random_transforms(&mut rng, false));
        let ball = ShapeNode::Sphere { center: rng.vec(-0.3, 0.3), radius: rng.range(0.3, 0.7) };
        let op = [CsgOp::Difference, CsgOp::Intersection, CsgOp::Merge][k % 3];
        let tree = ShapeNode::Csg { op, operands: vec![prism, node(&graph, ball, vec![])] };
        check_csg_against_the_march(&graph, tree, 300, &mut rng, &mut tally);
    }
    // The prisms fill more than 1/50 of their bounds (prisms_match_a_march_...); the ball
    // keeps or takes away half of that or less on average: more than 1/100.
    assert_aimed_floor(&tally, 0.01);
    assert!(tally.slivers < tally.rays / 50, "{tally:?}");
}

/// A lathe of each spline kind in turn: a closed star-shaped curve about (1, 0) in the (r, y)
/// half-plane, joined so that the last segment returns to the first point.
fn random_lathe(rng: &mut Rng, kind: SplineKind) -> ShapeNode {
    let k = 5 + (rng.next() * 4.0) as usize;
    let p: Vec<Vec2> = star(rng, k, 0.3, 0.7).iter().map(|&v| v + Vec2::X).collect();
    let points: Vec<Vec2> = match kind {
        SplineKind::Linear => p.iter().chain([&p[0]]).copied().collect(),
        SplineKind::Quadratic => [p[k - 1]].iter().chain(&p).chain([&p[0]]).copied().collect(),
        SplineKind::Cubic => [p[k - 1]].iter().chain(&p).chain([&p[0], &p[1]]).copied().collect(),
        SplineKind::Bezier => (0..k)
            .flat_map(|i| {
                let (a, b) = (p[i], p[(i + 1) % k]);
                let bulge = Vec2::new(a.y - b.y, b.x - a.x) * rng.range(-0.3, 0.3);
                [a, a + (b - a) / 3.0 + bulge, b - (b - a) / 3.0 + bulge, b]
            })
            .collect(),
    };
    ShapeNode::Lathe { segments: open_spline_segments(kind, &points).expect("enough points") }
}

/// A sor of 5 to 8 points, heights rising by 0.2 to 0.4, radii 0.2 to 1.
fn random_sor(rng: &mut Rng) -> ShapeNode {
    let n = 5 + (rng.next() * 4.0) as usize;
    let mut y = -0.8;
    let points: Vec<Vec2> = (0..n)
        .map(|_| {
            y += rng.range(0.2, 0.4);
            Vec2::new(rng.range(0.2, 1.0), y)
        })
        .collect();
    ShapeNode::Sor { pieces: sor_pieces(&points).expect("rising points"), open: false }
}

/// Solids made by `make` (for the k-th of `count`) under random transforms: first hits against
/// a march, aimed and grazing rays, inside against the crossings, normals out of the solid.
/// The solids fill more than `fill` of their bounds.
fn check_solid_family(
    seed: u64,
    count: usize,
    fill: f32,
    mut make: impl FnMut(&mut Rng, usize) -> ShapeNode,
) {
    let graph = empty_graph();
    let mut rng = Rng(seed);
    let mut tally = Tally::default();
    let (mut grazed, mut toggles) = (0, 0);
    for k in 0..count {
        let solid = make(&mut rng, k);
        let transforms = random_transforms(&mut rng, k % 6 == 5);
        let shape = built_shape(&graph, node(&graph, solid, transforms));
        let bounds = shape.bounds().expect("bounded");
        let (center, size) = (bounds.centroid(), bounds.extent().max_element());
        let tolerance = 2e-4 * size + 1e-5 * center.abs().max_element();
        for i in 0..300 {
            let origin = center + rng.direction() * 2.0 * size;
            let target = bounds.min + rng.vec(0.0, 1.0) * bounds.extent();
            let aimed_in = shape.contains(target);
            let mut ray = Ray::new(origin, (target - origin).normalize());
            if i % 2 == 1
                && let Some(graze) = grazing(&shape, &ray, &mut rng, size)
            {
                ray = graze;
                grazed += 1;
            } else {
                check_aimed(&shape, &ray, target, aimed_in, tolerance, &mut tally);
            }
            check_ray(&shape, &ray, 300, tolerance, &mut tally);
            toggles += check_inside_between_crossings(&shape, &ray, 4.0 * size, tolerance);
            if let Some(hit) = shape.intersect(&ray, f32::INFINITY) {
                let (out, back) = (hit.point + hit.normal * 1e-3, hit.point - hit.normal * 1e-3);
                if shape.contains(out) != shape.contains(back) {
                    assert!(shape.contains(back), "{hit:?}");
                }
            }
        }
    }
    assert!(grazed > 30 * count && toggles > 100 * count, "{grazed} {toggles}");
    assert_aimed_floor(&tally, fill);
    assert!(tally.slivers < tally.rays / 6, "{tally:?}");
}

#[test]
fn lathes_match_a_march_and_their_crossings_agree_with_inside() {
    // The profile, a star of radii 0.3 to 0.7 about r = 1, holds a disc of radius 0.3 cos 36°
    // (area 0.18): a ring of volume 2 pi 1 0.18 = 1.1 in a box of 3.4 x 1.4 x 3.4 = 16 or
    // less (0.07), that box 1/5 or more of its world box: 0.014.
    check_solid_family(53, 12, 0.01, |rng, k| random_lathe(rng, SPLINES[k % 4]));
}

#[test]
fn sors_match_a_march_and_their_crossings_agree_with_inside() {
    // A sor of radii uniform in 0.2 to 1 fills its cylinder by E[r^2] / 1 = 0.41 on average,
    // the cylinder pi / 4 of its box, the box 1/5 or more of its world box: 0.06; half that.
    check_solid_family(59, 12, 0.03, |rng, _| random_sor(rng));
}

#[test]
fn csg_with_lathe_and_sor_operands_matches_a_march_and_the_operands_inside_tests() {
    let graph = empty_graph();
    let mut rng = Rng(61);
    let mut tally = Tally::default();
    for k in 0..8 {
        let solid = if k % 2 == 0 {
            random_lathe(&mut rng, SPLINES[(k / 2) % 4])
        } else {
            random_sor(&mut rng)
        };
        let solid = node(&graph, solid, random_transforms(&mut rng, false));
        let ball = ShapeNode::Sphere { center: rng.vec(-0.3, 0.3), radius: rng.range(0.3, 0.7) };
        let op = [CsgOp::Difference, CsgOp::Intersection, CsgOp::Merge][k % 3];
        let tree = ShapeNode::Csg { op, operands: vec![solid, node(&graph, ball, vec![])] };
        check_csg_against_the_march(&graph, tree, 200, &mut rng, &mut tally);
    }
    // Both kinds fill 1/50 or more of their bounds (lathes_... and sors_...); the ball keeps
    // or takes away half of that or less on average.
    assert_aimed_floor(&tally, 0.01);
    assert!(tally.slivers < tally.rays / 50, "{tally:?}");
}

/// An ovus of bottom radius 0.6 and a top radius from 0.2 to 1.9 times that: both of POV-Ray's
/// cases (the joining arc's radius twice the bottom's or twice the top's).
fn random_ovus(rng: &mut Rng) -> ShapeNode {
    ShapeNode::Ovus { bottom: 0.6, top: 0.6 * rng.range(0.2, 1.9) }
}

/// A lemon along a tilted axis of length 1 to 1.5, end radii 0 to 0.5 (one end pointed one time
/// in three), its inner radius from its least (a sphere's arc) to three times that.
fn random_lemon(rng: &mut Rng, k: usize) -> ShapeNode {
    let base = rng.vec(-0.2, 0.2) - 0.5 * Vec3::Y;
    let cap = base + (Vec3::Y + rng.vec(-0.3, 0.3)).normalize() * rng.range(1.0, 1.5);
    let radii = [if k.is_multiple_of(3) { 0.0 } else { rng.range(0.0, 0.5) }, rng.range(0.0, 0.5)];
    let length = (cap - base).length();
    let [a, b] = radii.map(|r| f64::from(r / length));
    let least = lemon_min_inner_radius(a, b) as f32 * length;
    let inner_radius = least * if k % 4 == 1 { 1.0 } else { rng.range(1.0, 3.0) };
    ShapeNode::Lemon { ends: [base, cap], radii, inner_radius, open: false }
}

#[test]
fn ovus_match_a_march_and_their_crossings_agree_with_inside() {
    // An ovus holds its larger sphere, of radius R = max(bottom, top), and lies in a box of
    // about 2R by 2R across (its joining arc bulges past the spheres by a little) and
    // 2 bottom + top <= 3R high: (4/3) pi R^3 / 12 R^3 = 0.35 of its box, taken as 0.3; the box
    // is 1/5 or more of its world box: 0.06; half that.
    check_solid_family(67, 8, 0.03, |rng, _| random_ovus(rng));
}

#[test]
fn lemons_match_a_march_and_their_crossings_agree_with_inside() {
    // A lemon's radius is concave in the height (an arc bulging out), so it holds the cone or
    // frustum between its rims, and at the least the spindle of an arc from tip to tip: a
    // pointed lemon with a 0.5 rim fills 1/4 of its box, the thinnest spindle here (both radii
    // 0, three times its least inner radius) about 0.4; the box is 1/5 or more of its world
    // box: 0.05 or more; less than half that.
    check_solid_family(71, 8, 0.02, random_lemon);
}

#[test]
fn csg_with_ovus_and_lemon_operands_matches_a_march_and_the_operands_inside_tests() {
    let graph = empty_graph();
    let mut rng = Rng(73);
    let mut tally = Tally::default();
    for k in 0..8 {
        let solid = if k % 2 == 0 { random_ovus(&mut rng) } else { random_lemon(&mut rng, k) };
        let solid = node(&graph, solid, random_transforms(&mut rng, false));
        let ball = ShapeNode::Sphere { center: rng.vec(-0.3, 0.3), radius: rng.range(0.3, 0.7) };
        let op = [CsgOp::Difference, CsgOp::Intersection, CsgOp::Merge][k % 3];
        let tree = ShapeNode::Csg { op, operands: vec![solid, node(&graph, ball, vec![])] };
        check_csg_against_the_march(&graph, tree, 200, &mut rng, &mut tally);
    }
    // Both fill 1/50 or more of their bounds (the tests above); the ball keeps or takes away
    // half of that or less on average.
    assert_aimed_floor(&tally, 0.01);
    assert!(tally.slivers < tally.rays / 50, "{tally:?}");
}

/// The parametric surface and the other shape a `.pov` scene of the two builds to.
fn built_parametric_and_other(text: &str) -> (Shape, Shape) {
    let graph = raydiance::lang::parse_scene(Path::new("tests/solids.pov"), text)
        .unwrap_or_else(|e| panic!("{e}"));
    let scene = build(&graph).unwrap_or_else(|e| panic!("{e}"));
    let shapes: Vec<Shape> = scene.primitives.iter().map(|p| p.shape.clone()).collect();
    let (parametric, other): (Vec<Shape>, Vec<Shape>) =
        shapes.into_iter().partition(|s| matches!(s, Shape::Parametric(_)));
    (parametric[0].clone(), other[0].clone())
}

/// POV-Ray's parametric surface of the torus (1 + 0.3 cos v) (cos u, 0, sin u) + 0.3 sin v y,
/// under transforms (mirrored one time in three), against the analytic torus under the same:
/// rays aimed through the bounds and rays grazing the torus. Both hit within the pieces'
/// size, or the ray grazes (the torus' hit is at a glancing angle, or the point either finds
/// is within that size of the other's surface).
#[test]
fn parametric_tori_match_the_analytic_torus_on_aimed_and_grazing_rays() {
    let mut rng = Rng(79);
    let (mut rays, mut hits, mut grazes) = (0, 0, 0);
    for k in 0..3 {
        let mirror = if k % 3 == 2 { -1.0 } else { 1.0 };
        let transform = format!(
            "scale <{}, {}, {}> rotate <{}, {}, {}> translate <{}, {}, {}>",
            mirror * rng.range(0.6, 1.4),
            rng.range(0.6, 1.4),
            rng.range(0.6, 1.4),
            rng.range(-180.0, 180.0),
            rng.range(-180.0, 180.0),
            rng.range(-180.0, 180.0),
            rng.range(-0.5, 0.5),
            rng.range(-0.5, 0.5),
            rng.range(-0.5, 0.5),
        );
        let text = format!(
            "parametric {{ function {{ (1 + 0.3 * cos(v)) * cos(u) }} function {{ 0.3 * sin(v) }} \
             function {{ (1 + 0.3 * cos(v)) * sin(u) }} <0, 0>, <2 * pi, 2 * pi> \
             contained_by {{ box {{ <-1.4, -0.4, -1.4>, <1.4, 0.4, 1.4> }} }} max_gradient 1.5 \
             accuracy 0.002 {transform} }}\ntorus {{ 1, 0.3 {transform} }}"
        );
        let (parametric, torus) = built_parametric_and_other(&text);
        assert!(parametric.crossings(&Ray::new(Vec3::ZERO, Vec3::X), 9.0).list.is_empty());
        assert!(!parametric.contains(Vec3::ZERO), "an open surface has no inside");
        let bounds = torus.bounds().expect("bounded");
        let (center, size) = (bounds.centroid(), bounds.extent().max_element());
        // A piece is at most `accuracy` across in (u, v) or along the ray; its box reaches
        // max_gradient times that further, stretched by the transforms (1.4 at most).
        let tolerance = 0.02;
        for i in 0..120 {
            let origin = center + rng.direction() * 2.0 * size;
            let target = bounds.min + rng.vec(0.0, 1.0) * bounds.extent();
            let mut ray = Ray::new(origin, (target - origin).normalize());
            if i % 2 == 1
                && let Some(graze) = grazing(&torus, &ray, &mut rng, size)
            {
                ray = graze;
            }
            rays += 1;
            let exact = torus.intersect(&ray, f32::INFINITY);
            let traced = parametric.intersect(&ray, f32::INFINITY);
            // The ray's first pass through the torus is thin (it grazes the tube) or glancing.
            let sliver = |ray: &Ray| {
                let l = torus.crossings(ray, f32::INFINITY).list;
                let glancing = torus
                    .intersect(ray, f32::INFINITY)
                    .is_some_and(|e| e.normal.dot(Vec3::from(ray.dir)).abs() < 0.3);
                glancing || l.len() >= 2 && l[1].at.t - l[0].at.t < 0.1
            };
            // Within `tolerance` of the torus' surface: the inside test differs around it.
            let near_torus = |p: Vec3| {
                let probes = [Vec3::X, Vec3::Y, Vec3::Z, -Vec3::X, -Vec3::Y, -Vec3::Z];
                probes.iter().any(|&a| torus.contains(p + a * tolerance) != torus.contains(p))
            };
            match (&exact, &traced) {
                (Some(e), Some(t)) => {
                    let cosine = e.normal.dot(Vec3::from(ray.dir)).abs().max(0.05);
                    if (e.t - t.t).abs() <= tolerance / cosine {
                        hits += 1;
                        // The normal is the surface's, up to its side (an open surface).
                        let facing = e.normal.dot(t.normal).abs();
                        assert!(facing > 0.9 || cosine < 0.2, "{ray:?}: {e:?} {t:?}");
                    } else if t.t < e.t {
                        // A graze of the torus the analytic test calls a touch.
                        assert!(near_torus(t.point), "a hit off the torus: {ray:?}: {e:?} {t:?}");
                        grazes += 1;
                    } else {
                        assert!(sliver(&ray), "a crossing missed: {ray:?}: {e:?} {t:?}");
                        grazes += 1;
                    }
                }
                (Some(e), None) => {
                    assert!(sliver(&ray), "missed: {ray:?} {e:?}");
                    grazes += 1;
                }
                (None, Some(t)) => {
                    assert!(near_torus(t.point), "a hit off the torus: {ray:?} {t:?}");
                    grazes += 1;
                }
                (None, None) => {}
            }
        }
    }
    assert!(hits > rays / 4 && grazes < rays / 5, "{rays} rays: {hits} hits, {grazes} grazes");
}

#[test]
fn superellipsoids_match_a_march_and_their_crossings_agree_with_inside() {
    let graph = empty_graph();
    let mut rng = Rng(47);
    let mut tally = Tally::default();
    let (mut grazed, mut toggles) = (0, 0);
    for k in 0..16 {
        // Rounded boxes, ellipsoids, and pinched stars (exponents above 2).
        let shape = ShapeNode::Superellipsoid { e: rng.range(0.2, 3.0), n: rng.range(0.2, 3.0) };
        let transforms = random_transforms(&mut rng, k % 8 == 7);
        let shape = built_shape(&graph, node(&graph, shape, transforms));
        let bounds = shape.bounds().expect("bounded by its cube");
        let (center, size) = (bounds.centroid(), bounds.extent().max_element());
        let tolerance = 2e-4 * size + 1e-5 * center.abs().max_element();
        for i in 0..400 {
            let origin = center + rng.direction() * 2.0 * size;
            let target = bounds.min + rng.vec(0.0, 1.0) * bounds.extent();
            let aimed_in = shape.contains(target);
            let mut ray = Ray::new(origin, (target - origin).normalize());
            if i % 2 == 1
                && let Some(graze) = grazing(&shape, &ray, &mut rng, size)
            {
                ray = graze;
                grazed += 1;
            } else {
                check_aimed(&shape, &ray, target, aimed_in, tolerance, &mut tally);
            }
            check_ray(&shape, &ray, 300, tolerance, &mut tally);
            toggles += check_inside_between_crossings(&shape, &ray, 4.0 * size, tolerance);
        }
    }
    assert!(grazed > 500 && toggles > 3000, "{grazed} {toggles}");
    // A superellipsoid <e, n> fills 2 e n B(e / 2, e / 2) B(n / 2 + 1, n) / 8 of its cube: 31% on
    // average over e and n in [0.2, 3] (4.5% at least, at <3, 3>), and the world box of the
    // cube turned at random holds 2 to 5 times its volume: more than 1/50 of the bounds.
    assert_aimed_floor(&tally, 0.02);
    assert!(tally.slivers < tally.rays / 6, "{tally:?}");
}

/// A random CSG tree of the given depth, its operands random solids under random transforms.
fn random_tree(graph: &SceneGraph, rng: &mut Rng, depth: u32) -> ObjectNode {
    let transforms = random_transforms(rng, false);
    let shape = if depth == 0 {
        match (rng.next() * 6.0) as u32 {
            0 => ShapeNode::Sphere { center: rng.vec(-0.3, 0.3), radius: rng.range(0.4, 0.9) },
            1 => ShapeNode::Box { corner_a: rng.vec(-0.9, -0.2), corner_b: rng.vec(0.2, 0.9) },
            2 => ShapeNode::Cylinder {
                base: rng.vec(-0.3, 0.3) - Vec3::Y,
                cap: rng.vec(-0.3, 0.3) + Vec3::Y,
                radius: rng.range(0.2, 0.6),
            },
            3 => ShapeNode::Cone {
                base: rng.vec(-0.3, 0.3) - Vec3::Y,
                base_radius: rng.range(0.0, 0.8),
                cap: rng.vec(-0.3, 0.3) + Vec3::Y,
                cap_radius: rng.range(0.1, 0.5),
                open: false,
            },
            4 => ShapeNode::Torus { major: rng.range(0.4, 0.8), minor: rng.range(0.1, 0.3) },
            _ => ShapeNode::Plane { normal: rng.direction(), offset: rng.range(-0.3, 0.3) },
        }
    } else {
        let op =
            [CsgOp::Intersection, CsgOp::Difference, CsgOp::Merge][(rng.next() * 3.0) as usize];
        let children = 2 + (rng.next() * 2.0) as u32;
        let mut operands: Vec<_> =
            (0..children).map(|_| random_tree(graph, rng, depth - 1)).collect();
        // Every operation keeps a bounded first operand, so the tree is bounded.
        if matches!(operands[0].shape, ShapeNode::Plane { .. }) {
            operands[0].shape = ShapeNode::Sphere { center: Vec3::ZERO, radius: 0.8 };
        }
        if op == CsgOp::Merge {
            for o in &mut operands {
                if matches!(o.shape, ShapeNode::Plane { .. }) {
                    o.shape =
                        ShapeNode::Box { corner_a: Vec3::splat(-0.5), corner_b: Vec3::splat(0.5) };
                }
            }
        }
        ShapeNode::Csg { op, operands }
    };
    node(graph, shape, transforms)
}

/// Whether `p` is inside the tree, from each operand built alone as its own object.
fn inside_by_operands(
    graph: &SceneGraph,
    tree: &ObjectNode,
    parents: &[Transform],
    p: Vec3,
) -> bool {
    let mut transforms = tree.transforms.clone();
    transforms.extend_from_slice(parents);
    match &tree.shape {
        ShapeNode::Csg { op, operands } => {
            let mut inside = operands.iter().map(|o| inside_by_operands(graph, o, &transforms, p));
            // `Inverse` turns its first operand inside out, then subtracts the others.
            let first = inside.next().unwrap() != (*op == CsgOp::Inverse);
            inside.fold(first, |a, b| match op {
                CsgOp::Intersection | CsgOp::Clip => a && b,
                CsgOp::Difference | CsgOp::Inverse => a && !b,
                CsgOp::Merge => a || b,
            })
        }
        ShapeNode::Union(children) => {
            children.iter().any(|c| inside_by_operands(graph, c, &transforms, p))
        }
        ShapeNode::Instance(target) => inside_by_operands(graph, target, &transforms, p),
        ShapeNode::Plane { normal, offset } => {
            // Inside where n . q + d < 0 for q the point in the plane's own space.
            let q = compose(&transforms).inverse().transform_point3(p);
            normal.dot(q) + offset < 0.0
        }
        shape => {
            let alone = node(graph, shape.clone(), transforms);
            built_shape(graph, alone).contains(p)
        }
    }
}

#[test]
fn csg_trees_first_hits_match_a_march_and_inside_tests_match_the_operands() {
    let graph = empty_graph();
    let mut rng = Rng(5);
    let mut tally = Tally::default();
    let mut inside_points = 0;
    for _ in 0..60 {
        let tree = random_tree(&graph, &mut rng, 2);
        let shape = built_shape(&graph, tree.clone());
        assert!(matches!(shape, Shape::Csg(_)));
        let Some(bounds) = shape.bounds() else { continue };
        let (center, size) = (bounds.centroid(), bounds.extent().max_element());
        for _ in 0..80 {
            let p = bounds.min + rng.vec(0.0, 1.0) * bounds.extent();
            let inside = shape.contains(p);
            assert_eq!(inside, inside_by_operands(&graph, &tree, &[], p), "at {p}");
            inside_points += usize::from(inside);
        }
        for _ in 0..300 {
            let origin = center + rng.direction() * 2.0 * size;
            let target = bounds.min + rng.vec(0.0, 1.0) * bounds.extent();
            let ray = Ray::new(origin, (target - origin).normalize());
            check_ray(&shape, &ray, 400, 1e-4 * size, &mut tally);
        }
    }
    assert!(tally.hits > tally.rays / 8 && inside_points > 100, "{tally:?}, {inside_points}");
    assert!(tally.slivers < tally.rays / 100, "{tally:?}");
}

fn mesh_node(graph: &SceneGraph, file: &Path, transforms: Vec<Transform>) -> ObjectNode {
    node(graph, ShapeNode::Mesh { path: file.to_path_buf() }, transforms)
}

#[test]
fn csg_of_closed_meshes_instances_unions_and_nested_csg_matches_a_march() {
    let graph = empty_graph();
    let cube = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/meshes/cube.obj");
    let tetrahedron =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scenes/parts/tetrahedron.obj");
    let mut rng = Rng(11);
    let mut tally = Tally::default();
    for _ in 0..12 {
        let ball =
            Arc::new(node(&graph, ShapeNode::Sphere { center: Vec3::ZERO, radius: 0.5 }, vec![]));
        let instance = node(&graph, ShapeNode::Instance(ball), random_transforms(&mut rng, false));
        let union = node(
            &graph,
            ShapeNode::Union(vec![
                node(&graph, ShapeNode::Torus { major: 0.6, minor: 0.2 }, vec![]),
                mesh_node(&graph, &tetrahedron, vec![Transform::Translate(Vec3::splat(-0.3))]),
            ]),
            random_transforms(&mut rng, false),
        );
        let inner = node(
            &graph,
            ShapeNode::Csg {
                op: CsgOp::Intersection,
                operands: vec![
                    mesh_node(
                        &graph,
                        &cube,
                        vec![
                            Transform::Scale(Vec3::splat(2.5)),
                            Transform::Translate(Vec3::new(0.0, 1.7, 0.0)),
                        ],
                    ),
                    union,
                ],
            },
            random_transforms(&mut rng, false),
        );
        let op =
            [CsgOp::Difference, CsgOp::Merge, CsgOp::Intersection][(rng.next() * 3.0) as usize];
        let tree = node(
            &graph,
            ShapeNode::Csg { op, operands: vec![inner, instance] },
            random_transforms(&mut rng, false),
        );
        let shape = built_shape(&graph, tree.clone());
        let Some(bounds) = shape.bounds() else { continue };
        let (center, size) = (bounds.centroid(), bounds.extent().max_element());
        for _ in 0..100 {
            let p = bounds.min + rng.vec(0.0, 1.0) * bounds.extent();
            assert_eq!(shape.contains(p), inside_by_operands(&graph, &tree, &[], p), "at {p}");
        }
        for _ in 0..400 {
            let origin = center + rng.direction() * 2.0 * size;
            let target = bounds.min + rng.vec(0.0, 1.0) * bounds.extent();
            let ray = Ray::new(origin, (target - origin).normalize());
            check_ray(&shape, &ray, 400, 1e-4 * size, &mut tally);
        }
    }
    assert!(tally.hits > tally.rays / 8, "{tally:?}");
    // A mesh that is not closed is not a solid.
    let dir = tempfile::tempdir().unwrap();
    let open = dir.path().join("open.obj");
    std::fs::write(&open, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let mut graph = graph.clone();
    let operands = vec![mesh_node(&graph, &cube, vec![]), mesh_node(&graph, &open, vec![])];
    graph.objects = vec![node(&graph, ShapeNode::Csg { op: CsgOp::Difference, operands }, vec![])];
    let error = build(&graph).expect_err("an open mesh").to_string();
    assert!(
        error.contains("this mesh is not closed") && error.contains("is not a solid"),
        "{error}"
    );
}

#[test]
fn csg_normals_point_out_of_the_result_and_surfaces_keep_their_operands_material() {
    let mut graph = empty_graph();
    let (red, blue) = (Vec3::new(0.8, 0.0, 0.0), Vec3::new(0.0, 0.0, 0.8));
    let mut cube =
        node(&graph, ShapeNode::Box { corner_a: -Vec3::ONE, corner_b: Vec3::ONE }, vec![]);
    cube.material = Some(material(&graph, red, Vec3::ZERO));
    let mut ball = node(&graph, ShapeNode::Sphere { center: Vec3::ZERO, radius: 1.3 }, vec![]);
    ball.material = Some(material(&graph, blue, Vec3::ZERO));
    let csg = ShapeNode::Csg { op: CsgOp::Difference, operands: vec![cube, ball] };
    graph.objects = vec![node(&graph, csg, vec![Transform::Rotate(Vec3::new(10.0, 20.0, 30.0))])];
    let scene = build(&graph).unwrap();
    let shape = &scene.primitives[0].shape;
    let mut rng = Rng(3);
    let (mut cut, mut outer) = (0, 0);
    for _ in 0..20_000 {
        let origin = rng.direction() * 4.0;
        let ray = Ray::new(origin, (rng.vec(-1.0, 1.0) - origin).normalize());
        let Some(hit) = scene.intersect(&ray) else { continue };
        let d = Vec3::from(ray.dir);
        assert!(hit.normal.dot(d) < 0.0, "a ray from outside meets the outside of the result");
        let delta = 1e-3;
        let (behind, front) = (hit.point - hit.normal * delta, hit.point + hit.normal * delta);
        if shape.contains(behind) == shape.contains(front) {
            continue; // an edge
        }
        assert!(shape.contains(behind) && !shape.contains(front), "{hit:?}");
        let colour = scene.material(hit.primitive, hit.point).diffuse;
        // On the sphere (the cut, its normal towards the centre) the subtracted operand's
        // material; elsewhere the cube's.
        let on_sphere = hit.normal.dot(-hit.point.normalize()) > 0.9999;
        assert_eq!(colour, if on_sphere { blue } else { red }, "{hit:?}");
        if on_sphere { cut += 1 } else { outer += 1 }
    }
    assert!(cut > 500 && outer > 500, "{cut} {outer}");
}

#[test]
fn a_sphere_subtracted_from_a_cube_renders_its_analytic_silhouette_with_emission_only() {
    let mut graph = empty_graph();
    let (width, height) = (40, 30);
    graph.settings.width = width;
    graph.settings.height = height;
    graph.settings.samples = 64;
    let emissive = material(&graph, Vec3::ZERO, Vec3::ONE);
    let cube = node(&graph, ShapeNode::Box { corner_a: -Vec3::ONE, corner_b: Vec3::ONE }, vec![]);
    let ball = node(&graph, ShapeNode::Sphere { center: Vec3::ZERO, radius: 1.3 }, vec![]);
    let mut csg =
        node(&graph, ShapeNode::Csg { op: CsgOp::Difference, operands: vec![cube, ball] }, vec![]);
    csg.material = Some(emissive);
    // Seen from a corner, so that the cut faces are in view.
    graph.camera.form = raydiance::graph::CameraForm::LookAt {
        location: Vec3::new(3.0, 2.5, -4.0),
        look_at: Vec3::ZERO,
        up: Vec3::Y,
        angle: 50.0,
    };
    graph.objects = vec![csg];
    for integrator in [IntegratorKind::Direct, IntegratorKind::Path] {
        graph.settings.integrator = integrator;
        let scene: Scene = build(&graph).unwrap();
        assert!(
            scene.warnings.iter().any(|w| w.contains("not sampled as lights")),
            "{:?}",
            scene.warnings
        );
        let image = common::render_image(&scene);
        let (mut edge, mut error) = (0, 0.0);
        for y in 0..height {
            for x in 0..width {
                // Coverage of the pixel, and of the pixel with a margin of half a pixel around it
                // (where that is all or nothing, so is the pixel).
                let (pixel, size) = ((x as usize, y as usize), (width as usize, height as usize));
                let coverage = |margin: f32| {
                    common::pixel_coverage(
                        &scene.camera,
                        pixel,
                        size,
                        margin,
                        common::hits_carved_cube,
                    )
                };
                let (covered, around) = (coverage(0.0), coverage(0.5));
                let value = image.pixels[(y * width + x) as usize];
                assert_eq!(value.x, value.z);
                if around == 0.0 || around == 1.0 {
                    assert_eq!(value.x, covered, "pixel ({x}, {y}) with {integrator:?}");
                } else {
                    edge += 1;
                    error += (value.x - covered).abs();
                    assert!(
                        (value.x - covered).abs() < 0.3,
                        "pixel ({x}, {y}): {value} vs {covered}"
                    );
                }
            }
        }
        assert!(edge > 20 && error / (edge as f32) < 0.08, "{edge} edge pixels, error {error}");
    }
}

#[test]
fn operands_that_are_not_solids_are_located_errors_naming_them() {
    let graph = empty_graph();
    let cube = node(&graph, ShapeNode::Box { corner_a: -Vec3::ONE, corner_b: Vec3::ONE }, vec![]);
    let cases = [
        (ShapeNode::Triangle { a: Vec3::ZERO, b: Vec3::X, c: Vec3::Y }, "a triangle"),
        (ShapeNode::Quad { corner: Vec3::ZERO, edge1: Vec3::X, edge2: Vec3::Y }, "a quad"),
        (ShapeNode::Disk { center: Vec3::ZERO, normal: Vec3::Y, radius: 1.0, hole: 0.0 }, "a disk"),
        (
            ShapeNode::Cone {
                base: Vec3::ZERO,
                base_radius: 1.0,
                cap: Vec3::Y,
                cap_radius: 1.0,
                open: true,
            },
            "an open cylinder",
        ),
        (
            ShapeNode::Cone {
                base: Vec3::ZERO,
                base_radius: 1.0,
                cap: Vec3::Y,
                cap_radius: 0.5,
                open: true,
            },
            "an open cone",
        ),
        (
            ShapeNode::Lemon {
                ends: [Vec3::ZERO, Vec3::Y],
                radii: [0.3, 0.2],
                inner_radius: 1.0,
                open: true,
            },
            "an open lemon",
        ),
    ];
    for (shape, name) in cases {
        let mut graph = graph.clone();
        let operands = vec![cube.clone(), node(&graph, shape, vec![])];
        graph.objects =
            vec![node(&graph, ShapeNode::Csg { op: CsgOp::Intersection, operands }, vec![])];
        let error = build(&graph).expect_err("not a solid").to_string();
        assert!(error.contains(&format!("{name} is not a solid")), "{error}");
        assert!(error.starts_with("tests/solids.scn:1:1:"), "{error}");
    }
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

#[test]
fn csg_in_a_scene_shadow_rays_and_ray_batches_agree_with_one_ray_at_a_time() {
    use raydiance::lanes::{Floats, LANES, Lane, RayLanes, Wide};
    let mut graph = empty_graph();
    let mut rng = Rng(23);
    graph.objects = (0..4).map(|_| random_tree(&graph, &mut rng, 2)).collect();
    graph.objects.push(node(&graph, ShapeNode::Plane { normal: Vec3::Y, offset: 2.0 }, vec![]));
    // And an unbounded CSG object: a ball merged with the half-space x > 1.5.
    let ball =
        node(&graph, ShapeNode::Sphere { center: Vec3::new(1.0, 1.0, 0.0), radius: 0.7 }, vec![]);
    let side = node(&graph, ShapeNode::Plane { normal: -Vec3::X, offset: 1.5 }, vec![]);
    let merge = ShapeNode::Csg { op: CsgOp::Merge, operands: vec![ball, side] };
    graph.objects.push(node(&graph, merge, vec![]));
    let scene = build(&graph).unwrap();
    let mut hits = 0;
    for _ in 0..5000 {
        let rays: [Ray; LANES] = std::array::from_fn(|_| {
            let origin = rng.direction() * 4.0;
            Ray::new(origin, (rng.vec(-1.0, 1.0) - origin).normalize())
        });
        let t_max: [f32; LANES] = std::array::from_fn(|_| rng.range(0.5, 8.0));
        let lanes = RayLanes::new(&rays);
        let nearest = scene.intersect_lanes(&lanes, [true; LANES]);
        let occluded = scene.occluded_lanes(&lanes, Floats::from_fn(|lane| t_max[lane]));
        for lane in 0..LANES {
            let one = scene.intersect(&rays[lane]);
            let key = |h: Option<raydiance::geometry::Hit>| {
                h.map(|h| (h.primitive, h.t, h.point, h.normal))
            };
            assert_eq!(key(nearest.hits()[lane]), key(one));
            let blocked = one.is_some_and(|h| h.t < t_max[lane]);
            assert_eq!(scene.occluded(&rays[lane], t_max[lane]), blocked);
            assert_eq!(occluded.lane(lane), blocked);
            // (Primitives 0 to 3 are the bounded CSG objects, 4 the plane, 5 the unbounded
            // CSG object, then their surfaces.)
            hits += usize::from(one.is_some_and(|h| h.primitive as usize >= 6));
        }
    }
    assert!(hits > 1000, "{hits} hits on CSG surfaces");
}

#[test]
fn an_intersection_of_six_half_spaces_is_a_box() {
    let mut graph = empty_graph();
    let planes = [Vec3::X, Vec3::Y, Vec3::Z, -Vec3::X, -Vec3::Y, -Vec3::Z]
        .map(|normal| node(&graph, ShapeNode::Plane { normal, offset: -1.0 }, vec![]));
    let turn = vec![Transform::Rotate(Vec3::new(20.0, 30.0, 40.0))];
    let csg = ShapeNode::Csg { op: CsgOp::Intersection, operands: planes.to_vec() };
    graph.objects = vec![node(&graph, csg, turn.clone())];
    let planes_scene = build(&graph).unwrap();
    let cube = ShapeNode::Box { corner_a: -Vec3::ONE, corner_b: Vec3::ONE };
    graph.objects = vec![node(&graph, cube, turn)];
    let box_scene = build(&graph).unwrap();
    let mut rng = Rng(31);
    let mut hits = 0;
    for _ in 0..20_000 {
        let origin = rng.direction() * 4.0;
        let ray = Ray::new(origin, (rng.vec(-1.5, 1.5) - origin).normalize());
        let (a, b) = (planes_scene.intersect(&ray), box_scene.intersect(&ray));
        assert_eq!(a.is_some(), b.is_some(), "{ray:?}: {a:?} {b:?}");
        if let (Some(a), Some(b)) = (a, b) {
            assert!(
                (a.t - b.t).abs() < 1e-4 && (a.normal - b.normal).length() < 1e-3,
                "{a:?} {b:?}"
            );
            hits += 1;
        }
        // From inside, the way out.
        let inside = Ray::new(rng.direction() * rng.range(0.0, 0.95), rng.direction());
        let (a, b) =
            (planes_scene.intersect(&inside).unwrap(), box_scene.intersect(&inside).unwrap());
        assert!((a.t - b.t).abs() < 1e-4 && (a.normal - b.normal).length() < 1e-3, "{a:?} {b:?}");
    }
    assert!(hits > 5000, "{hits}");
}

#[test]
fn csg_surfaces_evaluate_textures_in_their_operands_own_space() {
    use raydiance::graph::Pattern;
    let mut graph = empty_graph();
    let (a, b) = (Vec3::new(0.9, 0.1, 0.1), Vec3::new(0.1, 0.1, 0.9));
    let mut checker = MaterialDesc::new(graph.camera.span.clone());
    checker.diffuse = TextureNode {
        pattern: Pattern::Checker(Box::new(TextureNode::solid(a)), Box::new(TextureNode::solid(b))),
        transforms: vec![],
    };
    let operand_transforms =
        vec![Transform::Translate(Vec3::new(0.3, 0.2, 0.1)), Transform::Scale(Vec3::splat(0.7))];
    let mut cube = node(
        &graph,
        ShapeNode::Box { corner_a: Vec3::splat(-1.75), corner_b: Vec3::splat(1.75) },
        operand_transforms.clone(),
    );
    cube.material = Some(Arc::new(checker));
    let ball = node(&graph, ShapeNode::Sphere { center: Vec3::ZERO, radius: 1.0 }, vec![]);
    let csg_transforms = vec![Transform::Rotate(Vec3::new(0.0, 30.0, 10.0))];
    let csg = ShapeNode::Csg { op: CsgOp::Difference, operands: vec![cube, ball] };
    graph.objects = vec![node(&graph, csg, csg_transforms.clone())];
    let scene = build(&graph).unwrap();
    let to_operand = compose(&[operand_transforms, csg_transforms].concat()).inverse();
    let mut rng = Rng(41);
    let mut checked = 0;
    for _ in 0..5000 {
        let origin = rng.direction() * 6.0;
        let ray = Ray::new(origin, (rng.vec(-1.0, 1.0) - origin).normalize());
        let Some(hit) = scene.intersect(&ray) else { continue };
        let q = to_operand.transform_point3(hit.point);
        if (q - q.round()).abs().min_element() < 1e-3 {
            continue; // on a cell boundary
        }
        let even = (q.x.floor() + q.y.floor() + q.z.floor()) as i32 % 2 == 0;
        assert_eq!(
            scene.material(hit.primitive, hit.point).diffuse,
            if even { a } else { b },
            "at {q}"
        );
        checked += 1;
    }
    assert!(checked > 1000, "{checked}");
}

#[test]
fn an_emissive_box_lights_as_its_six_faces_do() {
    let mut graph = empty_graph();
    graph.settings.width = 24;
    graph.settings.height = 24;
    graph.settings.samples = 256;
    graph.settings.integrator = IntegratorKind::Direct;
    let white = material(&graph, Vec3::splat(0.8), Vec3::ZERO);
    let light = material(&graph, Vec3::ZERO, Vec3::splat(2.0));
    let mut floor =
        node(&graph, ShapeNode::Plane { normal: Vec3::new(0.0, 0.0, -1.0), offset: 1.0 }, vec![]);
    floor.material = Some(white);
    let (lo, hi) = (Vec3::new(-0.3, -0.2, 0.2), Vec3::new(0.4, 0.3, 0.5));
    let mut cube = node(&graph, ShapeNode::Box { corner_a: lo, corner_b: hi }, vec![]);
    cube.material = Some(light.clone());
    graph.objects = vec![floor.clone(), cube];
    let whole = common::render_image(&build(&graph).unwrap());
    // The same box as six quads facing out, each its own light.
    let size = hi - lo;
    let [x, y, z] = [Vec3::X * size.x, Vec3::Y * size.y, Vec3::Z * size.z];
    let quads = [(lo, z, y), (hi, -y, -z), (lo, x, z), (hi, -z, -x), (lo, y, x), (hi, -x, -y)];
    graph.objects = vec![floor];
    for (corner, edge1, edge2) in quads {
        let mut quad = node(&graph, ShapeNode::Quad { corner, edge1, edge2 }, vec![]);
        quad.material = Some(light.clone());
        graph.objects.push(quad);
    }
    let faces = common::render_image(&build(&graph).unwrap());
    let (a, b) = (common::mean(&whole), common::mean(&faces));
    assert!((a - b).abs().max_element() < 0.02 * b.max_element(), "{a} vs {b}");
}

#[test]
fn cones_and_tori_with_impossible_dimensions_are_located_errors() {
    let graph = empty_graph();
    let cases = [
        ShapeNode::Cone {
            base: Vec3::ZERO,
            base_radius: 0.0,
            cap: Vec3::Y,
            cap_radius: 0.0,
            open: false,
        },
        ShapeNode::Cone {
            base: Vec3::ZERO,
            base_radius: -1.0,
            cap: Vec3::Y,
            cap_radius: 1.0,
            open: false,
        },
        ShapeNode::Cone {
            base: Vec3::Y,
            base_radius: 1.0,
            cap: Vec3::Y,
            cap_radius: 0.5,
            open: true,
        },
        ShapeNode::Torus { major: 1.0, minor: 0.0 },
        ShapeNode::Torus { major: f32::NAN, minor: 0.2 },
    ];
    for shape in cases {
        let mut graph = graph.clone();
        graph.objects = vec![node(&graph, shape.clone(), vec![])];
        let error = build(&graph).expect_err("impossible").to_string();
        assert!(error.starts_with("tests/solids.scn:1:1: error: a"), "{error}");
        // The same as a CSG operand.
        let cube =
            node(&graph, ShapeNode::Box { corner_a: -Vec3::ONE, corner_b: Vec3::ONE }, vec![]);
        let operands = vec![cube, node(&graph, shape, vec![])];
        graph.objects = vec![node(&graph, ShapeNode::Csg { op: CsgOp::Merge, operands }, vec![])];
        assert!(build(&graph).is_err());
    }
}

/// A bicubic patch's control points: a bowl over [0, 3]², z = f(x) + f(y) with f convex
/// (f(x) = -1.8 t (1 - t), t = x / 3: f'' = 0.4), so the surface lies on the side of its
/// normal dP/du x dP/dv (+z) of each of its tangent planes.
fn dome() -> [Vec3; 16] {
    std::array::from_fn(|k| {
        let (column, row) = ((k % 4) as f32, (k / 4) as f32);
        let inner = [column, row].iter().filter(|&&c| c == 1.0 || c == 2.0).count() as f32;
        Vec3::new(column, row, -0.6 * inner)
    })
}

fn patch_scene(points: &[Vec3; 16], items: &str) -> String {
    let list: Vec<String> = points.iter().map(|p| format!("<{}, {}, {}>", p.x, p.y, p.z)).collect();
    format!(
        "camera {{ location <0, 0, -5> look_at 0 }}\nbicubic_patch {{ type 1 u_steps 5 v_steps 5 \
         {} {items} }}",
        list.join(", ")
    )
}

/// Rays aimed at points of the patch's surface (from `patch_point`, under a mirroring,
/// non-uniform transform) from the side its tangent plane keeps free of it, up to 60° off its
/// normal, meet it there with the surface's normal there. The 32 x 32 pieces are within
/// f'' h² / 8 = 4.4e-4 of the surface along each of x and y (h = 3/32), 1.3e-3 in all once
/// stretched 1.5 times: 2.6e-3 along a ray at 60°.
#[test]
fn bicubic_patches_meet_rays_on_their_surface_with_its_normals() {
    use raydiance::mesh::bezier_patch::{patch_normal, patch_point};
    let points = dome();
    let items = "scale <-1, 0.5, 1.5> rotate <20, -30, 10> translate <0.3, -1, 2>";
    let text = patch_scene(&points, items);
    let graph = raydiance::lang::parse_scene(Path::new("patch.pov"), &text)
        .unwrap_or_else(|e| panic!("{e}"));
    let to_world = compose(&graph.objects[0].transforms);
    let normal_to_world = to_world.matrix3.inverse().transpose();
    let shape = built_shape(&graph, graph.objects[0].clone());
    let mut rng = Rng(34);
    for _ in 0..2000 {
        let (u, v) = (rng.range(0.02, 0.98), rng.range(0.02, 0.98));
        let target = to_world.transform_point3(patch_point(&points, u, v));
        let normal = (normal_to_world * patch_normal(&points, u, v)).normalize();
        // Within 60° of the normal, on the side away from the surface.
        let off = loop {
            let d = rng.direction();
            if d.dot(-normal) > 0.5 {
                break d;
            }
        };
        let origin = target + 3.0 * off;
        let ray = Ray::new(origin, (target - origin).normalize());
        let hit = shape.intersect(&ray, f32::INFINITY).expect("the ray meets the patch");
        assert!((hit.t - 3.0).abs() < 3e-3, "({u}, {v}): t {} for 3", hit.t);
        assert!(hit.shading_normal.dot(normal).abs() > 0.999, "({u}, {v}): {}", hit.shading_normal);
        assert!(hit.shading_normal.dot(hit.normal) > 0.0, "shading normal on the face's side");
    }
}

#[test]
fn bicubic_patches_are_not_solids_and_their_settings_are_checked() {
    let points = dome();
    let located = |text: &str| {
        raydiance::lang::parse_scene(Path::new("patch.pov"), text)
            .and_then(|graph| build(&graph).map(|_| ()))
            .expect_err("refused")
            .to_string()
    };
    let patch = patch_scene(&points, "");
    let operand = patch.replace("bicubic_patch", "intersection { sphere { 0, 1 } bicubic_patch");
    let error = located(&format!("{operand} }}"));
    assert!(error.starts_with("patch.pov:2:") && error.contains("not a solid"), "{error}");
    for (setting, said) in [
        ("u_steps 9", "u_steps is a whole number from 0 to 8"),
        ("v_steps 1.5", "v_steps is a whole number from 0 to 8"),
        ("type 2", "type is 0 or 1, not 2"),
        ("flatness -1", "flatness is 0 or more"),
    ] {
        let error = located(&patch.replace("v_steps 5", &format!("v_steps 5 {setting}")));
        assert!(error.starts_with("patch.pov:2:") && error.contains(said), "{setting}: {error}");
    }
    let error = located(&patch.replace("type 1", ""));
    assert!(error.contains("needs its `type`"), "{error}");
}

/// A julia fractal of parameter |c| <= 0.2 (quaternion) or 0.4, sampled finer than the march.
fn random_julia(rng: &mut Rng, algebra: Algebra, function: JuliaFunction, c: f64) -> ShapeNode {
    let parameter = glam::DVec4::new(
        f64::from(rng.range(-1.0, 1.0)),
        f64::from(rng.range(-1.0, 1.0)),
        f64::from(rng.range(-1.0, 1.0)),
        f64::from(rng.range(-1.0, 1.0)),
    );
    let slice = glam::DVec4::new(f64::from(rng.range(-0.3, 0.3)), 0.0, 0.0, 1.0);
    ShapeNode::JuliaFractal(Box::new(JuliaDesc {
        parameter: parameter.normalize() * c * f64::from(rng.range(0.3, 1.0)),
        algebra,
        function,
        max_iteration: 6,
        precision: 200.0,
        slice: (slice, f64::from(rng.range(-0.2, 0.2))),
    }))
}

#[test]
fn julia_fractals_match_a_march_and_their_crossings_agree_with_inside() {
    let graph = empty_graph();
    let mut rng = Rng(34);
    let (mut quaternions, mut hypercomplex) = (Tally::default(), Tally::default());
    let (mut grazed, mut toggles) = (0, 0);
    for k in 0..12 {
        let function = if k % 2 == 0 { JuliaFunction::Square } else { JuliaFunction::Cube };
        let (algebra, c, tally) = if k < 8 {
            (Algebra::Quaternion, 0.2, &mut quaternions)
        } else {
            (Algebra::Hypercomplex, 0.4, &mut hypercomplex)
        };
        let shape = random_julia(&mut rng, algebra, function, c);
        let transforms = random_transforms(&mut rng, k == 7);
        let shape = built_shape(&graph, node(&graph, shape, transforms));
        let bounds = shape.bounds().expect("bounded by its sphere");
        let (center, size) = (bounds.centroid(), bounds.extent().max_element());
        let tolerance = 2e-4 * size + 1e-5 * center.abs().max_element();
        for i in 0..240 {
            let origin = center + rng.direction() * 2.0 * size;
            let target = bounds.min + rng.vec(0.0, 1.0) * bounds.extent();
            let aimed_in = shape.contains(target);
            let mut ray = Ray::new(origin, (target - origin).normalize());
            if i % 2 == 1
                && let Some(graze) = grazing(&shape, &ray, &mut rng, size)
            {
                ray = graze;
                grazed += 1;
            } else {
                check_aimed(&shape, &ray, target, aimed_in, tolerance, tally);
            }
            check_ray(&shape, &ray, 200, tolerance, tally);
            toggles += check_inside_between_crossings(&shape, &ray, 4.0 * size, tolerance);
        }
    }
    assert!(grazed > 300 && toggles > 1000, "{grazed} {toggles}");
    // For |c| <= 0.2 the ball of radius (1 + sqrt(1 - 4 |c|)) / 2 >= 0.72 (squaring) or 0.8
    // (cubing: r^3 + |c| <= r) maps into itself, so it is inside: 11% of the cube of side
    // 2 (1 + |c|) <= 2.4 that bounds the sphere, and the world box of the cube turned at random
    // holds 2 to 5 times its volume: more than 1/50 of the bounds.
    assert_aimed_floor(&quaternions, 0.02);
    for tally in [&quaternions, &hypercomplex] {
        assert!(tally.hits + tally.slivers >= tally.aimed_inside, "{tally:?}");
        assert!(tally.slivers < tally.rays / 6, "{tally:?}");
    }
}

#[test]
fn julia_fractals_settings_are_checked() {
    let located = |text: &str| {
        raydiance::lang::parse_scene(Path::new("julia.pov"), text)
            .map(|_| ())
            .expect_err("refused")
            .to_string()
    };
    for (settings, said) in [
        ("hypercomplex exp", "function `exp` is not supported"),
        ("hypercomplex cube", "function `cube` is not supported in the hypercomplex numbers"),
        ("cube max_iteration 0", "max_iteration is a whole number from 1"),
        ("precision 1e6", "precision is at most"),
        ("slice <1, 0, 0, 0>, 0", "fourth component other than 0"),
    ] {
        let error = located(&format!("julia_fractal {{ <0.1, 0.2, 0, 0> {settings} }}"));
        assert!(error.starts_with("julia.pov:1:") && error.contains(said), "{settings}: {error}");
    }
    let error = located("julia_fractal { <0.1, 0.2, 0> }");
    assert!(error.contains("4-vector"), "{error}");
}

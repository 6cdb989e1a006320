//! POV-Ray's patterns, maps and bump mapping in scenes (`docs/language.md`, Patterns and Bump
//! mapping): every pattern reads the same in both dialects and stays within its map, maps
//! interpolate between their entries, and bump mapping changes nothing at amount 0, never
//! creates energy in a white furnace and stays finite and positive at grazing angles.

use crate::common;

use std::path::Path;

use glam::Vec3;
use raydiance::geometry::Ray;
use raydiance::lang::parse_scene;
use raydiance::scene::{Scene, build};

fn pov(text: &str) -> Scene {
    let graph = parse_scene(Path::new("tests/inline.pov"), text).unwrap_or_else(|e| panic!("{e}"));
    build(&graph).unwrap_or_else(|e| panic!("{e}"))
}

/// The diffuse colour of the scene's one object at `p` (its own space is the world's).
fn kd(scene: &Scene, p: Vec3) -> Vec3 {
    let hit = scene.intersect(&Ray::new(Vec3::new(0.0, 0.0, -50.0), Vec3::Z)).expect("the box");
    scene.material(hit.primitive, p).diffuse
}

const CAMERA: &str = "camera { location <0, 0, -200>  look_at <0, 0, 0> }";

const POINTS: [Vec3; 6] = [
    Vec3::new(0.13, 0.27, 0.31),
    Vec3::new(-1.7, 2.2, 0.9),
    Vec3::new(3.3, -0.4, -2.6),
    Vec3::new(0.5, 0.5, 0.5),
    Vec3::new(-0.25, 1.75, 4.1),
    Vec3::new(7.2, -3.1, 0.05),
];

#[test]
fn every_pattern_reads_the_same_in_both_dialects_and_stays_in_its_map() {
    let map = "color_map { [0 rgb 0] [1 rgb <1, 0.5, 0.25>] }";
    let words = [
        "agate",
        "bozo",
        "brick",
        "bumps",
        "cells",
        "checker",
        "crackle",
        "dents",
        "gradient x",
        "granite",
        "hexagon",
        "leopard",
        "mandel 20",
        "marble",
        "onion",
        "quilted",
        "radial",
        "ripples",
        "spiral1 3",
        "spiral2 3",
        "spotted",
        "waves",
        "wood",
        "wrinkles",
    ];
    for word in words {
        let modifiers = format!("{word} turbulence 0.3 frequency 2 {map} scale 0.7");
        let scn = common::scene(&format!(
            "{CAMERA} box {{ -100, 100  material {{ diffuse pattern {{ {modifiers} }} }} }}"
        ));
        let pov = pov(&format!(
            "box {{ -100, 100  pigment {{ {modifiers} }} finish {{ diffuse 1 ambient 0 }} }}"
        ));
        let mut values = Vec::new();
        for p in POINTS {
            let (a, b) = (kd(&scn, p), kd(&pov, p));
            assert!((a - b).abs().max_element() < 1e-6, "{word} at {p}: {a} vs {b}");
            assert!((0.0..=1.0).contains(&a.x), "{word} at {p}: {a}");
            assert!((a.y - 0.5 * a.x).abs() < 1e-6, "{word}: through the map, {a}");
            values.push(a.x);
        }
        assert!(values.iter().any(|v| *v != values[0]), "{word} is constant: {values:?}");
    }
}

#[test]
fn pattern_maps_interpolate_between_their_entries() {
    // pigment_map: a quarter of the way from red to blue at x = 0.25.
    let s = pov("box { -100, 100  pigment { gradient x  pigment_map { [0 color rgb <1, 0, 0>] \
                 [1 color rgb <0, 0, 1>] } }  finish { diffuse 1 ambient 0 } }");
    let c = kd(&s, Vec3::new(0.25, 3.0, 1.0));
    assert!((c - Vec3::new(0.75, 0.0, 0.25)).length() < 1e-5, "{c}");
    // An entry may itself be a pattern: halfway between black and a checker.
    let s = pov("box { -100, 100  pigment { gradient y  pigment_map { [0 rgb 0] \
                 [1 checker rgb 1, rgb <0, 1, 0>] } }  finish { diffuse 1 ambient 0 } }");
    assert!((kd(&s, Vec3::new(0.5, 0.5, 0.5)) - Vec3::splat(0.5)).length() < 1e-5);
    assert!((kd(&s, Vec3::new(1.5, 0.5, 0.5)) - Vec3::new(0.0, 0.5, 0.0)).length() < 1e-5);
    // `.scn`'s texture_map, and `average`'s weighted mean (weights 1 and 3).
    let s = common::scene(&format!(
        "{CAMERA} box {{ -100, 100  material {{ diffuse pattern {{ gradient x  texture_map {{ [0 rgb 0] \
         [0.5 checker {{ rgb 1, rgb 0 }}] [1 rgb 1] }} }} }} }}"
    ));
    assert!((kd(&s, Vec3::new(0.25, 0.5, 0.5)) - Vec3::splat(0.5)).length() < 1e-5);
    assert!((kd(&s, Vec3::new(0.75, 0.5, 0.5)) - Vec3::splat(1.0)).length() < 1e-5);
    let s = common::scene(&format!(
        "{CAMERA} box {{ -100, 100  material {{ diffuse pattern {{ average  texture_map {{ \
         [1 rgb 1] [3 rgb <0, 0, 1>] }} }} }} }}"
    ));
    assert!((kd(&s, Vec3::ONE) - Vec3::new(0.25, 0.25, 1.0)).length() < 1e-5);
    // A .pov texture_map of textures that differ only in pigment, and one whose finishes
    // differ: the first's is used, with a warning.
    let s = pov("box { -100, 100  texture { gradient x  texture_map { \
                 [0 pigment { rgb <1, 0, 0> } finish { diffuse 1 ambient 0 }] \
                 [1 pigment { rgb <0, 0, 1> } finish { diffuse 1 ambient 0 }] } } }");
    let c = kd(&s, Vec3::new(0.5, 3.0, 1.0));
    assert!((c - Vec3::new(0.5, 0.0, 0.5)).length() < 1e-5, "their finish: diffuse 1, {c}");
    let graph = parse_scene(
        Path::new("tests/inline.pov"),
        "box { -1, 1  texture { gradient x  texture_map { [0 pigment { rgb 1 }] \
         [1 pigment { rgb 1 } finish { phong 1 }] } } }",
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let warned = graph.warnings.iter().any(|w| w.contains(":1:") && w.contains("first texture"));
    assert!(warned, "{:?}", graph.warnings);
    // Block patterns take their colours in order: hexagon's three.
    let s =
        pov("box { -100, 100  pigment { hexagon rgb <1, 0, 0>, rgb <0, 1, 0>, rgb <0, 0, 1> } \
                 finish { diffuse 1 ambient 0 } }");
    let mut seen: Vec<Vec3> = Vec::new();
    for i in 0..64 {
        let c = kd(&s, Vec3::new((i % 8) as f32 * 0.45, 0.0, (i / 8) as f32 * 0.45));
        assert_eq!(c.element_sum(), 1.0, "one of the three: {c}");
        if !seen.contains(&c) {
            seen.push(c);
        }
    }
    assert_eq!(seen.len(), 3);
}

/// POV-Ray's manual: `checker texture { A } texture { B }` (and `brick`, `hexagon`) takes
/// textures where the colours stand, and `checker pigment { A } pigment { B }` pigments;
/// `tiles { A tile2 B }` is the old name of `checker`'s.
#[test]
fn block_patterns_and_tiles_take_textures_and_pigments_in_place_of_colours() {
    let finish = "finish { diffuse 1 ambient 0 }";
    let red = format!("texture {{ pigment {{ rgb <1, 0, 0> }} {finish} }}");
    let blue = format!("texture {{ pigment {{ rgb <0, 0, 1> }} {finish} }}");
    let checker = pov(&format!("box {{ -100, 100  texture {{ checker {red} {blue} }} }}"));
    let plain = pov(&format!(
        "box {{ -100, 100  pigment {{ checker rgb <1, 0, 0>, rgb <0, 0, 1> }} {finish} }}"
    ));
    let pigments = pov(&format!(
        "#declare Red = pigment {{ rgb <1, 0, 0> }}
         box {{ -100, 100  pigment {{ checker pigment {{ Red }}, pigment {{ rgb <0, 0, 1> }} }}
           {finish} }}"
    ));
    let tiles = pov(&format!("box {{ -100, 100  texture {{ tiles {{ {red} tile2 {blue} }} }} }}"));
    let mut seen = Vec::new();
    for p in POINTS.iter().chain(&[Vec3::new(1.5, 0.5, 0.5), Vec3::new(0.5, 0.5, 0.5)]) {
        let c = kd(&checker, *p);
        assert_eq!(c, kd(&plain, *p), "as the pigment's checker at {p}");
        assert_eq!(c, kd(&pigments, *p), "pigments as colours at {p}");
        assert_eq!(c, kd(&tiles, *p), "tiles as checker at {p}");
        seen.push(c);
    }
    assert!(seen.contains(&Vec3::X) && seen.contains(&Vec3::Z), "both textures show: {seen:?}");
    // A patterned pigment in a block: brick's mortar is the first (a gradient along x), the
    // brick the second; each keeps its own transforms.
    let brick = pov(&format!(
        "box {{ -100, 100  pigment {{ brick pigment {{ gradient x scale 4 }} pigment {{ rgb 1 }} }}
           {finish} }}"
    ));
    assert_eq!(kd(&brick, Vec3::new(2.0, 1.5, 1.0)), Vec3::ONE, "in a brick");
    let mortar = kd(&brick, Vec3::new(1.0, 0.1, 1.0));
    assert!((mortar - Vec3::splat(0.25)).abs().max_element() < 1e-4, "mortar: {mortar}");
    // A pigment in a pigment stands only after a block pattern.
    let refused = parse_scene(
        Path::new("tests/inline.pov"),
        "box { -1, 1  pigment { bozo pigment { rgb 1 } } }",
    )
    .unwrap_err()
    .to_string();
    assert!(refused.contains(":1:24") && refused.contains("pigment_map"), "{refused}");
    // A pattern that takes a map refuses textures, where it is written.
    let refused = parse_scene(
        Path::new("tests/inline.pov"),
        &format!("box {{ -1, 1  texture {{ gradient x {red} {blue} }} }}"),
    )
    .unwrap_err()
    .to_string();
    assert!(refused.contains(":1:24") && refused.contains("texture_map"), "{refused}");
}

#[test]
fn a_bump_of_amount_zero_changes_nothing_bit_for_bit() {
    let scene = |normal: &str| {
        common::scene(&format!(
            "settings {{ resolution 16, 12  samples 4 }}
             camera {{ location <0, 1, -3>  look_at <0, 0, 0> }}
             light_source {{ <1, 3, -2>  power rgb 20 }}
             plane {{ <0, 1, 0>, 0  material {{ diffuse rgb 0.7  specular rgb 0.2  roughness 0.2 {normal} }} }}
             sphere {{ <0, 0.5, 0>, 0.5  material {{ diffuse rgb <0.2, 0.4, 0.8> {normal} }} }}"
        ))
    };
    let plain = common::render_image(&scene(""));
    let zero = common::render_image(&scene("normal { bumps 0  scale 0.1 }"));
    assert_eq!(plain.pixels, zero.pixels);
    let bumped = common::render_image(&scene("normal { bumps 1  scale 0.1 }"));
    assert_ne!(plain.pixels, bumped.pixels, "a bump of amount 1 shows");
    // So for a bump_map.
    let (_dir, image) = checker_image();
    let bump_map =
        |size: f32| format!("normal {{ bump_map {{ \"{image}\" bump_size {size} }} scale 0.5 }}");
    assert_eq!(plain.pixels, common::render_image(&scene(&bump_map(0.0))).pixels);
    assert_ne!(plain.pixels, common::render_image(&scene(&bump_map(0.2))).pixels);
}

/// An 8 × 8 PNG of 2 × 2 texel squares, black and white, in a folder of its own: its path.
fn checker_image() -> (tempfile::TempDir, String) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("checker.png");
    image::GrayImage::from_fn(8, 8, |x, y| {
        image::Luma([if (x / 2 + y / 2) % 2 == 0 { 0 } else { 255 }])
    })
    .save(&path)
    .unwrap();
    let path = path.to_str().expect("a UTF-8 path").to_string();
    (dir, path)
}

/// `bump_map`: the image's gray is the height, bilinear between texel centres; the gradient is
/// the height's difference across one texel per texel width, times `bump_size`, as POV-Ray's
/// bump_map tilts by neighbouring texels' differences.
#[test]
fn a_bump_map_tilts_by_its_image_s_gray_differences() {
    use std::sync::Arc;
    let dir = tempfile::tempdir().unwrap();
    // Gray 0, 16, ..., 240 along x, one row: with `gamma 1` heights i·16/255.
    image::GrayImage::from_fn(16, 1, |x, _| image::Luma([(x * 16) as u8]))
        .save(dir.path().join("ramp.png"))
        .unwrap();
    let scene = dir.path().join("scene.pov");
    let normal = |options: &str| {
        let text = format!(
            "sphere {{ 0, 1  normal {{ bump_map {{ png \"ramp\" gamma 1 {options} }} }} }}"
        );
        let graph = parse_scene(&scene, &text).unwrap_or_else(|e| panic!("{e}"));
        let node =
            graph.objects[0].material.as_ref().and_then(|m| m.normal.clone()).expect("a normal");
        raydiance::texture::Bump::new(&node, &mut |path| {
            raydiance::texture::ImageMap::load(path).map(Arc::new)
        })
        .unwrap_or_else(|e| panic!("{e}"))
    };
    let bump = normal("bump_size 2");
    let slope = 2.0 * (16.0 / 255.0) / (1.0 / 16.0);
    for x in [0.2f32, 0.37, 0.5, 0.81] {
        let g = bump.perturbation(Vec3::new(x, 0.3, 0.7), Vec3::Z);
        assert!((g - Vec3::new(slope, 0.0, 0.0)).length() < 1e-4, "at x {x}: {g}, not {slope}");
        // The image repeats over the x-y plane (map_type 0).
        assert!((bump.perturbation(Vec3::new(x + 3.0, -5.3, 2.0), Vec3::Z) - g).length() < 1e-4);
    }
    assert_eq!(normal("bump_size 0").perturbation(Vec3::new(0.4, 0.3, 0.0), Vec3::Z), Vec3::ZERO);
    assert!(
        (normal("").perturbation(Vec3::new(0.4, 0.3, 0.0), Vec3::Z).x - slope / 2.0).abs() < 1e-4,
        "bump_size 1"
    );
    // `use_index`: a palette image's indices are the heights (POV-Ray's bump_map). Index x at
    // column x, its colour dark to light the other way: the index rises by 1 a texel where the
    // gray falls by 16/255.
    let mut bytes = Vec::new();
    {
        let mut encoder = png::Encoder::new(&mut bytes, 16, 1);
        encoder.set_color(png::ColorType::Indexed);
        encoder.set_depth(png::BitDepth::Four);
        let palette: Vec<u8> = (0..16u8).flat_map(|i| [240 - 16 * i; 3]).collect();
        encoder.set_palette(palette);
        let mut writer = encoder.write_header().unwrap();
        let packed: Vec<u8> = (0..8u8).map(|i| (2 * i) << 4 | (2 * i + 1)).collect();
        writer.write_image_data(&packed).unwrap();
    }
    std::fs::write(dir.path().join("ramp.png"), bytes).unwrap();
    let by_index =
        normal("bump_size 0.5 use_index").perturbation(Vec3::new(0.4, 0.3, 0.0), Vec3::Z);
    assert!((by_index - Vec3::new(0.5 * 16.0, 0.0, 0.0)).length() < 1e-3, "{by_index}");
    let by_gray = normal("bump_size 0.5").perturbation(Vec3::new(0.4, 0.3, 0.0), Vec3::Z);
    assert!((by_gray.x + 0.5 * slope / 2.0).abs() < 1e-4, "its colours fall: {by_gray}");
    // A pigment's options are refused in a bump_map, and bump_size in an image_map.
    let error = |text: &str| parse_scene(&scene, text).map(|_| ()).unwrap_err().to_string();
    let e = error("sphere { 0, 1  normal { bump_map { \"ramp.png\" filter all 0.5 } } }");
    assert!(e.contains(":1:47") && e.contains("not in a bump_map"), "{e}");
    let e = error("sphere { 0, 1  pigment { image_map { \"ramp.png\" bump_size 2 } } }");
    assert!(e.contains(":1:49") && e.contains("not in an image_map"), "{e}");
}

#[test]
fn a_strongly_bumped_white_object_in_a_white_furnace_creates_no_energy() {
    // (normal, lowest mean): what a bump loses is the light its tilted lobe would send through
    // the surface, more the stronger the tilt (tilts of 60° and more for amount 1 here).
    let cases = [
        ("bumps 1  scale 0.2", 0.6),
        ("crackle 1  scale 0.3", 0.6),
        ("ripples 0.5  frequency 10", 0.6),
        ("bumps 0.1  scale 0.2", 0.9),
    ];
    let (_dir, image) = checker_image();
    let bump_map = format!("bump_map {{ \"{image}\" bump_size 0.1 }} scale 0.5");
    let cases = cases.into_iter().chain([(bump_map.as_str(), 0.6)]);
    for (normal, lowest) in cases {
        let s = common::scene(&format!(
            "settings {{ resolution 20, 20  samples 64  max_depth 50  background rgb 1 }}
             camera {{ location <0, 0, -3>  look_at <0, 0, 0>  angle 40 }}
             sphere {{ <0, 0, 0>, 1  material {{ diffuse rgb 1  normal {{ {normal} }} }} }}"
        ));
        let film = common::render_film(&s);
        let image = film.image();
        let pixels = image.pixels.len() as f32;
        let standard_error = (film.variance_of_mean().iter().sum::<Vec3>() / (pixels * pixels))
            .map(f32::sqrt)
            .max_element();
        let mean = common::mean(&image);
        assert!(mean.max_element() <= 1.0 + 4.0 * standard_error, "{normal}: mean {mean}");
        assert!(mean.min_element() > lowest, "{normal}: mean {mean}, too dark");
        assert!(image.pixels.iter().all(|p| p.is_finite() && p.min_element() >= 0.0));
    }
}

#[test]
fn bumped_surfaces_at_grazing_angles_stay_finite_and_positive() {
    // The camera skims the plane: most hits see it at a few degrees.
    let s = common::scene(
        "settings { resolution 32, 16  samples 8  max_depth 8 }
         camera { location <0, 0.02, -6>  look_at <0, 0, 4>  angle 60 }
         light_source { <0, 0.3, 6>  power rgb 50 }
         plane { <0, 1, 0>, 0  material { diffuse rgb 0.8  specular rgb 0.15  roughness 0.05 \
           normal { bumps 2  scale 0.05 } } }",
    );
    let image = common::render_image(&s);
    assert!(image.pixels.iter().all(|p| p.is_finite() && p.min_element() >= 0.0));
    assert!(common::mean(&image).max_element() > 0.0, "the plane is lit");
}

#[test]
fn pov_normals_read_maps_and_declared_normals() {
    // A declared normal, a normal_map and a slope_map all read and render finite.
    let s = pov("#declare N = normal { granite 0.4  scale 0.2 }
         camera { location <0, 1, -3>  look_at 0 }
         light_source { <2, 4, -3> color rgb 1 }
         sphere { 0, 1  pigment { rgb 0.8 }  normal { N } }
         plane { y, -1  pigment { rgb 0.5 }  normal { gradient x  normal_map { [0 bumps 0.3] \
           [1 dents 0.6] } } }
         box { <2, -1, 0>, <3, 0, 1>  pigment { rgb 0.5 }  normal { onion 1  slope_map { \
           [0 <0, 1>] [0.5 <1, 0>] [1 <0, -1>] } } }");
    let image = common::render_image(&s);
    assert!(image.pixels.iter().all(|p| p.is_finite() && p.min_element() >= 0.0));
    // `average`'s entries may leave out their weights (1 each); other maps' may not.
    let graph = parse_scene(
        Path::new("tests/inline.pov"),
        "sphere { 0, 1  normal { average normal_map { [waves 2 frequency 3] [1 ripples 1] } } }",
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let normal = graph.objects[0].material.as_ref().and_then(|m| m.normal.clone());
    let Some(raydiance::graph::NormalNode {
        pattern: raydiance::graph::NormalPattern::Average(entries),
        ..
    }) = normal
    else {
        panic!("an average: {normal:?}")
    };
    assert_eq!(entries.iter().map(|e| e.0).collect::<Vec<_>>(), [1.0, 1.0]);
    let error = parse_scene(
        Path::new("tests/inline.pov"),
        "sphere { 0, 1  normal { gradient x  normal_map { [bumps 1] } } }",
    )
    .unwrap_err()
    .to_string();
    assert!(error.contains("needs its position"), "{error}");
}

/// POV-Ray's warps, against values `povray` 3.7 renders (a gradient x in flat light): a black
/// hole at c of radius r moves p within it to p + s (p − c), s = strength (1 − |p − c| / r)^falloff
/// (`inverse`: p − s (p − c)); its `repeat <r>` stands a hole in every block of size r; warps
/// apply from the last written to the first; and a declared pigment or an `average` takes
/// warps as a pattern does.
#[test]
fn warps_move_points_as_povray_s_do() {
    let finish = "finish { diffuse 1 ambient 0 }";
    let gradient = |warps: &str| {
        let s = pov(&format!("box {{ -100, 100  pigment {{ gradient x {warps} }} {finish} }}"));
        move |x: f32| kd(&s, Vec3::new(x, 0.0, 0.0)).x
    };
    let close = |a: f32, b: f32| (a - b).abs() < 1e-4;
    // s = 1 · (1 − 0.5)¹ = 0.5: 0.5 reads 0.75 (povray: 0.75), inverse 0.25.
    let hole = gradient("warp { black_hole <0, 0, 0>, 1  falloff 1 }");
    assert!(close(hole(0.5), 0.75), "{}", hole(0.5));
    assert!(close(hole(1.5), 0.5), "outside the hole: {}", hole(1.5));
    let inverse = gradient("warp { black_hole <0, 0, 0>, 1  falloff 1  strength 1  inverse }");
    assert!(close(inverse(0.5), 0.25), "{}", inverse(0.5));
    // Repeated every 3 along x (blkhole.pov's `repeat <2, 1.5, 0>` is this form).
    let repeated = gradient("warp { black_hole <0, 0, 0>, 1  falloff 1  repeat <3, 0, 0> }");
    assert!(close(repeated(3.5), 0.75) && close(repeated(-2.5), 0.75), "{}", repeated(3.5));
    assert!(close(repeated(1.5), 0.5), "between the holes: {}", repeated(1.5));
    // The black hole (written last) first: 0.3 → 0.45, then repeated into [0, 0.25): 0.2
    // (povray: values up to 0.24 in a period of 1/6); written order would give 0.075.
    let ordered = gradient(
        "warp { repeat x * 0.25 } warp { black_hole <0, 0, 0>, 1  strength 0.5  falloff 0 }",
    );
    assert!(close(ordered(0.3), 0.2), "{}", ordered(0.3));
    // Transforms written before a warp apply after it (povray: period 0.5, values below 0.25).
    let scaled = gradient("scale 2  warp { repeat x * 0.5 }");
    assert!(close(scaled(0.75), 0.125) && close(scaled(1.25), 0.125), "{}", scaled(0.75));
    let after = gradient("warp { repeat x * 0.5 }  scale 2");
    assert!(close(after(0.75), 0.375), "{}", after(0.75));
    // A declared pigment, and an average, warped.
    let declared = pov(&format!(
        "#declare P = pigment {{ gradient x }}
         box {{ -100, 100  pigment {{ P warp {{ black_hole <0, 0, 0>, 1  falloff 1 }} }} {finish} }}"
    ));
    assert!(close(kd(&declared, Vec3::new(0.5, 0.0, 0.0)).x, 0.75));
    let averaged = pov(&format!(
        "box {{ -100, 100  pigment {{ average pigment_map {{ [1 gradient x] [1 gradient x] }}
           warp {{ black_hole <0, 0, 0>, 1  falloff 1 }} }} {finish} }}"
    ));
    assert!(close(kd(&averaged, Vec3::new(0.5, 0.0, 0.0)).x, 0.75));
    // A warp's items are its kind's, refused by name where they stand.
    for (warp, says) in [
        ("warp { repeat x  strength 2 }", ":1:52: error: `strength` belongs to a `black_hole`"),
        ("warp { black_hole 0, 1  offset y }", ":1:59: error: `offset` belongs to a `repeat`"),
        ("warp { black_hole 0, 1  repeat <1, -1, 0> }", ":1:66: error: repeat [1, -1, 0]"),
        ("warp { turbulence 0.5  repeat x }", ":1:58: error: `repeat` in a `turbulence` warp"),
    ] {
        let text = format!("box {{ -1, 1  pigment {{ gradient x {warp} }} }}");
        let error = parse_scene(Path::new("tests/inline.pov"), &text).unwrap_err().to_string();
        assert!(error.contains(says), "{warp}: {error}");
    }
}

/// POV-Ray's `bump_size` in a normal is its amount, as the number after the pattern's word is
/// (the last written wins), and renews a declared normal's amount.
#[test]
fn bump_size_is_a_normal_s_amount() {
    use std::sync::Arc;
    let bump = |text: &str| {
        let graph =
            parse_scene(Path::new("tests/inline.pov"), text).unwrap_or_else(|e| panic!("{e}"));
        let node =
            graph.objects[0].material.as_ref().and_then(|m| m.normal.clone()).expect("a normal");
        raydiance::texture::Bump::new(&node, &mut |path| {
            raydiance::texture::ImageMap::load(path).map(Arc::new)
        })
        .unwrap_or_else(|e| panic!("{e}"))
    };
    let plain = bump("sphere { 0, 1  normal { crackle 0.4  scale 0.2 } }");
    let sized = bump("sphere { 0, 1  normal { crackle 0.9  scale 0.2  bump_size 0.4 } }");
    let declared = bump(
        "#declare N = normal { crackle 0.9  scale 0.2 }
         sphere { 0, 1  normal { N  bump_size 0.4 } }",
    );
    let stronger = bump("sphere { 0, 1  normal { crackle 0.9  scale 0.2 } }");
    let mut tilted = false;
    for p in POINTS {
        let n = p.normalize();
        let expected = plain.perturbation(p, n);
        assert_eq!(sized.perturbation(p, n), expected, "at {p}");
        assert_eq!(declared.perturbation(p, n), expected, "at {p}");
        tilted |= (stronger.perturbation(p, n) - expected).length() > 1e-4;
    }
    assert!(tilted, "the amount changes the tilt");
}

/// A new pattern word over a declared normal changes only its pattern, as POV-Ray reads it:
/// `normal { N dents }` is N's transforms, warps and amount (unless given) on dents. `povray`
/// renders each pair below the same, pixel for pixel.
#[test]
fn a_new_pattern_word_keeps_a_declared_normal_s_transforms_warps_and_amount() {
    let normal = |text: &str| {
        let text = format!(
            "#declare N = normal {{ bumps 0.3  warp {{ repeat x * 0.3 }}  scale 0.2 }}
             #declare M = normal {{ gradient x  normal_map {{ [0 bumps 0.3] [1 dents 0.6] }}  \
               scale 0.5 }}
             sphere {{ 0, 1  normal {{ {text} }} }}"
        );
        let graph =
            parse_scene(Path::new("tests/inline.pov"), &text).unwrap_or_else(|e| panic!("{e}"));
        graph.objects[0].material.as_ref().and_then(|m| m.normal.clone()).expect("a normal")
    };
    let pairs = [
        ("N dents", "dents 0.3  warp { repeat x * 0.3 }  scale 0.2"),
        ("N dents 0.8", "dents 0.8  warp { repeat x * 0.3 }  scale 0.2"),
        ("N dents 0.8  scale 2", "dents 0.8  warp { repeat x * 0.3 }  scale 0.2  scale 2"),
        // Its map too: a normal_map's pattern takes the new word.
        ("M onion", "onion  normal_map { [0 bumps 0.3] [1 dents 0.6] }  scale 0.5"),
    ];
    for (declared, written) in pairs {
        assert_eq!(normal(declared), normal(written), "normal {{ {declared} }}");
    }
}

/// A declared pigment given a `pigment_map` (or a `color_map`) is its pattern through the new
/// map, its transforms and warps kept, as POV-Ray reads `pigment { P pigment_map { ... } }`
/// (wallstucco.pov's wall: its bricks' pattern in brick colours instead of the grey it was
/// declared with).
#[test]
fn a_declared_pigment_takes_a_new_map() {
    let finish = "finish { diffuse 1 ambient 0 }";
    let remapped = |pigment: &str| {
        let s = pov(&format!(
            "#declare P = pigment {{ gradient x pigment_map {{ [0 rgb 0] [1 rgb 1] }} scale 2 }}
             box {{ -100, 100  pigment {{ {pigment} }} {finish} }}"
        ));
        move |x: f32| kd(&s, Vec3::new(x, 0.0, 0.0))
    };
    let close = |a: Vec3, b: Vec3| (a - b).abs().max_element() < 1e-4;
    // At 0.5 the scaled gradient is 0.25.
    let red_to_blue = "pigment_map { [0 rgb <1, 0, 0>] [1 rgb <0, 0, 1>] }";
    let pigments = remapped(&format!("P {red_to_blue}"));
    assert!(close(pigments(0.5), Vec3::new(0.75, 0.0, 0.25)), "{}", pigments(0.5));
    let colours = remapped("P color_map { [0 rgb <0, 1, 0>] [1 rgb 0] }");
    assert!(close(colours(0.5), Vec3::new(0.0, 0.75, 0.0)), "{}", colours(0.5));
    // Warped before the new map: 0.75 is repeated to 0.25, then scaled to 0.125.
    let warped = remapped(&format!("P warp {{ repeat x * 0.5 }} {red_to_blue}"));
    assert!(close(warped(0.75), Vec3::new(0.875, 0.0, 0.125)), "{}", warped(0.75));
}

/// A normal's transforms written before a warp apply to the point after it, as a pigment's do
/// (`warps_move_points_as_povray_s_do`): `gradient x sine_wave scale 2 warp { repeat x*0.5 }`
/// repeats every 0.5 of the object's space, so the bumps tilt at 0.75 and 1.25 as at 0.25
/// (the pattern at 0.125 of its period, rising). Scaled before the repeat instead, 0.75 would
/// fall at 0.375 of the period and tilt the other way.
#[test]
fn a_normal_s_transforms_before_a_warp_apply_after_it() {
    use std::sync::Arc;
    let bump = |modifiers: &str| {
        let text = format!("sphere {{ 0, 1  normal {{ gradient x 0.5 sine_wave {modifiers} }} }}");
        let graph =
            parse_scene(Path::new("tests/inline.pov"), &text).unwrap_or_else(|e| panic!("{e}"));
        let node =
            graph.objects[0].material.as_ref().and_then(|m| m.normal.clone()).expect("a normal");
        raydiance::texture::Bump::new(&node, &mut |path| {
            raydiance::texture::ImageMap::load(path).map(Arc::new)
        })
        .unwrap_or_else(|e| panic!("{e}"))
    };
    let tilt = |bump: &raydiance::texture::Bump, x: f32| {
        bump.perturbation(Vec3::new(x, 0.3, 0.0), Vec3::NEG_Z)
    };
    let before = bump("scale 2  warp { repeat x * 0.5 }");
    let first = tilt(&before, 0.25);
    assert!(first.x.abs() > 1e-3, "the bumps tilt: {first}");
    for x in [0.75, 1.25] {
        assert!(
            (tilt(&before, x) - first).length() < 1e-4,
            "at {x}: {} not {first}",
            tilt(&before, x)
        );
    }
    // Written after the warp, the scale applies before it: 0.75 is at 0.375 of the period.
    let after = bump("warp { repeat x * 0.5 }  scale 2");
    assert!(tilt(&after, 0.75).x * first.x < 0.0, "{} against {first}", tilt(&after, 0.75));
}

/// POV-Ray's mapping warps (warp.cpp; `povray` renders these values): a point becomes its turns
/// about y (x), its height on the surface (y) and its distance from it (z).
#[test]
fn mapping_warps_wrap_a_pattern_around_their_surface() {
    let value = |pattern: &str, p: Vec3| {
        let s = pov(&format!(
            "box {{ -100, 100  pigment {{ {pattern} }} finish {{ diffuse 1 ambient 0 }} }}"
        ));
        kd(&s, p).x
    };
    let cases = [
        ("gradient x warp { cylindrical }", Vec3::new(0.0, 0.3, 1.0), 0.25),
        ("gradient x warp { cylindrical }", Vec3::new(-1.0, 0.0, 0.0), 0.5),
        ("gradient y warp { cylindrical }", Vec3::new(1.0, 0.3, 0.0), 0.3),
        ("gradient x warp { cylindrical dist_exp 1 }", Vec3::new(0.0, 0.0, 0.5), 0.125),
        ("gradient y warp { spherical }", Vec3::new(1.0, 0.0, 0.0), 0.5),
        ("gradient y warp { spherical }", Vec3::new(1.0, 1.0, 0.0), 0.75),
        ("gradient y warp { toroidal }", Vec3::new(1.5, 0.0, 0.0), 0.5),
        ("gradient y warp { toroidal }", Vec3::new(1.0, -0.5, 0.0), 0.25),
        ("gradient y warp { toroidal major_radius 2 }", Vec3::new(2.0, -0.5, 0.0), 0.25),
        ("gradient z warp { planar z, 0.3 }", Vec3::new(0.7, 0.2, 0.9), 0.3),
        // The comma is optional, as in POV-Ray (textures.inc's `planar z 0`).
        ("gradient z warp { planar z 0.3 }", Vec3::new(0.7, 0.2, 0.9), 0.3),
        ("gradient x warp { planar }", Vec3::new(0.7, 0.2, 0.9), 0.7),
    ];
    for (pattern, p, expected) in cases {
        let v = value(pattern, p);
        assert!((v - expected).abs() < 1e-4, "{pattern} at {p}: {v}, not {expected}");
    }
    let text = "box { -1, 1  pigment { gradient x warp { spherical major_radius 2 } } }";
    let error = parse_scene(Path::new("tests/inline.pov"), text).unwrap_err().to_string();
    assert!(error.contains(":1:52: error: `major_radius` belongs to a `toroidal`"), "{error}");
}

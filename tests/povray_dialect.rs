//! The `.pov` dialect (language section 15, `docs/povray.md`): POV-Ray's conventions where `.scn`
//! differs — planes, the camera, light colours, `image_width`/`image_height` — and `.scn` unchanged.

use std::path::Path;

use glam::{Vec2, Vec3};
use raydiance::camera::Camera;
use raydiance::graph::{Pattern, SceneGraph, ShapeNode};
use raydiance::lang::parse_scene;

fn pov(text: &str) -> SceneGraph {
    parse_scene(Path::new("tests/inline.pov"), text).unwrap_or_else(|e| panic!("{e}"))
}

fn pov_error(text: &str) -> String {
    parse_scene(Path::new("tests/inline.pov"), text).map(|_| ()).unwrap_err().to_string()
}

fn camera(graph: &SceneGraph) -> Camera {
    let s = &graph.settings;
    Camera::new(&graph.camera, s.width, s.height).unwrap().0
}

fn plane(graph: &SceneGraph) -> (Vec3, f32) {
    match &graph.objects[0].shape {
        ShapeNode::Plane { normal, offset } => (*normal, *offset),
        other => panic!("not a plane: {other:?}"),
    }
}

/// The ray's direction, normalised, through image position (u, v) from the top left.
fn towards(camera: &Camera, u: f32, v: f32) -> Vec3 {
    Vec3::from(camera.ray(u, v, Vec2::ZERO).dir).normalize()
}

fn close(a: impl Into<Vec3>, b: Vec3) -> bool {
    (a.into() - b).length() < 1e-5
}

#[test]
fn a_pov_plane_is_the_points_at_distance_d_along_its_unit_normal() {
    let (normal, offset) = plane(&pov("plane { <0, 2, 0>, -1 }"));
    // n̂ · p = -1 is the floor y = -1: n · p + offset = 0 with n̂ and offset 1.
    assert!(close(normal, Vec3::Y), "{normal}");
    assert_eq!(offset, 1.0);
    // The same text in `.scn` keeps the course's meaning: n · p + d = 0.
    let scn = parse_scene(
        Path::new("tests/inline.scn"),
        "camera { location <0, 0, -1> look_at 0 } plane { <0, 2, 0>, -1 }",
    )
    .unwrap();
    assert_eq!(plane(&scn), (Vec3::new(0.0, 2.0, 0.0), -1.0));
}

#[test]
fn without_a_camera_a_pov_scene_has_povray_s_default_camera() {
    let graph = pov("");
    assert_eq!((graph.settings.width, graph.settings.height), (320, 240));
    let camera = camera(&graph);
    assert_eq!(camera.origin, Vec3::ZERO);
    assert!(close(towards(&camera, 0.5, 0.5), Vec3::Z));
    // `right` 1.33 x, `up` y, `direction` z: the image's right edge is at x = 0.665.
    assert!(close(towards(&camera, 1.0, 0.5), Vec3::new(0.665, 0.0, 1.0).normalize()));
    assert!(close(towards(&camera, 0.5, 0.0), Vec3::new(0.0, 0.5, 1.0).normalize()));
    // A `.scn` scene still needs its camera.
    let scn = parse_scene(Path::new("tests/inline.scn"), "").unwrap_err().to_string();
    assert!(scn.contains("a scene needs one `camera"), "{scn}");
}

#[test]
fn look_at_turns_right_up_and_direction_keeping_their_lengths() {
    let graph =
        pov("camera { location <0, 0, -5> right x*image_width/image_height up y direction 2*z \
         look_at <5, 0, 0> }");
    let camera = camera(&graph);
    let view = Vec3::new(5.0, 0.0, 5.0).normalize();
    assert!(close(towards(&camera, 0.5, 0.5), view));
    assert!((camera.forward.length() - 2.0).abs() < 1e-5, "direction keeps its length");
    // Left-handed as POV-Ray: right is sky x view.
    let right = Vec3::Y.cross(view).normalize() * (320.0 / 240.0);
    assert!(close(towards(&camera, 1.0, 0.5), (2.0 * view + 0.5 * right).normalize()));
    // A right-handed camera (`right -x`) mirrors the image.
    let mirrored = camera_of_pov("camera { location <0, 0, -5> right -1.33*x look_at 0 }");
    assert!(close(towards(&mirrored, 1.0, 0.5), Vec3::new(-0.665, 0.0, 5.0 / 5.0).normalize()));
}

fn camera_of_pov(text: &str) -> Camera {
    camera(&pov(text))
}

#[test]
fn angle_sets_the_horizontal_field_of_view_from_right() {
    let camera = camera_of_pov("camera { location 0 right 2*x up y angle 90 look_at z }");
    // Half the width is 1 at distance 1: the right edge is 45 degrees off the axis.
    assert!(close(towards(&camera, 1.0, 0.5), Vec3::new(1.0, 0.0, 1.0).normalize()));
    assert!(close(towards(&camera, 0.5, 0.0), Vec3::new(0.0, 0.5, 1.0).normalize()));
}

#[test]
fn a_camera_normal_tilts_each_ray_by_its_pattern_at_the_image_position() {
    let view = "location 0 right 2*x up y angle 90 look_at z";
    let straight = camera_of_pov(&format!("camera {{ {view} }}"));
    // Through (u, v) = (0.75, 0.25) the pattern is read at (0.25, 0.25, 0), where `gradient y`
    // rises with slope 1 along y and `gradient x` along x: amount 0.5 tilts by 2/15 of those
    // gradients (POV-Ray's strength, docs/language.md).
    let d = towards(&straight, 0.75, 0.25);
    let k = 0.5 * 2.0 / 15.0;
    for (pattern, gradient) in [("gradient y", Vec3::Y * k), ("gradient x", Vec3::X * k)] {
        let bent = camera_of_pov(&format!("camera {{ {view} normal {{ {pattern} 0.5 }} }}"));
        // As a surface normal is perturbed: minus the gradient's part across the direction.
        let expected = (d - (gradient - d * gradient.dot(d))).normalize();
        let got = towards(&bent, 0.75, 0.25);
        assert!((got - expected).length() < 1e-3, "{pattern}: {got} against {expected}");
    }
}

#[test]
fn sky_tilts_the_camera() {
    let camera = camera_of_pov("camera { location 0 sky x look_at z }");
    // With sky x, up is x and right is x cross z = -y (the image turned a quarter).
    assert!(close(towards(&camera, 0.5, 0.0), Vec3::new(0.5, 0.0, 1.0).normalize()));
    assert!(close(towards(&camera, 1.0, 0.5), Vec3::new(0.0, -0.665, 1.0).normalize()));
}

#[test]
fn an_orthographic_camera_sends_parallel_rays_from_its_image_plane() {
    let camera =
        camera_of_pov("camera { orthographic location <0, 0, -5> right 4*x up 3*y look_at 0 }");
    let (a, b) = (camera.ray(0.0, 0.0, Vec2::ZERO), camera.ray(1.0, 1.0, Vec2::ZERO));
    assert!(close(a.dir, Vec3::Z) && close(b.dir, Vec3::Z));
    assert!(close(a.origin, Vec3::new(-2.0, 1.5, -5.0)), "{}", a.origin);
    assert!(close(b.origin, Vec3::new(2.0, -1.5, -5.0)), "{}", b.origin);
}

#[test]
fn a_pov_light_colour_is_power_matched_at_the_distance_to_look_at() {
    let graph = pov("light_source { <0, 4, -3> color rgb <1, 0.5, 0> }\n\
         camera { location <0, 1, -4> look_at 0 }");
    let light = &graph.lights[0];
    // d² = 16 + 9: π·C·d² gives a white Lambertian surface there the radiance C·cos θ / π · π.
    let expected = std::f32::consts::PI * 25.0 * Vec3::new(1.0, 0.5, 0.0);
    assert!(close(light.power / 100.0, expected / 100.0), "{}", light.power);
}

#[test]
fn image_width_and_height_are_the_image_s_size() {
    let graph = pov("#declare W = image_width; #declare H = image_height; \
                     sphere { <W, H, 0>, 1 }");
    match &graph.objects[0].shape {
        ShapeNode::Sphere { center, .. } => assert_eq!(*center, Vec3::new(320.0, 240.0, 0.0)),
        other => panic!("{other:?}"),
    }
}

#[test]
fn pov_words_are_refused_in_scn_and_lab_words_in_pov() {
    let scn =
        parse_scene(Path::new("tests/inline.scn"), "camera { orthographic location 0 look_at z }")
            .unwrap_err()
            .to_string();
    assert!(scn.contains("`orthographic`") && scn.contains(":1:10"), "{scn}");
    let lab = pov_error("camera { origin 0 left x up y forward z }");
    assert!(
        lab.contains("`origin` is not a POV-Ray camera word") && lab.contains(":1:10"),
        "{lab}"
    );
    let zero = pov_error("camera { location 0 look_at 0 }");
    assert!(zero.contains("`look_at` is the camera's `location`"), "{zero}");
}

#[test]
fn a_light_s_colour_may_follow_its_position_without_color() {
    let graph = pov("light_source { <0, 0, -1>, rgb <1, 0, 0> }  light_source { <0, 0, -1> 0.5 }");
    // The default camera looks at <0, 0, 1>: d = 2.
    let pi4 = 4.0 * std::f32::consts::PI;
    assert!(close(graph.lights[0].power / pi4, Vec3::X), "{}", graph.lights[0].power);
    assert!(close(graph.lights[1].power / pi4, Vec3::splat(0.5)));
    let scn = parse_scene(
        Path::new("tests/inline.scn"),
        "camera { location 0 look_at z } light_source { <0, 1, 0>, rgb 1 }",
    )
    .unwrap_err()
    .to_string();
    assert!(scn.contains("`color`: a POV-Ray light's colour"), "{scn}");
}

#[test]
fn background_is_only_seen_and_focal_blur_is_warned_about() {
    let graph = pov("background { color rgb <0.1, 0.2, 0.3> }\n\
         camera { location <0, 0, -5> look_at 0 aperture 0.4 focal_point 0 blur_samples 20 }");
    assert!(close(graph.backdrop, Vec3::new(0.1, 0.2, 0.3)));
    assert_eq!(graph.settings.background, Vec3::ZERO, "it does not light");
    assert_eq!((graph.settings.width, graph.settings.height), (320, 240));
    assert!(!graph.warnings.iter().any(|w| w.contains("`background`")), "as POV-Ray's");
    assert!(
        graph.warnings.iter().any(|w| w.contains(":2:40: warning: POV-Ray's focal blur")),
        "{:?}",
        graph.warnings
    );
}

#[test]
fn colors_inc_is_built_in_for_pov_scenes_and_a_file_on_the_include_path_comes_first() {
    let graph = pov("#include \"colors.inc\"\n\
         sphere { <0, 0, 0>, 1 pigment { SkyBlue } finish { diffuse 1 } }");
    let m = graph.objects[0].material.as_ref().unwrap();
    assert!(matches!(m.diffuse.pattern, raydiance::graph::Pattern::Solid(c)
        if close(c, Vec3::new(0.196078, 0.6, 0.8))));
    // `.scn` has no built-in library.
    let scn = parse_scene(
        Path::new("tests/inline.scn"),
        "#include \"colors.inc\" camera { location 0 look_at z }",
    )
    .unwrap_err()
    .to_string();
    assert!(scn.contains("cannot read"), "{scn}");
    // RAYDIANCE_INCLUDE_PATH is searched before the library.
    let dir = std::env::temp_dir().join(format!("raydiance-include-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("inc")).unwrap();
    std::fs::write(dir.join("inc/colors.inc"), "#declare SkyBlue = rgb <1, 0, 0>;").unwrap();
    std::fs::write(
        dir.join("scene.pov"),
        "#include \"colors.inc\"\nbackground { SkyBlue }\nsphere { <0, 0, 5>, 1 }",
    )
    .unwrap();
    let run = |path: Option<&Path>| {
        let mut command = std::process::Command::new(env!("CARGO_BIN_EXE_raydiance"));
        command.args(["render", "scene.pov", "-o", "out.ppm", "--width", "8", "--height", "6"]);
        command.args(["--samples", "1"]).current_dir(&dir);
        match path {
            Some(p) => command.env("RAYDIANCE_INCLUDE_PATH", p),
            None => command.env_remove("RAYDIANCE_INCLUDE_PATH"),
        };
        let output = command.output().unwrap();
        assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
        // A plain PPM: "P3", width, height, maximum, then the pixels (lines with `#` are notes).
        let ppm = std::fs::read_to_string(dir.join("out.ppm")).unwrap();
        let numbers: Vec<f64> = ppm
            .lines()
            .filter(|l| !l.starts_with('#'))
            .flat_map(str::split_whitespace)
            .skip(4)
            .map(|n| n.parse().unwrap())
            .collect();
        // The top-left pixel is the background: red from the include path, else sky blue.
        (numbers[0], numbers[2])
    };
    let (red, blue) = run(Some(&dir.join("inc")));
    assert!(red > 0.0 && blue == 0.0, "the include path's file: {red} {blue}");
    let (red, blue) = run(None);
    assert!(red < blue, "the built-in SkyBlue: {red} {blue}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn povray_s_lenient_forms_are_read() {
    let graph = pov("# debug \"\"\n\
         #declare V = version;\n\
         #if (V >= 3.7) sphere { <sqr(2), 0, 0>, 1 } #end\n\
         disc { <0, 1, 0>, y, 2 }\n\
         object { sphere { 0, 1 } translate <0, 0, 3> }");
    match &graph.objects[0].shape {
        ShapeNode::Sphere { center, .. } => assert_eq!(*center, Vec3::new(4.0, 0.0, 0.0)),
        other => panic!("{other:?}"),
    }
    assert!(matches!(graph.objects[1].shape, ShapeNode::Disk { radius: 2.0, .. }));
    // The inline shape takes the outer items as its own.
    let inline = &graph.objects[2];
    assert!(matches!(inline.shape, ShapeNode::Sphere { .. }) && inline.transforms.len() == 1);
}

#[test]
fn a_fading_light_is_matched_where_the_camera_looks_and_modifiers_are_read_or_warned() {
    let graph = pov("light_source { <0, 0, 5> rgb 1 fade_distance 2 fade_power 2 shadowless }\n\
         camera { location <0, 0, -5> look_at 0 }\n\
         sphere { 0, 1 hollow on no_shadow double_illuminate bounded_by { sphere { 0, 2 } } }");
    // d = 5: POV-Ray's light there is 2 / (1 + (5/2)²) of its colour.
    let expected = std::f32::consts::PI * 25.0 * 2.0 / (1.0 + 6.25);
    assert!((graph.lights[0].power.x - expected).abs() < 1e-4, "{}", graph.lights[0].power);
    let warned = |what: &str| graph.warnings.iter().any(|w| w.contains(what));
    assert!(graph.lights[0].shadowless && !warned("shadowless"), "{:?}", graph.warnings);
    assert!(warned(":3:25: warning: `no_shadow` is not honoured"), "{:?}", graph.warnings);
    assert!(!warned("hollow") && !warned("double_illuminate"));
    let scn = parse_scene(
        Path::new("tests/inline.scn"),
        "camera { location 0 look_at z } sphere { 0, 1 hollow }",
    )
    .unwrap_err()
    .to_string();
    assert!(scn.contains("`hollow`: this POV-Ray object modifier"), "{scn}");
}

#[test]
fn a_declared_camera_is_used_by_name_and_may_be_changed() {
    let camera = camera_of_pov(
        "#declare C = camera { location <0, 0, -5> right 2*x angle 90 }\n\
         camera { C look_at <0, 0, 0> }",
    );
    assert_eq!(camera.origin, Vec3::new(0.0, 0.0, -5.0));
    assert!(close(towards(&camera, 1.0, 0.5), Vec3::new(1.0, 0.0, 1.0).normalize()));
    let scn = parse_scene(Path::new("tests/inline.scn"), "#declare C = 1 camera { C }")
        .unwrap_err()
        .to_string();
    assert!(scn.contains("cannot stand in a camera"), "{scn}");
}

#[test]
fn sky_sphere_is_read_with_its_pigment_transforms_and_emission() {
    let graph = pov("sky_sphere { pigment { gradient y color_map { [0 rgb 0] [1 rgb 1] } } \
         rotate <0, 0, 30> scale 2 emission rgb <1, 0.5, 0.25> }");
    let sky = graph.sky.expect("a sky");
    assert!(matches!(
        &sky.pigment.pattern,
        raydiance::graph::Pattern::Field { shape, .. }
            if matches!(shape.field, raydiance::graph::Field::Gradient(_))
    ));
    assert_eq!(sky.transforms.len(), 2);
    assert!(close(sky.emission, Vec3::new(1.0, 0.5, 0.25)));

    let second = pov_error("sky_sphere { pigment { rgb 1 } }\nsky_sphere { pigment { rgb 1 } }");
    assert!(second.contains(":2:1:") && second.contains("a second sky_sphere"), "{second}");
    let misplaced = pov_error("sky_sphere { finish { diffuse 1 } }");
    assert!(misplaced.contains(":1:14:") && misplaced.contains("in a sky_sphere"), "{misplaced}");
    // Layers: a see-through top shows a quarter of the white under it; an opaque one covers it.
    let layered = pov("sky_sphere { pigment { rgb 1 } pigment { rgbt <0, 0, 1, 0.25> } }");
    let pigment = &layered.sky.expect("a sky").pigment.pattern;
    assert!(matches!(pigment, Pattern::Solid(c) if close(*c, Vec3::new(0.25, 0.25, 1.0))));
    let covered = pov("sky_sphere { pigment { rgb 1 } pigment { rgb 0.5 } }");
    let pigment = &covered.sky.expect("a sky").pigment.pattern;
    assert!(matches!(pigment, Pattern::Solid(c) if close(*c, Vec3::splat(0.5))));

    let scn = parse_scene(Path::new("tests/inline.scn"), "sky_sphere { pigment { rgb 1 } }")
        .map(|_| ())
        .unwrap_err()
        .to_string();
    assert!(scn.contains(":1:1:") && scn.contains("settings { background"), "{scn}");
}

/// A declared sky (`#declare S = sky_sphere { ... }`) stands by name in the scene's, whose items
/// after the name change it, as POV-Ray's standard skies are used (`sky_sphere { S_Cloud4 }`).
#[test]
fn a_declared_sky_sphere_is_the_scene_s_sky_by_name() {
    let graph = pov("#declare S = sky_sphere { pigment { gradient y } rotate 30 * z \
         emission rgb 2 }\nsky_sphere { S scale 2 }");
    let sky = graph.sky.expect("a sky");
    let raydiance::graph::Pattern::Field { shape, .. } = &sky.pigment.pattern else {
        panic!("a pattern: {:?}", sky.pigment.pattern)
    };
    assert!(matches!(shape.field, raydiance::graph::Field::Gradient(_)), "{shape:?}");
    assert_eq!(sky.transforms.len(), 2, "the declared rotation, then the scale");
    assert!(close(sky.emission, Vec3::splat(2.0)));
    assert!(format!("{:?}", sky.span).contains(":2:1"), "the scene's sky_sphere: {:?}", sky.span);

    let declared_only = pov("#declare S = sky_sphere { pigment { rgb 1 } }");
    assert!(declared_only.sky.is_none(), "declaring a sky does not set it");
    let error = pov_error("#declare P = pigment { rgb 1 }\nsky_sphere { P }");
    assert!(error.contains(":2:14:") && error.contains("not a pigment"), "{error}");
}

/// A syntax error in a `.pov` scene names POV-Ray's word without `.scn`'s advice for it ("the sky
/// is `settings { background ... }`" misleads where `sky_sphere` is read).
#[test]
fn syntax_errors_in_pov_scenes_do_not_give_scn_advice() {
    let error = pov_error("sphere { 0, 1 } sky_sphere");
    assert!(error.contains("`sky_sphere`") && !error.contains("settings {"), "{error}");
    let error = pov_error("#if (1) background { rgb 1 } #end }");
    assert!(!error.contains("settings {"), "{error}");
}

#[test]
fn wide_projections_are_read_with_their_angles_and_a_fisheye_leaves_its_corners_dark() {
    // A fisheye of 180° looks along the camera's right at the image's right edge.
    let fisheye = camera_of_pov("camera { fisheye angle 180 right x up y location 0 look_at z }");
    assert!(close(towards(&fisheye, 1.0, 0.5), Vec3::X), "{}", towards(&fisheye, 1.0, 0.5));
    assert!(fisheye.sees(0.5, 0.5) && !fisheye.sees(0.02, 0.02), "the corners are dark");
    // A spherical camera's two angles: 360 across, 90 down (the top edge 45° up).
    let sphere = camera_of_pov("camera { spherical angle 360, 90 location 0 look_at z }");
    assert!(close(towards(&sphere, 0.75, 0.5), Vec3::X));
    assert!(close(towards(&sphere, 0.5, 0.0), Vec3::new(0.0, 1.0, 1.0).normalize()));
    // `cylinder 3` moves the ray's origin up its axis.
    let cylinder = camera_of_pov("camera { cylinder 3 up 4*y location 0 look_at z }");
    assert!(close(cylinder.ray(0.5, 0.0, Vec2::ZERO).origin, Vec3::new(0.0, 2.0, 0.0)));
    let kind = pov_error("camera { cylinder 5 location 0 look_at z }");
    assert!(kind.contains("1, 2, 3 or 4, not 5") && kind.contains(":1:19"), "{kind}");
    let two = pov_error("camera { fisheye angle 90, 45 location 0 look_at z }");
    assert!(two.contains("`angle`") && two.contains(":1:18"), "{two}");
    let scn = parse_scene(Path::new("tests/inline.scn"), "camera { fisheye location 0 }")
        .unwrap_err()
        .to_string();
    assert!(scn.contains("`fisheye`") && scn.contains(":1:10"), "{scn}");
}

#[test]
fn a_zero_scale_is_changed_to_one_and_a_2_vector_translation_gets_z_0() {
    let graph = pov("sphere { 0, 1 scale <0, 2, 1> translate <1, 2> }");
    use raydiance::graph::Transform;
    let expected = [
        Transform::Scale(Vec3::new(1.0, 2.0, 1.0)),
        Transform::Translate(Vec3::new(1.0, 2.0, 0.0)),
    ];
    assert_eq!(graph.objects[0].transforms, expected);
    let warning = graph.warnings.iter().find(|w| w.contains("zero component"));
    assert!(warning.is_some_and(|w| w.contains(":1:21")), "{:?}", graph.warnings);
    let scn = parse_scene(Path::new("tests/inline.scn"), "sphere { 0, 1 scale <0, 2, 1> }")
        .unwrap_err()
        .to_string();
    assert!(scn.contains("zero component"), "{scn}");
}

#[test]
fn a_negative_surface_colour_is_clamped_with_a_warning() {
    let graph = pov("sphere { 0, 1 pigment { rgb <-1, 0.5, 0.5> * 2 } }");
    let material = graph.objects[0].material.as_ref().expect("the default texture's material");
    match &material.diffuse.pattern {
        raydiance::graph::Pattern::Solid(c) => {
            assert!(c.x == 0.0 && c.y > 0.5, "clamped red, kept green: {c}")
        }
        other => panic!("{other:?}"),
    }
    let warning = graph.warnings.iter().find(|w| w.contains("negative component"));
    assert!(warning.is_some_and(|w| w.contains(":1:25")), "{:?}", graph.warnings);
    // A negative light is left out (povray_lights: a_negative_light_is_left_out_...).
}

#[test]
fn height_fields_and_sphere_sweeps_refuse_what_they_cannot_be_where_it_stands() {
    let cases = [
        // An image type raydiance does not decode, named at its word.
        ("height_field { gif \"hills.gif\" }", "inline.pov:1:16", "`gif`"),
        // No type word and an extension that says none.
        ("height_field { \"hills.bmp\" }", "inline.pov:1:16", "`hills.bmp`"),
        ("height_field { png \"no such hills.png\" }", "inline.pov:1:20", "cannot find"),
        ("height_field { function 1, 5 { x } }", "inline.pov:1:25", "1 x 5"),
        ("height_field { function 8, 8 { x } water_level 2 }", "inline.pov:1:48", "water_level"),
        ("height_field { function 8, 8 { -1 } water_level 0.5 }", "inline.pov:1:1", "below"),
        (
            "sphere_sweep { linear_spline 3, <0, 0, 0>, 1, <1, 0, 0>, 1 }",
            "inline.pov:1:1",
            "3 spheres",
        ),
        ("sphere_sweep { b_spline 3, 0, 1, x, 1, y, 1 }", "inline.pov:1:25", "at least 4"),
        ("sphere_sweep { linear_spline 2, 0, -1, x, 1 }", "inline.pov:1:36", "0 or more"),
    ];
    for (scene, at, says) in cases {
        let error = pov_error(scene);
        assert!(error.contains(at) && error.contains(says), "{scene}:\n{error}");
    }
}

/// An ovus whose top radius is twice its bottom one or more is POV-Ray's top sphere alone, with
/// a warning as POV-Ray gives; a lemon's inner radius too small for its rims is raised to the
/// least that reaches them, with a warning; bad radii and a lemon without length are located
/// errors.
#[test]
fn ovus_and_lemons_are_read_and_checked_as_povray_reads_them() {
    let graph = pov("ovus { 1, 0.65 }\novus { 0.5, 1 }");
    assert!(matches!(graph.objects[0].shape, ShapeNode::Ovus { bottom: 1.0, top: 0.65 }));
    match graph.objects[1].shape {
        ShapeNode::Sphere { center, radius } => {
            assert!(close(center, Vec3::new(0.0, 0.5, 0.0)) && radius == 1.0)
        }
        ref other => panic!("{other:?}"),
    }
    assert!(graph.warnings.iter().any(|w| w.contains(":2:13: warning: the ovus' top radius")));
    let graph = pov("lemon { <0, 0, 0>, 0.5, <0, 2, 0>, 0.3, 0.1 open }");
    match graph.objects[0].shape {
        ShapeNode::Lemon { ends, radii, inner_radius, open } => {
            assert!(close(ends[1], Vec3::new(0.0, 2.0, 0.0)) && radii == [0.5, 0.3] && open);
            // sqrt(((b - a)^2 + 1) ((a + b)^2 + 1)) / 2 for the axis of length 1, times 2.
            let least = ((0.01f32 + 1.0) * (0.16 + 1.0)).sqrt();
            assert!((inner_radius - least).abs() < 1e-5, "{inner_radius} {least}");
        }
        ref other => panic!("{other:?}"),
    }
    assert!(graph.warnings.iter().any(|w| w.contains("inner radius 0.1 is too small")));
    for (text, expected) in [
        ("ovus { 0, 1 }", "1:8: error: the ovus' bottom radius 0 is zero"),
        ("lemon { <1, 2, 3>, 0.5, <1, 2, 3>, 0.3, 1 }", "the lemon's base and cap are the same"),
        ("lemon { 0, -0.5, y, 0.3, 1 }", "the lemon's base radius"),
    ] {
        let error = pov_error(text);
        assert!(error.contains(expected), "{text}: {error}");
    }
}

/// POV-Ray's disc takes a hole radius below its radius; `.scn`'s disk takes none.
#[test]
fn a_disc_s_hole_radius_is_read_and_checked() {
    let graph = pov("disc { <0, 1, 0>, y, 2, 0.5 }\ndisc { 0, y, 1 }");
    assert!(matches!(graph.objects[0].shape, ShapeNode::Disk { radius: 2.0, hole: 0.5, .. }));
    assert!(matches!(graph.objects[1].shape, ShapeNode::Disk { hole: 0.0, .. }));
    let error = pov_error("disc { 0, y, 1, 1 }");
    assert!(
        error.contains("1:17: error: the disc's hole radius 1 is not below its radius"),
        "{error}"
    );
    let error = pov_error("disc { 0, y, 1, -0.5 }");
    assert!(error.contains("hole radius -0.5 is negative"), "{error}");
    let scn = parse_scene(Path::new("tests/inline.scn"), "disk { 0, y, 1, 0.5 }");
    let error = scn.map(|_| ()).unwrap_err().to_string();
    assert!(error.contains("a disk has no hole radius"), "{error}");
}

/// A parametric surface is open: CSG refuses it by name, where it stands.
#[test]
fn a_parametric_surface_is_not_a_csg_operand() {
    let graph = pov("intersection {\n  parametric { function { u } function { v } function { 0 } \
         <0, 0>, <1, 1> }\n  sphere { 0, 1 }\n}");
    let error = raydiance::scene::build(&graph).map(|_| ()).unwrap_err().to_string();
    assert!(
        error.contains("inline.pov:2:3") && error.contains("a parametric surface is not a solid"),
        "{error}"
    );
}

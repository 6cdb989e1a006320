//! POV-Ray 3.7 (Debian's `povray`, which CI installs) as the oracle for the `.pov` dialect's
//! geometry: a scene in flat emissive colours rendered by both agrees pixel for pixel away from
//! edges — the camera (`right`, `up`, `sky`, `angle`, `look_at`, transforms; orthographic and
//! the wide projections),
//! planes with offsets, `#default`, `inverse` and `clipped_by`; the algebraic surfaces,
//! blobs, prisms and superellipsoids; boxes flat in one coordinate; shapes_old.inc's infinite
//! quadrics cut by CSG; bicubic patches; meshes of triangles and smooth triangles,
//! `smooth_triangle` and `mesh2`; julia fractals; lathes, sors and polygons; height fields, alone
//! and in CSG; sphere sweeps; points and triangles made by directives; shapes2.inc's `Pyramid2`;
//! ovus, and lemons (which POV-Ray 3.7.0 lacks) against the CSG of a quartic that is the same
//! solid; parametric surfaces; where an object's texture lies (only the transforms written after
//! it move it), what a new pattern word over a declared pigment keeps, and the spirals.

use crate::common;

use glam::Vec3;
use raydiance::tonemap::srgb_transfer;
use std::path::Path;
use std::process::Command;

const SCENE: &str = r#"
#default { finish { emission 1 ambient 0 diffuse 0 } }
background { rgb 0 }
sphere { <0, 0, 0>, 1 pigment { rgb <1, 0, 0> } }
sphere { <2, 0, 1>, 0.7 pigment { rgb <0, 1, 0> } }
box { <-2, -1.5, -1>, <-1, -0.5, 0> pigment { rgb <0, 0, 1> } }
plane { y, -2 pigment { rgb <1, 1, 0> } }
"#;

const CAMERAS: [&str; 5] = [
    "camera { location <1, 2, -6> right x*image_width/image_height up y sky <0.3, 1, 0> \
     angle 50 look_at <0.5, 0.3, 0> }",
    "camera { location <-3, 1, -5> right -1.33*x direction 1.5*z look_at <0, 0, 0> }",
    "camera { orthographic location <0, 3, -6> right 8*x up 6*y look_at <0, 0, 0> }",
    // Transforms move the camera POV-Ray has built, wherever they stand.
    "camera { location <0, 0, -6> rotate <0, 30, 0> look_at <1, 0, 0> translate <0, 1, 0> \
     right x*image_width/image_height }",
    // Looking along `sky`: the camera keeps its `right`.
    "camera { location <0, 8, 0> right x*image_width/image_height look_at <0, 0, 0> }",
];

/// The size of both renders and raydiance's samples a pixel.
#[derive(Clone, Copy)]
struct Render {
    width: usize,
    height: usize,
    samples: usize,
}

/// What every comparison renders unless it says otherwise.
const USUAL: Render = Render { width: 64, height: 48, samples: 16 };

/// The pixels of a binary (P6) or plain (P3) PPM as numbers in [0, 1].
fn ppm(path: &Path) -> Vec<f32> {
    common::read_ppm(path).samples
}

/// Each pixel's colour as which channels are lit.
fn classes(pixels: &[f32]) -> Vec<[bool; 3]> {
    pixels.chunks(3).map(|p| [p[0] > 0.5, p[1] > 0.5, p[2] > 0.5]).collect()
}

/// Surfaces that only `inverse` and `clipped_by` make, each facing the camera (an emitter here
/// glows on its outer side only): a box bitten by an inverted sphere, a sphere clipped to its
/// upper half, a floor clipped to a rectangle.
const SHAPED: &str = r#"
camera { location <0, 2.5, -4.5> right x*image_width/image_height look_at <0, -0.2, 0> }
#default { finish { emission 1 ambient 0 diffuse 0 } }
background { rgb 0 }
intersection {
  box { <0.3, -1, -1>, <2.3, 0.8, 1> }
  sphere { <1.3, 0.8, -1>, 0.9 inverse }
  pigment { rgb <0, 1, 0> }
}
sphere { <-1.5, 0, 0>, 1 pigment { rgb <1, 0, 0> } clipped_by { plane { -y, 0 } } }
plane { y, -1 pigment { rgb <1, 1, 0> } clipped_by { box { <-3, -2, -1.5>, <3, 0, 3> } } }
"#;

#[test]
fn flat_emissive_scenes_match_povray_away_from_edges() {
    let test = "flat_emissive_scenes_match_povray_away_from_edges";
    if !common::outside_tool("povray", "povray", test) {
        return;
    }
    for (n, camera) in CAMERAS.iter().enumerate() {
        agree_with_povray(&format!("{camera}\n{SCENE}"), &format!("camera {n}"));
    }
}

#[test]
fn inverse_and_clipped_by_match_povray_away_from_edges() {
    let test = "inverse_and_clipped_by_match_povray_away_from_edges";
    if common::outside_tool("povray", "povray", test) {
        agree_with_povray(SHAPED, "inverse and clipped_by");
    }
}

/// POV-Ray's wide projections, each looking at the scene from above its floor.
const WIDE_CAMERAS: [&str; 11] = [
    "fisheye angle 180",
    // POV-Ray's default angle.
    "fisheye",
    "ultra_wide_angle angle 160",
    "omnimax",
    "panoramic",
    "cylinder 1 angle 150",
    "cylinder 2 angle 120",
    "cylinder 3 angle 200 up 4*y",
    "cylinder 4 angle 100",
    "spherical angle 270, 120",
    "spherical",
];

#[test]
fn wide_projections_match_povray_away_from_edges() {
    let test = "wide_projections_match_povray_away_from_edges";
    if !common::outside_tool("povray", "povray", test) {
        return;
    }
    for projection in WIDE_CAMERAS {
        let camera = format!(
            "camera {{ {projection} location <1, 1, -5> right x*image_width/image_height \
             look_at <0, 0, 0> }}"
        );
        agree_with_povray(&format!("{camera}\n{SCENE}"), projection);
    }
}

/// POV-Ray's algebraic surfaces, each seen from outside: a `quartic` torus tilted towards the
/// camera, a `quadric` ellipsoid with a cross term, a `cubic` cut by a sphere, and a `poly` of
/// order 4 (a rounded cube) turned and mirrored.
const ALGEBRAIC: &str = r#"
camera { location <0, 2, -6> right x*image_width/image_height angle 38 look_at <0, 0, 0> }
#default { finish { emission 1 ambient 0 diffuse 0 } }
background { rgb 0 }
quartic {
  < 1, 0, 0, 0, 2, 0, 0, 2, 0, -104, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
    1, 0, 0, 2, 0, 56, 0, 0, 0, 0, 1, 0, -104, 0, 784 >
  sturm
  scale 0.1 rotate -60*x translate <-1.4, 0.6, 0>
  pigment { rgb <1, 0, 0> }
}
quadric { <1, 2, 1.5>, <0.8, 0, 0>, <0, 0, 0>, -0.8 translate <1.5, 0.7, 0> pigment { rgb <0, 1, 0> } }
intersection {
  cubic { <0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0.45, 0, 1, 0, 0, 0, 0, 1, 0, -1> sturm }
  sphere { 0, 1.3 }
  scale 0.8 translate <-1.2, -1.1, 0>
  pigment { rgb <0, 0, 1> }
}
poly { 4, < 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
            1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, -0.4 >
  scale <-1, 1, 1> rotate <20, 35, 0> translate <1.3, -1.1, 0>
  pigment { rgb <1, 1, 0> }
}
"#;

#[test]
fn algebraic_surfaces_match_povray_away_from_edges() {
    let test = "algebraic_surfaces_match_povray_away_from_edges";
    if common::outside_tool("povray", "povray", test) {
        agree_with_povray(ALGEBRAIC, "quartic, quadric, cubic and poly");
    }
}

/// POV-Ray's blobs: spheres with a negative one biting in, capsules (one turned in the
/// blob), the old `component` form with a stretched sphere, the blob mirrored.
const BLOBS: &str = r#"
camera { location <0, 2, -6> right x*image_width/image_height angle 38 look_at <0, 0, 0> }
#default { finish { emission 1 ambient 0 diffuse 0 } }
background { rgb 0 }
blob {
  threshold 0.5
  sphere { <-0.5, 0, 0>, 1.5, 1 }
  sphere { <0.5, 0.2, 0>, 1.4, strength 1.2 }
  sphere { <0.2, 0.5, -0.6>, 0.8, -3 }
  scale 0.8 translate <-1.5, 0.8, 0>
  pigment { rgb <1, 0, 0> }
}
blob {
  threshold 0.4
  cylinder { <-1, 0, 0>, <1, 0, 0>, 0.5, 1 }
  cylinder { <0, -1, 0>, <0, 1, 0>, 0.45, 1 rotate 30*z }
  rotate <-30, 20, 0> translate <1.4, 0.6, 0>
  pigment { rgb <0, 1, 0> }
}
blob {
  threshold 0.6
  component 1.0, 1.4, <0.75, 0, 0>
  component 1.0, 1.4, <-0.375, 0.64952, 0>
  component 1.0, 1.4, <-0.375, -0.64952, 0>
  sphere { 0, 0.8, 1 scale <1, 1, 2> }
  scale <-0.7, 0.7, 0.7> rotate 40*x translate <0, -1.2, 0>
  pigment { rgb <0, 0, 1> }
}
"#;

#[test]
fn blobs_match_povray_away_from_edges() {
    let test = "blobs_match_povray_away_from_edges";
    if common::outside_tool("povray", "povray", test) {
        agree_with_povray(BLOBS, "blobs");
    }
}

/// POV-Ray's prisms, one of each spline: a square with a square hole, a conic sweep turned
/// upside down, a mirrored cubic spline, a turned Bézier.
const PRISMS: &str = r#"
camera { location <0, 4, -7> right x*image_width/image_height angle 38 look_at <0, 0, 0> }
#default { finish { emission 1 ambient 0 diffuse 0 } }
background { rgb 0 }
prism {
  linear_sweep linear_spline 0, 0.2, 10,
  <-1, -1>, <1, -1>, <1, 1>, <-1, 1>, <-1, -1>,
  <-0.6, -0.6>, <0.6, -0.6>, <0.6, 0.6>, <-0.6, 0.6>, <-0.6, -0.6>
  rotate 20*y translate <-1.8, 0.8, 0>
  pigment { rgb <1, 0, 0> }
}
prism {
  conic_sweep quadratic_spline 0.3, 1, 7,
  <-1, 0>, <0, -1>, <1, 0>, <0, 1>, <-1, 0>, <0, -1>, <1, 0>
  rotate 180*x translate <1.8, 1.8, 0>
  pigment { rgb <0, 1, 0> }
}
prism {
  cubic_spline 0, 0.6, 8,
  <0, 1>, <-1, 0>, <0, -1>, <1, 0>, <0, 1>, <-1, 0>, <0, -1>, <1, 0>
  scale <-1, 1, 1> translate <-1.5, -1.5, 0>
  pigment { rgb <0, 0, 1> }
}
prism {
  bezier_spline -0.3, 0.3, 8,
  <-1, 0>, <-1, 1.2>, <1, 1.2>, <1, 0>, <1, 0>, <0.5, -1>, <-0.5, -1>, <-1, 0>
  rotate <-30, 30, 0> translate <1.5, -1.2, 0>
  pigment { rgb <1, 1, 0> }
}
"#;

#[test]
fn prisms_match_povray_away_from_edges() {
    let test = "prisms_match_povray_away_from_edges";
    if common::outside_tool("povray", "povray", test) {
        agree_with_povray(PRISMS, "prisms");
    }
}

/// POV-Ray's superellipsoids: a rounded box, a stretched cushion, a pinched star (exponents
/// above 2, the star given as one number, which POV-Ray promotes to <e, e>), a mirrored one.
const SUPERELLIPSOIDS: &str = r#"
camera { location <0, 3, -7> right x*image_width/image_height angle 38 look_at <0, 0, 0> }
#default { finish { emission 1 ambient 0 diffuse 0 } }
background { rgb 0 }
superellipsoid { <0.25, 0.25> rotate <20, 30, 0> scale 0.8 translate <-1.6, 0.9, 0> pigment { rgb <1, 0, 0> } }
superellipsoid { <1, 0.3> scale <1, 0.6, 0.8> rotate 60*x translate <1.6, 0.9, 0> pigment { rgb <0, 1, 0> } }
superellipsoid { 2.5 rotate <-20, 10, 0> translate <-1.4, -1.3, 0> pigment { rgb <0, 0, 1> } }
superellipsoid { <0.6, 1.8> scale <-1, 1, 1> rotate <30, 20, 0> translate <1.4, -1.2, 0> pigment { rgb <1, 1, 0> } }
"#;

#[test]
fn superellipsoids_match_povray_away_from_edges() {
    let test = "superellipsoids_match_povray_away_from_edges";
    if common::outside_tool("povray", "povray", test) {
        agree_with_povray(SUPERELLIPSOIDS, "superellipsoids");
    }
}

/// shapes_old.inc's infinite quadrics bounded by CSG: a cylinder cut by a box, a paraboloid
/// by a plane, a box less a cone, a hyperboloid cut by a box.
const QUADRICS: &str = r#"
#include "shapes.inc"
camera { location <0, 4, -7> right x*image_width/image_height angle 40 look_at <0, 0, 0> }
#default { finish { emission 1 ambient 0 diffuse 0 } }
background { rgb 0 }
intersection { object { Cylinder_X } box { <-1, -2, -2>, <1, 2, 2> } scale 0.8 translate <-1.8, 1, 0> pigment { rgb <1, 0, 0> } }
intersection { object { Paraboloid_Y } plane { y, 1.5 } translate <1.6, 0.3, 0> pigment { rgb <0, 1, 0> } }
difference { box { <-1, -1, -1>, <1, 1, 1> } object { QCone_Y scale <0.8, 1, 0.8> } rotate 20*y translate <-1.5, -1.5, 0> pigment { rgb <0, 0, 1> } }
intersection { object { Hyperboloid_Y } box { -1.2, 1.2 } scale 0.7 translate <1.6, -1.5, 0> pigment { rgb <1, 1, 0> } }
"#;

#[test]
fn shapes_old_quadrics_match_povray_away_from_edges() {
    let test = "shapes_old_quadrics_match_povray_away_from_edges";
    if common::outside_tool("povray", "povray", test) {
        agree_with_povray(QUADRICS, "shapes_old.inc's quadrics");
    }
}

/// POV-Ray's bicubic patches, each facing the camera (an emitter here glows on its outer side
/// only): a dome of type 1, a bent sheet under non-uniform scale, a patch of type 0 with an
/// edge collapsed to a point.
const PATCHES: &str = r#"
camera { location <0, 4, -7> right x*image_width/image_height angle 34 look_at <0, 0, 0> }
#default { finish { emission 1 ambient 0 diffuse 0 } }
background { rgb 0 }
bicubic_patch { type 1 flatness 0 u_steps 4 v_steps 3
  <0, 3, 0>, <1, 3, -0.5>, <2, 3, -0.5>, <3, 3, 0>,
  <0, 2, -0.5>, <1, 2, -1.5>, <2, 2, -1.5>, <3, 2, -0.5>,
  <0, 1, -0.5>, <1, 1, -1.5>, <2, 1, -1.5>, <3, 1, -0.5>,
  <0, 0, 0>, <1, 0, -0.5>, <2, 0, -0.5>, <3, 0, 0>
  translate <-1.5, -1.5, 0> scale 0.6 rotate <-20, 15, 0> translate <-1.6, 0.6, 0>
  pigment { rgb <1, 0, 0> }
}
bicubic_patch { type 1 u_steps 3 v_steps 4
  <0, 0, 3> <1, 0.5, 3> <2, -0.5, 3> <3, 0, 3>
  <0, 0.5, 2> <1, 1.5, 2> <2, 1.5, 2> <3, 0.5, 2>
  <0, 0.5, 1> <1, 1.5, 1> <2, 1.5, 1> <3, 0.5, 1>
  <0, 0, 0> <1, 0.5, 0> <2, -0.5, 0> <3, 0, 0>
  translate <-1.5, 0, -1.5> scale <0.7, 0.9, 0.7> rotate 25*y translate <1.5, 0.2, 0>
  pigment { rgb <0, 1, 0> }
}
// An edge collapsed to a point, as at the top of the teapot's lid.
bicubic_patch { type 0 flatness 0.05 u_steps 3 v_steps 3
  <1.5, 3, 0>, <1.5, 3, 0>, <1.5, 3, 0>, <1.5, 3, 0>,
  <0.5, 2, -0.3>, <1.2, 2, -0.8>, <1.8, 2, -0.8>, <2.5, 2, -0.3>,
  <0, 1, -0.3>, <1, 1, -1>, <2, 1, -1>, <3, 1, -0.3>,
  <0, 0, 0>, <1, 0, -0.5>, <2, 0, -0.5>, <3, 0, 0>
  translate <-1.5, -1.5, 0> scale 0.6 translate <0, -1.6, 0>
  pigment { rgb <0, 0, 1> }
}
"#;

#[test]
fn bicubic_patches_match_povray_away_from_edges() {
    let test = "bicubic_patches_match_povray_away_from_edges";
    if common::outside_tool("povray", "povray", test) {
        agree_with_povray(PATCHES, "bicubic patches");
    }
}

/// POV-Ray's triangles written in the scene, each facing the camera: a mesh of flat and smooth
/// triangles, a smooth triangle, a mesh2 with normals and one without.
const MESHES: &str = r#"
camera { location <0, 4, -7> right x*image_width/image_height angle 31 look_at <0, 0, 0> }
#default { finish { emission 1 ambient 0 diffuse 0 } }
background { rgb 0 }
mesh {
  triangle { <0, 0, -0.5>, <0.5, 0.866, 0>, <1, 0, 0> }
  smooth_triangle { <0, 0, -0.5>, <0, 0, -1>, <-0.5, 0.866, 0>, <-0.5, 0.866, -1>, <0.5, 0.866, 0>, <0.5, 0.866, -1> }
  triangle { <0, 0, -0.5>, <-1, 0, 0>, <-0.5, 0.866, 0> }
  smooth_triangle { <0, 0, -0.5>, <0, 0, -1>, <-0.5, -0.866, 0>, <-0.5, -0.866, -1>, <-1, 0, 0>, <-1, 0, -1> }
  triangle { <0, 0, -0.5>, <0.5, -0.866, 0>, <-0.5, -0.866, 0> }
  smooth_triangle { <0, 0, -0.5>, <0, 0, -1>, <1, 0, 0>, <1, 0, -1>, <0.5, -0.866, 0>, <0.5, -0.866, -1> }
  rotate <-20, 10, 0> translate <-1.2, 0.8, 0>
  pigment { rgb <1, 0, 0> }
}
smooth_triangle { <0, 0, 0>, <0, 0.3, -1>, <0, 1.6, 0>, <0.2, 0, -1>, <1.8, 0, 0>, <0, 0, -1>
  scale <1, 0.8, 1> rotate <-30, -20, 0> translate <0.8, 0.3, 0> pigment { rgb <0, 1, 0> } }
mesh2 {
  vertex_vectors { 6, <0, 0, 0>, <1, 0, -0.4>, <2, 0, 0>, <0, 1, 0>, <1, 1, -0.4>, <2, 1, 0> }
  normal_vectors { 3, <-0.4, 0, -1>, <0, 0, -1>, <0.4, 0, -1> }
  face_indices { 4, <0, 3, 1>, <1, 3, 4>, <1, 4, 2>, <2, 4, 5> }
  normal_indices { 4, <0, 0, 1>, <1, 0, 1>, <1, 1, 2>, <2, 1, 2> }
  scale <1.2, 1, 1> rotate -15*x translate <-2.2, -1.7, 0>
  pigment { rgb <0, 0, 1> }
}
mesh2 {
  vertex_vectors { 4, <0, 0, 0>, <0, 1.4, 0.3>, <1.6, 0, 0>, <1.6, 1.4, -0.3> }
  face_indices { 2, <0, 1, 2>, <2, 1, 3> }
  rotate <-10, 20, 0> translate <0.6, -1.8, 0>
  pigment { rgb <1, 1, 0> }
}
"#;

#[test]
fn meshes_of_triangles_and_mesh2_match_povray_away_from_edges() {
    let test = "meshes_of_triangles_and_mesh2_match_povray_away_from_edges";
    if common::outside_tool("povray", "povray", test) {
        agree_with_povray(MESHES, "meshes");
    }
}

/// POV-Ray's julia fractals: squares and cubes in the quaternions, squares in the hypercomplex
/// numbers, one in a slice other than w = 0 (the hypercomplex cube is not yet POV-Ray's).
const JULIA: &str = r#"
camera { location <0, 3, -7> right x*image_width/image_height angle 44 look_at <0, 0, 0> }
#default { finish { emission 1 ambient 0 diffuse 0 } }
background { rgb 0 }
julia_fractal { <-0.083, 0.0, -0.83, -0.025> quaternion sqr max_iteration 8 precision 50
  rotate <20, 30, 0> scale 0.75 translate <-1.5, 1, 0> pigment { rgb <1, 0, 0> } }
julia_fractal { <-0.3, 0.4, 0.2, 0.1> quaternion cube max_iteration 6 precision 50
  scale <1.2, 0.9, 1> translate <1.5, 1, 0> pigment { rgb <0, 1, 0> } }
julia_fractal { <0.2, 0.1, 0.59, -0.2> hypercomplex sqr max_iteration 7 precision 50
  rotate <83, 0, -70> translate <-1.5, -1.2, 0> pigment { rgb <0, 0, 1> } }
julia_fractal { <-0.2, 0.3, 0.1, 0.2> hypercomplex sqr max_iteration 6 precision 50 slice <0.2, 0, 0, 1>, 0.1
  translate <1.5, -1.2, 0> pigment { rgb <1, 1, 0> } }
"#;

#[test]
fn julia_fractals_match_povray_away_from_edges() {
    let test = "julia_fractals_match_povray_away_from_edges";
    if common::outside_tool("povray", "povray", test) {
        agree_with_povray(JULIA, "julia fractals");
    }
}

/// Boxes whose corners are equal in one coordinate: POV-Ray draws the rectangle; equal in two,
/// a line, nothing. (An emitting rectangle glows towards +y here, towards the camera.)
const FLAT_BOXES: &str = r#"
camera { location <0.5, 3, -3> right x*image_width/image_height look_at <0, 0, 0> }
#default { finish { emission 1 ambient 0 diffuse 0 } }
background { rgb 0 }
box { <-2.5, 0, -1.5>, <1.5, 0, 2> pigment { rgb <0, 1, 0> } }
box { <1, 1, -1>, <2, 1, -1> pigment { rgb <0, 0, 1> } }
"#;

#[test]
fn flat_boxes_match_povray_away_from_edges() {
    let test = "flat_boxes_match_povray_away_from_edges";
    if common::outside_tool("povray", "povray", test) {
        agree_with_povray(FLAT_BOXES, "flat boxes");
    }
}

/// POV-Ray's lathes (a linear ring turned on its side, a cubic vase, a Bézier bulb), a sor
/// with its caps seen from above, and a polygon with a hole (its outline closed by POV-Ray).
const REVOLUTIONS: &str = r#"
camera { location <0, 4, -7> right x*image_width/image_height angle 42 look_at <0, 0, 0> }
#default { finish { emission 1 ambient 0 diffuse 0 } }
background { rgb 0 }
lathe {
  linear_spline 5, <0.4, -0.3>, <0.9, -0.3>, <0.9, 0.3>, <0.4, 0.3>, <0.4, -0.3>
  rotate 70*x translate <-2, 1, 0>
  pigment { rgb <1, 0, 0> }
}
lathe {
  cubic_spline 8,
  <0, -1>, <0, -0.8>, <0.6, -0.6>, <0.3, 0>, <0.7, 0.6>, <0.4, 0.8>, <0, 0.8>, <0, 1>
  scale <1, 1, -1> rotate -20*z translate <0, 1.2, 0>
  pigment { rgb <0, 1, 0> }
}
lathe {
  bezier_spline 8,
  <0, -0.5>, <0.8, -0.5>, <0.8, 0.2>, <0.3, 0.3>, <0.3, 0.3>, <0.2, 0.5>, <0.1, 0.6>, <0, 0.6>
  rotate <30, 0, 20> translate <2, 1, 0>
  pigment { rgb <0, 0, 1> }
}
sor {
  6, <0.2, -0.2>, <0.6, 0>, <0.3, 0.4>, <0.8, 0.8>, <0.6, 1.1>, <0.5, 1.3>
  translate <-1.8, -1.6, 0>
  pigment { rgb <1, 1, 0> }
}
polygon {
  9, <-1, -1>, <1, -1>, <1, 1>, <-1, 1>, <-1, -1>, <-0.4, -0.4>, <0.4, -0.4>, <0.4, 0.4>, <-0.4, 0.4>
  rotate <60, 20, 0> translate <1.5, -1.2, 0>
  pigment { rgb <1, 0, 1> }
}
"#;

#[test]
fn lathes_sors_and_polygons_match_povray_away_from_edges() {
    let test = "lathes_sors_and_polygons_match_povray_away_from_edges";
    if common::outside_tool("povray", "povray", test) {
        agree_with_povray(REVOLUTIONS, "revolutions");
    }
}

/// Object modifiers on a wrapper (`object { W pigment { } }`) modify the texture the wrapped
/// object wears, down a chain of wrappers; a wrapper's opaque texture covers it; a group without
/// one of its own gives the wrapper's only to its bare parts; the declared object is unchanged.
/// (Bumps change nothing in an emitter's flat colour, in either renderer.)
const WRAPPERS: &str = r#"
camera { location <0, 0, -5.2> right x*image_width/image_height look_at <0, 0, 0> }
#default { finish { emission 1 ambient 0 diffuse 0 } }
background { rgb 0 }
#declare W = box { -0.6, 0.6 texture { pigment { rgb 1 } } }
#declare A = object { W }
#declare U = union { sphere { 0, 0.6 pigment { rgb <0, 1, 0> } } sphere { 1.4*y, 0.6 } }
object { W pigment { rgb <1, 0, 0> } translate <-2.1, 0.8, 0> }
object { A pigment { rgb <0, 0, 1> } translate <-0.7, 0.8, 0> }
object { W texture { pigment { rgb <1, 1, 0> } } translate <0.7, 0.8, 0> }
object { U pigment { rgb <1, 0, 1> } translate <2.1, -0.7, 0> }
object { W translate <-2.1, -0.7, 0> }
object { W finish { emission 0 } translate <-0.7, -0.7, 0> }
object { W normal { bumps 1 scale 0.1 } pigment { rgb <0, 1, 1> } translate <0.7, -0.7, 0> }
"#;

#[test]
fn wrappers_modify_the_wrapped_object_s_texture_as_povray_s_do() {
    let test = "wrappers_modify_the_wrapped_object_s_texture_as_povray_s_do";
    if common::outside_tool("povray", "povray", test) {
        agree_with_povray(WRAPPERS, "wrappers");
    }
}

/// Cells of a checker, clear and black, over a red emitter: where a texture lies shows as light
/// and dark cells (a patterned pigment glows in one colour, so the cells are seen through).
/// Thin slabs, each within one layer of cells in depth.
const CELLS: &str = r#"
camera { orthographic location <0, 0, -10> right 8*x*image_width/image_height up 8*y
         look_at <0, 0, 0> }
background { rgb 0 }
#default { finish { ambient 0 diffuse 0 } }
plane { -z, -1 pigment { rgb <1, 0, 0> } finish { emission 1 } }
#declare Cells = pigment { checker rgbt <1, 1, 1, 1>, rgb 0 }
#declare Slab = box { <-1, -1, 0.1>, <1, 1, 0.2> }
"#;

/// An object's transforms written before its texture do not move it; those after do: cells of
/// 1 on a slab scaled before its pigment, of 0.9 under a pigment scaled and then moved with its
/// slab, of 1 unturned under a texture given after a turn, and a wrapper's pigment given after
/// its `translate` lies where the scene's cells do.
const LAID_ON_OBJECTS: &str = r#"
object { Slab scale <1.8, 1.8, 1> translate <-2.6, 1.9, 0> pigment { checker rgbt <1, 1, 1, 1>, rgb 0 } }
object { Slab pigment { Cells scale 0.5 } scale <1.8, 1.8, 1> translate <2.6, 1.9, 0> }
object { Slab scale <1.8, 1.8, 1> rotate 30*z texture { pigment { Cells } } translate <-2.6, -1.9, 0> }
#declare T = object { Slab scale <1.8, 1.8, 1> pigment { Cells } }
object { T translate <2.6, -1.9, 0> pigment { Cells scale 0.7 } }
"#;

/// A group's texture lies in the group's space as it stands when it is given, whatever its
/// parts' own transforms: a union's given after its scale, one given before it, a part's own
/// under the union's scale, and an intersection's.
const LAID_ON_GROUPS: &str = r#"
union { object { Slab scale <1.2, 1.2, 1> } scale 1.5 translate <-2.6, 1.9, 0> pigment { Cells } }
union { object { Slab scale <1.2, 1.2, 1> } pigment { Cells } scale 1.5 translate <2.6, 1.9, 0> }
union { object { Slab pigment { Cells } } scale <1.8, 1.8, 1> translate <-2.6, -1.9, 0> }
intersection {
  object { Slab scale <1.2, 1.2, 1> } sphere { 0, 10 }
  scale 1.5 translate <2.6, -1.9, 0> pigment { Cells }
}
"#;

#[test]
fn only_the_transforms_after_a_texture_move_it_as_povray_s_do() {
    let test = "only_the_transforms_after_a_texture_move_it_as_povray_s_do";
    if common::outside_tool("povray", "povray", test) {
        agree_with_povray(&format!("{CELLS}{LAID_ON_OBJECTS}"), "textures on objects");
        agree_with_povray(&format!("{CELLS}{LAID_ON_GROUPS}"), "textures on groups");
    }
}

/// A new pattern word over a declared pigment changes only its pattern: its color_map, its
/// warp and its transforms stay (onion rings in red and green, repeated every 1.2 along x),
/// whether it is named in a pigment, moved after the word, or under a declared texture.
const NEW_WORD: &str = r#"
camera { orthographic location <0, 0, -10> right 8*x*image_width/image_height up 8*y
         look_at <0, 0, 0> }
background { rgb 0 }
#default { finish { emission 1 ambient 0 diffuse 0 } }
#declare P = pigment { gradient x color_map { [0.5 rgb <1, 0, 0>] [0.5 rgb <0, 1, 0>] }
                       warp { repeat x*0.6 } scale 2 }
#declare T = texture { pigment { P } }
box { <-6, 1.4, 0>, <6, 3.8, 1> pigment { P onion } }
box { <-6, -1.2, 0>, <6, 1.2, 1> pigment { P onion translate <0.3, 0.4, 0> } }
box { <-6, -3.8, 0>, <6, -1.4, 1> texture { T pigment { onion } } }
"#;

/// Its frequency, phase and wave stay too, unless the word has its own wave: marble's triangle
/// wave and frequency on a gradient, and a gradient's phase on marble, which waves it its way.
const NEW_WORD_MODIFIERS: &str = r#"
camera { orthographic location <0, 0, -10> right 4*x up 3*y look_at <0, 0, 0> }
background { rgb 0 }
#default { finish { emission 1 ambient 0 diffuse 0 } }
#declare P = pigment { marble color_map { [0.5 rgb <1, 0, 0>] [0.5 rgb <0, 1, 0>] } frequency 2
                       scale 0.7 }
#declare Q = pigment { gradient y color_map { [0.3 rgb <1, 0, 0>] [0.3 rgb <0, 0, 1>] } phase 0.2
                       scale 0.5 }
box { <-2, 0, 0>, <2, 1.5, 1> pigment { P gradient y } }
box { <-2, -1.5, 0>, <2, 0, 1> pigment { Q marble } }
"#;

#[test]
fn a_new_pattern_word_keeps_the_declared_pigment_s_map_warps_and_transforms() {
    let test = "a_new_pattern_word_keeps_the_declared_pigment_s_map_warps_and_transforms";
    if common::outside_tool("povray", "povray", test) {
        agree_with_povray(NEW_WORD, "a new pattern word");
        agree_with_povray(NEW_WORD_MODIFIERS, "a new pattern word's modifiers");
    }
}

/// The spirals as POV-Ray's: `spiral1` (its own triangle wave, and a ramp), `spiral2` (the
/// rings' and the spiral's triangle waves summed), each split by its map at one value.
const SPIRALS: &str = r#"
camera { orthographic location <0, 0, -10> right 4*x up 3*y look_at <0, 0, 0> }
background { rgb 0 }
#default { finish { emission 1 ambient 0 diffuse 0 } }
#declare Split = color_map { [0.45 rgb <1, 0, 0>] [0.45 rgb <0, 1, 0>] }
box { <-2, 0, 0>, <0, 1.5, 1> pigment { spiral1 3 color_map { Split } translate <-1, 0.75, 0.3> } }
box { <0, 0, 0>, <2, 1.5, 1>
  pigment { spiral1 2 ramp_wave color_map { Split } translate <1, 0.75, 0> } }
box { <-2, -1.5, 0>, <0, 0, 1>
  pigment { spiral2 3 color_map { Split } scale 1.5 translate <-1, -0.75, 0.2> } }
box { <0, -1.5, 0>, <2, 0, 1> pigment { spiral2 5 color_map { Split } translate <1, -0.75, 0> } }
"#;

#[test]
fn spirals_match_povray_away_from_edges() {
    let test = "spirals_match_povray_away_from_edges";
    if common::outside_tool("povray", "povray", test) {
        agree_with_povray(SPIRALS, "spirals");
    }
}

/// Height fields seen from above at a slant, so that their heights shape what each pixel sees:
/// an 8-bit gray PNG (its full range), a 4-bit palette PNG (index × 256) with `smooth`, and a
/// function of x and y (y along −z) with a water level that cuts it, each steep and lopsided.
const HEIGHT_FIELDS: &str = r#"
camera { location <0, 3.5, -4> right x*image_width/image_height angle 50 look_at <0, 0.3, 0> }
#default { finish { emission 1 ambient 0 diffuse 0 } }
background { rgb 0 }
height_field { png "gray.png" translate <-0.5, 0, -0.5> scale <2.2, 1.5, 2.6> translate <-1.3, 0, 0>
  pigment { rgb <1, 0, 0> } }
height_field { "palette.png" smooth translate <-0.5, 0, -0.5> scale <2.2, 2, 1.8> translate <1, 0, 0.9>
  pigment { rgb <0, 1, 0> } }
height_field { function 24, 20 { y * y * (0.3 + 0.7 * x) } water_level 0.25
  translate <-0.5, 0, -0.5> scale <2.4, 1.5, 2> translate <1.2, 0, -1.1>
  pigment { rgb <0, 0, 1> } }
"#;

/// A PNG of `width` × `height` samples (8 bits, or 4 with a palette), rows from the top.
fn png(width: u32, height: u32, palette: bool, samples: &[u8]) -> Vec<u8> {
    let mut bytes = Vec::new();
    let mut encoder = png::Encoder::new(&mut bytes, width, height);
    if palette {
        encoder.set_color(png::ColorType::Indexed);
        encoder.set_depth(png::BitDepth::Four);
        // Colours unlike the indices: the heights are the indices, not the colours.
        encoder.set_palette((0..48).map(|i| (i * 37 % 256) as u8).collect::<Vec<u8>>());
    } else {
        encoder.set_color(png::ColorType::Grayscale);
        encoder.set_depth(png::BitDepth::Eight);
    }
    let packed: Vec<u8> = if palette {
        samples
            .chunks(width as usize)
            .flat_map(|row| row.chunks(2).map(|p| p[0] << 4 | p.get(1).copied().unwrap_or(0)))
            .collect()
    } else {
        samples.to_vec()
    };
    encoder.write_header().unwrap().write_image_data(&packed).unwrap();
    bytes
}

#[test]
fn height_fields_match_povray_away_from_edges() {
    let test = "height_fields_match_povray_away_from_edges";
    if !common::outside_tool("povray", "povray", test) {
        return;
    }
    // A ridge rising to the right, highest in the image's top rows (far from the camera).
    let gray: Vec<u8> = (0..12 * 10).map(|k| ((k % 12) * 20 + (9 - k / 12) * 3) as u8).collect();
    // A block of index 15 in one corner on a floor of index 2.
    let palette: Vec<u8> =
        (0..8 * 8).map(|k| if k % 8 < 3 && k / 8 < 4 { 15 } else { 2 }).collect();
    let files =
        [("gray.png", png(12, 10, false, &gray)), ("palette.png", png(8, 8, true, &palette))];
    agree_with_povray_beside(HEIGHT_FIELDS, "height fields", &files);
}

/// Height fields from POV-Ray's other image types: a plain PGM whose largest value is 9 (scaled
/// to 8 bits), a raw 8-bit PPM (red the high byte, green the low), and a run-length Targa palette
/// image stored bottom row first (index × 256).
const NETPBM_TGA_FIELDS: &str = r#"
camera { location <0, 3.5, -4> right x*image_width/image_height angle 50 look_at <0, 0.3, 0> }
#default { finish { emission 1 ambient 0 diffuse 0 } }
background { rgb 0 }
height_field { pgm "ridge.pgm" translate <-0.5, 0, -0.5> scale <2.2, 1.5, 2.6> translate <-1.3, 0, 0>
  pigment { rgb <1, 0, 0> } }
height_field { "steps.ppm" translate <-0.5, 0, -0.5> scale <2.2, 2, 1.8> translate <1, 0, 0.9>
  pigment { rgb <0, 1, 0> } }
height_field { tga "block.tga" translate <-0.5, 0, -0.5> scale <2.4, 1.5, 2> translate <1.2, 0, -1.1>
  pigment { rgb <0, 0, 1> } }
"#;

#[test]
fn height_fields_from_pgm_ppm_and_tga_match_povray_away_from_edges() {
    let test = "height_fields_from_pgm_ppm_and_tga_match_povray_away_from_edges";
    if !common::outside_tool("povray", "povray", test) {
        return;
    }
    // A ridge rising to the right and towards the top rows, values 0 to 9.
    let ridge: Vec<String> =
        (0..10 * 8).map(|k| ((k % 10) + (7 - k / 10) / 4).min(9).to_string()).collect();
    let pgm = format!("P2\n# a ridge\n10 8\n9\n{}\n", ridge.join(" ")).into_bytes();
    // Steps: red rising along the columns, green a little with the rows.
    let mut ppm = b"P6\n9 7\n255\n".to_vec();
    for k in 0..9 * 7 {
        ppm.extend([((k % 9) * 25) as u8, ((k / 9) * 30) as u8, 200]);
    }
    // A Targa palette image (type 9), 8 × 6: a block of index 200 in the bottom-left corner of
    // the image on a floor of index 20, stored bottom row first, in runs.
    let mut tga = vec![0u8; 18];
    tga[1] = 1;
    tga[2] = 9;
    tga[5] = 0; // 256 palette entries of 24 bits
    tga[6] = 1;
    tga[7] = 24;
    tga[12] = 8;
    tga[14] = 6;
    tga[16] = 8;
    tga.extend((0..256 * 3).map(|i| (i * 53 % 256) as u8));
    for stored_row in 0..6 {
        let block = if stored_row < 3 { 3 } else { 0 };
        if block > 0 {
            tga.extend([0x80 | (block - 1), 200]);
        }
        tga.extend([0x80 | (8 - block - 1), 20]);
    }
    let files = [("ridge.pgm", pgm), ("steps.ppm", ppm), ("block.tga", tga)];
    agree_with_povray_beside(NETPBM_TGA_FIELDS, "height fields from PGM, PPM and TGA", &files);
}

/// A height field as the solid below its sheet: cut by a sphere (its sheet and the sphere's
/// part below it), cutting a sphere (the cap above the sheet, and the sheet seen from below), and
/// clipping a cylinder (its side below the sheet). The sphere and the cylinder stay inside the
/// field's square and above its floor, where raydiance's solid and POV-Ray's agree (docs/povray.md).
const HEIGHT_FIELD_SOLIDS: &str = r#"
camera { location <0, -0.3, -9> right x*image_width/image_height angle 30 look_at <0, -0.3, 0> }
#default { finish { emission 1 ambient 0 diffuse 0 } }
background { rgb 0 }
#declare Field = height_field { function 16, 16 { 0.3 + 0.4 * x + 0.2 * y * y }
  scale <4, 2, 4> translate <-2, -1, -2> }
intersection {
  object { Field pigment { rgb <1, 0, 0> } }
  sphere { <0, 0, 0>, 0.9 pigment { rgb <0, 1, 0> } }
  translate <-1.6, 0, 0>
}
difference {
  sphere { <0, 0, 0>, 0.9 pigment { rgb <1, 1, 0> } }
  object { Field pigment { rgb <1, 0, 1> } }
  translate <0, 0.3, 1.8>
}
cylinder { <0, -1.5, 0>, <0, 3, 0>, 0.8
  clipped_by { object { Field } }
  pigment { rgb <0, 0, 1> } translate <1.6, 0, 0> }
"#;

#[test]
fn height_fields_in_csg_match_povray_away_from_edges() {
    let test = "height_fields_in_csg_match_povray_away_from_edges";
    if common::outside_tool("povray", "povray", test) {
        agree_with_povray(HEIGHT_FIELD_SOLIDS, "height fields in CSG");
    }
}

/// Points and triangles with directives among them: a prism's points from an array in `#for`, a
/// mesh's triangles in `#while`, a sphere sweep's spheres in `#for`, a mesh's triangles (with
/// `uv_vectors`) made by a macro called alone and in `#for`, and its transform by another.
const LISTED: &str = r#"
camera { location <0, 3, -7> right x*image_width/image_height angle 34 look_at <0, 0, 0> }
#default { finish { emission 1 ambient 0 diffuse 0 } }
background { rgb 0 }
#declare Star = array[10]
#for (K, 0, 9)
  #declare Star[K] = (1 - 0.5 * mod(K, 2)) * <sin(K * pi / 5), cos(K * pi / 5)>;
#end
prism { linear_spline -0.3, 0.3, 11,
  #for (K, 0, 10) Star[mod(K, 10)] #end
  rotate -60*x translate <-1.8, 1, 0> pigment { rgb <1, 0, 0> } }
mesh {
  #local I = 0;
  #while (I < 6)
    triangle { <0, 0, 0>, <cos((I + 1) * pi / 3), sin((I + 1) * pi / 3), 0>, <cos(I * pi / 3), sin(I * pi / 3), 0> }
    #local I = I + 1;
  #end
  translate <1.8, 1, 0> pigment { rgb <0, 1, 0> } }
sphere_sweep { linear_spline 4,
  #for (K, 0, 3) <K * 0.6 - 0.9, 0.4 * mod(K, 2), 0>, 0.15 + 0.05 * K #end
  translate <-1.8, -1.3, 0> pigment { rgb <0, 0, 1> } }
#macro Blade(A)
  triangle { <0, 0, 0>, <cos(A + pi / 4), sin(A + pi / 4), 0>, <cos(A), sin(A), 0>
    uv_vectors <0, 0>, <1, 0>, <0, 1> }
#end
#macro Placed() translate <1.8, -1.3, 0> #end
mesh { Blade(0) #for (K, 1, 3) Blade(K * pi / 2) #end Placed() pigment { rgb <1, 1, 0> } }
"#;

#[test]
fn points_and_triangles_made_by_directives_match_povray_away_from_edges() {
    let test = "points_and_triangles_made_by_directives_match_povray_away_from_edges";
    if common::outside_tool("povray", "povray", test) {
        agree_with_povray(LISTED, "points and triangles made by directives");
    }
}

/// shapes2.inc's `Pyramid2` (POV-Ray's own file against raydiance's), seen from inside the box
/// POV-Ray bounds it by, where POV-Ray shows all of it (docs/povray.md).
const PYRAMID2: &str = r#"
#include "shapes.inc"
#include "shapes2.inc"
camera { location <0.95, 0.9, -0.95> right x*image_width/image_height angle 70 look_at <0, -0.4, 0> }
#default { finish { emission 1 ambient 0 diffuse 0 } }
background { rgb 0 }
object { Pyramid2 pigment { rgb <1, 1, 0> } }
plane { y, -1.5 pigment { rgb <0, 0, 1> } }
"#;

#[test]
fn pyramid2_matches_povray_away_from_edges() {
    let test = "pyramid2_matches_povray_away_from_edges";
    if common::outside_tool("povray", "povray", test) {
        agree_with_povray(PYRAMID2, "Pyramid2");
    }
}

/// Sphere sweeps along each of POV-Ray's three splines, their radii changing along them, one
/// turned and mirrored.
const SWEEPS: &str = r#"
camera { location <0, 1, -6> right x*image_width/image_height angle 50 look_at <0, 0, 0> }
#default { finish { emission 1 ambient 0 diffuse 0 } }
background { rgb 0 }
sphere_sweep { linear_spline 4, <-3, 1.2, 0>, 0.2, <-1.5, 2, 0>, 0.5, <0, 1.3, 0.5>, 0.1, <1.5, 1.8, 0>, 0.35
  pigment { rgb <1, 0, 0> } }
sphere_sweep { cubic_spline 6, <-3, 0, 0>, 0.1, <-2.5, 0, 0>, 0.2, <-1.2, 0.8, 0>, 0.4, <0, -0.3, 0>, 0.15,
  <1.2, 0.6, 0>, 0.45, <2, 0, 0>, 0.2 tolerance 0.001
  pigment { rgb <0, 1, 0> } }
sphere_sweep { b_spline 5, <-2, -1.8, 0>, 0.3, <-1, -0.6, 0>, 0.5, <0, -1.8, 0>, 0.1, <1, -0.6, 0>, 0.6, <2, -1.8, 0>, 0.3
  scale <-1, 1, 1> rotate 20*y
  pigment { rgb <0, 0, 1> } }
"#;

#[test]
fn sphere_sweeps_match_povray_away_from_edges() {
    let test = "sphere_sweeps_match_povray_away_from_edges";
    if common::outside_tool("povray", "povray", test) {
        agree_with_povray(SWEEPS, "sphere sweeps");
    }
}

/// POV-Ray's ovus in both of its cases (the top radius below and above the bottom one), turned,
/// stretched and mirrored, and one whose top radius is twice its bottom one (the top sphere
/// alone, with a warning).
const OVUS: &str = r#"
camera { location <0, 1, -7> right x*image_width/image_height angle 50 look_at <0, 0.4, 0> }
#default { finish { emission 1 ambient 0 diffuse 0 } }
background { rgb 0 }
ovus { 1, 0.65 rotate 25*z translate <-2.3, -0.6, 0> pigment { rgb <1, 0, 0> } }
ovus { 0.6, 0.9 scale <1, 1.2, 0.8> rotate <30, 0, -15> translate <0, -0.9, 0> pigment { rgb <0, 1, 0> } }
ovus { 0.5, 0.2 scale <-1.5, 1.5, 1.5> rotate <-20, 0, -40> translate <2.1, 0.3, 0> pigment { rgb <0, 0, 1> } }
ovus { 0.3, 0.6 rotate 150*x translate <0, 2.2, 1> pigment { rgb <1, 1, 0> } }
"#;

#[test]
fn ovus_match_povray_away_from_edges() {
    let test = "ovus_match_povray_away_from_edges";
    if common::outside_tool("povray", "povray", test) {
        agree_with_povray(OVUS, "ovus");
    }
}

/// POV-Ray 3.8's lemon of end radii a and b along the y axis from 0 to 1 with inner radius r,
/// written for POV-Ray 3.7 (which has no lemon): its arc is centred at (-c, v), c >= 0
/// (lemon.cpp), and with S = |p - v y|^2 + c^2 - r^2 its solid is where S < -2 c rho: where
/// S < 0 (a sphere) and S^2 - 4 c^2 rho^2 > 0 (a quartic, negated to be POV-Ray's inside),
/// between the planes of its ends.
fn lemon_as_csg(a: f64, b: f64, r: f64, items: &str) -> String {
    let chord_squared = (b - a).powi(2) + 1.0;
    let f = (4.0 * r * r / chord_squared - 1.0).sqrt();
    let (c, v) = ((f - a - b) / 2.0, ((b - a) * f + 1.0) / 2.0);
    assert!(c > 0.0, "an arc off the axis");
    let k = c * c - r * r;
    // POV-Ray's order of a quartic's 35 terms: x^4 is the 1st, x^2 y^2 the 5th, x^2 z^2 the
    // 8th, x^2 the 10th, y^4 the 21st, y^2 z^2 the 24th, y^2 the 26th, z^4 the 31st, z^2 the
    // 33rd, the constant the 35th.
    let mut terms = [0.0; 35];
    for (place, value) in [
        (1, 1.0),
        (5, 2.0),
        (8, 2.0),
        (10, 2.0 * k - 4.0 * c * c),
        (21, 1.0),
        (24, 2.0),
        (26, 2.0 * k),
        (31, 1.0),
        (33, 2.0 * k - 4.0 * c * c),
        (35, k * k),
    ] {
        terms[place - 1] = -value;
    }
    let terms: Vec<String> = terms.iter().map(|t| t.to_string()).collect();
    format!(
        "intersection {{ quartic {{ <{}> sturm translate {v}*y }} sphere {{ <0, {v}, 0>, {} }} \
         box {{ <-3, 0, -3>, <3, 1, 3> }} {items} }}",
        terms.join(", "),
        (r * r - c * c).sqrt()
    )
}

#[test]
fn lemons_match_povray_s_csg_of_the_same_solid_away_from_edges() {
    let test = "lemons_match_povray_s_csg_of_the_same_solid_away_from_edges";
    if !common::outside_tool("povray", "povray", test) {
        return;
    }
    let header = "camera { location <0, 1, -7> right x*image_width/image_height angle 36 \
                  look_at <0, 0.4, 0> }\n#default { finish { emission 1 ambient 0 diffuse 0 } }\n\
                  background { rgb 0 }\n";
    let lemons = [
        (
            0.3,
            0.2,
            0.9,
            "scale 1.6 rotate 20*z translate <-2.4, -0.8, 0> pigment { rgb <1, 0, 0> }",
        ),
        (
            0.0,
            0.4,
            1.2,
            "scale <1.5, 2, 1.5> rotate <-30, 0, 10> translate <0, -1, 0> pigment { rgb <0, 1, 0> }",
        ),
        (
            0.45,
            0.45,
            2.0,
            "scale <-1.4, 1.4, 1.4> rotate 100*z translate <2.7, 0, 0> pigment { rgb <0, 0, 1> }",
        ),
        (0.2, 0.0, 0.8, "scale 1.5 rotate 160*x translate <0, 2.6, 1> pigment { rgb <1, 1, 0> }"),
    ];
    let (mut ours, mut theirs) = (header.to_string(), header.to_string());
    for (a, b, r, items) in lemons {
        ours.push_str(&format!("lemon {{ <0, 0, 0>, {a}, <0, 1, 0>, {b}, {r} {items} }}\n"));
        theirs.push_str(&lemon_as_csg(a, b, r, items));
        theirs.push('\n');
    }
    agree_with_povray_as(&ours, &theirs, "lemons");
}

/// Discs with and without a hole radius, tilted, stretched and mirrored (an emitter here glows
/// on both sides of a disc).
const DISCS: &str = r#"
camera { location <0, 1, -6> right x*image_width/image_height angle 50 look_at <0, 0, 0> }
#default { finish { emission 1 ambient 0 diffuse 0 } }
background { rgb 0 }
disc { <-1.8, 0.8, 0>, <0, 0, -1>, 1.1, 0.5 pigment { rgb <1, 0, 0> } }
disc { <0, 0, 0>, <0.3, 1, -1>, 1, 0.7 scale <-1.6, 1, 1> rotate 20*z translate <1.4, 0.8, 0> pigment { rgb <0, 1, 0> } }
disc { <0, -1.2, 0>, <0, 1, -0.6>, 1.2 pigment { rgb <0, 0, 1> } }
disc { <0, -1.2, -0.5>, <0, 1, -0.6>, 0.6, 0.3 pigment { rgb <1, 1, 0> } }
"#;

#[test]
fn discs_with_holes_match_povray_away_from_edges() {
    let test = "discs_with_holes_match_povray_away_from_edges";
    if common::outside_tool("povray", "povray", test) {
        agree_with_povray(DISCS, "discs");
    }
}

/// Patterned glows: each point emits its pigment's colour there, as POV-Ray's glow does (a
/// sphere, sampled as an area light, and a box, in checkers of two colours each; a wall in
/// bands of a `gradient`'s colour_map). One colour over each surface would differ from POV-Ray's
/// on every square of one of its colours.
const PATTERNED_GLOWS: &str = r#"
camera { location <0, 2.5, -4.5> right x*image_width/image_height look_at <0, -0.2, 0> }
#default { finish { emission 1 ambient 0 diffuse 0 } }
background { rgb 0 }
sphere { <-1.2, 0, 0>, 1 pigment { checker rgb <1, 0, 0> rgb <0, 0, 1> scale 0.5 } }
box { <0.3, -1, -1>, <2.3, 0.8, 1> pigment { checker rgb <0, 1, 0> rgb <1, 0, 1> scale 0.5 } }
plane { z, 3 pigment { gradient x color_map { [0.5 rgb <1, 1, 0>] [0.5 rgb <0, 1, 1>] } scale 3 } }
"#;

#[test]
fn patterned_glows_match_povray_away_from_edges() {
    let test = "patterned_glows_match_povray_away_from_edges";
    if common::outside_tool("povray", "povray", test) {
        agree_with_povray(PATTERNED_GLOWS, "patterned glows");
    }
}

/// A glow fades by the light its pigment lets through, as POV-Ray's does (glow × P × (1 − f −
/// t)): a white disc of transmit 0.8 glows 0.2, a pale yellow one of filter 0.45 glows yellow
/// (0.55, 0.55, 0.33), and so do the transparent squares of a checker in red (0.2); unfaded,
/// the first and the squares would glow white, the second pale yellow.
const FADED_GLOWS: &str = r#"
camera { location <0, 0, -3.2> right x*image_width/image_height look_at <0, 0, 0> }
#default { finish { emission 1 ambient 0 diffuse 0 } }
background { rgb 0 }
disc { <-1.2, 0.8, 0.25>, -z, 0.8 pigment { rgbt <1, 1, 1, 0.8> } }
disc { <1.2, 0.8, 0.25>, -z, 0.8 pigment { rgbf <1, 1, 0.6, 0.45> } }
box { <-2.4, -1.9, 0.25>, <2.4, -0.1, 0.25>
  pigment { checker rgbt <1, 1, 1, 0.8> rgb <1, 0, 0> scale 0.5 } }
"#;

#[test]
fn glows_fade_by_their_pigment_s_transparency_as_povray_s_do() {
    let test = "glows_fade_by_their_pigment_s_transparency_as_povray_s_do";
    if common::outside_tool("povray", "povray", test) {
        agree_with_povray(FADED_GLOWS, "faded glows");
    }
}

/// `ambient_light` multiplies a glow by `ambient` and not one by `emission`, as POV-Ray's
/// does: the left disc glows (1, 0.1, 0), red, and the right one cyan (unmultiplied, the left
/// would be yellow).
const AMBIENT_LIGHT: &str = r#"
camera { location <0, 0, -3.2> right x*image_width/image_height look_at <0, 0, 0> }
global_settings { max_trace_level 5 ambient_light rgb <1, 0.1, 1> }
background { rgb 0 }
disc { <-1.2, 0, 0.25>, -z, 1 pigment { rgb <1, 1, 0> } finish { ambient 1 diffuse 0 } }
disc { <1.2, 0, 0.25>, -z, 1 pigment { rgb <0, 1, 1> } finish { emission 1 ambient 0 diffuse 0 } }
"#;

#[test]
fn ambient_light_multiplies_an_ambient_glow_as_povray_s_does() {
    let test = "ambient_light_multiplies_an_ambient_glow_as_povray_s_does";
    if common::outside_tool("povray", "povray", test) {
        agree_with_povray(AMBIENT_LIGHT, "ambient_light");
    }
}

/// `assumed_gamma G`: POV-Ray 3.7 takes the scene's colours as encoded with gamma G and writes
/// what it computes re-encoded for the file (sRGB), so a flat colour c shows as linear c^G does:
/// `rgb 0.5` as 128 under 2.2 (raydiance's linear 0.5 would show as 188). Flat glows of a few
/// colours, plain and in a checker, by `ambient` and by `emission`.
fn gamma_glows(gamma: f32) -> String {
    format!(
        "global_settings {{ assumed_gamma {gamma} }}
camera {{ location <0, 0, -3.2> right x*image_width/image_height look_at <0, 0, 0> }}
#default {{ finish {{ ambient 1 diffuse 0 }} }}
background {{ rgb 0 }}
box {{ <-2.4, 0.1, 0.25>, <-0.9, 1.6, 0.25> pigment {{ rgb 0.5 }} }}
box {{ <-0.75, 0.1, 0.25>, <0.75, 1.6, 0.25> pigment {{ rgb <0.2, 0.8, 0.1> }} }}
box {{ <0.9, 0.1, 0.25>, <2.4, 1.6, 0.25> pigment {{ rgb 0.25 }}
  finish {{ emission 1 ambient 0 diffuse 0 }} }}
box {{ <-2.4, -1.9, 0.25>, <2.4, -0.1, 0.25>
  pigment {{ checker rgb <0.9, 0.4, 0.6> rgb <0.05, 0.3, 0.7> scale 0.6 }} }}
"
    )
}

#[test]
fn assumed_gamma_makes_flat_colours_show_as_povray_s_values() {
    let test = "assumed_gamma_makes_flat_colours_show_as_povray_s_values";
    if common::outside_tool("povray", "povray", test) {
        for gamma in [2.2, 1.5] {
            values_agree_with_povray(&gamma_glows(gamma), &format!("assumed_gamma {gamma}"), 3.0);
        }
    }
}

/// POV-Ray's parametric surfaces, cheap enough for the debug build (a ray's search of the (u, v)
/// pieces is most of the cost): a saddle, part of a cylinder mirrored and turned, and a paraboloid
/// cap needing a `max_gradient` above 1, each with a coarse `accuracy` (POV-Ray's hits depend on
/// it as raydiance's do), one with `precompute`.
const PARAMETRICS: &str = r#"
camera { location <0, 1, -5.5> right x*image_width/image_height angle 45 look_at <0, 0, 0> }
#default { finish { emission 1 ambient 0 diffuse 0 } }
background { rgb 0 }
parametric { function { u } function { 0.8 * u * v } function { v } <-1, -1>, <1, 1>
  contained_by { box { <-1, -0.8, -1>, <1, 0.8, 1> } } accuracy 0.01 precompute 10, x, y, z
  rotate <-25, 35, 0> translate <-1.2, 0.5, 0.3> pigment { rgb <1, 0, 0> } }
parametric { function { cos(u) } function { v } function { sin(u) } <0, -0.8>, <0.7 * pi, 0.8>
  contained_by { box { <-0.6, -0.8, 0>, <1, 0.8, 1> } } accuracy 0.01
  scale <-1, 1, 1> rotate <0, 30, 20> translate <1.4, 0.4, 0> pigment { rgb <0, 1, 0> } }
parametric { function { u } function { u * u + v * v } function { v } <-0.7, -0.7>, <0.7, 0.7>
  contained_by { box { <-0.7, 0, -0.7>, <0.7, 1, 0.7> } } max_gradient 1.5 accuracy 0.01
  rotate 180*x translate <0, -0.2, 0> pigment { rgb <0, 0, 1> } }
"#;

#[test]
fn parametric_surfaces_match_povray_away_from_edges() {
    let test = "parametric_surfaces_match_povray_away_from_edges";
    if common::outside_tool("povray", "povray", test) {
        // Fewer samples than usual: the search of the (u, v) pieces is most of the time.
        let few = Render { samples: 4, ..USUAL };
        compare_with_povray(PARAMETRICS, PARAMETRICS, "parametric surfaces", &[], few);
    }
}

/// Renders `text` with POV-Ray and with raydiance and compares which channels each pixel lights.
fn agree_with_povray(text: &str, name: &str) {
    agree_with_povray_beside(text, name, &[]);
}

/// `agree_with_povray` with `files` (name, contents) written beside the scene.
fn agree_with_povray_beside(text: &str, name: &str, files: &[(&str, Vec<u8>)]) {
    compare_with_povray(text, text, name, files, USUAL);
}

/// `agree_with_povray` where POV-Ray renders `theirs`, the same geometry written otherwise.
fn agree_with_povray_as(ours: &str, theirs: &str, name: &str) {
    compare_with_povray(ours, theirs, name, &[], USUAL);
}

fn compare_with_povray(
    text: &str,
    theirs_text: &str,
    name: &str,
    files: &[(&str, Vec<u8>)],
    render: Render,
) {
    let (theirs, ours, _) = render_both(text, theirs_text, files, render);
    let (a, b) = (classes(&theirs), classes(&ours));
    let wrong: Vec<usize> = (0..a.len())
        .filter(|&k| a[k] != b[k] && !on_edge(k, render, 1, |j| a[j] != a[k]))
        .collect();
    assert!(wrong.is_empty(), "{name}: pixels {wrong:?} differ from POV-Ray's");
    let lit = a.iter().filter(|c| c.iter().any(|&l| l)).count();
    assert!(lit > a.len() / 4, "{name}: the scene is in view ({lit} pixels lit)");
}

/// Renders `text` with POV-Ray and with raydiance and compares each pixel's values, raydiance's
/// linear light sRGB-encoded as POV-Ray's output is by default: they must agree within `levels`
/// of 255 away from edges (within two pixels of where POV-Ray's own values differ by more: a
/// pixel of raydiance's takes samples a little beyond its square).
fn values_agree_with_povray(text: &str, name: &str, levels: f32) {
    let render = Render { samples: 4, ..USUAL };
    let (theirs, ours, max) = render_both(text, text, &[], render);
    let ours: Vec<f32> = ours.iter().map(|c| srgb_transfer(c * max)).collect();
    let pixel = |image: &[f32], k: usize| Vec3::from_slice(&image[3 * k..3 * k + 3]) * 255.0;
    let apart = |a: Vec3, b: Vec3| (a - b).abs().max_element() > levels;
    let wrong: Vec<(usize, Vec3, Vec3)> = (0..render.width * render.height)
        .filter(|&k| !on_edge(k, render, 2, |j| apart(pixel(&theirs, j), pixel(&theirs, k))))
        .map(|k| (k, pixel(&theirs, k), pixel(&ours, k)))
        .filter(|&(_, a, b)| apart(a, b))
        .collect();
    let first = &wrong[..wrong.len().min(5)];
    assert!(
        wrong.is_empty(),
        "{name}: {} pixels differ, first (index, POV-Ray's, ours) {first:?}",
        wrong.len()
    );
    let lit = (0..render.width * render.height).filter(|&k| pixel(&theirs, k).max_element() > 10.0);
    assert!(lit.count() > render.width * render.height / 4, "{name}: the scene is in view");
}

/// Whether pixel `k` lies on an edge: a pixel j at most `reach` steps away along rows and
/// columns `differs` (its four neighbours for a reach of 1).
fn on_edge(k: usize, render: Render, reach: i64, differs: impl Fn(usize) -> bool) -> bool {
    let (width, height) = (render.width as i64, render.height as i64);
    let (x, y) = ((k as i64) % width, (k as i64) / width);
    let steps = (-reach..=reach).flat_map(|dx| (-reach..=reach).map(move |dy| (dx, dy)));
    steps.filter(|(dx, dy)| dx.abs() + dy.abs() <= reach).any(|(dx, dy)| {
        let (u, v) = (x + dx, y + dy);
        (0..width).contains(&u) && (0..height).contains(&v) && differs((v * width + u) as usize)
    })
}

/// Renders `text` with raydiance and `theirs_text` with POV-Ray, with `files` (name, contents)
/// beside them: POV-Ray's pixels and raydiance's, each channel in [0, 1], and the linear light
/// raydiance's 1 stands for (its HDR `.ppm`'s `#MAX`).
fn render_both(
    text: &str,
    theirs_text: &str,
    files: &[(&str, Vec<u8>)],
    render: Render,
) -> (Vec<f32>, Vec<f32>, f32) {
    let Render { width, height, samples } = render;
    let dir = tempfile::tempdir().unwrap();
    for (file, contents) in files {
        std::fs::write(dir.path().join(file), contents).unwrap();
    }
    let scene = dir.path().join("scene.pov");
    std::fs::write(&scene, text).unwrap();
    let theirs_scene = dir.path().join("theirs.pov");
    std::fs::write(&theirs_scene, theirs_text).unwrap();
    let ours = dir.path().join("ours.ppm");
    let theirs = dir.path().join("theirs.ppm");
    // POV-Ray finds the scene's files in its working folder.
    let povray = Command::new("povray")
        .current_dir(dir.path())
        .arg(format!("+I{}", theirs_scene.display()))
        .arg(format!("+O{}", theirs.display()))
        .args(["+FP", &format!("+W{width}"), &format!("+H{height}"), "-D", "-A"])
        .output()
        .expect("POV-Ray is the oracle: install Debian's `povray`");
    assert!(povray.status.success(), "{}", String::from_utf8_lossy(&povray.stderr));
    let size = [width.to_string(), height.to_string(), samples.to_string()];
    let status = Command::new(env!("CARGO_BIN_EXE_raydiance"))
        .args(["render", scene.to_str().unwrap(), "-o", ours.to_str().unwrap()])
        .args(["--width", &size[0], "--height", &size[1], "--samples", &size[2]])
        .output()
        .unwrap();
    assert!(status.status.success(), "{}", String::from_utf8_lossy(&status.stderr));
    let text = std::fs::read_to_string(&ours).unwrap();
    let max = text.lines().find_map(|line| line.strip_prefix("#MAX=")).expect("a #MAX line");
    let (theirs, ours) = (ppm(&theirs), ppm(&ours));
    assert_eq!((theirs.len(), ours.len()), (3 * width * height, 3 * width * height));
    (theirs, ours, max.parse().unwrap())
}

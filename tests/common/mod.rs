//! Helpers shared by the integration tests: scenes from text, small renders.
#![allow(dead_code)] // each test binary uses its own subset

pub mod preview;

use std::path::Path;

use glam::Vec3;
use raydiance::film::Film;
use raydiance::image::Image;
use raydiance::integrator::{Path as PathTracer, Strategy};
use raydiance::progress::Silent;
use raydiance::render::{render, render_with};
use raydiance::scene::{Scene, build};

/// The walls of the course's Lab 4 box, for tests that set their own camera.
macro_rules! lab_walls {
    () => {
        r#"
plane { <1, 0, 0>, 1   material { diffuse rgb <0.8, 0.1, 0.1> } }
plane { <-1, 0, 0>, 1  material { diffuse rgb <0.1, 0.8, 0.1> } }
plane { <0, 1, 0>, 1   material { diffuse rgb 0.8 } }
plane { <0, -1, 0>, 1  material { diffuse rgb 0.8 } }
plane { <0, 0, -1>, 1  material { diffuse rgb 0.8 } }
"#
    };
}
pub const LAB_WALLS: &str = lab_walls!();

/// The lab box of the course's Lab 4 scene without lights or spheres, for tests to add to.
pub const LAB_BOX: &str = concat!(
    "\ncamera { origin <0, 0, -3.5>  left <-1, 0, 0>  up <0, 1, 0>  forward <0, 0, 3> }",
    lab_walls!()
);

/// Builds a scene from `.scn` text (as if read from `tests/inline.scn`).
pub fn scene(text: &str) -> Scene {
    let graph = raydiance::lang::parse_scene(Path::new("tests/inline.scn"), text)
        .unwrap_or_else(|e| panic!("test scene does not parse:\n{e}"));
    build(&graph).unwrap_or_else(|e| panic!("test scene does not build:\n{e}"))
}

pub fn scene_file(path: &str) -> Scene {
    let graph = raydiance::lang::load_scene(Path::new(path)).unwrap_or_else(|e| panic!("{e}"));
    build(&graph).unwrap_or_else(|e| panic!("{e}"))
}

/// Renders with the scene's own settings.
pub fn render_image(scene: &Scene) -> Image {
    render(scene, &Silent).0.image()
}

pub fn render_film(scene: &Scene) -> Film {
    render(scene, &Silent).0
}

pub fn max_abs_difference(a: &Image, b: &Image) -> f32 {
    assert_eq!((a.width, a.height), (b.width, b.height));
    a.pixels.iter().zip(&b.pixels).map(|(p, q)| (*p - *q).abs().max_element()).fold(0.0, f32::max)
}

pub fn mean(image: &Image) -> Vec3 {
    image.pixels.iter().sum::<Vec3>() / image.pixels.len() as f32
}

/// Whether an outside program a test runs (e.g. OpenEXR's `exrheader`) is on the PATH. Without it the test is skipped, with one line on the terminal saying so; under CI
/// (`CI=true`, where `.ci/run` installs it) its absence fails the test.
pub fn outside_tool(name: &str, package: &str, test: &str) -> bool {
    let found = std::env::var_os("PATH").is_some_and(|paths| {
        std::env::split_paths(&paths).any(|folder| folder.join(name).is_file())
    });
    if found {
        return true;
    }
    assert!(
        std::env::var("CI").as_deref() != Ok("true"),
        "{test}: `{name}` (Debian package `{package}`) must be installed under CI"
    );
    // Written to stderr directly: the test harness captures `eprintln!` of passing tests.
    use std::io::Write;
    let line = format!("skipped {test}: `{name}` is not installed (Debian package `{package}`)\n");
    let _ = std::io::stderr().write_all(line.as_bytes());
    false
}

/// The segment of the ray's line inside the box (slab test), if any.
pub fn clip(ray: &raydiance::geometry::Ray, min: Vec3, max: Vec3) -> Option<(f32, f32)> {
    let (o, d) = (Vec3::from(ray.origin), Vec3::from(ray.dir));
    let (t0, t1) = ((min - o) / d, (max - o) / d);
    let (near, far) = (t0.min(t1).max_element(), t0.max(t1).min_element());
    (near <= far && far > 0.0).then_some((near.max(0.0), far))
}

/// Whether the ray meets `box { -1, 1 }` minus `sphere { 0, 1.3 }`, analytically: the ray's
/// segment in the cube is not all inside the sphere.
pub fn hits_carved_cube(ray: &raydiance::geometry::Ray) -> bool {
    let Some((t0, t1)) = clip(ray, -Vec3::ONE, Vec3::ONE) else { return false };
    let (o, d) = (Vec3::from(ray.origin), Vec3::from(ray.dir));
    let b = o.dot(d);
    let disc = b * b - (o.length_squared() - 1.69);
    if disc < 0.0 {
        return true;
    }
    let (s0, s1) = (-b - disc.sqrt(), -b + disc.sqrt());
    t0 < s0 || t1 > s1
}

/// The fraction of pixel (x, y) of a `width` x `height` image, widened by `margin` pixels on each
/// side, whose pinhole rays `hits`, on a 12 x 12 grid.
pub fn pixel_coverage(
    camera: &raydiance::camera::Camera,
    (x, y): (usize, usize),
    (width, height): (usize, usize),
    margin: f32,
    hits: impl Fn(&raydiance::geometry::Ray) -> bool,
) -> f32 {
    let n = 12;
    let hits = (0..n * n).filter(|i| {
        let fraction = |k: usize| (k as f32 + 0.5) / n as f32;
        let u = x as f32 - margin + (1.0 + 2.0 * margin) * fraction(i % n);
        let v = y as f32 - margin + (1.0 + 2.0 * margin) * fraction(i / n);
        hits(&camera.ray(u / width as f32, v / height as f32, glam::Vec2::ZERO))
    });
    hits.count() as f32 / (n * n) as f32
}

/// An integrator one path at a time (`SampleIntegrator::radiance`, the scalar reference), not through
/// its own `radiance_of_all` (which may trace paths in lanes).
pub struct OneAtATime<'a, I>(pub &'a I);

impl<I: raydiance::integrator::SampleIntegrator> raydiance::integrator::SampleIntegrator
    for OneAtATime<'_, I>
{
    fn radiance(
        &self,
        scene: &Scene,
        ray: raydiance::geometry::Ray,
        sampler: &mut raydiance::sampling::Sampler,
    ) -> Vec3 {
        self.0.radiance(scene, ray, sampler)
    }
}

/// The shipped scenes (`mesh-heavy` when its generated mesh is there), sorted by file name, each
/// at 20 x 16 pixels and 4 samples per pixel, with its file's name.
pub fn small_shipped_scenes() -> Vec<(String, Scene)> {
    let mut files: Vec<_> = std::fs::read_dir("scenes")
        .unwrap()
        .map(|entry| entry.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "scn"))
        .filter(|p| !p.ends_with("mesh-heavy.scn") || Path::new("scenes/data/bumpy.ply").exists())
        .collect();
    files.sort();
    assert!(files.len() >= 8, "{files:?}");
    let small = |file: &std::path::PathBuf| {
        let mut scene = scene_file(file.to_str().unwrap());
        scene.settings.width = 20;
        scene.settings.height = 16;
        scene.settings.samples = 4;
        (file.display().to_string(), scene)
    };
    files.iter().map(small).collect()
}

/// A PPM as another program (Debian's `povray`) writes it: its size, the largest stored value,
/// and every sample divided by that value, in [0, 1].
pub struct Ppm {
    pub width: usize,
    pub height: usize,
    pub max: u32,
    pub samples: Vec<f32>,
}

/// Reads a binary (P6, one or two bytes a sample, big-endian) or plain (P3) PPM.
pub fn read_ppm(path: &Path) -> Ppm {
    let data = std::fs::read(path).unwrap();
    let mut tokens = Vec::new();
    let mut i = 0;
    while tokens.len() < 4 {
        while data[i].is_ascii_whitespace() {
            i += 1;
        }
        if data[i] == b'#' {
            while data[i] != b'\n' {
                i += 1;
            }
            continue;
        }
        let start = i;
        while !data[i].is_ascii_whitespace() {
            i += 1;
        }
        tokens.push(String::from_utf8(data[start..i].to_vec()).unwrap());
    }
    let [width, height, max] = [1, 2, 3].map(|k| tokens[k].parse::<usize>().unwrap());
    let scale = max as f32;
    let samples = match tokens[0].as_str() {
        "P6" if max < 256 => data[i + 1..].iter().map(|&b| f32::from(b) / scale).collect(),
        "P6" => data[i + 1..]
            .chunks_exact(2)
            .map(|b| f32::from(u16::from_be_bytes([b[0], b[1]])) / scale)
            .collect(),
        "P3" => {
            let text: String = String::from_utf8(data[i..].to_vec()).unwrap();
            let lines = text.lines().filter(|l| !l.starts_with('#'));
            lines
                .flat_map(str::split_whitespace)
                .map(|n| n.parse::<f32>().unwrap() / scale)
                .collect()
        }
        other => panic!("not a PPM: {other}"),
    };
    Ppm { width, height, max: max as u32, samples }
}

/// The path tracer with `strategy` for its light (light samples, BSDF samples or both).
pub fn path_with(scene: &Scene, strategy: Strategy) -> Film {
    render_with(scene, &PathTracer { max_depth: scene.settings.max_depth, strategy }, &Silent).0
}

/// `path` with light samples alone and with BSDF samples alone each agree with MIS
/// (`assert_films_agree`): the light through every path is counted once.
pub fn assert_light_and_bsdf_sampling_agree_with_mis(scene: &Scene, what: &str) {
    let mis = path_with(scene, Strategy::Mis);
    for (strategy, name) in
        [(Strategy::LightSampling, "light sampling"), (Strategy::BsdfSampling, "BSDF sampling")]
    {
        assert_films_agree(&path_with(scene, strategy), &mis, &format!("{what}: {name} vs MIS"));
    }
}

/// The mean over all pixels of a film whose pixels all estimate `expected`, checked against a
/// bound of 5 standard errors (from the film's own variance estimate).
pub fn assert_uniform_radiance(film: &Film, expected: Vec3, what: &str) {
    let n = film.sum.len() as f32;
    let image = film.image();
    let mean = image.pixels.iter().sum::<Vec3>() / n;
    let standard_error = (film.variance_of_mean().iter().sum::<Vec3>() / (n * n)).map(f32::sqrt);
    let deviation = (mean - expected).abs();
    assert!(
        deviation.cmple(5.0 * standard_error + 1e-6 * expected).all(),
        "{what}: mean {mean}, expected {expected}, standard error {standard_error}"
    );
    assert!(
        standard_error.max_element() < 0.02 * expected.max_element(),
        "{what}: too noisy to tell"
    );
}

/// Two estimators of the same image agree: few channels beyond 4 standard errors, and the
/// image means within 2 %.
pub fn assert_films_agree(a: &Film, b: &Film, what: &str) {
    let (ia, ib) = (a.image(), b.image());
    let (va, vb) = (a.variance_of_mean(), b.variance_of_mean());
    let mut outliers = 0;
    for i in 0..ia.pixels.len() {
        let z = (ia.pixels[i] - ib.pixels[i]).abs()
            / (va[i] + vb[i]).map(f32::sqrt).max(Vec3::splat(1e-6));
        outliers += z.to_array().iter().filter(|&&z| z > 4.0).count();
    }
    let channels = 3 * ia.pixels.len();
    assert!(outliers * 200 < channels, "{what}: {outliers} of {channels} channels beyond 4 sigma");
    let (ma, mb) = (mean(&ia), mean(&ib));
    assert!((ma - mb).abs().max_element() < 0.02 * ma.max_element(), "{what}: {ma} vs {mb}");
}

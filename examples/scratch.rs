use glam::Vec3;
use raydiance::diagnostic::{SourceFile, Span};
use raydiance::scene::graph::*;
use std::path::PathBuf;
use std::sync::Arc;

fn main() {
    let file = Arc::new(SourceFile { path: PathBuf::from("x.scn"), text: String::new() });
    let span = Span { file, line: 1, col: 1 };
    let mat = |kd: Vec3, ks: Vec3, kt: Vec3, le: Vec3, fresnel: bool| {
        Some(Arc::new(MaterialDesc {
            name: None,
            diffuse: kd,
            specular: ks,
            transmission: kt,
            ior: 1.5,
            emission: le,
            fresnel,
            span: span.clone(),
        }))
    };
    let z = Vec3::ZERO;
    let obj = |shape, m| ObjectNode { shape, material: m, transforms: vec![], span: span.clone() };
    let which = std::env::args().nth(1).unwrap_or_default();
    let mut objects = vec![
        obj(
            ShapeNode::Plane { normal: Vec3::X, offset: 1.0 },
            mat(Vec3::new(0.8, 0.1, 0.1), z, z, z, false),
        ),
        obj(
            ShapeNode::Plane { normal: -Vec3::X, offset: 1.0 },
            mat(Vec3::new(0.1, 0.8, 0.1), z, z, z, false),
        ),
        obj(
            ShapeNode::Plane { normal: Vec3::Y, offset: 1.0 },
            mat(Vec3::splat(0.8), z, z, z, false),
        ),
        obj(
            ShapeNode::Plane { normal: -Vec3::Y, offset: 1.0 },
            mat(Vec3::splat(0.8), z, z, z, false),
        ),
        obj(
            ShapeNode::Plane { normal: -Vec3::Z, offset: 1.0 },
            mat(Vec3::splat(0.8), z, z, z, false),
        ),
    ];
    let mut lights = vec![];
    let integrator;
    if which == "s4" || which == "s3" || which == "s5" {
        objects.push(obj(
            ShapeNode::Quad {
                corner: Vec3::new(-0.25, 0.99, -0.25),
                edge1: Vec3::new(0.5, 0., 0.),
                edge2: Vec3::new(0., 0., 0.5),
            },
            mat(z, z, z, Vec3::splat(10.0), false),
        ));
        integrator = IntegratorKind::Path;
    } else {
        lights.push(PointLightDesc {
            position: Vec3::new(0., 0.5, 0.),
            power: Vec3::ONE,
            span: span.clone(),
        });
        integrator = if which == "s2" { IntegratorKind::Path } else { IntegratorKind::Direct };
    }
    if which == "s4" {
        objects.push(obj(
            ShapeNode::Sphere { center: Vec3::new(-0.5, -0.7, 0.25), radius: 0.3 },
            mat(z, Vec3::splat(0.9), z, z, false),
        ));
        objects.push(obj(
            ShapeNode::Sphere { center: Vec3::new(0.5, -0.7, -0.25), radius: 0.3 },
            mat(z, z, Vec3::ONE, z, true),
        ));
    } else {
        objects.push(obj(
            ShapeNode::Sphere { center: Vec3::new(-0.5, -0.7, 0.25), radius: 0.3 },
            mat(Vec3::new(0.2, 0.4, 0.8), z, z, z, false),
        ));
        if which == "s5" {
            objects.push(obj(
                ShapeNode::Mesh { path: "/work/shared/data/bunny.ply".into() },
                mat(Vec3::new(0.8, 0.7, 0.2), z, z, z, false),
            ));
        } else if which == "s6" {
            objects.pop();
            objects.push(obj(
                ShapeNode::Mesh { path: "/work/shared/data/bumpy.ply".into() },
                mat(Vec3::splat(0.8), z, z, z, false),
            ));
        } else {
            objects.push(obj(
                ShapeNode::Sphere { center: Vec3::new(0.5, -0.7, -0.25), radius: 0.3 },
                mat(Vec3::new(0.8, 0.7, 0.2), z, z, z, false),
            ));
        }
    }
    let spp: u32 = std::env::args().nth(2).map(|s| s.parse().unwrap()).unwrap_or(16);
    let graph = SceneGraph {
        settings: Settings { samples: spp, integrator, ..Settings::default() },
        camera: CameraDesc {
            form: CameraForm::Lab {
                origin: Vec3::new(0., 0., -3.5),
                left: -Vec3::X,
                up: Vec3::Y,
                forward: Vec3::new(0., 0., 3.),
            },
            aperture: 0.0,
            focal_distance: None,
            span: span.clone(),
        },
        lights,
        objects,
    };
    let t = std::time::Instant::now();
    let scene = raydiance::scene::build(&graph).unwrap();
    let build = t.elapsed().as_secs_f64();
    let (film, stats) = raydiance::render::render(&scene, &raydiance::render::Silent);
    println!(
        "{which}: build {build:.3}s render {:.3}s {:.2} Msamples/s",
        stats.seconds,
        stats.samples_per_second(&film) / 1e6
    );
    let img = film.image();
    let bytes: Vec<u8> = img
        .pixels
        .iter()
        .flat_map(|p| {
            p.to_array().map(|c| (c.clamp(0.0, 1.0).powf(1.0 / 2.2) * 255.0).round() as u8)
        })
        .collect();
    image::save_buffer(format!("/tmp/{which}.png"), &bytes, 256, 256, image::ColorType::Rgb8)
        .unwrap();
}

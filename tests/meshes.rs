//! Meshes: PLY (ASCII, binary) and OBJ files give the same surface as the `box` primitive, real
//! data loads with its counts, bad files give located errors, instances share one mesh.

use crate::common;

use common::{LAB_BOX, max_abs_difference, render_image, scene};
use raydiance::geometry::Shape;

fn render_with(object: &str) -> raydiance::image::Image {
    render_image(&scene(&format!(
        "{LAB_BOX}
         settings {{ resolution 32, 32  samples 4  integrator direct }}
         light_source {{ <0.3, 0.6, -0.8>  power rgb 1 }}
         {object}"
    )))
}

#[test]
fn a_cube_as_ply_and_obj_renders_as_the_box_primitive() {
    let material = "material { diffuse rgb <0.7, 0.5, 0.3> }";
    let reference =
        render_with(&format!("box {{ <-0.3, -1, -0.3>, <0.3, -0.4, 0.3>  {material} }}"));
    let seen = reference.pixels.iter().filter(|p| (p.x - p.z).abs() > 0.01).count();
    assert!(seen > 20, "the cube covers pixels ({seen})");
    for file in ["cube.obj", "cube_ascii.ply", "cube_binary.ply"] {
        // tests/inline.scn is the scene's path, so mesh paths are relative to tests/.
        let image = render_with(&format!("mesh {{ \"meshes/{file}\"  {material} }}"));
        let difference = max_abs_difference(&reference, &image);
        assert!(difference < 1e-4, "{file} differs by {difference}");
    }
}

#[test]
fn the_bunny_loads_with_its_counts() {
    let mesh = raydiance::mesh::load(std::path::Path::new("scenes/data/bunny.ply")).unwrap();
    assert_eq!(mesh.positions.len(), 1839);
    assert_eq!(mesh.triangles.len(), 3674);
    assert!(mesh.normals.is_none(), "flat shaded");
}

#[test]
fn malformed_meshes_give_errors_that_say_where() {
    for (file, expected) in [
        ("bad_index.obj", "meshes/bad_index.obj: line 3: vertex index 3 is out of range"),
        (
            "bad_index.ply",
            "meshes/bad_index.ply: face 0 uses vertex 7, but there are only 3 vertices",
        ),
        (
            "truncated.ply",
            "meshes/truncated.ply: vertex 5: the file ends too early (at byte 68 of the data)",
        ),
        (
            "not_finite.obj",
            "meshes/not_finite.obj: vertex 1 has a coordinate that is not a finite number",
        ),
    ] {
        let text =
            format!("{} mesh {{ \"meshes/{file}\" }}", &LAB_BOX[..LAB_BOX.find("plane").unwrap()]);
        let graph =
            raydiance::lang::parse_scene(std::path::Path::new("tests/inline.scn"), &text).unwrap();
        let error = raydiance::scene::build(&graph).unwrap_err().to_string();
        assert!(error.contains(expected), "{file}:\n{error}");
        assert!(error.starts_with("tests/inline.scn:"), "located at the mesh statement:\n{error}");
    }
}

#[test]
fn instances_share_one_mesh() {
    let instances: String = (0..100)
        .map(|i| format!("object {{ Bunny translate <{}, 0, {}> }}\n", i % 10, i / 10))
        .collect();
    let s = scene(&format!(
        "camera {{ location <5, 3, -10>  look_at <5, 0, 5> }}
         #declare Bunny = mesh {{ \"../scenes/data/bunny.ply\" }}
         {instances}"
    ));
    let meshes: Vec<_> = s
        .primitives
        .iter()
        .filter_map(|p| match &p.shape {
            Shape::Mesh { mesh, .. } => Some(mesh.clone()),
            _ => None,
        })
        .collect();
    assert_eq!(meshes.len(), 100);
    assert!(meshes.iter().all(|m| std::sync::Arc::ptr_eq(m, &meshes[0])), "one mesh, shared");
    assert_eq!(meshes[0].triangle_count(), 3674);
}

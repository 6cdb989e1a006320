//! The scene's environment light: `.scn`'s `background` (a constant sky) or POV-Ray's
//! `sky_sphere` (a pigment over directions), bounded by a sphere around what photons from it
//! must reach.

use std::path::Path;
use std::sync::Arc;

use glam::{Mat3, Vec3};

use crate::aabb::Aabb;
use crate::diagnostic::SceneError;
use crate::graph::{SceneGraph, compose};
use crate::light::Environment;
use crate::texture::{ImageMap, Texture};

/// The environment light of `graph`, if it has a sky that shines: its sphere bounds `bounds`
/// (the bounded primitives') and the camera at `eye`, so that photons from the sky reach what
/// the camera sees near it.
pub fn environment(
    graph: &SceneGraph,
    bounds: &[Aabb],
    eye: Vec3,
) -> Result<Option<Environment>, SceneError> {
    let extent = bounds.iter().fold(Aabb::EMPTY.grow(eye), |all, b| all.union(*b));
    let centre = extent.centroid();
    // A scene of planes only, seen from one point, has no extent: a unit sphere around it.
    let radius = extent.extent().length() / 2.0;
    let radius = if radius > 0.0 { radius } else { 1.0 };
    let sky = match &graph.sky {
        Some(sky) => {
            let mut load = |path: &Path| ImageMap::load(path).map(Arc::new);
            let pigment = Texture::new(&sky.pigment, &mut load).map_err(|e| {
                SceneError::at(&sky.span, format!("cannot read the image_map: {e}"))
            })?;
            let to_sky = Mat3::from(compose(&sky.transforms).matrix3).inverse();
            Environment::textured(pigment, to_sky, sky.emission, centre, radius)
        }
        None => Environment::constant(graph.settings.background, centre, radius),
    };
    Ok((sky.integral().max_element() > 0.0).then_some(sky))
}

//! The part of a material that varies over a surface, evaluated at each hit in the object's
//! own space (`Scene::material`): the `diffuse` texture, or a POV-Ray pigment's colour with its
//! filter and transmit, from which the lobes' shares are made there (`material::pov_shares`),
//! and its glow.

use std::path::Path;
use std::sync::Arc;

use glam::Vec3;

use crate::graph::{MaterialDesc, Pattern, PovFinish};
use crate::light::pov_glow;
use crate::material::{Material, pov_shares};
use crate::texture::{ImageMap, ImageMapError, Texture};

#[derive(Debug, Clone)]
pub struct SurfaceTexture {
    /// `diffuse`, or the pigment's colour (shared with the area light of a glowing pigment).
    colour: Arc<Texture>,
    pigment: Option<SeeThrough>,
}

/// A POV-Ray pigment's filter and filter + transmit, its finish, and its glow (`PigmentDesc`).
#[derive(Debug, Clone)]
struct SeeThrough {
    filter: Texture,
    /// Shared with the area light of a glowing pigment, as `colour` is.
    through: Arc<Texture>,
    finish: PovFinish,
    glow: Vec3,
}

impl SurfaceTexture {
    /// The textures of `desc`, if any part of it varies over the surface; `load` reads images.
    pub fn new(
        desc: &MaterialDesc,
        load: &mut dyn FnMut(&Path) -> Result<Arc<ImageMap>, ImageMapError>,
    ) -> Result<Option<SurfaceTexture>, ImageMapError> {
        let pigment = match &desc.pigment {
            Some(p) => Some(SeeThrough {
                filter: Texture::new(&p.filter, load)?,
                through: Arc::new(Texture::new(&p.through, load)?),
                finish: p.finish,
                glow: p.glow,
            }),
            None if matches!(desc.diffuse.pattern, Pattern::Solid(_)) => return Ok(None),
            None => None,
        };
        let colour = Arc::new(Texture::new(&desc.diffuse, load)?);
        Ok(Some(SurfaceTexture { colour, pigment }))
    }

    /// A glowing pigment's pattern: its glow, colour and light through (`light::pov_glow`).
    pub fn glow(&self) -> Option<(Vec3, Arc<Texture>, Arc<Texture>)> {
        let pigment = self.pigment.as_ref()?;
        (pigment.glow.max_element() > 0.0)
            .then(|| (pigment.glow, Arc::clone(&self.colour), Arc::clone(&pigment.through)))
    }

    /// Fills in `material` at `p`, a point in the object's own space.
    #[inline]
    pub fn apply(&self, material: &mut Material, p: Vec3) {
        let colour = self.colour.eval(p);
        let Some(pigment) = &self.pigment else {
            material.diffuse = colour;
            return;
        };
        let filter = pigment.filter.grey(p);
        let through = pigment.through.grey(p);
        material.share(pov_shares(&pigment.finish, colour, filter, through));
        material.emission = pov_glow(pigment.glow, colour, through);
    }
}

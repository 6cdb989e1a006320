//! POV-Ray's `image_map { [type] "file" options }` in a pigment (`.pov`): the image's colour,
//! and its filter and transmit (`filter all`, `transmit all`, the file's alpha, and all light
//! through outside a `once` image), projected as `map_type` says (`docs/povray.md`).

use std::path::{Path, PathBuf};

use super::Evaluator;
use super::pigment::Pigment;
use crate::diagnostic::{SceneError, Span};
use crate::graph::{ImageChannel, ImageLook, ImageProjection, Pattern, TextureNode};
use crate::lang::syntax::{Expr, Item};
use crate::texture::ImageMap;

/// The file types POV-Ray finds a name without extension by, in its order of search.
const EXTENSIONS: [&str; 3] = ["png", "jpg", "jpeg"];

impl Evaluator {
    pub(super) fn image_pigment(
        &mut self,
        file: &Expr,
        options: &[Item],
        span: &Span,
    ) -> Result<Pigment, SceneError> {
        let name = self.string(file, "`image_map`")?;
        let path = self.image_file(&file.span.file.path, &name);
        if !path.is_file() {
            return Err(SceneError::at(&file.span, super::not_found(&name, &path)));
        }
        let mut look = ImageLook::colour();
        let (mut filter, mut transmit) = (0.0, 0.0);
        for option in options {
            let Item::PovParam { key, value, .. } = option else {
                return Err(SceneError::at(
                    option.span(),
                    format!("{} cannot stand in an image_map", option.describe()),
                ));
            };
            let value = value.as_ref().map(|v| &v.value);
            let needs =
                |what: &str| SceneError::at(&key.span, format!("`{}` needs {what}", key.name));
            match key.name.as_str() {
                "map_type" => {
                    let v = value.ok_or_else(|| needs("a number"))?;
                    look.projection = match self.integer(v, 0, 7)? {
                        0 => ImageProjection::Planar,
                        1 => ImageProjection::Spherical,
                        2 => ImageProjection::Cylindrical,
                        5 => ImageProjection::Torus,
                        other => {
                            return Err(SceneError::at(
                                &v.span,
                                format!(
                                    "`map_type {other}`: an image_map is projected planar (0), \
                                     spherical (1), cylindrical (2) or toroidal (5), as in \
                                     POV-Ray 3.7, which refuses the other values too"
                                ),
                            ));
                        }
                    };
                }
                "once" => look.once = true,
                // POV-Ray's 2 is bilinear; its 3 (bicubic) and 4 (normalised distance) are
                // smooth too, read as bilinear (docs/povray.md).
                "interpolate" => {
                    let v = value.ok_or_else(|| needs("a number"))?;
                    look.bilinear = self.integer(v, 0, 4)? >= 2;
                }
                "gamma" => {
                    let v = value.ok_or_else(|| needs("a value"))?;
                    look.gamma = Some(self.positive(v, "the image's gamma")?);
                }
                "filter all" => filter = self.unit(value.ok_or_else(|| needs("a value"))?)?,
                "transmit all" => transmit = self.unit(value.ok_or_else(|| needs("a value"))?)?,
                // The default for images that are not palettes; a palette's colours are
                // read as colours too.
                "use_color" | "use_colour" => {}
                "filter" | "transmit" | "use_index" | "use_alpha" | "premultiplied" => {
                    return Err(SceneError::at(
                        &key.span,
                        format!(
                            "`{}`: raydiance reads an image_map's colours and alpha as they \
                             are, with `filter all` and `transmit all` over the whole image, \
                             not per palette entry (`filter N, V`), by index or premultiplied",
                            key.name
                        ),
                    ));
                }
                other => unreachable!("the grammar gives no image_map option `{other}`"),
            }
        }
        let alpha = ImageMap::has_alpha(&path)
            .map_err(|e| SceneError::at(span, format!("cannot read the image_map: {e}")))?;
        let node = |channel| {
            let pattern =
                Pattern::Image { path: path.clone(), look: ImageLook { channel, ..look } };
            TextureNode { pattern, transforms: Vec::new() }
        };
        let colour = node(ImageChannel::Colour);
        if !alpha && !look.once && filter == 0.0 && transmit == 0.0 {
            return Ok(Pigment::opaque(colour));
        }
        Ok(Pigment {
            colour,
            filter: node(ImageChannel::Filter(filter)),
            through: node(ImageChannel::Through(filter + transmit)),
        })
    }

    /// A value in [0, 1].
    fn unit(&mut self, expr: &Expr) -> Result<f32, SceneError> {
        let value = self.single(expr)?;
        if !(0.0..=1.0).contains(&value) {
            return Err(SceneError::at(&expr.span, format!("{value} is not in [0, 1]")));
        }
        Ok(value)
    }
}

impl Evaluator {
    /// The image file named: beside the scene, else in the include folders, else in POV-Ray's
    /// installed library (where its `test.png` is), as height fields and fonts are found; a name without extension that is nowhere is looked for
    /// with the image types' extensions (`image_map { "sign" }` finds `sign.jpg`).
    fn image_file(&self, from: &Path, name: &str) -> PathBuf {
        let find = |name: &str| {
            let local = super::resolve(from, name);
            if local.is_file() {
                return Some(local);
            }
            let folders = self.include_folders().into_iter().chain(super::text::povray_library());
            folders.map(|f| f.join(name)).find(|p| p.is_file())
        };
        let fallback = || {
            let bare = Path::new(name).extension().is_none();
            EXTENSIONS.iter().filter(|_| bare).find_map(|ext| find(&format!("{name}.{ext}")))
        };
        find(name).or_else(fallback).unwrap_or_else(|| super::resolve(from, name))
    }
}

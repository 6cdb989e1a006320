//! POV-Ray's `image_map { [type] "file" options }` in a pigment (`.pov`): the image's colour,
//! and its filter and transmit (`filter all`, `transmit all`, the file's alpha, and all light
//! through outside a `once` image), projected as `map_type` says (`docs/povray.md`); and
//! `bump_map { }` in a normal (both dialects), the image's gray as heights.

use std::path::{Path, PathBuf};

use super::Evaluator;
use super::pigment::Pigment;
use crate::diagnostic::{SceneError, Span};
use crate::graph::{ImageChannel, ImageLook, ImageProjection, NormalPattern, Pattern, TextureNode};
use crate::lang::syntax::{Expr, Item};
use crate::texture::ImageMap;

/// The file types POV-Ray finds a name without extension by, in its order of search.
const EXTENSIONS: [&str; 3] = ["png", "jpg", "jpeg"];

/// Which image a file and options stand for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum ImageUse {
    /// `image_map` in a pigment.
    Pigment,
    /// `bump_map` in a normal.
    Bump,
}

/// An image's file and options as read.
struct ImageOptions {
    path: PathBuf,
    look: ImageLook,
    filter: f32,
    transmit: f32,
    /// A bump_map's `bump_size`.
    bump_size: f32,
}

impl Evaluator {
    pub(super) fn image_pigment(
        &mut self,
        file: &Expr,
        options: &[Item],
        span: &Span,
    ) -> Result<Pigment, SceneError> {
        let ImageOptions { path, look, filter, transmit, .. } =
            self.image_options(file, options, ImageUse::Pigment)?;
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

    /// `bump_map { [type] "file" options }`: the image's gray (`use_index`: a palette image's
    /// indices) as heights, `bump_size` (1) the amount; always bilinear, so that the heights
    /// have a gradient between texel centres.
    pub(super) fn bump_image(
        &mut self,
        file: &Expr,
        options: &[Item],
    ) -> Result<NormalPattern, SceneError> {
        let ImageOptions { path, look, bump_size, .. } =
            self.image_options(file, options, ImageUse::Bump)?;
        Ok(NormalPattern::Image {
            path,
            look: ImageLook { bilinear: true, ..look },
            amount: bump_size,
        })
    }

    fn image_options(
        &mut self,
        file: &Expr,
        options: &[Item],
        used: ImageUse,
    ) -> Result<ImageOptions, SceneError> {
        let (word, a_word) = match used {
            ImageUse::Pigment => ("image_map", "an image_map"),
            ImageUse::Bump => ("bump_map", "a bump_map"),
        };
        let name = self.string(file, &format!("`{word}`"))?;
        let path = self.image_file(&file.span.file.path, &name);
        if !path.is_file() {
            return Err(SceneError::at(&file.span, super::not_found(&name, &path)));
        }
        let mut look = ImageLook::colour();
        let (mut filter, mut transmit, mut bump_size) = (0.0, 0.0, 1.0);
        for option in options {
            let Item::PovParam { key, value, .. } = option else {
                return Err(SceneError::at(
                    option.span(),
                    format!("{} cannot stand in {a_word}", option.describe()),
                ));
            };
            let value = value.as_ref().map(|v| &v.value);
            let needs =
                |what: &str| SceneError::at(&key.span, format!("`{}` needs {what}", key.name));
            let only_in = |other: &str| {
                SceneError::at(
                    &key.span,
                    format!("`{}` stands in {other}, not in {a_word}", key.name),
                )
            };
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
                                    "`map_type {other}`: {a_word} is projected planar (0), \
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
                "filter all" | "transmit all" if used == ImageUse::Bump => {
                    return Err(only_in("an image_map"));
                }
                "filter all" => filter = self.unit(value.ok_or_else(|| needs("a value"))?)?,
                "transmit all" => transmit = self.unit(value.ok_or_else(|| needs("a value"))?)?,
                "bump_size" if used == ImageUse::Pigment => return Err(only_in("a bump_map")),
                "bump_size" => bump_size = self.single(value.ok_or_else(|| needs("a value"))?)?,
                // The default for images that are not palettes; a palette's colours are
                // read as colours too.
                "use_color" | "use_colour" => look.channel = ImageChannel::Colour,
                // POV-Ray's bump_map: a palette image's indices as the heights.
                "use_index" if used == ImageUse::Bump => look.channel = ImageChannel::Index,
                "filter" | "transmit" | "use_index" | "use_alpha" | "premultiplied" => {
                    return Err(SceneError::at(
                        &key.span,
                        format!(
                            "`{}`: raydiance reads {a_word}'s colours and alpha as they \
                             are, with `filter all` and `transmit all` over the whole image, \
                             not per palette entry (`filter N, V`), by index or premultiplied",
                            key.name
                        ),
                    ));
                }
                other => unreachable!("the grammar gives no image option `{other}`"),
            }
        }
        Ok(ImageOptions { path, look, filter, transmit, bump_size })
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

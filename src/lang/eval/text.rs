//! `text { ttf "font.ttf" "string" thickness, offset }`: a union of the string's glyphs, each
//! the closed solid of its outline extruded from z = 0 to the thickness, shared by every
//! occurrence of the glyph.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::{Evaluator, resolve};
use crate::diagnostic::{SceneError, Span};
use crate::graph::{ObjectNode, ShapeNode, Transform};
use crate::lang::syntax::{Expr, FontName};
use crate::mesh::extrude::extrude;
use crate::mesh::font::Font;

/// POV-Ray 3.7's built-in fonts by `internal` number (an out-of-range number means 0); here
/// they are read from their files, found as any font is.
const INTERNAL_FONTS: [&str; 4] = ["povlogo.ttf", "timrom.ttf", "cyrvetic.ttf", "crystal.ttf"];

/// Where POV-Ray's own library is installed (Debian's `povray-includes` puts its fonts there):
/// searched last, so that a POV-Ray scene finds `timrom.ttf` as POV-Ray would.
const POVRAY_LIBRARY: [&str; 2] =
    ["/usr/share/povray-3.7/include", "/usr/local/share/povray-3.7/include"];

/// POV-Ray's installed library folders that exist here (searched after the include folders).
pub(super) fn povray_library() -> impl Iterator<Item = PathBuf> {
    POVRAY_LIBRARY.iter().map(PathBuf::from).filter(|f| f.is_dir())
}

/// Fonts larger than this are refused rather than read (the largest CJK fonts are ~20 MB).
const MAX_FONT_BYTES: u64 = 64 << 20;

impl Evaluator {
    /// The shape of a `text` object: a union of its glyphs placed along x.
    pub(super) fn text_shape(
        &mut self,
        font: &FontName,
        string: &Expr,
        thickness: &Expr,
        offset: &Expr,
        span: &Span,
    ) -> Result<ShapeNode, SceneError> {
        let (name, at) = match font {
            FontName::File(name) => (self.string(name, "`ttf`")?, &name.span),
            FontName::Internal(number) => {
                let n = self.number(number, "`internal`")?;
                let index =
                    if (0.0..INTERNAL_FONTS.len() as f64).contains(&n) { n as usize } else { 0 };
                (INTERNAL_FONTS[index].to_string(), &number.span)
            }
        };
        let string = self.string(string, "the text of `text`")?;
        let thickness = f64::from(self.positive(thickness, "the text's thickness")?);
        let offset = self.promoted_vector(offset, "the text's offset")?;
        let path = self.find_font(at, &name)?;
        let bytes = crate::input::read(&path, MAX_FONT_BYTES).map_err(|e| {
            SceneError::at(at, format!("cannot read the font `{}`: {e}", path.display()))
        })?;
        let font = Font::parse(bytes)
            .map_err(|e| SceneError::at(at, format!("`{}`: {e}", path.display())))?;
        let mut solids: HashMap<u16, Option<Arc<crate::mesh::Mesh>>> = HashMap::new();
        let mut glyphs = Vec::new();
        for placed in font.layout(&string, offset) {
            let solid = solids
                .entry(placed.glyph)
                .or_insert_with(|| extrude(&font.outline(placed.glyph), thickness).map(Arc::new));
            if let Some(solid) = solid {
                glyphs.push(ObjectNode {
                    shape: ShapeNode::Extrusion(solid.clone()),
                    material: None,
                    transforms: vec![Transform::Translate(placed.at.as_vec3())],
                    depth: 1,
                    span: span.clone(),
                });
            }
        }
        self.objects_made += glyphs.len() as u64;
        Ok(ShapeNode::Union(glyphs))
    }

    /// The font file `name` names where the scene at `at` writes it: `name` and, as POV-Ray
    /// does, `name.ttf`, where `find_in_library` looks.
    fn find_font(&self, at: &Span, name: &str) -> Result<PathBuf, SceneError> {
        self.find_in_library(at, &[name.to_string(), format!("{name}.ttf")], "the font")
    }

    /// The file named `names[0]` (or one of the other spellings in `names`) where the scene at
    /// `at` writes it: beside the scene, then in the include folders (as `#include` searches),
    /// then in POV-Ray's installed library. `what` names the file in the error.
    pub(super) fn find_in_library(
        &self,
        at: &Span,
        names: &[String],
        what: &str,
    ) -> Result<PathBuf, SceneError> {
        let scene_folder = resolve(&at.file.path, "");
        let mut folders = vec![scene_folder];
        folders.extend(self.include_folders());
        folders.extend(povray_library());
        let found = folders
            .iter()
            .flat_map(|folder| names.iter().map(move |name| folder.join(name)))
            .find(|path| path.is_file());
        found.ok_or_else(|| {
            let searched: Vec<String> = folders.iter().map(|f| display(f)).collect();
            SceneError::at(
                at,
                format!(
                    "cannot find {what} `{}`: it is in none of {} (the scene's folder, \
                     --include-path, RAYDIANCE_INCLUDE_PATH and POV-Ray's library)",
                    names[0],
                    searched.join(", ")
                ),
            )
        })
    }
}

/// A folder as a message names it: `.` for the current one.
fn display(folder: &Path) -> String {
    if folder.as_os_str().is_empty() { ".".to_string() } else { folder.display().to_string() }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use glam::Vec3;

    use crate::graph::{ObjectNode, ShapeNode, Transform};
    use crate::lang::{Frame, load_scene_with, parse_scene};

    /// The folder of the tests' font, `blocks.ttf` (`tests/fonts/make_blocks.py`).
    fn fonts() -> std::path::PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fonts")
    }

    fn text_of(scene: &str) -> Result<ObjectNode, String> {
        let graph = parse_scene(&fonts().join("scene.pov"), scene).map_err(|e| e.to_string())?;
        Ok(graph.objects.into_iter().next().expect("the text"))
    }

    /// The bounds of a text's glyphs, each solid moved to its place.
    fn bounds(text: &ObjectNode) -> (Vec3, Vec3) {
        let ShapeNode::Union(glyphs) = &text.shape else { panic!("a union of glyphs") };
        let mut bounds = (Vec3::MAX, Vec3::MIN);
        for glyph in glyphs {
            let (ShapeNode::Extrusion(mesh), [Transform::Translate(at)]) =
                (&glyph.shape, glyph.transforms.as_slice())
            else {
                panic!("a placed glyph")
            };
            for &p in &mesh.positions {
                bounds = (bounds.0.min(p + *at), bounds.1.max(p + *at));
            }
        }
        bounds
    }

    #[test]
    fn a_text_spans_its_glyphs_advances() {
        // I at 0 (outline 0.1 to 0.3), O at 0.35 after the kerning, D at 1.15 (to 1.15 + 0.7).
        let text = text_of("text { ttf \"blocks.ttf\" \"IOD\" 0.25, 0 }").unwrap();
        let (low, high) = bounds(&text);
        assert!((low - Vec3::new(0.1, 0.0, 0.0)).length() < 1e-6, "{low}");
        assert!((high - Vec3::new(1.85, 0.7, 0.25)).length() < 1e-6, "{high}");
        // The offset adds to every advance; the name may leave out `.ttf`, as in POV-Ray.
        let text = text_of("text { ttf \"blocks\" \"IOD\" 1, <0.1, 0.2, 0> }").unwrap();
        let (low, high) = bounds(&text);
        assert!((low - Vec3::new(0.1, 0.0, 0.0)).length() < 1e-6, "{low}");
        assert!((high - Vec3::new(2.05, 1.1, 1.0)).length() < 1e-6, "{high}");
        // Spaces have no solid; the two Is share one.
        let text = text_of("text { ttf \"blocks.ttf\" \"I I\" 1, 0 }").unwrap();
        let ShapeNode::Union(glyphs) = &text.shape else { panic!("a union") };
        let [ShapeNode::Extrusion(a), ShapeNode::Extrusion(b)] =
            [&glyphs[0].shape, &glyphs[1].shape]
        else {
            panic!("two glyphs")
        };
        assert!(glyphs.len() == 2 && std::sync::Arc::ptr_eq(a, b));
    }

    #[test]
    fn a_text_is_a_solid_for_csg() {
        let scene = "difference { box { <0, -1, -1>, <3, 2, 0.5> } \
                     text { ttf \"blocks.ttf\" \"OID\" 1, 0 translate <0.1, 0, -0.5> } }";
        let graph = parse_scene(&fonts().join("scene.pov"), scene).unwrap();
        crate::scene::build(&graph).unwrap_or_else(|e| panic!("{e}"));
    }

    #[test]
    fn fonts_are_found_on_the_include_path_and_errors_say_where_they_looked() {
        let folder = tempfile::tempdir().unwrap();
        let scene = folder.path().join("scene.pov");
        std::fs::write(&scene, "text { ttf \"blocks.ttf\" \"O\" 1, 0 }").unwrap();
        let load = |include: &[std::path::PathBuf]| {
            load_scene_with(&scene, Frame::default(), None, include).map_err(|e| e.to_string())
        };
        assert!(load(&[fonts()]).is_ok());
        let error = load(&[]).unwrap_err();
        assert!(error.starts_with(&format!("{}:1:12:", scene.display())), "{error}");
        assert!(error.contains("cannot find the font `blocks.ttf`"), "{error}");
        assert!(error.contains(&folder.path().display().to_string()), "{error}");

        std::fs::write(folder.path().join("bad.ttf"), "not a font").unwrap();
        std::fs::write(&scene, "text { ttf \"bad.ttf\" \"O\" 1, 0 }").unwrap();
        let error = load(&[]).unwrap_err();
        assert!(error.starts_with(&format!("{}:1:12:", scene.display())), "{error}");
        assert!(error.contains("bad.ttf`: not a TrueType or OpenType font"), "{error}");
    }

    #[test]
    fn a_thickness_must_be_positive() {
        let error = text_of("text { ttf \"blocks.ttf\" \"O\" 0, 0 }").unwrap_err();
        assert!(error.contains("the text's thickness 0 is zero"), "{error}");
    }
}

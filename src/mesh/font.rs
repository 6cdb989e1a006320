//! TrueType and OpenType fonts (`.ttf`, `.otf`, the first font of a `.ttc`): glyph outlines as
//! flat contours and the placing of a string's glyphs, in units of the font's em (POV-Ray's
//! `text`: one unit of height per em, the baseline along x).

use glam::{DVec2, DVec3};
use ttf_parser::{Face, GlyphId, OutlineBuilder};

/// Curves are cut into straight segments until they stray from the curve by at most this
/// fraction of an em (a thousandth: invisible on a letter filling the image).
const TOLERANCE: f64 = 1e-3;

/// No curve is cut into more segments than this, however large its control points.
const MAX_SEGMENTS: u32 = 64;

/// A font file's contents, checked to be a font.
#[derive(Debug)]
pub struct Font {
    data: Vec<u8>,
}

/// Bytes that are not a font raydiance can read.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum FontError {
    #[error("not a TrueType or OpenType font: {0}")]
    NotAFont(#[from] ttf_parser::FaceParsingError),
    #[error("the font's em is 0 units")]
    NoEm,
}

/// A glyph of a string and where its origin goes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlacedGlyph {
    pub glyph: u16,
    pub at: DVec3,
}

impl Font {
    /// The font in `data`, or why it is not one.
    pub fn parse(data: Vec<u8>) -> Result<Font, FontError> {
        let face = Face::parse(&data, 0)?;
        if face.units_per_em() == 0 {
            return Err(FontError::NoEm);
        }
        Ok(Font { data })
    }

    fn face(&self) -> Face<'_> {
        Face::parse(&self.data, 0).expect("checked by Font::parse")
    }

    /// The glyphs of `text` from the origin along x: each glyph after the one before by its
    /// advance width and the font's kerning (its `kern` table) of the pair, plus `offset`
    /// (POV-Ray's extra spacing between characters). A character the font lacks is its
    /// missing-glyph (glyph 0), as POV-Ray draws it.
    pub fn layout(&self, text: &str, offset: DVec3) -> Vec<PlacedGlyph> {
        let face = self.face();
        let em = f64::from(face.units_per_em());
        let glyphs: Vec<GlyphId> =
            text.chars().map(|c| face.glyph_index(c).unwrap_or(GlyphId(0))).collect();
        let mut at = DVec3::ZERO;
        let mut placed = Vec::with_capacity(glyphs.len());
        for (i, &glyph) in glyphs.iter().enumerate() {
            placed.push(PlacedGlyph { glyph: glyph.0, at });
            let advance = f64::from(face.glyph_hor_advance(glyph).unwrap_or(0));
            let kerning = glyphs.get(i + 1).map_or(0.0, |&next| kerning(&face, glyph, next));
            at += DVec3::new((advance + kerning) / em, 0.0, 0.0) + offset;
        }
        placed
    }

    /// The closed contours of a glyph, in ems (none for a glyph without an outline, such as a
    /// space).
    pub fn outline(&self, glyph: u16) -> Vec<Vec<DVec2>> {
        let face = self.face();
        let mut flattener = Flattener {
            scale: 1.0 / f64::from(face.units_per_em()),
            contours: Vec::new(),
            current: Vec::new(),
        };
        face.outline_glyph(GlyphId(glyph), &mut flattener);
        flattener.close();
        flattener.contours
    }
}

/// The horizontal kerning of a pair in font units, summed over the `kern` table's subtables.
fn kerning(face: &Face, left: GlyphId, right: GlyphId) -> f64 {
    let Some(table) = face.tables().kern else { return 0.0 };
    table
        .subtables
        .into_iter()
        .filter(|s| s.horizontal && !s.has_cross_stream)
        .filter_map(|s| s.glyphs_kerning(left, right))
        .map(f64::from)
        .sum()
}

/// Collects an outline as polygons: each curve replaced by points along it.
struct Flattener {
    scale: f64,
    contours: Vec<Vec<DVec2>>,
    current: Vec<DVec2>,
}

impl Flattener {
    fn point(&self, x: f32, y: f32) -> DVec2 {
        DVec2::new(f64::from(x), f64::from(y)) * self.scale
    }

    fn last(&self) -> DVec2 {
        self.current.last().copied().unwrap_or(DVec2::ZERO)
    }

    /// Points along `curve(t)` for t in (0, 1], `segments` of them.
    fn follow(&mut self, segments: u32, curve: impl Fn(f64) -> DVec2) {
        let segments = segments.clamp(1, MAX_SEGMENTS);
        self.current.extend((1..=segments).map(|i| curve(f64::from(i) / f64::from(segments))));
    }
}

/// Segments enough that straight lines stray at most `TOLERANCE` from a curve whose second
/// derivative is at most `bend`: a chord over a parameter step h strays at most bend h² / 8.
fn segments_for(bend: f64) -> u32 {
    (bend / (8.0 * TOLERANCE)).sqrt().ceil() as u32
}

impl OutlineBuilder for Flattener {
    fn move_to(&mut self, x: f32, y: f32) {
        self.close();
        self.current.push(self.point(x, y));
    }

    fn line_to(&mut self, x: f32, y: f32) {
        self.current.push(self.point(x, y));
    }

    fn quad_to(&mut self, x1: f32, y1: f32, x: f32, y: f32) {
        let (p0, p1, p2) = (self.last(), self.point(x1, y1), self.point(x, y));
        let bend = 2.0 * (p0 - 2.0 * p1 + p2).length();
        self.follow(segments_for(bend), |t| {
            let s = 1.0 - t;
            s * s * p0 + 2.0 * s * t * p1 + t * t * p2
        });
    }

    fn curve_to(&mut self, x1: f32, y1: f32, x2: f32, y2: f32, x: f32, y: f32) {
        let (p0, p1, p2, p3) =
            (self.last(), self.point(x1, y1), self.point(x2, y2), self.point(x, y));
        // The second derivative is linear in t: largest at an end.
        let bend = 6.0 * (p0 - 2.0 * p1 + p2).length().max((p1 - 2.0 * p2 + p3).length());
        self.follow(segments_for(bend), |t| {
            let s = 1.0 - t;
            s * s * s * p0 + 3.0 * s * s * t * p1 + 3.0 * s * t * t * p2 + t * t * t * p3
        });
    }

    fn close(&mut self) {
        if !self.current.is_empty() {
            self.contours.push(std::mem::take(&mut self.current));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The tests' font (`tests/fonts/make_blocks.py` tells its glyphs).
    const BLOCKS: &[u8] = include_bytes!("../../tests/fonts/blocks.ttf");

    fn blocks() -> Font {
        Font::parse(BLOCKS.to_vec()).expect("a font")
    }

    fn xs(placed: &[PlacedGlyph]) -> Vec<f64> {
        placed.iter().map(|p| (p.at.x * 1e6).round() / 1e6).collect()
    }

    #[test]
    fn glyphs_follow_advances_kerning_and_the_offset() {
        let font = blocks();
        // I (400) kerned -50 before O, O (800), space (300), D.
        assert_eq!(xs(&font.layout("IO D", DVec3::ZERO)), [0.0, 0.35, 1.15, 1.45]);
        // Not kerned the other way round.
        assert_eq!(xs(&font.layout("OI", DVec3::ZERO)), [0.0, 0.8]);
        let placed = font.layout("IOD", DVec3::new(0.1, 0.2, 0.0));
        assert_eq!(xs(&placed), [0.0, 0.45, 1.35]);
        assert!((placed[2].at.y - 0.4).abs() < 1e-12);
        let glyphs: Vec<u16> = font.layout("I?", DVec3::ZERO).iter().map(|p| p.glyph).collect();
        assert_eq!(glyphs[1], 0, "a character the font lacks is its missing glyph");
        assert_ne!(glyphs[0], 0);
    }

    #[test]
    fn outlines_are_in_ems() {
        let font = blocks();
        let o = font.layout("O", DVec3::ZERO)[0].glyph;
        let contours = font.outline(o);
        assert_eq!(contours.len(), 2, "the square and its hole");
        let all = contours.iter().flatten();
        let (min, max) = all.fold((DVec2::MAX, DVec2::MIN), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
        assert!(
            (min - DVec2::new(0.1, 0.0)).length() < 1e-9
                && (max - DVec2::splat(0.7)).length() < 1e-9
        );
        let space = font.layout(" ", DVec3::ZERO)[0].glyph;
        assert!(font.outline(space).is_empty());
    }

    /// The largest distance from points along `curve` to the polyline.
    fn stray(polyline: &[DVec2], curve: impl Fn(f64) -> DVec2) -> f64 {
        let to_segment = |p: DVec2, a: DVec2, b: DVec2| {
            let t = ((p - a).dot(b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
            (a + t * (b - a)).distance(p)
        };
        (0..=2000)
            .map(|i| curve(f64::from(i) / 2000.0))
            .map(|p| {
                polyline.windows(2).map(|w| to_segment(p, w[0], w[1])).fold(f64::MAX, f64::min)
            })
            .fold(0.0, f64::max)
    }

    #[test]
    fn curves_are_flattened_within_the_tolerance() {
        let mut flattener = Flattener { scale: 1.0, contours: Vec::new(), current: Vec::new() };
        let (p0, p1, p2, p3) =
            (DVec2::ZERO, DVec2::new(0.2, 0.9), DVec2::new(0.9, -0.4), DVec2::new(1.0, 0.5));
        flattener.move_to(0.0, 0.0);
        flattener.quad_to(0.2, 0.9, 0.9, -0.4);
        let quad = flattener.current.clone();
        let bezier2 = |t: f64| (1.0 - t) * (1.0 - t) * p0 + 2.0 * (1.0 - t) * t * p1 + t * t * p2;
        assert!(stray(&quad, bezier2) <= TOLERANCE, "{}", stray(&quad, bezier2));
        assert!(quad.len() < 40, "{} points: too fine", quad.len());
        flattener.move_to(0.0, 0.0);
        flattener.curve_to(0.2, 0.9, 0.9, -0.4, 1.0, 0.5);
        let cubic = flattener.current.clone();
        let bezier3 = |t: f64| {
            let s = 1.0 - t;
            s * s * s * p0 + 3.0 * s * s * t * p1 + 3.0 * s * t * t * p2 + t * t * t * p3
        };
        assert!(stray(&cubic, bezier3) <= TOLERANCE, "{}", stray(&cubic, bezier3));
        flattener.close();
        assert_eq!(flattener.contours.len(), 2);
    }

    #[test]
    fn a_damaged_font_is_an_error_never_a_panic() {
        let error = Font::parse(b"not a font at all".to_vec()).unwrap_err();
        assert!(matches!(error, FontError::NotAFont(_)) && error.to_string().contains("TrueType"));
        for length in 0..BLOCKS.len() {
            let mut bytes = BLOCKS[..length].to_vec();
            bytes.extend(std::iter::repeat_n(0xA5, BLOCKS.len() - length));
            if let Ok(font) = Font::parse(bytes) {
                for placed in font.layout("IOD ?", DVec3::ZERO) {
                    font.outline(placed.glyph);
                }
            }
        }
    }
}

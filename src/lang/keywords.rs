//! The one list of the language's keywords. It feeds the check that a name is not a keyword, the
//! did-you-mean table of parse errors, and how each keyword reads in "expected ..." messages. The
//! grammar's `kw_` rules name a subset of these words (a test keeps the two in step); functions
//! and constants are told apart from names here, not in the grammar.

/// What a keyword is, beyond being reserved.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KeywordKind {
    /// A word of the syntax (`sphere`, `translate`, ...), matched by a `kw_` rule.
    Syntax,
    /// A built-in function, called as `word(...)`.
    Function(Function),
    /// A value: `pi`, the unit vectors `x`, `y`, `z`, POV-Ray's truth values, and the
    /// animation's `clock` and `frame_number`.
    Constant(Constant),
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Constant {
    Pi,
    X,
    Y,
    Z,
    /// `true`, `yes`, `on`: 1.
    True,
    /// `false`, `no`, `off`: 0.
    False,
    /// The animation's clock (`docs/language.md`, Animation): 0 without animation options.
    Clock,
    /// The frame's number: 0 without animation options.
    FrameNumber,
    /// POV-Ray's `clock_on`: 1 when the frame is one of an animation, else 0.
    ClockOn,
    /// POV-Ray's `clock_delta`: the clock's step between frames; 0 for a still image.
    ClockDelta,
}

/// The built-in functions (`docs/language.md`, Expressions and Comparisons).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Function {
    Sin,
    Cos,
    Tan,
    Asin,
    Acos,
    Atan,
    Sinh,
    Cosh,
    Tanh,
    Asinh,
    Acosh,
    Atanh,
    Atan2,
    Sqrt,
    /// POV-Ray's `sqr(x)`: x².
    Sqr,
    Pow,
    Abs,
    Min,
    Max,
    Radians,
    Degrees,
    Floor,
    Ceil,
    Int,
    Mod,
    Exp,
    Ln,
    Log,
    Vlength,
    Vnormalize,
    Vdot,
    Vcross,
    Vrotate,
    Select,
    Seed,
    Rand,
    Concat,
    Str,
    DimensionSize,
    /// POV-Ray's `dimensions(array)`: how many dimensions the array has.
    Dimensions,
    /// POV-Ray's `div(a, b)`: the integer part of a / b.
    Div,
    /// POV-Ray's `vaxis_rotate(v, axis, degrees)`: v turned about the axis.
    VaxisRotate,
    /// POV-Ray's `vturbulence(lambda, omega, octaves, p)`: the turbulence displacement a
    /// `warp { turbulence }` with those parameters gives at p.
    Vturbulence,
    /// POV-Ray's string functions: `strlen(s)`, `substr(s, start, length)` (from 1),
    /// `strupr(s)`, `strlwr(s)`, `chr(code)`, `asc(s)`, `val(s)`, `vstr(n, v, separator,
    /// width, decimals)`.
    Strlen,
    Substr,
    Strupr,
    Strlwr,
    Chr,
    Asc,
    Val,
    Vstr,
    /// POV-Ray's `file_exists(name)`: 1 if the file can be read where `#include` would look.
    FileExists,
    /// POV-Ray's `defined(Name)`: 1 if the name is declared.
    Defined,
    /// POV-Ray's `min_extent(Object)` and `max_extent(Object)`: its bounding box's corners.
    MinExtent,
    MaxExtent,
    /// POV-Ray's `trace(Object, Start, Direction [, Normal])`: the first point of its surface
    /// along the ray (the origin where none), its normal stored in `Normal`.
    Trace,
    /// POV-Ray's `inside(Object, Point)`: 1 if the point is inside its solid.
    Inside,
}

pub struct Keyword {
    pub word: &'static str,
    /// The word in backquotes, for messages.
    pub shown: &'static str,
    pub kind: KeywordKind,
}

macro_rules! keywords {
    ($($word:literal => $kind:expr),* $(,)?) => {
        &[$(Keyword { word: $word, shown: concat!("`", $word, "`"), kind: $kind }),*]
    };
}

use KeywordKind::{Constant as C, Function as F, Syntax as S};

pub const KEYWORDS: &[Keyword] = keywords![
    "settings" => S, "resolution" => S, "samples" => S, "integrator" => S, "max_depth" => S,
    "seed" => F(Function::Seed), "background" => S, "photons" => S, "photon_k" => S,
    "photon_radius" => S, "global_settings" => S, "ambient_light" => S, "assumed_gamma" => S,
    "sky_sphere" => S,
    "camera" => S, "origin" => S, "left" => S, "up" => S, "forward" => S, "location" => S,
    "look_at" => S, "angle" => S, "aperture" => S, "focal_distance" => S, "right" => S,
    "direction" => S, "sky" => S, "focal_point" => S, "blur_samples" => S, "perspective" => S, "orthographic" => S,
    "light_source" => S, "power" => S, "colour" => S, "color" => S,
    "plane" => S, "sphere" => S, "box" => S, "triangle" => S, "quad" => S, "disk" => S, "disc" => S,
    "cylinder" => S, "cone" => S, "torus" => S, "open" => S, "mesh" => S, "union" => S,
    "text" => S, "ttf" => S,
    "intersection" => S, "difference" => S, "merge" => S, "object" => S, "material" => S,
    "translate" => S, "rotate" => S, "scale" => S, "matrix" => S, "transform" => S,
    "diffuse" => S, "specular" => S, "transmission" => S, "emission" => S, "ior" => S,
    "fresnel" => S, "roughness" => S, "coat" => S, "coat_roughness" => S, "rgb" => S,
    "checker" => S, "stripes" => S, "gradient" => S, "noise" => S, "marble" => S, "wood" => S,
    "image_map" => S, "mix" => S, "axis" => S, "octaves" => S, "turbulence" => S,
    "color_map" => S, "colour_map" => S, "array" => S,
    "pigment" => S, "finish" => S, "texture" => S, "interior" => S, "normal" => S, "bozo" => S,
    "spotted" => S, "pattern" => S, "ambient" => S, "brilliance" => S, "phong" => S, "phong_size" => S,
    "reflection" => S, "metallic" => S, "conserve_energy" => S, "crand" => S, "irid" => S, "falloff" => S,
    "exponent" => S, "rgbf" => S, "rgbt" => S, "rgbft" => S, "srgb" => S,
    "fade_distance" => S, "fade_power" => S, "shadowless" => S, "hollow" => S,
    "double_illuminate" => S, "no_shadow" => S, "no_image" => S, "no_reflection" => S,
    "bounded_by" => S, "inverse" => S, "clipped_by" => S, "function" => S, "isosurface" => S,
    "quadric" => S, "cubic" => S, "quartic" => S, "poly" => S, "sturm" => S, "blob" => S,
    "strength" => S, "component" => S, "threshold" => S, "hierarchy" => S, "prism" => S, "lathe" => S, "sor" => S, "polygon" => S,
    "linear_spline" => S, "quadratic_spline" => S, "cubic_spline" => S, "bezier_spline" => S,
    "linear_sweep" => S, "conic_sweep" => S, "superellipsoid" => S, "bicubic_patch" => S, "smooth_triangle" => S, "mesh2" => S, "julia_fractal" => S,
    "height_field" => S, "sphere_sweep" => S, "ovus" => S, "lemon" => S, "parametric" => S,
    "atmosphere" => S, "medium" => S, "absorption" => S, "scattering" => S, "anisotropy" => S,
    "fog" => S, "media" => S,
    "pi" => C(Constant::Pi), "x" => C(Constant::X), "y" => C(Constant::Y), "z" => C(Constant::Z),
    "true" => C(Constant::True), "yes" => C(Constant::True), "on" => C(Constant::True),
    "false" => C(Constant::False), "no" => C(Constant::False), "off" => C(Constant::False),
    "clock" => C(Constant::Clock), "frame_number" => C(Constant::FrameNumber),
    "clock_on" => C(Constant::ClockOn), "clock_delta" => C(Constant::ClockDelta),
    "sin" => F(Function::Sin), "cos" => F(Function::Cos), "tan" => F(Function::Tan),
    "asin" => F(Function::Asin), "acos" => F(Function::Acos), "atan" => F(Function::Atan),
    "sinh" => F(Function::Sinh), "cosh" => F(Function::Cosh), "tanh" => F(Function::Tanh),
    "asinh" => F(Function::Asinh), "acosh" => F(Function::Acosh), "atanh" => F(Function::Atanh),
    "atan2" => F(Function::Atan2),
    "sqrt" => F(Function::Sqrt), "sqr" => F(Function::Sqr), "pow" => F(Function::Pow), "abs" => F(Function::Abs),
    "min" => F(Function::Min), "max" => F(Function::Max), "radians" => F(Function::Radians),
    "degrees" => F(Function::Degrees), "floor" => F(Function::Floor), "ceil" => F(Function::Ceil),
    "int" => F(Function::Int), "mod" => F(Function::Mod), "exp" => F(Function::Exp),
    "ln" => F(Function::Ln), "log" => F(Function::Log), "vlength" => F(Function::Vlength),
    "vnormalize" => F(Function::Vnormalize), "vdot" => F(Function::Vdot),
    "vcross" => F(Function::Vcross), "vrotate" => F(Function::Vrotate),
    "select" => F(Function::Select), "rand" => F(Function::Rand),
    "concat" => F(Function::Concat), "str" => F(Function::Str),
    "dimension_size" => F(Function::DimensionSize), "dimensions" => F(Function::Dimensions),
    "div" => F(Function::Div),
    "vaxis_rotate" => F(Function::VaxisRotate), "vturbulence" => F(Function::Vturbulence),
    "strlen" => F(Function::Strlen), "substr" => F(Function::Substr), "strupr" => F(Function::Strupr),
    "strlwr" => F(Function::Strlwr), "chr" => F(Function::Chr), "asc" => F(Function::Asc),
    "val" => F(Function::Val), "vstr" => F(Function::Vstr), "file_exists" => F(Function::FileExists),
    "defined" => F(Function::Defined),
    "min_extent" => F(Function::MinExtent), "max_extent" => F(Function::MaxExtent),
    "trace" => F(Function::Trace), "inside" => F(Function::Inside),
];

/// The keyword spelt `word`, if it is one.
pub fn lookup(word: &str) -> Option<&'static Keyword> {
    KEYWORDS.iter().find(|k| k.word == word)
}

/// Every keyword's spelling, for did-you-mean suggestions.
pub fn words() -> impl Iterator<Item = &'static str> {
    KEYWORDS.iter().map(|k| k.word)
}

impl Function {
    pub fn name(self) -> &'static str {
        KEYWORDS.iter().find(|k| k.kind == KeywordKind::Function(self)).map_or("?", |k| k.word)
    }

    /// How many arguments it takes: at least the first, at most the second (`None`: any
    /// number, `concat`).
    pub fn arity(self) -> (usize, Option<usize>) {
        use Function::*;
        let exactly = |n| (n, Some(n));
        match self {
            Sin | Cos | Tan | Asin | Acos | Atan | Sinh | Cosh | Tanh | Asinh | Acosh | Atanh
            | Sqrt | Sqr | Abs | Radians | Degrees | Floor | Ceil | Int | Exp | Ln | Log
            | Vlength | Vnormalize | Seed | Rand | Strlen | Strupr | Strlwr | Chr | Asc | Val
            | FileExists | Defined | Dimensions | MinExtent | MaxExtent => exactly(1),
            Pow | Min | Max | Mod | Div | Atan2 | Vdot | Vcross | Vrotate | DimensionSize
            | Inside => exactly(2),
            Select | Str | VaxisRotate | Substr => exactly(3),
            Trace => (3, Some(4)),
            Vturbulence => exactly(4),
            Vstr => exactly(5),
            Concat => (1, None),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_grammar_names_only_listed_keywords_and_every_syntax_keyword() {
        let grammar = include_str!("../../grammar/scn.pest");
        let mut in_grammar = Vec::new();
        for line in grammar.lines().filter(|l| l.starts_with("kw_")) {
            let word = line.split('"').nth(1).expect("a kw_ rule spells its word");
            let rule = line.split(' ').next().unwrap();
            assert_eq!(rule, format!("kw_{word}"), "the rule is named after its word");
            in_grammar.push(word);
        }
        for word in &in_grammar {
            assert!(lookup(word).is_some(), "`{word}` is in the grammar but not in KEYWORDS");
        }
        for k in KEYWORDS.iter().filter(|k| k.kind == KeywordKind::Syntax) {
            assert!(in_grammar.contains(&k.word), "`{}` has no kw_ rule", k.word);
        }
    }

    #[test]
    fn every_function_has_one_spelling() {
        for k in KEYWORDS {
            if let KeywordKind::Function(f) = k.kind {
                assert_eq!(f.name(), k.word);
            }
        }
        let mut words: Vec<&str> = words().collect();
        words.sort_unstable();
        words.dedup();
        assert_eq!(words.len(), KEYWORDS.len(), "no keyword is listed twice");
    }
}

//! The owned syntax tree of a `.scn` file: what the text says, with a span on everything an error
//! may point at, and nothing evaluated. `lang::tree` builds it from the parser's pairs; the
//! interpreter (`lang::eval`) runs it.

use std::sync::Arc;

use super::keywords::{Constant, Function};
use crate::diagnostic::Span;

#[derive(Debug, Clone)]
pub struct Ident {
    pub name: String,
    pub span: Span,
}

/// An item of a body (the file itself, an object, a material, a texture, a macro): a directive,
/// or what the body's kind allows. Bodies reached through a macro call may hold any item; each
/// body's evaluator says which it accepts.
#[derive(Debug, Clone)]
pub enum Item {
    Declare(Declare),
    Undef(Ident),
    Include {
        file: Expr,
        span: Span,
    },
    If {
        branches: Vec<(Condition, Vec<Item>)>,
        otherwise: Option<Vec<Item>>,
        span: Span,
    },
    /// POV-Ray's `#switch` (`.pov`): the first clause whose test holds runs, and those after it
    /// until one that ends in `#break`; `otherwise` (`#else`) runs when none holds.
    Switch {
        value: Expr,
        clauses: Vec<SwitchClause>,
        otherwise: Option<Vec<Item>>,
        span: Span,
    },
    While {
        condition: Expr,
        body: Vec<Item>,
        span: Span,
    },
    For {
        variable: Ident,
        from: Expr,
        to: Expr,
        step: Option<Expr>,
        body: Vec<Item>,
        span: Span,
    },
    Macro(Arc<MacroDef>),
    Message {
        kind: MessageKind,
        text: Expr,
        span: Span,
    },
    /// POV-Ray's `#fopen`, `#read`, `#write` or `#fclose` (`.pov`).
    File(FileDirective),
    /// POV-Ray's `global_settings`: its `ambient_light` and `assumed_gamma` (the last of each
    /// written), and whether anything else stands in it (accepted, with a warning).
    GlobalSettings {
        ambient_light: Option<Colour>,
        assumed_gamma: Option<Expr>,
        others: bool,
        span: Span,
    },
    /// POV-Ray's `#version`, a lone `#`, a light's media flag or `photons { }`: accepted, with
    /// a warning.
    Ignored {
        what: Ignored,
        span: Span,
    },
    /// A macro called where an item stands.
    Call(Call),
    Settings {
        items: Vec<Item>,
        span: Span,
    },
    Setting(Setting),
    Camera {
        items: Vec<Item>,
        span: Span,
    },
    CameraParam {
        key: Ident,
        value: Expr,
    },
    /// POV-Ray's `perspective`, `orthographic`, `fisheye`, `cylinder N`, ... (`.pov` only).
    CameraProjection {
        projection: ProjectionWord,
        span: Span,
    },
    Light {
        position: Expr,
        items: Vec<Item>,
        span: Span,
    },
    LightPower {
        key: Span,
        colour: Colour,
    },
    Object(Object),
    Material(Material),
    /// A declared material named among an object's items.
    MaterialName(Ident),
    Transform(Transform),
    MaterialParam(MaterialParam),
    Texture(Texture),
    TextureParam(TextureParam),
    ColorMap {
        entries: Vec<Item>,
        span: Span,
    },
    /// `[position colour]`, or (`.pov`) `[position, end colour colour]`: the colour goes to
    /// the second at `end`.
    MapEntry {
        position: Expr,
        colour: Colour,
        end: Option<(Expr, Colour)>,
    },
    /// A value standing alone (a macro's body such as `(X * X)`).
    Value(Expr),
    /// POV-Ray's `image_map { [type] "file" options }` in a pigment (`.pov`), or `bump_map {
    /// }` in a normal: the file's name and the options (`PovParam`s: `map_type`, `once`,
    /// `interpolate`, `gamma`, `filter`, `transmit`, `filter all`, `transmit all`, `bump_size`,
    /// ...).
    ImageMap {
        file: Expr,
        options: Vec<Item>,
        span: Span,
    },
    /// POV-Ray's `clipped_by { objects }` (`.pov`): its items.
    ClippedBy {
        items: Vec<Item>,
        span: Span,
    },
    /// POV-Ray's `#default { ... }` (`.pov`).
    Default {
        items: Vec<Item>,
        span: Span,
    },
    /// POV-Ray's `pigment`, `finish`, `texture`, `interior` or `normal` (`.pov`).
    Appearance(Appearance),
    /// POV-Ray's `sky_sphere { ... }` (`.pov`).
    SkySphere {
        items: Vec<Item>,
        span: Span,
    },
    /// A pigment's, normal's or `pattern { }` texture's pattern (`checker Red, Blue`,
    /// `gradient y`, `bumps 0.5`).
    Pattern {
        kind: PatternKind,
        /// `checker`'s colours, `gradient`'s axis, `mandel`'s iterations; in a normal, last,
        /// its amount.
        arguments: Vec<Colour>,
        /// `function { }`'s own function (its kind `Function`), or `pigment_pattern`'s pigment as
        /// a colour function (its kind `PigmentPattern`).
        function: Option<Box<FunctionDef>>,
        span: Span,
    },
    /// `pigment_map`, `normal_map`, `texture_map` or `slope_map { [position items] ... }`:
    /// its entries (`MapBlock`s, or a declared map's name as a `Value`).
    PatternMap {
        kind: MapKind,
        entries: Vec<Item>,
        span: Span,
    },
    /// `[position items]` of a pattern map (`average`'s may leave out the position, its
    /// weight: 1).
    MapBlock {
        position: Option<Expr>,
        items: Vec<Item>,
        span: Span,
    },
    /// An item of a finish, an interior or a `reflection { }`: its key, its value if given, and
    /// (`reflection { }`) its own items.
    PovParam {
        key: Ident,
        value: Option<Colour>,
        items: Vec<Item>,
    },
    /// POV-Ray's `uv_vectors <uv1> <uv2> <uv3>` of a mesh's triangle (`.pov`): the uv
    /// coordinates of its corners, right after them.
    UvVectors {
        corners: Box<[Expr; 3]>,
        span: Span,
    },
}

#[derive(Debug, Clone)]
pub struct Appearance {
    pub kind: AppearanceKind,
    pub items: Vec<Item>,
    pub span: Span,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AppearanceKind {
    Pigment,
    Finish,
    Texture,
    Interior,
    Normal,
}

impl AppearanceKind {
    pub fn word(self) -> &'static str {
        match self {
            AppearanceKind::Pigment => "pigment",
            AppearanceKind::Finish => "finish",
            AppearanceKind::Texture => "texture",
            AppearanceKind::Interior => "interior",
            AppearanceKind::Normal => "normal",
        }
    }
}

/// POV-Ray's patterns, by their words.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PatternKind {
    Agate,
    Average,
    Boxed,
    Bozo,
    Brick,
    Bumps,
    Cells,
    Checker,
    Crackle,
    Cylindrical,
    Dents,
    /// `function { expr }`: the function's value at the point.
    Function,
    Gradient,
    Granite,
    Hexagon,
    /// `julia <c>, iterations`.
    Julia,
    Leopard,
    /// `magnet 1 mandel iterations` (or `magnet 2`).
    Magnet,
    /// `magnet 1 julia <c>, iterations` (or `magnet 2`).
    MagnetJulia,
    Mandel,
    Marble,
    Onion,
    /// `pigment_pattern { }`: its pigment's gray at the point.
    PigmentPattern,
    Planar,
    Quilted,
    Radial,
    Ripples,
    Spherical,
    Spiral1,
    Spiral2,
    Spotted,
    Waves,
    Wood,
    Wrinkles,
}

impl PatternKind {
    pub const ALL: [PatternKind; 34] = [
        PatternKind::Agate,
        PatternKind::Average,
        PatternKind::Boxed,
        PatternKind::Bozo,
        PatternKind::Brick,
        PatternKind::Bumps,
        PatternKind::Cells,
        PatternKind::Checker,
        PatternKind::Crackle,
        PatternKind::Cylindrical,
        PatternKind::Dents,
        PatternKind::Function,
        PatternKind::Gradient,
        PatternKind::Granite,
        PatternKind::Hexagon,
        PatternKind::Julia,
        PatternKind::Leopard,
        PatternKind::Magnet,
        PatternKind::MagnetJulia,
        PatternKind::Mandel,
        PatternKind::Marble,
        PatternKind::Onion,
        PatternKind::PigmentPattern,
        PatternKind::Planar,
        PatternKind::Quilted,
        PatternKind::Radial,
        PatternKind::Ripples,
        PatternKind::Spherical,
        PatternKind::Spiral1,
        PatternKind::Spiral2,
        PatternKind::Spotted,
        PatternKind::Waves,
        PatternKind::Wood,
        PatternKind::Wrinkles,
    ];

    pub fn word(self) -> &'static str {
        match self {
            PatternKind::Agate => "agate",
            PatternKind::Average => "average",
            PatternKind::Boxed => "boxed",
            PatternKind::Bozo => "bozo",
            PatternKind::Brick => "brick",
            PatternKind::Bumps => "bumps",
            PatternKind::Cells => "cells",
            PatternKind::Checker => "checker",
            PatternKind::Crackle => "crackle",
            PatternKind::Cylindrical => "cylindrical",
            PatternKind::Dents => "dents",
            PatternKind::Function => "function",
            PatternKind::Gradient => "gradient",
            PatternKind::Granite => "granite",
            PatternKind::Hexagon => "hexagon",
            PatternKind::Julia => "julia",
            PatternKind::Leopard => "leopard",
            PatternKind::Magnet => "magnet",
            PatternKind::MagnetJulia => "magnet julia",
            PatternKind::Mandel => "mandel",
            PatternKind::Marble => "marble",
            PatternKind::Onion => "onion",
            PatternKind::PigmentPattern => "pigment_pattern",
            PatternKind::Planar => "planar",
            PatternKind::Quilted => "quilted",
            PatternKind::Radial => "radial",
            PatternKind::Ripples => "ripples",
            PatternKind::Spherical => "spherical",
            PatternKind::Spiral1 => "spiral1",
            PatternKind::Spiral2 => "spiral2",
            PatternKind::Spotted => "spotted",
            PatternKind::Waves => "waves",
            PatternKind::Wood => "wood",
            PatternKind::Wrinkles => "wrinkles",
        }
    }

    /// The pattern called `word`, if any.
    pub fn named(word: &str) -> Option<PatternKind> {
        PatternKind::ALL.into_iter().find(|kind| kind.word() == word)
    }
}

/// What a pattern map's entries are.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MapKind {
    Pigment,
    Normal,
    Texture,
    Slope,
}

impl MapKind {
    pub fn word(self) -> &'static str {
        match self {
            MapKind::Pigment => "pigment_map",
            MapKind::Normal => "normal_map",
            MapKind::Texture => "texture_map",
            MapKind::Slope => "slope_map",
        }
    }
}

impl Item {
    /// What the item is, for "cannot stand here" messages.
    pub fn describe(&self) -> &'static str {
        match self {
            Item::Declare(_) => "`#declare`",
            Item::Undef(_) => "`#undef`",
            Item::Include { .. } => "`#include`",
            Item::If { .. } => "`#if`",
            Item::Switch { .. } => "`#switch`",
            Item::While { .. } => "`#while`",
            Item::For { .. } => "`#for`",
            Item::Macro(_) => "`#macro`",
            Item::Message { .. } => "a message",
            Item::File(directive) => match directive.action {
                FileAction::Open { .. } => "`#fopen`",
                FileAction::Read(_) => "`#read`",
                FileAction::Write(_) => "`#write`",
                FileAction::Close => "`#fclose`",
            },
            Item::GlobalSettings { .. } => "`global_settings`",
            Item::Ignored { what: Ignored::Version, .. } => "`#version`",
            Item::Ignored { what: Ignored::StrayHash, .. } => "a lone `#`",
            Item::Ignored { what: Ignored::LightMedia, .. } => "a light's media flag",
            Item::Ignored { what: Ignored::Photons, .. } => "`photons { }`",
            Item::Call(_) => "a macro call",
            Item::Settings { .. } => "`settings`",
            Item::Setting(_) => "a setting",
            Item::Camera { .. } => "a camera",
            Item::CameraParam { .. } => "a camera parameter",
            Item::CameraProjection { .. } => "a camera's projection",
            Item::Light { .. } => "a light_source",
            Item::LightPower { .. } => "a light's power",
            Item::Object(_) => "an object",
            Item::Material(_) => "a material",
            Item::MaterialName(_) => "a material's name",
            Item::Transform(_) => "a transform",
            Item::MaterialParam(_) => "a material parameter",
            Item::Texture(_) => "a texture",
            Item::TextureParam(_) => "a texture parameter",
            Item::ColorMap { .. } => "a color_map",
            Item::MapEntry { .. } => "a color_map entry",
            Item::Value(_) => "a value",
            Item::ClippedBy { .. } => "`clipped_by`",
            Item::ImageMap { .. } => "an `image_map`",
            Item::Default { .. } => "`#default`",
            Item::SkySphere { .. } => "a sky_sphere",
            Item::Appearance(a) => match a.kind {
                AppearanceKind::Pigment => "a pigment",
                AppearanceKind::Finish => "a finish",
                AppearanceKind::Texture => "a texture",
                AppearanceKind::Interior => "an interior",
                AppearanceKind::Normal => "a normal",
            },
            Item::Pattern { .. } => "a pattern",
            Item::PatternMap { kind, .. } => match kind {
                MapKind::Pigment => "a pigment_map",
                MapKind::Normal => "a normal_map",
                MapKind::Texture => "a texture_map",
                MapKind::Slope => "a slope_map",
            },
            Item::MapBlock { .. } => "a map's entry",
            Item::PovParam { .. } => "a finish or interior item",
            Item::UvVectors { .. } => "a mesh triangle's `uv_vectors`",
        }
    }

    /// Where the item starts.
    pub fn span(&self) -> &Span {
        match self {
            Item::Declare(d) => &d.span,
            Item::Undef(name) => &name.span,
            Item::Include { span, .. }
            | Item::If { span, .. }
            | Item::Switch { span, .. }
            | Item::While { span, .. }
            | Item::For { span, .. }
            | Item::Message { span, .. }
            | Item::File(FileDirective { span, .. })
            | Item::Ignored { span, .. }
            | Item::GlobalSettings { span, .. }
            | Item::Settings { span, .. }
            | Item::Camera { span, .. }
            | Item::CameraProjection { span, .. }
            | Item::Light { span, .. }
            | Item::ColorMap { span, .. }
            | Item::Default { span, .. }
            | Item::SkySphere { span, .. }
            | Item::ClippedBy { span, .. }
            | Item::ImageMap { span, .. }
            | Item::Pattern { span, .. }
            | Item::PatternMap { span, .. }
            | Item::MapBlock { span, .. }
            | Item::UvVectors { span, .. } => span,
            Item::Appearance(a) => &a.span,
            Item::PovParam { key, .. } => &key.span,
            Item::Macro(m) => &m.span,
            Item::Call(c) => &c.span,
            Item::Setting(s) => &s.span,
            Item::CameraParam { key, .. } => &key.span,
            Item::LightPower { key, .. } => key,
            Item::Object(o) => &o.span,
            Item::Material(m) => &m.span,
            Item::MaterialName(name) => &name.span,
            Item::Transform(t) => &t.span,
            Item::MaterialParam(p) => &p.span,
            Item::Texture(t) => &t.span,
            Item::TextureParam(p) => &p.span,
            Item::MapEntry { position, .. } => &position.span,
            Item::Value(e) => &e.span,
        }
    }
}

/// What POV-Ray has and raydiance reads without effect.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ignored {
    Version,
    /// A `#` with no directive's word after it.
    StrayHash,
    /// A light's `media_interaction` or `media_attenuation`.
    LightMedia,
    /// The `photons { }` block of a light or an object.
    Photons,
}

impl Ignored {
    /// The warning given where it stands.
    pub fn warning(self) -> &'static str {
        match self {
            Ignored::Version => {
                "`#version` has no effect: raydiance reads one version of its language"
            }
            Ignored::StrayHash => {
                "this `#` begins no directive (no word follows it): it is read as nothing, as \
                 POV-Ray reads it"
            }
            Ignored::LightMedia => {
                "POV-Ray's `media_interaction` and `media_attenuation` have no effect here: a \
                 light scatters in participating media and is attenuated by them as physics has it"
            }
            Ignored::Photons => {
                "POV-Ray's `photons { }` of a light or an object has no effect here: photon \
                 mapping (`settings { integrator photon }`) traces photons from every light to \
                 every object"
            }
        }
    }
}

/// `#declare` or `#local`, of a name or of an array's element (`#declare B[2] = ...`).
#[derive(Debug, Clone)]
pub struct Declare {
    pub local: bool,
    pub name: Ident,
    pub indices: Vec<Expr>,
    pub value: Declared,
    pub span: Span,
}

#[derive(Debug, Clone)]
pub enum Declared {
    Material(Material),
    Object(Box<Object>),
    Texture(Texture),
    Array(ArrayLiteral),
    Value(Expr),
    /// POV-Ray's declared `pigment`, `finish`, `texture` or `interior` (`.pov`).
    Appearance(Appearance),
    /// POV-Ray's declared layered texture (`.pov`): each `texture` over the ones before it.
    LayeredTexture {
        layers: Vec<Appearance>,
        span: Span,
    },
    /// POV-Ray's declared `color_map` (`.pov`): its entries.
    ColorMap {
        entries: Vec<Item>,
        span: Span,
    },
    /// POV-Ray's declared `media` (`.pov`): its items.
    Media {
        items: Vec<Item>,
        span: Span,
    },
    /// POV-Ray's declared camera (`.pov`): its items.
    Camera {
        items: Vec<Item>,
        span: Span,
    },
    /// POV-Ray's declared `light_source` (`.pov`): placed where `light_source { Name }` or
    /// `object { Name }` uses it.
    Light {
        position: Expr,
        items: Vec<Item>,
        span: Span,
    },
    /// POV-Ray's declared `sky_sphere` (`.pov`): its items.
    Sky {
        items: Vec<Item>,
        span: Span,
    },
    /// POV-Ray's float function (`.pov`).
    Function(FunctionDef),
    /// POV-Ray's declared `transform` (`.pov`).
    Transform(Transform),
    /// `#if (c) a #elseif (d) b #else e #end` as the value.
    If {
        branches: Vec<(Condition, Declared)>,
        otherwise: Option<Box<Declared>>,
        span: Span,
    },
}

/// A `#case (v)` or `#range (low, high)` of a `#switch`, with its items up to the next clause
/// or its `#break`.
#[derive(Debug, Clone)]
pub struct SwitchClause {
    pub test: CaseTest,
    pub items: Vec<Item>,
    /// Ends in `#break`: the clauses after it do not run.
    pub breaks: bool,
}

#[derive(Debug, Clone)]
pub enum CaseTest {
    /// `#case (v)`: the switch's value equals v (within POV-Ray's tolerance).
    Case(Expr),
    /// `#range (low, high)`: low ≤ value ≤ high.
    Range(Expr, Expr),
}

#[derive(Debug, Clone)]
pub enum Condition {
    Expr(Expr),
    /// `#ifdef (Name)` (`defined`), `#ifndef (Name)` (not); with `indices`, an array's
    /// element (`#ifdef (A[i])`: whether it is set).
    Defined {
        name: Ident,
        indices: Vec<Expr>,
        defined: bool,
    },
}

/// A directive on a text file named by its handle (`.pov`).
#[derive(Debug, Clone)]
pub struct FileDirective {
    pub handle: Ident,
    pub action: FileAction,
    pub span: Span,
}

#[derive(Debug, Clone)]
pub enum FileAction {
    /// `#fopen Handle "name" read|write|append`.
    Open { name: Expr, mode: OpenMode },
    /// `#read (Handle, A, B, ...)`: the names the values read are bound to.
    Read(Vec<Ident>),
    /// `#write (Handle, items...)`.
    Write(Vec<WriteItem>),
    /// `#fclose Handle`.
    Close,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OpenMode {
    Read,
    /// Writes a new file, replacing one of the same name.
    Write,
    /// Writes after what the file holds.
    Append,
}

/// A value `#write` writes: as text, or as binary integers of a word type.
#[derive(Debug, Clone)]
pub struct WriteItem {
    pub word: Option<BinaryWord>,
    pub value: Expr,
}

/// POV-Ray's binary word types: each value is rounded to the nearest integer of the type's
/// range and written in two's complement.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BinaryWord {
    Uint8,
    Sint8,
    Uint16Be,
    Uint16Le,
    Sint16Be,
    Sint16Le,
    Sint32Be,
    Sint32Le,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MessageKind {
    Debug,
    Warning,
    Error,
}

#[derive(Debug)]
pub struct MacroDef {
    pub name: Ident,
    pub parameters: Vec<Ident>,
    pub body: Vec<Item>,
    pub span: Span,
}

#[derive(Debug, Clone)]
pub struct Call {
    pub name: Ident,
    pub arguments: Vec<Expr>,
    pub span: Span,
}

#[derive(Debug, Clone)]
pub struct Setting {
    pub kind: SettingKind,
    pub span: Span,
}

#[derive(Debug, Clone)]
pub enum SettingKind {
    Resolution(Expr, Expr),
    Samples(Expr),
    Integrator(Ident),
    MaxDepth(Expr),
    Seed(Expr),
    Background(Colour),
    Photons(Expr),
    PhotonK(Expr),
    PhotonRadius(Expr),
}

#[derive(Debug, Clone)]
pub struct Object {
    pub shape: Shape,
    /// Modifiers, directives, and (in a union) child objects.
    pub items: Vec<Item>,
    pub span: Span,
}

#[derive(Debug, Clone)]
pub enum Shape {
    Plane {
        normal: Expr,
        offset: Expr,
    },
    Sphere {
        center: Expr,
        radius: Expr,
    },
    Box {
        corner_a: Expr,
        corner_b: Expr,
    },
    Triangle {
        a: Expr,
        b: Expr,
        c: Expr,
    },
    Quad {
        corner: Expr,
        edge1: Expr,
        edge2: Expr,
    },
    /// POV-Ray's `disc` may have a hole radius (`.pov`).
    Disk {
        center: Expr,
        normal: Expr,
        radius: Expr,
        hole: Option<Expr>,
    },
    /// `open`: the side alone, no end disks.
    Cylinder {
        base: Expr,
        cap: Expr,
        radius: Expr,
        open: bool,
    },
    Cone {
        base: Expr,
        base_radius: Expr,
        cap: Expr,
        cap_radius: Expr,
        open: bool,
    },
    Torus {
        major: Expr,
        minor: Expr,
    },
    Mesh {
        file: Expr,
    },
    /// `text { ttf "font.ttf" "string" thickness, offset }`.
    Text {
        font: FontName,
        string: Expr,
        thickness: Expr,
        offset: Expr,
    },
    /// POV-Ray's `quadric { <A,B,C>, <D,E,F>, <G,H,I>, J }`: A x^2 + B y^2 + C z^2 + D xy +
    /// E xz + F yz + G x + H y + I z + J = 0.
    Quadric {
        squares: Expr,
        products: Expr,
        linear: Expr,
        constant: Expr,
    },
    /// POV-Ray's `cubic`, `quartic` and `poly { order, <...> }`: the coefficients of every
    /// term of the order, in POV-Ray's order.
    Poly {
        order: PolyOrder,
        coefficients: Expr,
    },
    /// POV-Ray's `blob`: its components and `threshold` are among its items.
    Blob,
    /// POV-Ray's `ovus { bottom_radius, top_radius }`.
    Ovus {
        bottom: Expr,
        top: Expr,
    },
    /// POV-Ray's `lemon { base, base_radius, cap, cap_radius, inner_radius [open] }`.
    Lemon {
        base: Expr,
        base_radius: Expr,
        cap: Expr,
        cap_radius: Expr,
        inner_radius: Expr,
        open: bool,
    },
    /// POV-Ray's `superellipsoid { <e, n> }`.
    Superellipsoid {
        exponents: Expr,
    },
    /// POV-Ray's `bicubic_patch`.
    BicubicPatch(Box<BicubicPatch>),
    /// POV-Ray's `smooth_triangle { p1, n1, p2, n2, p3, n3 }`.
    SmoothTriangle {
        corners: Box<[Expr; 3]>,
        normals: Box<[Expr; 3]>,
    },
    /// POV-Ray's `mesh { triangle { } smooth_triangle { } ... }`: the triangles as objects,
    /// among the directives that run through them.
    TriangleMesh {
        triangles: Vec<Item>,
    },
    /// POV-Ray's `mesh2`.
    Mesh2(Box<Mesh2>),
    /// POV-Ray's `julia_fractal`.
    JuliaFractal(Box<JuliaFractal>),
    /// POV-Ray's `prism`: `count` points (x, z) joined by a spline, swept between two heights.
    Prism {
        spline: crate::geometry::SplineKind,
        sweep: crate::geometry::Sweep,
        heights: [Expr; 2],
        count: Expr,
        /// The points as values, among the directives that run through them.
        points: Vec<Item>,
        open: bool,
    },
    /// POV-Ray's `lathe`: `count` points (r, y) joined by a spline, turned about y.
    Lathe {
        spline: crate::geometry::SplineKind,
        count: Expr,
        /// The points as values, among the directives that run through them.
        points: Vec<Item>,
    },
    /// POV-Ray's `sor`: `count` points (r, y), r^2 interpolated by a cubic in y.
    Sor {
        count: Expr,
        /// The points as values, among the directives that run through them.
        points: Vec<Item>,
        open: bool,
    },
    /// POV-Ray's `polygon`: `count` points of closed outlines in one plane.
    Polygon {
        count: Expr,
        /// The points as values, among the directives that run through them.
        points: Vec<Item>,
    },
    /// A component of a blob: a sphere, or a cylinder with hemispherical ends, and its strength.
    BlobSphere {
        center: Expr,
        radius: Expr,
        strength: Expr,
    },
    BlobCylinder {
        a: Expr,
        b: Expr,
        radius: Expr,
        strength: Expr,
    },
    Union,
    /// CSG: the operands are the objects among the items.
    Intersection,
    Difference,
    Merge,
    Instance {
        of: Expr,
    },
    /// POV-Ray's `isosurface { }` (`.pov`).
    Isosurface(Box<Isosurface>),
    /// POV-Ray's `parametric { }`.
    Parametric(Box<Parametric>),
    /// POV-Ray's `height_field { }` (`.pov`).
    HeightField(Box<HeightField>),
    /// POV-Ray's `sphere_sweep`: `count` pairs of a centre and a radius along a spline.
    SphereSweep {
        spline: SweepSpline,
        count: Expr,
        /// The points as values, among the directives that run through them.
        points: Vec<Item>,
        tolerance: Option<Expr>,
    },
}

/// The spline a `sphere_sweep` follows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SweepSpline {
    Linear,
    /// Catmull–Rom: through every point but the first and last.
    Cubic,
    /// The uniform cubic B-spline of the points.
    BSpline,
}

/// `height_field { [type] "file" | function W, H { body }  settings... }`: what the text says,
/// each setting by its word (the last of a word counts, as in POV-Ray).
#[derive(Debug, Clone)]
pub struct HeightField {
    pub source: HeightSource,
    /// `smooth`, `hierarchy`: the word and its truth value (on unless written off).
    pub flags: Vec<(Ident, bool)>,
    pub water_level: Option<Expr>,
}

/// Where a height field's heights come from.
#[derive(Debug, Clone)]
pub enum HeightSource {
    /// An image file: its type word (`png`, ...) if written, its name, and `gamma` (with its
    /// value) or `premultiplied` where written.
    Image { format: Option<Ident>, file: Expr, options: Vec<(Ident, Option<Expr>)> },
    /// `function W, H { body }`: the function sampled on a W by H grid.
    Function { width: Expr, height: Expr, body: Box<FunctionDef> },
}

/// POV-Ray's `function { expr }`, `function(a, b) { expr }` or `function { pattern { } }`.
#[derive(Debug, Clone)]
pub struct FunctionDef {
    /// The parameters' names; none written: `x`, `y`, `z`.
    pub parameters: Vec<Ident>,
    pub body: FunctionBody,
    pub span: Span,
}

#[derive(Debug, Clone)]
pub enum FunctionBody {
    Expr(Expr),
    /// `pattern { ... }`: the pattern's value (a `pattern` texture).
    Pattern(Texture),
    /// `pigment { ... }`: a colour function, its pigment's colour at (x, y, z).
    Pigment(Appearance),
    /// `transform { ... }`: a transform function, the image of the point (x, y, z).
    Transform(Transform),
}

/// `isosurface { function { } contained_by { box | sphere } settings... }`: what the text says,
/// each setting by its word.
#[derive(Debug, Clone)]
pub struct Isosurface {
    pub function: Option<FunctionDef>,
    /// `contained_by`'s box or sphere.
    pub container: Option<Object>,
    /// `threshold`, `accuracy`, `max_gradient`, `max_trace`, `evaluate`, `open`,
    /// `all_intersections`: the word and its values.
    pub settings: Vec<(Ident, Vec<Expr>)>,
}

/// `parametric { function { x(u, v) } function { y(u, v) } function { z(u, v) } <u0, v0>,
/// <u1, v1> contained_by { box | sphere } settings... }`: what the text says, each setting by
/// its word.
#[derive(Debug, Clone)]
pub struct Parametric {
    pub functions: Box<[FunctionDef; 3]>,
    pub uv: [Expr; 2],
    pub container: Option<Object>,
    /// `max_gradient`, `accuracy`, `precompute`: the word and its values.
    pub settings: Vec<(Ident, Vec<Expr>)>,
}

/// `bicubic_patch { settings... 16 points }`: each setting as written (the last of a word
/// counts, as in POV-Ray), the control points row by row.
#[derive(Debug, Clone)]
pub struct BicubicPatch {
    pub patch_type: Option<Expr>,
    pub flatness: Option<Expr>,
    pub u_steps: Option<Expr>,
    pub v_steps: Option<Expr>,
    /// `uv_vectors`: the corners' uv coordinates, none if not given.
    pub uv_vectors: Vec<Expr>,
    pub points: Vec<Expr>,
}

/// `mesh2 { vertex_vectors { } normal_vectors { } uv_vectors { } face_indices { }
/// normal_indices { } uv_indices { } }`: each list as written (the last of a word counts).
#[derive(Debug, Clone)]
pub struct Mesh2 {
    pub vertices: Option<VectorList>,
    pub normals: Option<VectorList>,
    pub uvs: Option<VectorList>,
    pub faces: Option<VectorList>,
    pub normal_indices: Option<VectorList>,
    pub uv_indices: Option<VectorList>,
}

/// `julia_fractal { <c> settings... }`: each setting as written (the last of a word counts).
#[derive(Debug, Clone)]
pub struct JuliaFractal {
    pub parameter: Expr,
    pub algebra: crate::geometry::Algebra,
    /// The function's word (`sqr`, `cube`, `exp`, `pwr`, ...), where written.
    pub function: Option<Ident>,
    pub max_iteration: Option<Expr>,
    pub precision: Option<Expr>,
    /// The slice's 4-D normal and distance.
    pub slice: Option<(Expr, Expr)>,
}

/// A list of a `mesh2`: the count it says, then its entries.
#[derive(Debug, Clone)]
pub struct VectorList {
    pub count: Expr,
    pub entries: Vec<Expr>,
}

/// The font of a `text`: a file (`ttf "name"`) or POV-Ray's built-in font number (`internal N`).
#[derive(Debug, Clone)]
pub enum FontName {
    File(Expr),
    Internal(Expr),
}

/// The order of a polynomial surface: fixed by its keyword, or written.
#[derive(Debug, Clone)]
pub enum PolyOrder {
    Cubic,
    Quartic,
    Written(Expr),
}

#[derive(Debug, Clone)]
pub struct Transform {
    pub kind: TransformKind,
    pub span: Span,
}

#[derive(Debug, Clone)]
pub enum TransformKind {
    Translate(Expr),
    Rotate(Expr),
    Scale(Expr),
    Matrix(Expr),
    /// POV-Ray's `transform T` (`.pov`): a transform value (declared, or a macro's).
    Value(Expr),
    /// POV-Ray's `transform { items }` (`.pov`): its transforms, transform values and
    /// `inverse`s (`PovParam`s) composed in order.
    Block(Vec<Item>),
}

#[derive(Debug, Clone)]
pub struct Material {
    /// `material { White ... }`: a declared material to start from (a name, or an array's
    /// element: `Materials[i]`).
    pub base: Option<Expr>,
    pub items: Vec<Item>,
    pub span: Span,
}

#[derive(Debug, Clone)]
pub struct MaterialParam {
    pub kind: MaterialParamKind,
    pub span: Span,
}

#[derive(Debug, Clone)]
pub enum MaterialParamKind {
    Diffuse(TextureArg),
    Specular(Colour),
    Transmission(Colour),
    Emission(Colour),
    Ior(Expr),
    Fresnel,
    Roughness(Expr),
    Coat(Expr),
    CoatRoughness(Expr),
}

/// `rgb <r, g, b>`, `rgb s`, or an expression, where a colour is expected.
#[derive(Debug, Clone)]
pub struct Colour {
    pub value: Expr,
    pub span: Span,
}

/// A texture node or a colour, where `diffuse` and the texture nodes take one.
#[derive(Debug, Clone)]
pub enum TextureArg {
    Texture(Texture),
    Colour(Colour),
}

#[derive(Debug, Clone)]
pub struct Texture {
    pub kind: TextureKind,
    /// The positional arguments (checker, stripes: two; mix: three).
    pub arguments: Vec<TextureArg>,
    /// `image_map`'s file.
    pub file: Option<Expr>,
    pub items: Vec<Item>,
    pub span: Span,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TextureKind {
    Checker,
    Stripes,
    Gradient,
    Noise,
    Marble,
    Wood,
    ImageMap,
    Mix,
    /// `pattern { WORD ... }`: POV-Ray's patterns; the pattern is the first item.
    Pattern,
}

#[derive(Debug, Clone)]
pub struct TextureParam {
    pub kind: TextureParamKind,
    pub value: Expr,
    pub span: Span,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TextureParamKind {
    Axis,
    Octaves,
    Turbulence,
}

impl TextureParamKind {
    pub fn word(self) -> &'static str {
        match self {
            TextureParamKind::Axis => "axis",
            TextureParamKind::Octaves => "octaves",
            TextureParamKind::Turbulence => "turbulence",
        }
    }
}

/// `array[n]...` with its optional initialiser.
#[derive(Debug, Clone)]
pub struct ArrayLiteral {
    pub dimensions: Vec<Expr>,
    pub elements: Option<Vec<ArrayElement>>,
    pub span: Span,
}

#[derive(Debug, Clone)]
pub enum ArrayElement {
    /// `{ ... }`: the elements of one row of a further dimension.
    Row(Vec<ArrayElement>, Span),
    Value(Box<Declared>, Span),
}

/// A name used as a value.
impl From<Ident> for Expr {
    fn from(name: Ident) -> Expr {
        Expr { kind: ExprKind::Ident(name.name), span: name.span }
    }
}

/// POV-Ray's camera projection as written (`docs/povray.md`).
#[derive(Debug, Clone)]
pub enum ProjectionWord {
    Perspective,
    Orthographic,
    Fisheye,
    UltraWideAngle,
    Omnimax,
    Panoramic,
    Spherical,
    /// `cylinder N`, N from 1 to 4.
    Cylinder(Expr),
}

#[derive(Debug, Clone)]
pub struct Expr {
    pub kind: ExprKind,
    pub span: Span,
}

#[derive(Debug, Clone)]
pub enum ExprKind {
    Number(f64),
    String(String),
    Constant(Constant),
    Ident(String),
    Vector(Vec<Expr>),
    /// `rgb e`: a colour (a number is promoted to grey).
    Rgb(Box<Expr>),
    /// POV-Ray's `rgbf`, `rgbt`, `rgbft` or `srgb` colour (`.pov`).
    PovColour(PovColourKind, Box<Expr>),
    /// POV-Ray's colour by components (`color red 1 green 0.5`), or a colour with some of
    /// them changed (`Red filter 0.3`) (`.pov`).
    ColourParts {
        base: Option<Box<Expr>>,
        parts: Vec<(ColourChannel, Expr)>,
    },
    Unary {
        op: UnaryOp,
        operand: Box<Expr>,
    },
    /// `span` of the `Expr` is where `left` starts; `op_span` is the operator's.
    Binary {
        op: BinaryOp,
        op_span: Span,
        left: Box<Expr>,
        right: Box<Expr>,
    },
    Ternary {
        condition: Box<Expr>,
        then: Box<Expr>,
        otherwise: Box<Expr>,
    },
    Component {
        value: Box<Expr>,
        /// x, y, z, filter, transmit: 0 to 4; `function::GRAY` the colour's gray.
        axis: usize,
        span: Span,
    },
    Index {
        array: Box<Expr>,
        index: Box<Expr>,
    },
    Function(Function, Vec<Expr>),
    Call(Call),
    /// A block given to a macro as its argument (`Gamma(pigment { ... }, 1.5)`, `.pov`): its
    /// value is what `#declare` of it binds.
    Block(Box<Declared>),
}

/// A component of POV-Ray's colour `<red, green, blue, filter, transmit>`, its index there.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ColourChannel {
    Red = 0,
    Green = 1,
    Blue = 2,
    Filter = 3,
    Transmit = 4,
}

/// How a POV-Ray colour's components are written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PovColourKind {
    /// `<r, g, b, filter>`
    Rgbf,
    /// `<r, g, b, transmit>`
    Rgbt,
    /// `<r, g, b, filter, transmit>`
    Rgbft,
    /// `<r, g, b>` in sRGB's encoding.
    Srgb,
}

impl Expr {
    /// The name, if the expression is a lone identifier (passed to a macro by reference).
    pub fn lone_ident(&self) -> Option<&str> {
        match &self.kind {
            ExprKind::Ident(name) => Some(name),
            _ => None,
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UnaryOp {
    Negate,
    Plus,
    Not,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BinaryOp {
    Or,
    And,
    Less,
    LessEqual,
    Greater,
    GreaterEqual,
    Equal,
    NotEqual,
    Add,
    Subtract,
    Multiply,
    Divide,
}

impl BinaryOp {
    /// POV-Ray's precedence: `&` and `|` lowest (together), then comparisons, `+ -`, `* /`.
    pub fn precedence(self) -> u8 {
        match self {
            BinaryOp::Or | BinaryOp::And => 1,
            BinaryOp::Less
            | BinaryOp::LessEqual
            | BinaryOp::Greater
            | BinaryOp::GreaterEqual
            | BinaryOp::Equal
            | BinaryOp::NotEqual => 2,
            BinaryOp::Add | BinaryOp::Subtract => 3,
            BinaryOp::Multiply | BinaryOp::Divide => 4,
        }
    }

    pub fn symbol(self) -> &'static str {
        match self {
            BinaryOp::Or => "|",
            BinaryOp::And => "&",
            BinaryOp::Less => "<",
            BinaryOp::LessEqual => "<=",
            BinaryOp::Greater => ">",
            BinaryOp::GreaterEqual => ">=",
            BinaryOp::Equal => "=",
            BinaryOp::NotEqual => "!=",
            BinaryOp::Add => "+",
            BinaryOp::Subtract => "-",
            BinaryOp::Multiply => "*",
            BinaryOp::Divide => "/",
        }
    }
}

//! The scene graph: what a `.scn` file says, evaluated (numbers, not expressions) but not yet
//! flattened. Produced by `lang`, consumed by `scene::build`. Every node keeps its span so that
//! errors found while building still point at the text.

use std::path::PathBuf;
use std::sync::Arc;

use glam::{Affine3A, Mat3, Vec2, Vec3};

use crate::diagnostic::Span;
pub use crate::geometry::CsgOp;
use crate::geometry::ScalarField;

#[derive(Debug, Clone)]
pub struct SceneGraph {
    pub settings: Settings,
    pub camera: CameraDesc,
    pub lights: Vec<LightDesc>,
    pub objects: Vec<ObjectNode>,
    /// POV-Ray's `sky_sphere`: an environment light from a pigment (`.pov`).
    pub sky: Option<SkyDesc>,
    /// POV-Ray's `background { C }`: what rays the camera sees leave the scene towards where no
    /// sky is; it does not light (`.pov`).
    pub backdrop: Vec3,
    /// A medium filling the whole scene, outside objects with a medium of their own
    /// (`atmosphere { }`; POV-Ray's `fog` and scene-wide `media`).
    pub atmosphere: Option<MediumDesc>,
    /// What the language found worth saying that is not an error (POV-Ray's `#version`).
    pub warnings: Vec<String>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum IntegratorKind {
    Direct,
    Path,
    /// Jensen's two-pass photon mapping, the course's one map (`docs/language.md`, Photon
    /// mapping).
    Photon,
    /// Jensen's photon mapping with a caustic map and final gathering from a global map.
    FinalGather,
    /// Stochastic progressive photon mapping (Hachisuka and Jensen 2009).
    Sppm,
}

impl IntegratorKind {
    pub fn name(self) -> &'static str {
        match self {
            IntegratorKind::Direct => "direct",
            IntegratorKind::Path => "path",
            IntegratorKind::Photon => "photon",
            IntegratorKind::FinalGather => "final_gather",
            IntegratorKind::Sppm => "sppm",
        }
    }

    /// Every integrator, for parsing names and listing them in messages.
    pub const ALL: [IntegratorKind; 5] = [
        IntegratorKind::Direct,
        IntegratorKind::Path,
        IntegratorKind::Photon,
        IntegratorKind::FinalGather,
        IntegratorKind::Sppm,
    ];

    /// The integrator called `name`, if any.
    pub fn named(name: &str) -> Option<IntegratorKind> {
        IntegratorKind::ALL.into_iter().find(|kind| kind.name() == name)
    }
}

/// `settings { ... }`; `Default` gives the language's defaults.
#[derive(Debug, Clone, PartialEq)]
pub struct Settings {
    pub width: u32,
    pub height: u32,
    pub samples: u32,
    pub integrator: IntegratorKind,
    pub max_depth: u32,
    pub seed: u64,
    pub background: Vec3,
    /// Photons per pass (`photon`, `final_gather`) or iteration (`sppm`); `None`: the
    /// integrator's default.
    pub photons: Option<u32>,
    /// `photon`: photons in each density estimate (`final_gather`: in each global one).
    pub photon_k: u32,
    /// `sppm`: the initial gather radius, in scene units.
    pub photon_radius: f32,
}

impl Settings {
    /// The integrator's parameters beyond samples and seed, by name, for the image's header.
    pub fn parameters(&self) -> Vec<(&'static str, String)> {
        let depth = ("max_depth", self.max_depth.to_string());
        let photons = ("photons", self.photons().to_string());
        match self.integrator {
            IntegratorKind::Direct | IntegratorKind::Path => vec![depth],
            IntegratorKind::Photon | IntegratorKind::FinalGather => {
                vec![depth, photons, ("photon_k", self.photon_k.to_string())]
            }
            IntegratorKind::Sppm => {
                vec![depth, photons, ("photon_radius", self.photon_radius.to_string())]
            }
        }
    }

    /// Photons per pass or iteration: as set, else 1,000,000 for `photon` and 200,000 for
    /// `sppm` (`docs/language.md`, Photon mapping).
    pub fn photons(&self) -> u32 {
        self.photons.unwrap_or(match self.integrator {
            IntegratorKind::Sppm => 200_000,
            IntegratorKind::Direct
            | IntegratorKind::Path
            | IntegratorKind::Photon
            | IntegratorKind::FinalGather => 1_000_000,
        })
    }
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            width: 256,
            height: 256,
            samples: 16,
            integrator: IntegratorKind::Path,
            max_depth: 32,
            seed: 0,
            background: Vec3::ZERO,
            photons: None,
            photon_k: 100,
            photon_radius: 0.05,
        }
    }
}

#[derive(Debug, Clone, PartialEq)]
pub enum CameraForm {
    /// The lab's camera: image plane `origin + forward + a*left + b*up`, a, b in [-1, 1].
    Lab { origin: Vec3, left: Vec3, up: Vec3, forward: Vec3 },
    /// POV-Ray's camera: `angle` is the horizontal field of view in degrees.
    LookAt { location: Vec3, look_at: Vec3, up: Vec3, angle: f32 },
    /// POV-Ray's `orthographic` camera: parallel rays along `forward` from the image plane
    /// `origin + a*left + b*up`, a, b in [-1, 1].
    Orthographic { origin: Vec3, left: Vec3, up: Vec3, forward: Vec3 },
    /// POV-Ray's wide projections (`fisheye`, `panoramic`, `cylinder`, ...) from its vectors.
    Wide { projection: crate::projection::Projection, frame: crate::projection::Frame },
}

#[derive(Debug, Clone, PartialEq)]
pub struct CameraDesc {
    pub form: CameraForm,
    /// Thin-lens radius; 0 is a pinhole.
    pub aperture: f32,
    /// Distance along the view direction that is in focus; `None` means the image plane's.
    pub focal_distance: Option<f32>,
    /// POV-Ray's `normal { }` in a camera: each ray's direction tilted as a bumped surface's
    /// normal is, by the pattern at the image position (x - 1/2, 1/2 - y, 0).
    pub normal: Option<NormalNode>,
    pub span: Span,
}

/// POV-Ray's `sky_sphere { pigment { ... } transforms emission E }`: radiance towards
/// direction d is the pigment at the unit vector T^-1 d (T's linear part: the sky is infinitely
/// far, translations do not move it) times `emission`.
#[derive(Debug, Clone, PartialEq)]
pub struct SkyDesc {
    pub pigment: TextureNode,
    pub transforms: Vec<Transform>,
    pub emission: Vec3,
    pub span: Span,
}

/// `light_source { <c> power rgb p form }`: p acts as radiant intensity (the course's Lab 4
/// formula; a spotlight's on its axis), a parallel light's as irradiance on a surface facing it.
#[derive(Debug, Clone)]
pub struct LightDesc {
    pub position: Vec3,
    pub power: Vec3,
    pub form: LightForm,
    /// POV-Ray's `shadowless`: the light's direct light is never blocked.
    pub shadowless: bool,
    /// POV-Ray's `looks_like`: an object, placed at the light, seen but not blocking it.
    pub looks_like: Option<Arc<ObjectNode>>,
    pub span: Span,
}

/// POV-Ray's spotlight cone: full intensity within `radius` degrees of the axis, none beyond
/// `falloff` degrees, narrowed by cos^`tightness`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpotCone {
    pub radius: f32,
    pub falloff: f32,
    pub tightness: f32,
}

/// An emitter's beam (a `.pov` area spotlight's): its emission shaped by a spotlight's cone
/// about the unit `axis`, in world space (`light::emitted`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BeamDesc {
    pub axis: Vec3,
    pub cone: SpotCone,
}

/// How a light sends its power out.
#[derive(Debug, Clone, PartialEq)]
pub enum LightForm {
    /// The same intensity in every direction.
    Point,
    /// Towards `point_at`, with POV-Ray's spotlight profile (`light::SpotProfile`).
    Spot { point_at: Vec3, cone: SpotCone },
    /// From infinitely far away, along the direction from the light's position to `point_at`.
    Parallel { point_at: Vec3 },
}

/// What lies under a coat, and so what its strength takes from the light beneath.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Covers {
    /// `.scn`'s `coat` (`docs/language.md`): the diffuse base alone, which sees a physical
    /// coat's 1 - F whatever the strength (the strength dims only the coat's reflection,
    /// Mitsuba's `specular_reflectance`); a mirror or transmission stands beside the coat.
    Base,
    /// POV-Ray's highlight (`docs/povray.md`): everything, under a coat of weight c that
    /// reflects c F and lets 1 - c F through to the base, the mirror and the transmission
    /// (Weidlich and Wilkie 2007's layering, pbrt-v4's `CoatedDiffuse`): a clear pigment
    /// under a highlight passes all the light the coat does not reflect.
    Everything,
}

/// `material { ... }`, all fields explicit (defaults filled in by `lang`).
#[derive(Debug, Clone, PartialEq)]
pub struct MaterialDesc {
    /// The declared name, if it came from `#declare Name = material {...}`; for messages.
    pub name: Option<String>,
    /// kd: a colour or a procedural texture; under a POV-Ray `pigment`, its colour.
    pub diffuse: TextureNode,
    pub specular: Vec3,
    pub transmission: Vec3,
    pub ior: f32,
    pub emission: Vec3,
    /// `emission` leaves both sides of the surface (POV-Ray's glow), not only the normal's.
    pub two_sided: bool,
    pub fresnel: bool,
    /// GGX alpha of the `specular` and `transmission` lobes, in [0, 1]; 0: perfect lobes.
    pub roughness: f32,
    /// The strength of a glossy coat over `diffuse`, in [0, 1]; 0: no coat.
    pub coat: f32,
    /// GGX alpha of the coat, in (0, 1].
    pub coat_roughness: f32,
    /// What the coat lies over: the diffuse base (`.scn`) or everything (POV-Ray's highlight).
    pub coat_covers: Covers,
    /// Bump mapping: how the shading normal is perturbed; `None`: not at all.
    pub normal: Option<NormalNode>,
    /// The medium inside objects of this material (`medium { }`; POV-Ray's `interior`
    /// fade and `media`), if any.
    pub interior: Option<Arc<MediumDesc>>,
    /// The beam that shapes `emission`, if any; `emission` is then the intensity per unit area
    /// on its axis.
    pub beam: Option<BeamDesc>,
    /// A POV-Ray patterned pigment (`.pov`): the lobes' shares are then made at each point
    /// from its colour (`diffuse`), filter and transmit there, and `specular`, `transmission`
    /// and `coat` are made there too.
    pub pigment: Option<PigmentDesc>,
    pub span: Span,
}

/// A POV-Ray pigment's transparency over a surface, and the finish that shares the light at
/// each point with it (`material::pov_shares`).
#[derive(Debug, Clone, PartialEq)]
pub struct PigmentDesc {
    /// POV-Ray's `filter` (light through, tinted by the colour), grey.
    pub filter: TextureNode,
    /// `filter` + `transmit`: all the light through, grey.
    pub through: TextureNode,
    pub finish: PovFinish,
    /// The glow: the pigment's colour times `glow` is emitted at each point (POV-Ray's
    /// `emission`, and `ambient` where `diffuse` is 0); `MaterialDesc::emission` is then its
    /// brightest.
    pub glow: Vec3,
}

/// What of a POV-Ray finish the light at a point is shared between, with the pigment.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PovFinish {
    /// `diffuse`: the Lambertian share of the pigment's opaque part.
    pub diffuse: f32,
    /// `reflection`'s mirror, before the pigment tints it.
    pub reflection: Vec3,
    /// `metallic`: the pigment tints the reflection.
    pub metallic: bool,
    /// The highlights' coat (`MaterialDesc::coat`).
    pub coat: f32,
}

/// A homogeneous participating medium, its coefficients per unit length of scene space
/// (`docs/language.md`, Media).
#[derive(Debug, Clone, PartialEq)]
pub struct MediumDesc {
    /// sigma_a, per channel.
    pub absorption: Vec3,
    /// sigma_s, per channel.
    pub scattering: Vec3,
    /// Radiance emitted per unit length.
    pub emission: Vec3,
    /// Henyey–Greenstein's g of its scattering, in (-1, 1); 0 is isotropic.
    pub anisotropy: f32,
    /// Ground fog's density, if it thins with height; the coefficients are those at density 1.
    pub ground: Option<GroundDesc>,
    pub span: Span,
}

/// Ground fog: density 1 up to height `offset` along the unit vector `up`, and 1 / (1 + (h -
/// offset) / falloff)² at height h above it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GroundDesc {
    pub up: Vec3,
    pub offset: f32,
    pub falloff: f32,
}

impl MaterialDesc {
    /// `coat_roughness` when not given (Mitsuba's `roughplastic`'s default alpha).
    pub const DEFAULT_COAT_ROUGHNESS: f32 = 0.1;

    /// `material { }`: the language's defaults, all zero and `ior 1`.
    pub fn new(span: Span) -> Self {
        MaterialDesc {
            name: None,
            diffuse: TextureNode::solid(Vec3::ZERO),
            specular: Vec3::ZERO,
            transmission: Vec3::ZERO,
            ior: 1.0,
            emission: Vec3::ZERO,
            two_sided: false,
            fresnel: false,
            roughness: 0.0,
            coat: 0.0,
            coat_roughness: MaterialDesc::DEFAULT_COAT_ROUGHNESS,
            coat_covers: Covers::Base,
            normal: None,
            interior: None,
            beam: None,
            pigment: None,
            span,
        }
    }
}

/// A texture: a pattern, and transforms that move the pattern (its value at p is the plain
/// pattern's at T^-1(p)), evaluated in the object's own space.
#[derive(Debug, Clone, PartialEq)]
pub struct TextureNode {
    pub pattern: Pattern,
    pub transforms: Vec<Transform>,
}

impl TextureNode {
    pub fn solid(colour: Vec3) -> Self {
        TextureNode { pattern: Pattern::Solid(colour), transforms: Vec::new() }
    }

    /// How many nodes the texture holds, and how deeply they nest (a solid colour: 1, 1).
    pub fn size_and_depth(&self) -> (usize, u32) {
        let children: Vec<&TextureNode> = match &self.pattern {
            Pattern::Checker(a, b) | Pattern::Stripes { a, b, .. } => vec![a, b],
            Pattern::Mix { a, b, t } => vec![a, b, t],
            Pattern::Warped { node, .. } => vec![node],
            Pattern::Field { map, .. } | Pattern::Average(map) => {
                map.iter().map(|(_, node)| node).collect()
            }
            Pattern::Solid(_)
            | Pattern::Gradient { .. }
            | Pattern::Noise { .. }
            | Pattern::Marble { .. }
            | Pattern::Wood { .. }
            | Pattern::Image { .. } => Vec::new(),
        };
        children
            .iter()
            .map(|c| c.size_and_depth())
            .fold((1, 1), |(size, depth), (s, d)| (size + s, depth.max(d + 1)))
    }

    /// The texture with each colour c made c^gamma: colours encoded with that gamma, decoded to
    /// linear light (POV-Ray's `assumed_gamma`). A mix's weights are not colours, and an image
    /// is decoded by its own gamma, so both stay.
    pub fn gamma_decoded(&self, gamma: f32) -> TextureNode {
        let node = |n: &TextureNode| Box::new(n.gamma_decoded(gamma));
        let colours = |m: &ColorMap| m.iter().map(|(at, c)| (*at, c.powf(gamma))).collect();
        let textures =
            |m: &TextureMap| m.iter().map(|(at, n)| (*at, n.gamma_decoded(gamma))).collect();
        let pattern = match &self.pattern {
            Pattern::Solid(c) => Pattern::Solid(c.powf(gamma)),
            Pattern::Checker(a, b) => Pattern::Checker(node(a), node(b)),
            Pattern::Stripes { a, b, axis } => {
                Pattern::Stripes { a: node(a), b: node(b), axis: *axis }
            }
            Pattern::Gradient { axis, map } => Pattern::Gradient { axis: *axis, map: colours(map) },
            Pattern::Noise { octaves, map } => {
                Pattern::Noise { octaves: *octaves, map: colours(map) }
            }
            Pattern::Marble { turbulence, octaves, map } => {
                Pattern::Marble { turbulence: *turbulence, octaves: *octaves, map: colours(map) }
            }
            Pattern::Wood { turbulence, octaves, map } => {
                Pattern::Wood { turbulence: *turbulence, octaves: *octaves, map: colours(map) }
            }
            Pattern::Image { .. } => self.pattern.clone(),
            Pattern::Mix { a, b, t } => Pattern::Mix { a: node(a), b: node(b), t: t.clone() },
            Pattern::Field { shape, map } => {
                Pattern::Field { shape: shape.clone(), map: textures(map) }
            }
            Pattern::Average(map) => Pattern::Average(textures(map)),
            Pattern::Warped { warp, node: n } => Pattern::Warped { warp: *warp, node: node(n) },
        };
        TextureNode { pattern, transforms: self.transforms.clone() }
    }

    /// The largest value in any channel the texture can take (for the energy check).
    pub fn max_value(&self) -> Vec3 {
        match &self.pattern {
            Pattern::Solid(c) => *c,
            Pattern::Checker(a, b) | Pattern::Stripes { a, b, .. } => {
                a.max_value().max(b.max_value())
            }
            Pattern::Mix { a, b, .. } => a.max_value().max(b.max_value()),
            Pattern::Warped { node, .. } => node.max_value(),
            Pattern::Field { map, .. } | Pattern::Average(map) => {
                map.iter().fold(Vec3::ZERO, |m, (_, c)| m.max(c.max_value()))
            }
            Pattern::Gradient { map, .. }
            | Pattern::Noise { map, .. }
            | Pattern::Marble { map, .. }
            | Pattern::Wood { map, .. } => map.iter().fold(Vec3::ZERO, |m, (_, c)| m.max(*c)),
            // Decoded 8-bit images are at most 1.
            Pattern::Image { look, .. } => match look.channel {
                ImageChannel::Colour | ImageChannel::Through(_) => Vec3::ONE,
                ImageChannel::Filter(f) => Vec3::splat(f),
                ImageChannel::Index => Vec3::splat(255.0),
            },
        }
    }
}

/// What a node of the graph holds below it.
#[derive(Debug, Clone, Copy)]
pub enum Below<'a> {
    /// Nothing: a shape.
    Nothing,
    /// A union's children.
    Children(&'a [ObjectNode]),
    /// A CSG object's operands.
    Operands(&'a [ObjectNode]),
    /// The declared object an instance shares.
    Shared(&'a Arc<ObjectNode>),
}

impl ShapeNode {
    /// What this node holds below it: the one place that sorts the kinds into shapes and nodes
    /// of nodes, for walks over the graph.
    pub fn below(&self) -> Below<'_> {
        match self {
            ShapeNode::Union(children) => Below::Children(children),
            ShapeNode::Csg { operands, .. } => Below::Operands(operands),
            ShapeNode::Instance(target) => Below::Shared(target),
            ShapeNode::Plane { .. }
            | ShapeNode::Sphere { .. }
            | ShapeNode::Box { .. }
            | ShapeNode::Triangle { .. }
            | ShapeNode::Quad { .. }
            | ShapeNode::Disk { .. }
            | ShapeNode::Cylinder { .. }
            | ShapeNode::Cone { .. }
            | ShapeNode::Torus { .. }
            | ShapeNode::Isosurface(_)
            | ShapeNode::Parametric(_)
            | ShapeNode::Algebraic { .. }
            | ShapeNode::Blob { .. }
            | ShapeNode::Prism { .. }
            | ShapeNode::Lathe { .. }
            | ShapeNode::Sor { .. }
            | ShapeNode::Ovus { .. }
            | ShapeNode::Lemon { .. }
            | ShapeNode::Polygon { .. }
            | ShapeNode::Superellipsoid { .. }
            | ShapeNode::JuliaFractal(_)
            | ShapeNode::Mesh { .. }
            | ShapeNode::Extrusion(_)
            | ShapeNode::HeightField { .. } => Below::Nothing,
        }
    }
}

/// `color_map { [position colour] ... }`, positions ascending in [0, 1].
pub type ColorMap = Vec<(f32, Vec3)>;

#[derive(Debug, Clone, PartialEq)]
pub enum Pattern {
    Solid(Vec3),
    /// The first where floor(x) + floor(y) + floor(z) is even.
    Checker(Box<TextureNode>, Box<TextureNode>),
    /// Alternating unit bands along `axis`.
    Stripes {
        a: Box<TextureNode>,
        b: Box<TextureNode>,
        axis: Vec3,
    },
    /// A ramp along `axis` through the map, repeating every unit.
    Gradient {
        axis: Vec3,
        map: ColorMap,
    },
    /// Perlin fBm in [0, 1] through the map.
    Noise {
        octaves: u32,
        map: ColorMap,
    },
    /// Bands along x perturbed by turbulence.
    Marble {
        turbulence: f32,
        octaves: u32,
        map: ColorMap,
    },
    /// Rings around the z axis perturbed by turbulence.
    Wood {
        turbulence: f32,
        octaves: u32,
        map: ColorMap,
    },
    /// An image projected onto the unit square (or wrapped around the y axis), read as its
    /// `look` says.
    Image {
        path: PathBuf,
        look: ImageLook,
    },
    /// a (1 - t) + b t.
    Mix {
        a: Box<TextureNode>,
        b: Box<TextureNode>,
        t: Box<TextureNode>,
    },
    /// POV-Ray's patterns: a shaped value in [0, 1] through a map of textures (a color_map's
    /// entries are solid colours), interpolated between the entries either side.
    Field {
        shape: Box<FieldShape>,
        map: TextureMap,
    },
    /// POV-Ray's `average`: the weighted mean of the textures (weights need not sum to 1).
    Average(TextureMap),
    /// The texture at the point moved by a warp (`pigment { P_Declared warp { } }`,
    /// `average ... warp { }`).
    Warped {
        warp: Warp,
        node: Box<TextureNode>,
    },
}

/// How an image is projected, sampled and decoded, and which of a pigment's parts it gives
/// (POV-Ray's `image_map { map_type once interpolate gamma filter transmit }`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImageLook {
    pub projection: ImageProjection,
    /// Only one copy, on the unit square: outside it the image lets all light through.
    pub once: bool,
    /// Bilinear between the texel centres, else the nearest texel.
    pub bilinear: bool,
    /// The file's values to linear: `None` the sRGB curve, `Some(g)` the power g.
    pub gamma: Option<f32>,
    pub channel: ImageChannel,
}

/// POV-Ray's `map_type`: where a point of the pattern's space falls in the image's (u, v).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ImageProjection {
    /// `map_type 0`: (u, v) = (x, y).
    Planar,
    /// `map_type 1`: u the longitude around y from +x towards +z, v the latitude from -y (0)
    /// to +y (1).
    Spherical,
    /// `map_type 2`: u the longitude as the sphere's, v = y.
    Cylindrical,
    /// `map_type 5`: u the longitude as the sphere's, v the angle around the tube of the torus
    /// of major radius 1 about y, from its inner equator down under the tube first (1/4 at its
    /// bottom, 1/2 at its outer equator, 3/4 on its top).
    Torus,
}

/// The part of a pigment an image gives at each point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ImageChannel {
    /// The texels' linear colour (black outside a `once` image).
    Colour,
    /// `filter all F` (0 outside a `once` image).
    Filter(f32),
    /// Filter + transmit: the given `filter all` + `transmit all` plus the texels' transparency
    /// (1 - alpha), at most 1; 1 outside a `once` image.
    Through(f32),
    /// A palette image's index of each texel, 0 to 255, on every channel (a bump_map's
    /// `use_index`); the colour in an image without a palette.
    Index,
}

impl ImageLook {
    /// `.scn`'s `image_map { "file" }`: planar, repeating, the nearest texel, sRGB.
    pub fn colour() -> ImageLook {
        ImageLook {
            projection: ImageProjection::Planar,
            once: false,
            bilinear: false,
            gamma: None,
            channel: ImageChannel::Colour,
        }
    }
}

/// Bump mapping (`normal { PATTERN AMOUNT }`): a perturbation of the shading normal, from a
/// pattern, moved by its transforms as a texture is, in the object's own space.
#[derive(Debug, Clone, PartialEq)]
pub struct NormalNode {
    pub pattern: NormalPattern,
    pub transforms: Vec<Transform>,
}

#[derive(Debug, Clone, PartialEq)]
pub enum NormalPattern {
    /// The surface is displaced by `amount` times the pattern's value (through the slope map's
    /// heights, if any): the normal tilts against the value's gradient, taken by central
    /// differences `accuracy` apart in pattern space (POV-Ray's `accuracy`).
    Bumps { shape: Box<FieldShape>, amount: f32, slopes: SlopeMap, accuracy: f32 },
    /// `normal_map`: the entries' perturbations, interpolated by the pattern's value.
    Map { shape: Box<FieldShape>, map: Vec<(f32, NormalNode)> },
    /// `average`: the weighted mean of the entries' perturbations.
    Average(Vec<(f32, NormalNode)>),
    /// `bump_map`: displaced by `amount` times the image's gray (0.297 r + 0.589 g + 0.114 b)
    /// where the image lies (`look`'s projection; bilinear), its gradient taken across a texel.
    Image { path: PathBuf, look: ImageLook, amount: f32 },
}

/// `slope_map { [position <height, slope>] }`: a height profile over the pattern's value,
/// cubic between the entries with the given heights and slopes; empty: the value itself.
pub type SlopeMap = Vec<(f32, f32, f32)>;

/// `[position texture]` entries, positions ascending in [0, 1] (`average`: weights > 0).
pub type TextureMap = Vec<(f32, TextureNode)>;

/// A POV-Ray pattern's value at each point: the field of its pattern, at the point moved by the
/// warps (first written, first applied), then `frequency` and `phase` and the wave.
#[derive(Debug, Clone, PartialEq)]
pub struct FieldShape {
    pub field: Field,
    /// Classic `turbulence` where the pattern adds it itself (marble, wood, agate, spirals);
    /// elsewhere it is the first warp.
    pub turbulence: Option<Turbulence>,
    pub warps: Vec<Warp>,
    pub wave: Wave,
    pub frequency: f32,
    pub phase: f32,
}

/// A fractal pattern: which set, its iterations, and how points that escape (`exterior`) and
/// points that stay (`interior`) are valued.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fractal {
    pub set: FractalSet,
    /// z^exponent + c (2, 3 or 4; `mandel` and `julia` only).
    pub exponent: u32,
    pub iterations: u32,
    pub interior: FractalColouring,
    pub exterior: FractalColouring,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FractalSet {
    /// z -> z^n + p, from z = p.
    Mandel,
    /// z -> z^n + c from z = p.
    Julia(Vec2),
    /// POV-Ray's `magnet 1` and `magnet 2` formulas, Mandelbrot-like (c = p) or Julia-like.
    Magnet { formula: u32, julia: Option<Vec2> },
}

/// POV-Ray's fractal colourings (`interior TYPE, FACTOR`, `exterior TYPE, FACTOR`): of the
/// last z = a + bi, 0 the factor alone, 1 (exterior) the iterations' share or (interior) the
/// orbit's nearest approach to 0, 2 a, 3 b, 4 a², 5 b², 6 |z| (exterior) or |z|² (interior),
/// each times the factor.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FractalColouring {
    pub kind: u32,
    pub factor: f32,
}

/// A function pattern's function of (x, y, z) (the language's compiled `function { }`), equal
/// to another only where both are the one compiled function.
#[derive(Debug, Clone)]
pub struct PatternFunction(pub Arc<dyn ScalarField>);

impl PartialEq for PatternFunction {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.0, &other.0)
    }
}

/// The patterns (`docs/language.md`, Patterns), each a value in [0, 1].
#[derive(Debug, Clone, PartialEq)]
pub enum Field {
    /// Veins: a sine of z bent by turbulence scaled by `turbulence` (`agate_turb`).
    Agate {
        turbulence: f32,
    },
    /// Noise (`bumps`, `spotted` are the same).
    Bozo,
    /// Bricks of `size` in rows along x, every other row shifted by half a brick; 0 in the
    /// mortar (`mortar` wide), 1 in a brick.
    Brick {
        size: Vec3,
        mortar: f32,
    },
    Bumps,
    /// A random value for each unit cube.
    Cells,
    /// 0 where floor(x) + floor(y) + floor(z) is even, else 1.
    Checker,
    /// Voronoi cells of one random point per unit cube: `form` weighs the distances to the
    /// nearest, second and third nearest points, each measured in the `metric` (the m-norm,
    /// (|dx|^m + |dy|^m + |dz|^m + offset)^(1/m)); `solid`: the nearest point's cell's random
    /// value instead.
    Crackle(Crackle),
    /// Noise cubed.
    Dents,
    /// frac(p . axis), `axis` a unit vector.
    Gradient(Vec3),
    /// POV-Ray's function pattern: the function of (x, y, z), wrapped into [0, 1] by the wave.
    Function(PatternFunction),
    /// Six octaves of |noise - 0.5| at 4 times the scale.
    Granite,
    /// Hexagons of unit side in the x-z plane, coloured 0, 0.5 and 1 so that neighbours differ.
    Hexagon,
    /// ((sin x + sin y + sin z) / 3)^2.
    Leopard,
    /// POV-Ray's fractal patterns in the x-y plane (`mandel`, `julia`, `magnet`), valued by
    /// their `exterior` and `interior` colourings.
    Fractal(Fractal),
    /// 1 - |y| down to 0 at |y| = 1 (`planar`).
    Planar,
    /// 1 - |p| down to 0 at |p| = 1 (`spherical`).
    Spherical,
    /// 1 - the distance from the y axis, down to 0 at 1 (`cylindrical`).
    Cylindrical,
    /// 1 - the largest of |x|, |y|, |z|, down to 0 at 1 (`boxed`).
    Boxed,
    /// x plus turbulence, through a triangle wave by default.
    Marble,
    /// frac(|p|): concentric spheres.
    Onion,
    /// Each unit cube shaded from its centre out by a cubic with the two control values.
    Quilted {
        control0: f32,
        control1: f32,
    },
    /// The angle about y, a turn from 0 to 1.
    Radial,
    /// Circular waves from ten sources in the unit cube (sines of distance).
    Ripples,
    /// A screw about z with `arms` threads: frac(z + arms * angle / 2 pi).
    Spiral1 {
        arms: f32,
    },
    /// Two such screws in opposite directions.
    Spiral2 {
        arms: f32,
    },
    Spotted,
    /// Like `ripples`, cosines fading with distance.
    Waves,
    /// Rings about the z axis (distance from it), through a triangle wave by default.
    Wood,
    /// Ten octaves of |noise| (sharp creases).
    Wrinkles,
}

/// POV-Ray's crackle parameters (defaults: form <-1, 1, 0>, metric 2, offset 0, not solid).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Crackle {
    pub form: Vec3,
    pub metric: f32,
    pub offset: f32,
    pub solid: bool,
}

impl Crackle {
    pub const DEFAULT: Crackle =
        Crackle { form: Vec3::new(-1.0, 1.0, 0.0), metric: 2.0, offset: 0.0, solid: false };
}

/// POV-Ray's `turbulence amount octaves omega lambda`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Turbulence {
    pub amount: Vec3,
    pub octaves: u32,
    pub omega: f32,
    pub lambda: f32,
}

/// POV-Ray's `warp { }`: moves the points a pattern is evaluated at.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Warp {
    /// p + amount * the vector turbulence at p.
    Turbulence(Turbulence),
    /// `repeat <direction> offset <o> flip <f>`: the slab [0, width) along the direction's
    /// axis repeats; the k-th copy is moved by k * offset and, when k is odd, mirrored along the
    /// axes where `flip` is not 0.
    Repeat { axis: usize, width: f32, offset: Vec3, flip: Vec3 },
    /// `black_hole <centre>, radius  strength falloff inverse repeat <r> turbulence <t>`.
    BlackHole(BlackHole),
    /// `planar`, `cylindrical`, `spherical`, `toroidal`: the point's place on that surface.
    Mapping(Mapping),
    /// The inverse of a pigment's transforms written before a later warp: POV-Ray applies them
    /// to the point after that warp (`gradient x scale 2 warp { repeat x*0.5 }` repeats every
    /// 0.5 of the object's space).
    Transform(Affine3A),
}

/// POV-Ray's mapping warps (warp.cpp): the point p becomes (u, v, d), its place on a surface and
/// its distance from it, so that a pattern of x and y wraps around the surface. u is the angle
/// about y from +x towards +z in turns (planar: x), v the angle from the x-z plane (spherical,
/// from −y at 0 to +y at 1), y (cylindrical, planar) or the angle around the torus's tube in
/// turns; u and v are multiplied by d^`dist_exp` (0: not). The result's axes are turned so that
/// its z lies along `orientation` (z when not given).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mapping {
    pub surface: MappingSurface,
    pub orientation: Vec3,
    pub dist_exp: f32,
}

/// The surface of a mapping warp.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MappingSurface {
    /// `planar <orientation>, offset`: (x, y, offset).
    Planar { offset: f32 },
    /// About the y axis: (turns about y, y, distance from the axis).
    Cylindrical,
    /// About the origin: (turns about y, height 0 to 1, distance from the origin).
    Spherical,
    /// About the circle of radius `major_radius` in the x-z plane: (turns about y, turns around
    /// the tube, distance from the circle).
    Toroidal { major_radius: f32 },
}

/// POV-Ray's black hole warp: a point p within `radius` of the centre c is moved to
/// p + s (p - c) (p - s (p - c) when `inverse`), s = min(strength (1 - |p - c| / radius)^falloff,
/// 1), so that the pattern looks drawn into the hole (pushed out of it). With `repeat`, a hole
/// stands in every block of that size (the components that are 0 do not repeat), each moved
/// within its block by a random part of `jitter` (POV-Ray's `turbulence` here).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BlackHole {
    pub centre: Vec3,
    pub radius: f32,
    pub strength: f32,
    pub falloff: f32,
    pub inverse: bool,
    pub repeat: Vec3,
    pub jitter: Vec3,
}

impl Default for BlackHole {
    /// POV-Ray's: a hole of radius 1 at the origin, strength 1, falloff 2, not repeated.
    fn default() -> Self {
        BlackHole {
            centre: Vec3::ZERO,
            radius: 1.0,
            strength: 1.0,
            falloff: 2.0,
            inverse: false,
            repeat: Vec3::ZERO,
            jitter: Vec3::ZERO,
        }
    }
}

/// How a value in [0, 1) is shaped (POV-Ray's wave types).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Wave {
    Ramp,
    /// 0.5 + 0.5 sin(2 pi v).
    Sine,
    /// Up to 1 at 0.5 and back down.
    Triangle,
    /// |sin(pi v)|.
    Scallop,
    /// 3v^2 - 2v^3.
    Cubic,
    /// v^exponent.
    Poly(f32),
}

/// A transform as written; `ObjectNode::transforms` applies them first written, first applied.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Transform {
    Translate(Vec3),
    /// Degrees about x, then y, then z (POV-Ray).
    Rotate(Vec3),
    Scale(Vec3),
    /// POV-Ray's `matrix <m00, .., m22, t0, t1, t2>`: x' = m00 x + m10 y + m20 z + t0, and so on,
    /// so `linear` is `Mat3::from_cols_array` of the first nine numbers in written order.
    Matrix {
        linear: Mat3,
        translation: Vec3,
    },
}

impl Transform {
    pub fn to_affine(self) -> Affine3A {
        match self {
            Transform::Translate(v) => Affine3A::from_translation(v),
            Transform::Rotate(deg) => {
                let r = deg * (std::f32::consts::PI / 180.0);
                // About x first, then y, then z: R = Rz * Ry * Rx. In the left-handed space
                // this is the same matrix POV-Ray uses (rotations are about the axis, clockwise
                // when looking along it from the positive end).
                Affine3A::from_rotation_z(r.z)
                    * Affine3A::from_rotation_y(r.y)
                    * Affine3A::from_rotation_x(r.x)
            }
            Transform::Scale(s) => Affine3A::from_scale(s),
            Transform::Matrix { linear, translation } => {
                Affine3A::from_mat3_translation(linear, translation)
            }
        }
    }
}

/// Below this |determinant| an object's transforms flatten it: a 32-bit matrix has no useful
/// inverse.
pub const FLATTENING_DETERMINANT: f32 = 1e-12;

/// The composition of transforms in written order (first written, first applied).
pub fn compose(transforms: &[Transform]) -> Affine3A {
    transforms.iter().fold(Affine3A::IDENTITY, |acc, t| t.to_affine() * acc)
}

#[derive(Debug, Clone)]
pub struct ObjectNode {
    pub shape: ShapeNode,
    /// Applies to this node, and to children without a material of their own.
    pub material: Option<Arc<MaterialDesc>>,
    pub transforms: Vec<Transform>,
    /// Levels of groups and instances below and including this node (1 for a shape): kept
    /// so that `lang` can refuse chains deep enough to overflow a stack when walked.
    pub depth: u32,
    pub span: Span,
}

#[derive(Debug, Clone)]
pub enum ShapeNode {
    /// Points p with `normal . p + offset = 0` (the course's Lab 4 convention).
    Plane {
        normal: Vec3,
        offset: f32,
    },
    Sphere {
        center: Vec3,
        radius: f32,
    },
    /// Two opposite corners, in any order.
    Box {
        corner_a: Vec3,
        corner_b: Vec3,
    },
    Triangle {
        a: Vec3,
        b: Vec3,
        c: Vec3,
    },
    /// Emits towards `edge1 x edge2`.
    Quad {
        corner: Vec3,
        edge1: Vec3,
        edge2: Vec3,
    },
    /// With a hole of radius `hole` (0: none; below `radius`) about its centre.
    Disk {
        center: Vec3,
        normal: Vec3,
        radius: f32,
        hole: f32,
    },
    /// Closed: with both caps. (An open cylinder is a `Cone` with equal radii and `open`.)
    Cylinder {
        base: Vec3,
        cap: Vec3,
        radius: f32,
    },
    /// `cone { base, base_radius, cap, cap_radius [open] }`: radii >= 0, not both 0; closed
    /// by its end disks (none where a radius is 0) unless `open`, which leaves the side alone
    /// (not a solid then). Equal radii make a cylinder.
    Cone {
        base: Vec3,
        base_radius: f32,
        cap: Vec3,
        cap_radius: f32,
        open: bool,
    },
    /// `torus { major, minor }`: the points at distance `minor` from the circle of radius
    /// `major` about the y axis in the x-z plane (POV-Ray's torus). Radii > 0.
    Torus {
        major: f32,
        minor: f32,
    },
    /// POV-Ray's `isosurface { }`: where a function is below its threshold in a container.
    Isosurface(Arc<crate::geometry::IsosurfaceDesc>),
    /// POV-Ray's `parametric { }`: an open surface, not a solid.
    Parametric(Arc<crate::geometry::ParametricDesc>),
    /// The surface P(x, y, z) = 0 of the polynomial with these terms (POV-Ray's `quadric`,
    /// `cubic`, `quartic`, `poly`), solid where P < 0; total degree at most
    /// `geometry::MAX_DEGREE`, some term other than the constant not 0.
    Algebraic {
        terms: Vec<crate::geometry::Term>,
    },
    /// POV-Ray's blob: the solid where the components' summed field exceeds `threshold` (> 0);
    /// some component of positive strength.
    Blob {
        threshold: f32,
        components: Vec<crate::geometry::BlobComponent>,
    },
    /// POV-Ray's `superellipsoid { <e, n> }`: (|x|^(2/e) + |y|^(2/e))^(e/n) + |z|^(2/n) = 1,
    /// e and n > 0.
    Superellipsoid {
        e: f32,
        n: f32,
    },
    /// POV-Ray's `julia_fractal`: its parameter, algebra, function, iterations, precision and
    /// slice, checked.
    JuliaFractal(Box<crate::geometry::JuliaDesc>),
    /// POV-Ray's prism: closed curves of `segments` in the x-z plane swept along y between
    /// `heights` (distinct), solid by the even-odd rule unless `open` (the side alone, not a
    /// solid).
    Prism {
        segments: Vec<crate::geometry::Segment>,
        sweep: crate::geometry::Sweep,
        heights: [f32; 2],
        open: bool,
    },
    /// POV-Ray's lathe: a curve of `segments` (points (r, y), r >= 0) turned about the y axis,
    /// solid inside the curve by the even-odd rule.
    Lathe {
        segments: Vec<crate::geometry::Segment>,
    },
    /// POV-Ray's surface of revolution: r^2 a cubic of the height piece by piece, closed by
    /// discs at its ends unless `open` (then not a solid).
    Sor {
        pieces: Vec<crate::geometry::SorPiece>,
        open: bool,
    },
    /// POV-Ray's `ovus { bottom, top }`: spheres of these radii at the origin and at
    /// (0, bottom, 0) joined smoothly (`geometry::ArcSolid::ovus`); 0 < top < 2 bottom.
    Ovus {
        bottom: f32,
        top: f32,
    },
    /// POV-Ray's `lemon { base, base_radius, cap, cap_radius, inner_radius [open] }`
    /// (`geometry::ArcSolid::lemon`): base and cap distinct, radii >= 0, `inner_radius` at
    /// least `geometry::lemon_min_inner_radius` of the radii over the axis' length times that
    /// length; `open` leaves the end discs off (then not a solid).
    Lemon {
        ends: [Vec3; 2],
        radii: [f32; 2],
        inner_radius: f32,
        open: bool,
    },
    /// POV-Ray's polygon: closed outlines (`geometry::close_outlines`) of `points`, all in one
    /// plane, enclosing an area; not a solid.
    Polygon {
        points: Vec<Vec3>,
    },
    /// `intersection`, `difference`, `merge { ... }`: a solid made of solid operands (sphere,
    /// box, closed cylinder and cone, torus, plane as the half-space n . p + d < 0, closed
    /// mesh, CSG, and `Union`/`Instance` nodes of solids; a union operand counts as the merge
    /// of its children). Each operand keeps its own material (a material on this node applies
    /// to operands without one) and transforms; `scene::build` reports any other operand as a
    /// located error at the operand's span.
    Csg {
        op: CsgOp,
        operands: Vec<ObjectNode>,
    },
    /// `mesh { "file.ply" }`: triangles from a PLY or OBJ file (path resolved by `lang`).
    Mesh {
        path: PathBuf,
    },
    /// A mesh the scene makes, in its own space: a glyph of a `text` extruded (closed, shared
    /// by every instance of the glyph), a `bicubic_patch` cut into smooth triangles, POV-Ray's
    /// triangles written in the scene (`smooth_triangle`, `mesh { triangle { } }`, `mesh2`).
    Extrusion(Arc<crate::mesh::Mesh>),
    /// POV-Ray's `height_field`: its sheet, which is what is seen, and its heights, whose solid
    /// (the sheet closed by walls and a floor, `mesh::height_field::solid`) CSG reads, made only
    /// where CSG needs it.
    HeightField {
        sheet: Arc<crate::mesh::Mesh>,
        heights: Arc<crate::mesh::heights::Heights>,
    },
    /// `union { ... }`: a group.
    Union(Vec<ObjectNode>),
    /// `object { Name ... }`: an instance of a declared object, shared, not copied.
    Instance(Arc<ObjectNode>),
}

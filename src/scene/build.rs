//! SceneGraph -> Scene: flattens groups and instances into world-space primitives, resolves
//! material inheritance, collects lights, builds the BVH and the camera.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{Affine3A, Vec3};

use super::{Primitive, Scene, SurfaceTexture};
use crate::aabb::Aabb;
use crate::accel::{Bvh, MAX_PRIMITIVES, Planes};
use crate::camera::Camera;
use crate::diagnostic::{SceneError, Span};
use crate::geometry::{
    Algebraic, ArcSolid, Blob, Cone, Csg, CsgNode, CsgOp, Cuboid, FewShapes, Isosurface, Julia,
    JuliaDesc, Lathe, Parametric, Placement, Planar, PlanarKind, Polygon, Prism, QuadricFrame,
    QuadricKind, Shape, Sor, Superellipsoid, Torus, TriangleMesh, outline_normal, similarity_scale,
};
use crate::graph::{
    Below, GroundDesc, IntegratorKind, LightDesc, LightForm, MaterialDesc, MediumDesc, ObjectNode,
    SceneGraph, ShapeNode, compose,
};
use crate::light::{BeamSampler, GlowPattern, Light, Spot, SpotProfile};
use crate::material::Material;
use crate::medium::{Density, HenyeyGreenstein, Medium};
use crate::mesh::heights::Heights;
use crate::mesh::{Mesh, height_field};
use crate::texture::{Bump, ImageMap};

/// Scenes whose simple bounded primitives (spheres, planar shapes, boxes as their six faces)
/// are at most this many (a box counting six), beside at most `ALONE_MAX` others, test rays
/// traced in lanes against all of them instead of traversing the BVH. (Measured: the lab
/// box with 16 spheres and the area light renders as fast either way, one thread.)
const FEW_BOUNDED_MAX: usize = 16;

/// The most bounded primitives other than simple ones (a mesh, a CSG object) beside which the
/// simple ones are still tested in lanes; each lane then walks a BVH of the others alone. (S5,
/// the bunny's mesh beside a sphere and the area light: 10 % fewer instructions than each lane
/// walking the scene's BVH, callgrind; more than one was not measured.)
const ALONE_MAX: usize = 1;

/// The most primitives a scene may expand to (about 100 bytes each, with the BVH).
pub const MAX_SCENE_PRIMITIVES: u64 = 1 << 24;

/// The primitives `node` expands to; a shared (declared) object is counted once and its count
/// reused, so counting takes time in the size of the text, not of the expansion.
fn primitive_count(node: &ObjectNode, counts: &mut HashMap<*const ObjectNode, u64>) -> u64 {
    match node.shape.below() {
        Below::Children(children) => {
            children.iter().fold(0, |sum, child| sum.saturating_add(primitive_count(child, counts)))
        }
        Below::Shared(target) => match counts.get(&Arc::as_ptr(target)) {
            Some(&count) => count,
            None => {
                let count = primitive_count(target, counts);
                counts.insert(Arc::as_ptr(target), count);
                count
            }
        },
        // A CSG object is one primitive, however many operands it has.
        Below::Operands(_) | Below::Nothing => 1,
    }
}

/// The core light of a described light, unblocked within `bulb` of it; a parallel light's
/// photons cover the sphere (`centre`, `radius`) around the scene.
fn light(desc: &LightDesc, bulb: f32, centre: Vec3, radius: f32) -> Light {
    let LightDesc { position, power, ref form, shadowless, .. } = *desc;
    let light = match *form {
        LightForm::Point => Light::Point { position, power },
        LightForm::Spot { point_at, cone } => {
            let profile = SpotProfile::from_degrees(cone.radius, cone.falloff, cone.tightness);
            let axis = (point_at - position).normalize();
            Light::Spot(Spot::new(position, axis, power, profile))
        }
        LightForm::Parallel { point_at } => {
            let direction = (point_at - position).normalize();
            Light::Distant { direction, irradiance: power, centre, radius }
        }
    };
    if shadowless || bulb > 0.0 {
        Light::Modified { light: Box::new(light), bulb, shadowless }
    } else {
        light
    }
}

/// The distance from `point` to the farthest corner of `bounds`.
fn farthest(bounds: &Aabb, point: Vec3) -> f32 {
    (bounds.min - point).abs().max((bounds.max - point).abs()).length()
}

/// A sphere around the finite objects' boxes and the camera (the part of the scene a distant
/// light's photons must reach).
fn bounding_sphere(bounds: &[Aabb], camera: Vec3) -> (Vec3, f32) {
    let (min, max) =
        bounds.iter().fold((camera, camera), |(min, max), b| (min.min(b.min), max.max(b.max)));
    let centre = 0.5 * (min + max);
    (centre, (0.5 * (max - min).length()).max(1e-3))
}

/// Builds the render-ready scene. `graph.settings` are final (command-line overrides applied).
pub fn build(graph: &SceneGraph) -> Result<Scene, SceneError> {
    let settings = graph.settings.clone();
    let (camera, camera_warnings) = Camera::new(&graph.camera, settings.width, settings.height)?;
    // Counted before anything is expanded: a few lines of nested instances can stand for 2^26
    // primitives, which must be an error, not gigabytes.
    let mut counts = HashMap::new();
    let mut total = 0u64;
    for node in &graph.objects {
        total = total.saturating_add(primitive_count(node, &mut counts));
        if total > MAX_SCENE_PRIMITIVES {
            return Err(SceneError::at(
                &node.span,
                format!(
                    "with this object the scene has {total} primitives once its groups and \
                     instances are expanded; at most {MAX_SCENE_PRIMITIVES} are supported (a \
                     mesh counts one for each instance)"
                ),
            ));
        }
    }
    let mut flat = Flattener::default();
    for node in &graph.objects {
        flat.add(node, Affine3A::IDENTITY, None)?;
    }
    // Each light's `looks_like` object, moved to the light: the distance to its farthest
    // point is where the light's shadow rays stop and its photons start.
    let mut bulbs = Vec::with_capacity(graph.lights.len());
    for light in &graph.lights {
        let first = flat.primitives.len();
        if let Some(node) = &light.looks_like {
            flat.add(node, Affine3A::from_translation(light.position), None)?;
        }
        let bulb = flat.primitives[first..].iter().fold(0.0f32, |bulb, p| {
            p.shape.bounds().map_or(f32::INFINITY, |b| bulb.max(farthest(&b, light.position)))
        });
        bulbs.push(bulb);
    }

    let (mut bounded, unbounded): (Vec<Primitive>, Vec<Primitive>) =
        flat.primitives.into_iter().partition(|p| p.shape.bounds().is_some());
    // Unbounded: the planes, then any other (a CSG object that merges or only intersects
    // half-spaces).
    let (planes, others): (Vec<Primitive>, Vec<Primitive>) =
        unbounded.into_iter().partition(|p| matches!(p.shape, Shape::Plane { .. }));
    let bounds: Vec<_> = bounded.iter().filter_map(|p| p.shape.bounds()).collect();
    if bounds.len() > MAX_PRIMITIVES {
        return Err(SceneError::unlocated(format!(
            "the scene has {} bounded objects; at most {MAX_PRIMITIVES} are supported",
            bounds.len()
        )));
    }
    let (bvh, order) = Bvh::build(&bounds, 1);
    let mut slots: Vec<Option<Primitive>> = bounded.drain(..).map(Some).collect();
    let mut primitives: Vec<Primitive> =
        order.iter().flatten().filter_map(|&i| slots[i as usize].take()).collect();
    let bounded_count = primitives.len();
    primitives.extend(planes.iter().cloned());
    let others_start = primitives.len();
    primitives.extend(others);

    let (centre, radius) = bounding_sphere(&bounds, camera.origin);
    let mut lights: Vec<Light> =
        graph.lights.iter().zip(bulbs).map(|(l, bulb)| light(l, bulb, centre, radius)).collect();
    for (i, prim) in primitives.iter_mut().enumerate() {
        let area = prim.shape.area();
        let material = &flat.materials[prim.material as usize];
        if let Some(area) = area.filter(|_| material.is_emissive()) {
            prim.light = Some(lights.len() as u32);
            let (shape, emission) = (prim.shape.clone(), material.emission);
            let (beam, two_sided) = (material.beam.map(BeamSampler::new), material.two_sided);
            let texture = flat.textures[prim.material as usize].as_ref();
            let pattern = texture.and_then(SurfaceTexture::glow).map(|(glow, colour, through)| {
                let to_object = flat.frames[prim.frame as usize];
                Box::new(GlowPattern { glow, colour, through, to_object })
            });
            lights.push(Light::Area {
                shape,
                emission,
                pattern,
                beam,
                two_sided,
                area,
                primitive: i as u32,
            });
        }
    }
    // The sky goes last: the lights before keep the indices their primitives name.
    let environment = super::sky::environment(graph, &bounds, camera.origin)?.map(|sky| {
        lights.push(Light::Environment(Box::new(sky)));
        lights.len() - 1
    });
    let backdrop = if environment.is_some() { Vec3::ZERO } else { graph.backdrop };
    let mut warnings = graph.warnings.clone();
    warnings.extend(camera_warnings);
    warnings.extend(flat.warnings);
    let emits = !lights.is_empty() || flat.materials.iter().any(Material::is_emissive);
    if !emits {
        warnings.push(
            "warning: the scene emits no light (no light_source, no material with `emission`, \
             a black background): every pixel will be black. Add `light_source { <x, y, z> \
             power rgb <r, g, b> }`, give an object `material { emission rgb <r, g, b> }`, or \
             set `settings { background rgb <r, g, b> }`"
                .to_string(),
        );
    }
    let mut media = flat.media;
    let atmosphere = graph.atmosphere.as_ref().map(|desc| {
        media.push(medium(desc));
        flat.medium_spans.push(desc.span.clone());
        media.len() as u32 - 1
    });
    if let Some(span) = flat.medium_spans.first() {
        refuse_media(settings.integrator, span)?;
    }
    // Rays traced in lanes meet few simple shapes at less cost than the BVH's.
    let (simple, alone): (Vec<usize>, Vec<usize>) =
        (0..bounded_count).partition(|&i| FewShapes::takes(&primitives[i].shape));
    let few_holds_bounded =
        simple.iter().map(|&i| FewShapes::size(&primitives[i].shape)).sum::<usize>()
            <= FEW_BOUNDED_MAX
            && alone.len() <= ALONE_MAX;
    let few = FewShapes::new(
        primitives
            .iter()
            .enumerate()
            .take(others_start)
            .filter(|&(i, p)| i >= bounded_count || few_holds_bounded && FewShapes::takes(&p.shape))
            .map(|(i, p)| (i as u32, &p.shape)),
    );
    // The others under a BVH of their own: its boxes spare most lanes their tests (a mesh
    // tested by every lane cost S5 8 % more instructions than walking the scene's BVH).
    let alone = if few_holds_bounded { alone } else { Vec::new() };
    let alone_bounds: Vec<Aabb> =
        alone.iter().filter_map(|&i| primitives[i].shape.bounds()).collect();
    let (alone_bvh, alone_order) = Bvh::build(&alone_bounds, 1);
    let alone = alone_order.iter().flatten().map(|&k| alone[k as usize]).collect();
    // The surfaces of CSG operands go last: hits on them are named by them (their material
    // and texture space), they are not traced themselves.
    let first_surface = primitives.len() as u32;
    for primitive in &mut primitives {
        if let Shape::Csg(csg) = &mut primitive.shape {
            csg.surfaces += first_surface;
        }
    }
    primitives.extend(flat.surfaces);
    let mut scene = Scene {
        settings,
        camera,
        primitives,
        bounded: bounded_count,
        others: others_start..first_surface as usize,
        bvh,
        planes: Planes::new(
            &planes
                .iter()
                .filter_map(|p| match p.shape {
                    Shape::Plane { normal, offset } => Some((normal, offset)),
                    _ => None,
                })
                .collect::<Vec<_>>(),
        ),
        few,
        few_holds_bounded,
        alone,
        alone_bvh,
        see_through: flat
            .materials
            .iter()
            .any(|m| m.passes_straight() && m.transmission.max_element() > 0.0),
        materials: flat.materials,
        textures: flat.textures,
        bumps: flat.bumps,
        media,
        interiors: flat.interiors,
        atmosphere,
        frames: flat.frames,
        lights,
        environment,
        backdrop,
        light_cdf: Vec::new(),
        warnings,
    };
    scene.light_cdf = light_selection_cdf(&scene.lights);
    Ok(scene)
}

/// The cumulative distribution by which next-event estimation chooses a light: half in
/// proportion to power, half uniform over the lights that emit. By power alone, a huge dim
/// emitter (POV-Ray's sky spheres of radius 3000) takes nearly every choice, and a point light
/// beside it, which only light sampling can find, is almost never sampled: its light arrives
/// as rare fireflies. The uniform half bounds every emitting light's probability below by
/// 1 / (2 n). Lights with no power are never chosen; none at all: an empty distribution.
fn light_selection_cdf(lights: &[Light]) -> Vec<f32> {
    let powers: Vec<f32> = lights.iter().map(|light| light.power().max(0.0)).collect();
    let total: f32 = powers.iter().sum();
    let emitting = powers.iter().filter(|&&p| p > 0.0).count();
    if emitting == 0 || !total.is_finite() {
        return Vec::new();
    }
    powers
        .iter()
        .scan(0.0, |acc, &p| {
            if p > 0.0 {
                *acc += 0.5 * p / total + 0.5 / emitting as f32;
            }
            Some(*acc)
        })
        .collect()
}

#[derive(Default)]
struct Flattener {
    primitives: Vec<Primitive>,
    materials: Vec<Material>,
    textures: Vec<Option<SurfaceTexture>>,
    /// Per material, its bump mapping (`Scene::bumps`).
    bumps: Vec<Option<Bump>>,
    images: HashMap<PathBuf, Arc<ImageMap>>,
    /// World to object space of every object that holds primitives.
    frames: Vec<Affine3A>,
    warnings: Vec<String>,
    meshes: HashMap<PathBuf, Arc<TriangleMesh>>,
    /// The meshes the scene made (`ShapeNode::Extrusion`), by address, each kept alive with
    /// its key.
    extrusions: HashMap<*const Mesh, (Arc<Mesh>, Arc<TriangleMesh>)>,
    /// The solids of the height fields in CSG, by their heights' address, each kept alive with
    /// its key.
    height_field_solids: HashMap<*const Heights, (Arc<Heights>, Arc<TriangleMesh>)>,
    /// Index of each distinct material description, by address: declared materials are shared.
    material_index: HashMap<*const MaterialDesc, u32>,
    /// The surfaces of CSG operands (material and frame of each), in the order of the CSG
    /// primitives' operands.
    surfaces: Vec<Primitive>,
    /// The media inside materials, and where each is written.
    media: Vec<Medium>,
    medium_spans: Vec<Span>,
    /// Per material, the index in `media` of its interior's medium.
    interiors: Vec<Option<u32>>,
}

/// The medium a description gives.
fn medium(desc: &MediumDesc) -> Medium {
    Medium {
        absorption: desc.absorption,
        scattering: desc.scattering,
        emission: desc.emission,
        phase: HenyeyGreenstein { g: desc.anisotropy },
        density: match desc.ground {
            None => Density::Uniform,
            Some(GroundDesc { up, offset, falloff }) => Density::Ground { up, offset, falloff },
        },
    }
}

/// Only `path` renders participating media: the others refuse a scene with one, naming it.
fn refuse_media(integrator: IntegratorKind, medium: &Span) -> Result<(), SceneError> {
    match integrator {
        IntegratorKind::Path => Ok(()),
        IntegratorKind::Direct
        | IntegratorKind::Photon
        | IntegratorKind::FinalGather
        | IntegratorKind::Sppm => Err(SceneError::at(
            medium,
            format!(
                "the `{}` integrator does not render participating media, such as this medium \
                 (an interior, fog or atmosphere): render the scene with `integrator path`",
                integrator.name()
            ),
        )),
    }
}

/// Why a mesh is not a solid.
const NOT_CLOSED: &str =
    "this mesh is not closed (some edge is not shared by exactly two triangles), so it";

/// A closed mesh as a CSG operand placed by `to_world`; `None` if it is not closed.
fn closed_mesh(mesh: Arc<TriangleMesh>, to_world: Affine3A) -> Option<Shape> {
    let placement = (to_world != Affine3A::IDENTITY).then(|| Box::new(Placement::new(to_world)));
    mesh.is_closed().then_some(Shape::Mesh { mesh, placement })
}

/// Refuses an object's transforms that a 32-bit matrix cannot invert: ones that flatten it, and
/// ones that scale it past what 32-bit floats hold (`scale 1e30` is not singular, but too large).
fn check_invertible(to_world: &Affine3A, span: &Span) -> Result<(), SceneError> {
    let determinant = to_world.matrix3.determinant();
    let message = if !determinant.is_finite() {
        "the transforms of this object scale it beyond what 32-bit floats hold (its volume \
         grows past 3.4e38 times)"
    } else if determinant.abs() < crate::graph::FLATTENING_DETERMINANT {
        "the transforms of this object are singular: they flatten it"
    } else {
        return Ok(());
    };
    Err(SceneError::at(span, message))
}

impl Flattener {
    fn add(
        &mut self,
        node: &ObjectNode,
        parent: Affine3A,
        inherited: Option<&Arc<MaterialDesc>>,
    ) -> Result<(), SceneError> {
        let to_world = parent * compose(&node.transforms);
        check_invertible(&to_world, &node.span)?;
        let material = node.material.as_ref().or(inherited);
        match &node.shape {
            ShapeNode::Union(children) => {
                children.iter().try_for_each(|c| self.add(c, to_world, material))
            }
            ShapeNode::Instance(target) => self.add(target, to_world, material),
            ShapeNode::Csg { op, operands } => {
                let first = self.surfaces.len() as u32;
                let mut shapes = Vec::new();
                let root = self.operation(*op, operands, to_world, material, &mut shapes)?;
                let mut csg = Csg::new(root, shapes);
                let emissive = self.surfaces[first as usize..]
                    .iter()
                    .any(|s| self.materials[s.material as usize].is_emissive());
                if emissive {
                    self.warnings.push(format!(
                        "{:?}: warning: the emissive surfaces of this CSG object are not sampled \
                         as lights; only rays that hit them see their light",
                        node.span
                    ));
                }
                let material = self.material(material)?;
                self.frames.push(to_world.inverse());
                let frame = self.frames.len() as u32 - 1;
                csg.surfaces = first;
                let shape = Shape::Csg(Box::new(csg));
                self.primitives.push(Primitive { shape, material, frame, light: None });
                Ok(())
            }
            ShapeNode::Mesh { path } => {
                let mesh = self.mesh(path, node)?;
                self.add_mesh(mesh, to_world, material, node)
            }
            ShapeNode::Extrusion(made) | ShapeNode::HeightField { sheet: made, .. } => {
                let mesh = self.extrusion(made);
                self.add_mesh(mesh, to_world, material, node)
            }
            shape => {
                check_dimensions(shape, node)?;
                let material = self.material(material)?;
                self.frames.push(to_world.inverse());
                for shape in world_shapes(shape, to_world) {
                    self.push(shape, material, node);
                }
                Ok(())
            }
        }
    }

    /// The tree of an operation on `operands` placed by `to_world`, their solids appended to
    /// `shapes` and their surfaces to `self.surfaces`.
    fn operation(
        &mut self,
        op: CsgOp,
        operands: &[ObjectNode],
        to_world: Affine3A,
        material: Option<&Arc<MaterialDesc>>,
        shapes: &mut Vec<Shape>,
    ) -> Result<CsgNode, SceneError> {
        let children = operands
            .iter()
            .map(|operand| self.operand(operand, to_world, material, shapes))
            .collect::<Result<_, _>>()?;
        Ok(CsgNode::Operation { op, children })
    }

    /// One operand of a CSG operation: a solid, or a located error.
    fn operand(
        &mut self,
        node: &ObjectNode,
        parent: Affine3A,
        inherited: Option<&Arc<MaterialDesc>>,
        shapes: &mut Vec<Shape>,
    ) -> Result<CsgNode, SceneError> {
        let to_world = parent * compose(&node.transforms);
        check_invertible(&to_world, &node.span)?;
        let material = node.material.as_ref().or(inherited);
        let not_solid = |what: &str| {
            SceneError::at(
                &node.span,
                format!(
                    "{what} is not a solid: the operands of intersection, difference and merge \
                     must be solids (sphere, box, closed cylinder or cone, torus, plane, closed \
                     mesh, a polynomial surface, a blob, CSG, or objects and unions of these)"
                ),
            )
        };
        let shape = match &node.shape {
            ShapeNode::Csg { op, operands } => {
                return self.operation(*op, operands, to_world, material, shapes);
            }
            ShapeNode::Union(children) => {
                return self.operation(CsgOp::Merge, children, to_world, material, shapes);
            }
            ShapeNode::Instance(target) => return self.operand(target, to_world, material, shapes),
            ShapeNode::Triangle { .. } => return Err(not_solid("a triangle")),
            ShapeNode::Quad { .. } => return Err(not_solid("a quad")),
            ShapeNode::Disk { .. } => return Err(not_solid("a disk")),
            ShapeNode::Cone { open: true, base_radius, cap_radius, .. } => {
                let what =
                    if base_radius == cap_radius { "an open cylinder" } else { "an open cone" };
                return Err(not_solid(what));
            }
            ShapeNode::Prism { open: true, .. } => return Err(not_solid("an open prism")),
            ShapeNode::Sor { open: true, .. } => return Err(not_solid("an open sor")),
            ShapeNode::Lemon { open: true, .. } => return Err(not_solid("an open lemon")),
            ShapeNode::Polygon { .. } => return Err(not_solid("a polygon")),
            ShapeNode::Parametric(_) => return Err(not_solid("a parametric surface")),
            ShapeNode::Mesh { path } => {
                let mesh = self.mesh(path, node)?;
                closed_mesh(mesh, to_world).ok_or_else(|| not_solid(NOT_CLOSED))?
            }
            ShapeNode::Extrusion(made) => {
                let mesh = self.extrusion(made);
                closed_mesh(mesh, to_world).ok_or_else(|| not_solid(NOT_CLOSED))?
            }
            ShapeNode::HeightField { heights, .. } => {
                let mesh = self.height_field_solid(heights);
                closed_mesh(mesh, to_world).ok_or_else(|| not_solid(NOT_CLOSED))?
            }
            shape => {
                check_dimensions(shape, node)?;
                let mut world = world_shapes(shape, to_world);
                match (world.pop(), world.is_empty()) {
                    (Some(shape), true) => shape,
                    _ => return Err(not_solid("this object")),
                }
            }
        };
        let index = shapes.len() as u32;
        let material = self.material(material)?;
        self.frames.push(to_world.inverse());
        let frame = self.frames.len() as u32 - 1;
        self.surfaces.push(Primitive { shape: shape.clone(), material, frame, light: None });
        shapes.push(shape);
        Ok(CsgNode::Operand(index))
    }

    fn add_mesh(
        &mut self,
        mesh: Arc<TriangleMesh>,
        to_world: Affine3A,
        material: Option<&Arc<MaterialDesc>>,
        node: &ObjectNode,
    ) -> Result<(), SceneError> {
        let placement =
            (to_world != Affine3A::IDENTITY).then(|| Box::new(Placement::new(to_world)));
        let material = self.material(material)?;
        self.frames.push(to_world.inverse());
        self.push(Shape::Mesh { mesh, placement }, material, node);
        Ok(())
    }

    fn push(&mut self, shape: Shape, material: u32, node: &ObjectNode) {
        if self.materials[material as usize].is_emissive() && shape.area().is_none() {
            self.warnings.push(format!(
                "{:?}: warning: this emitter cannot be sampled as a light (an infinite plane, a \
                 mesh, or a sphere, cylinder, cone or torus under non-uniform scale); only rays \
                 that hit it see its light",
                node.span
            ));
        }
        let frame = self.frames.len() as u32 - 1;
        self.primitives.push(Primitive { shape, material, frame, light: None });
    }

    /// The mesh of a file, loaded and accelerated once however often (and however named) it is
    /// used.
    fn mesh(&mut self, path: &Path, node: &ObjectNode) -> Result<Arc<TriangleMesh>, SceneError> {
        let file = std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf());
        if let Some(mesh) = self.meshes.get(&file) {
            return Ok(mesh.clone());
        }
        let mesh =
            crate::mesh::load(path).map_err(|e| SceneError::at(&node.span, e.to_string()))?;
        let mesh = Arc::new(TriangleMesh::new(mesh));
        self.meshes.insert(file, mesh.clone());
        Ok(mesh)
    }

    /// A mesh the scene made, accelerated once however many instances share it.
    fn extrusion(&mut self, made: &Arc<Mesh>) -> Arc<TriangleMesh> {
        let key = Arc::as_ptr(made);
        let mesh = self
            .extrusions
            .entry(key)
            .or_insert_with(|| (Arc::clone(made), Arc::new(TriangleMesh::new(Mesh::clone(made)))));
        mesh.1.clone()
    }

    /// A height field's solid, made and accelerated once however many instances share it.
    fn height_field_solid(&mut self, heights: &Arc<Heights>) -> Arc<TriangleMesh> {
        let key = Arc::as_ptr(heights);
        let made = self.height_field_solids.entry(key).or_insert_with(|| {
            (Arc::clone(heights), Arc::new(TriangleMesh::new(height_field::solid(heights))))
        });
        made.1.clone()
    }

    fn material(&mut self, desc: Option<&Arc<MaterialDesc>>) -> Result<u32, SceneError> {
        // An object with no material anywhere up its groups is black (POV-Ray's default pigment).
        let key = desc.map_or(std::ptr::null(), Arc::as_ptr);
        if let Some(&index) = self.material_index.get(&key) {
            return Ok(index);
        }
        let images = &mut self.images;
        // Keyed by the file itself, however the scene names it.
        let mut load = |path: &Path| {
            let file = std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf());
            match images.get(&file) {
                Some(image) => Ok(image.clone()),
                None => {
                    let image = Arc::new(ImageMap::load(path)?);
                    images.insert(file, image.clone());
                    Ok(image)
                }
            }
        };
        let (texture, bump) = match desc {
            Some(d) => {
                let texture = SurfaceTexture::new(d, &mut load).map_err(|e| {
                    SceneError::at(&d.span, format!("cannot read the image_map: {e}"))
                })?;
                let bump = match &d.normal {
                    Some(normal) => Some(Bump::new(normal, &mut load).map_err(|e| {
                        SceneError::at(&d.span, format!("cannot read the bump_map: {e}"))
                    })?),
                    None => None,
                };
                (texture, bump)
            }
            None => (None, None),
        };
        if let Some(d) = desc {
            // Given but unused parameters are reported (warnings: the language allows them).
            let refracts = d.transmission.max_element() > 0.0;
            if d.ior != 1.0 && !refracts && !d.fresnel {
                self.warnings.push(format!(
                    "{:?}: warning: `ior` has no effect without `transmission` or `fresnel`",
                    d.span
                ));
            }
            if d.roughness > 0.0 && !refracts && d.specular.max_element() <= 0.0 {
                self.warnings.push(format!(
                    "{:?}: warning: `roughness` has no effect without `specular` or `transmission`",
                    d.span
                ));
            }
            if d.coat_roughness != MaterialDesc::DEFAULT_COAT_ROUGHNESS && d.coat == 0.0 {
                self.warnings.push(format!(
                    "{:?}: warning: `coat_roughness` has no effect without `coat`",
                    d.span
                ));
            }
            if d.fresnel && !refracts && d.specular.max_element() <= 0.0 {
                self.warnings.push(format!(
                    "{:?}: warning: `fresnel` has no effect without `specular` or `transmission`",
                    d.span
                ));
            }
        }
        let index = self.materials.len() as u32;
        self.materials.push(desc.map_or_else(Material::default, |d| Material::from(&**d)));
        self.textures.push(texture);
        self.bumps.push(bump);
        let interior = desc.and_then(|d| d.interior.as_ref()).map(|interior| {
            self.media.push(medium(interior));
            self.medium_spans.push(interior.span.clone());
            self.media.len() as u32 - 1
        });
        self.interiors.push(interior);
        self.material_index.insert(key, index);
        Ok(index)
    }
}

/// A located error for a cone or torus the graph gives impossible dimensions (the language
/// checks the other shapes' as it reads them).
fn check_dimensions(shape: &ShapeNode, node: &ObjectNode) -> Result<(), SceneError> {
    let problem = match *shape {
        ShapeNode::Cone { base, base_radius, cap, cap_radius, .. } => {
            // (Written so that NaN fails each test.)
            let radii_valid =
                base_radius >= 0.0 && cap_radius >= 0.0 && base_radius.max(cap_radius) > 0.0;
            let axis_valid = base.distance_squared(cap) > 0.0;
            if !radii_valid {
                Some("a cone's radii must be at least 0, and not both 0")
            } else if !axis_valid {
                Some("a cone's base and cap centres must differ")
            } else {
                None
            }
        }
        ShapeNode::Torus { major, minor } if !(major > 0.0 && minor > 0.0) => {
            Some("a torus' radii must be greater than 0")
        }
        _ => None,
    };
    problem.map_or(Ok(()), |message| Err(SceneError::at(&node.span, message)))
}

/// The world-space shapes of one primitive node under `m`.
fn world_shapes(shape: &ShapeNode, m: Affine3A) -> Vec<Shape> {
    // A mirroring transform would turn edge1 x edge2 inside out; normals transform by the
    // inverse transpose and keep their side, so swap the edges to follow them.
    let mirrored = m.matrix3.determinant() < 0.0;
    let face = |kind, origin: Vec3, e1: Vec3, e2: Vec3| {
        let (origin, e1, e2) =
            (m.transform_point3(origin), m.transform_vector3(e1), m.transform_vector3(e2));
        let (e1, e2) = if mirrored { (e2, e1) } else { (e1, e2) };
        Planar::new(kind, origin, e1, e2)
    };
    let planar = |kind, origin: Vec3, e1: Vec3, e2: Vec3| Shape::Planar(face(kind, origin, e1, e2));
    // A disk (or cone cap) with the given centre and unit normal.
    let disk = |center: Vec3, normal: Vec3, radius: f32| {
        let (t, b) = tangents(normal);
        face(PlanarKind::Disk, center, t * radius, b * radius)
    };
    let cone = |base: Vec3, base_radius: f32, cap: Vec3, cap_radius: f32, open: bool| {
        let axis = cap - base;
        let direction = axis.normalize();
        let (t, b) = tangents(direction);
        // The side in a frame of the larger radius: a cylinder's is its tube's as always.
        let radius = base_radius.max(cap_radius);
        let frame = m * Affine3A::from_mat3_translation(
            glam::Mat3::from_cols(t * radius, b * radius, axis),
            base,
        );
        let pi = std::f32::consts::PI;
        let side_area = similarity_scale(&m).map(|s| {
            let side = if base_radius == cap_radius {
                // Side area 2 pi r h, scaled by the square of a similarity's scale.
                2.0 * pi * radius * axis.length()
            } else {
                let slant = axis.length().hypot(cap_radius - base_radius);
                pi * (base_radius + cap_radius) * slant
            };
            side * s * s
        });
        let cap_disk = |center, normal, r: f32| (!open && r > 0.0).then(|| disk(center, normal, r));
        Shape::Cone(Box::new(Cone::new(
            QuadricFrame::new(frame, side_area),
            [base_radius / radius, cap_radius / radius],
            [cap_disk(base, -direction, base_radius), cap_disk(cap, direction, cap_radius)],
            open,
            side_area,
        )))
    };
    match *shape {
        ShapeNode::Plane { normal, offset } => {
            // n . q + d = 0 with q = A^-1 (p - t): (A^-T n) . p + d - (A^-T n) . t = 0.
            let n = m.matrix3.inverse().transpose() * glam::Vec3A::from(normal);
            let n = Vec3::from(n);
            let offset = offset - n.dot(m.translation.into());
            let length = n.length();
            vec![Shape::Plane { normal: n / length, offset: offset / length }]
        }
        ShapeNode::Sphere { center, radius } => {
            let to_world = m * Affine3A::from_scale_rotation_translation(
                Vec3::splat(radius),
                glam::Quat::IDENTITY,
                center,
            );
            match similarity_scale(&to_world) {
                Some(scale) => {
                    vec![Shape::Sphere { center: to_world.translation.into(), radius: scale }]
                }
                None => {
                    let frame = Box::new(QuadricFrame::new(to_world, None));
                    vec![Shape::Quadric { kind: QuadricKind::Ellipsoid, frame }]
                }
            }
        }
        ShapeNode::Box { corner_a, corner_b } => {
            let (lo, size) = (corner_a.min(corner_b), (corner_a - corner_b).abs());
            let [x, y, z] = [Vec3::X * size.x, Vec3::Y * size.y, Vec3::Z * size.z];
            let hi = lo + size;
            // Each face as corner, edge1, edge2 with edge1 x edge2 pointing out of the box.
            let faces = [
                face(PlanarKind::Quad, lo, z, y),
                face(PlanarKind::Quad, hi, -y, -z),
                face(PlanarKind::Quad, lo, x, z),
                face(PlanarKind::Quad, hi, -z, -x),
                face(PlanarKind::Quad, lo, y, x),
                face(PlanarKind::Quad, hi, -x, -y),
            ];
            let to_cube = m * Affine3A::from_scale_rotation_translation(
                size.max(Vec3::splat(f32::MIN_POSITIVE)),
                glam::Quat::IDENTITY,
                lo,
            );
            vec![Shape::Box(Box::new(Cuboid::new(faces, to_cube)))]
        }
        ShapeNode::Triangle { a, b, c } => vec![planar(PlanarKind::Triangle, a, b - a, c - a)],
        ShapeNode::Quad { corner, edge1, edge2 } => {
            vec![planar(PlanarKind::Quad, corner, edge1, edge2)]
        }
        ShapeNode::Disk { center, normal, radius, hole } => {
            vec![Shape::Planar(disk(center, normal.normalize(), radius).with_hole(hole / radius))]
        }
        ShapeNode::Cylinder { base, cap, radius } => vec![cone(base, radius, cap, radius, false)],
        ShapeNode::Cone { base, base_radius, cap, cap_radius, open } => {
            vec![cone(base, base_radius, cap, cap_radius, open)]
        }
        ShapeNode::Torus { major, minor } => {
            vec![Shape::Torus(Box::new(Torus::new(major, minor, m)))]
        }
        ShapeNode::Isosurface(ref desc) => {
            vec![Shape::Isosurface(Box::new(Isosurface::new(desc.clone(), m)))]
        }
        ShapeNode::Parametric(ref desc) => {
            vec![Shape::Parametric(Box::new(Parametric::new(desc.clone(), m)))]
        }
        ShapeNode::Algebraic { ref terms } => {
            vec![Shape::Algebraic(Box::new(Algebraic::new(terms, m)))]
        }
        ShapeNode::Blob { threshold, ref components } => {
            vec![Shape::Blob(Box::new(Blob::new(components, threshold, m)))]
        }
        ShapeNode::Superellipsoid { e, n } => {
            vec![Shape::Superellipsoid(Box::new(Superellipsoid::new(e, n, m)))]
        }
        ShapeNode::JuliaFractal(ref desc) => {
            vec![Shape::Julia(Box::new(Julia::new(JuliaDesc::clone(desc), m)))]
        }
        ShapeNode::Prism { ref segments, sweep, heights, open } => {
            vec![Shape::Prism(Box::new(Prism::new(segments, sweep, heights, open, m)))]
        }
        ShapeNode::Lathe { ref segments } => vec![Shape::Lathe(Box::new(Lathe::new(segments, m)))],
        ShapeNode::Ovus { bottom, top } => {
            let ovus = ArcSolid::ovus(f64::from(bottom), f64::from(top), m);
            vec![Shape::ArcSolid(Box::new(ovus))]
        }
        ShapeNode::Lemon { ends, radii, inner_radius, open } => {
            let lemon = ArcSolid::lemon(ends, radii.map(f64::from), inner_radius.into(), open, m);
            vec![Shape::ArcSolid(Box::new(lemon))]
        }
        ShapeNode::Sor { ref pieces, open } => {
            vec![Shape::Sor(Box::new(Sor::new(pieces, open, m)))]
        }
        ShapeNode::Polygon { ref points } => {
            let world: Vec<Vec3> = points.iter().map(|&p| m.transform_point3(p)).collect();
            // A transform that flattens the plane leaves nothing to see.
            outline_normal(&world)
                .map(|normal| Shape::Polygon(Box::new(Polygon::new(&world, normal))))
                .into_iter()
                .collect()
        }
        ShapeNode::Union(_)
        | ShapeNode::Instance(_)
        | ShapeNode::Mesh { .. }
        | ShapeNode::Extrusion(_)
        | ShapeNode::HeightField { .. }
        | ShapeNode::Csg { .. } => Vec::new(),
    }
}

/// Unit tangents (t, b) with t x b = n.
fn tangents(n: Vec3) -> (Vec3, Vec3) {
    let (t, b) = n.any_orthonormal_pair();
    if t.cross(b).dot(n) < 0.0 { (b, t) } else { (t, b) }
}

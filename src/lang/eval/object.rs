//! Objects: shapes checked where they are written, modifiers, groups and instances.

use std::sync::Arc;

use glam::{Affine3A, Mat3, Vec3};

use super::Look;
use super::expression::{single, single_vector, text_of};
use super::texture_space::worn_space;
use super::transform::matrix_of;
use super::{
    Body, Evaluator, MAX_CSG_DEPTH, MAX_CSG_OPERANDS, MAX_OBJECT_DEPTH, MAX_OBJECTS_MADE, resolve,
};
use crate::diagnostic::{SceneError, Span};
use crate::graph::{
    Below, CsgOp, FLATTENING_DETERMINANT, MaterialDesc, ObjectNode, ShapeNode, Transform, compose,
};
use crate::lang::dialect::Dialect;
use crate::lang::syntax::{self, AppearanceKind, Item, Shape, TransformKind};
use crate::lang::value::Value;

impl Evaluator {
    pub(super) fn object(&mut self, object: &syntax::Object) -> Result<ObjectNode, SceneError> {
        let span = self.here(&object.span);
        // Lights this object holds (its own, or a declared light it places) move with it.
        let held = self.held_lights.len();
        let shape = match &object.shape {
            Shape::Plane { normal, offset } => {
                let normal = self.nonzero(normal, "the plane's normal")?;
                let offset = self.single(offset)?;
                match self.dialect {
                    Dialect::Scn => ShapeNode::Plane { normal, offset },
                    // POV-Ray's plane: the points p with n̂ · p = d.
                    Dialect::Pov => {
                        ShapeNode::Plane { normal: normal.normalize(), offset: -offset }
                    }
                }
            }
            Shape::Sphere { center, radius } => ShapeNode::Sphere {
                center: self.vec3(center)?,
                radius: self.positive(radius, "radius")?,
            },
            Shape::Box { corner_a, corner_b } => {
                let at = corner_b.span.clone();
                let (corner_a, corner_b) = (self.vec3(corner_a)?, self.vec3(corner_b)?);
                self.box_shape(corner_a, corner_b, &at)?
            }
            Shape::Triangle { a, b, c } => {
                let at = c.span.clone();
                let (a, b, c) = (self.vec3(a)?, self.vec3(b)?, self.vec3(c)?);
                if (b - a).cross(c - a).length() <= 1e-12 * (b - a).length() * (c - a).length() {
                    return Err(SceneError::at(
                        &at,
                        "the triangle's corners are collinear: it has no area",
                    ));
                }
                ShapeNode::Triangle { a, b, c }
            }
            Shape::Quad { corner, edge1, edge2 } => {
                let at = edge2.span.clone();
                let (corner, edge1, edge2) =
                    (self.vec3(corner)?, self.vec3(edge1)?, self.vec3(edge2)?);
                if edge1.cross(edge2).length() <= 1e-12 * edge1.length() * edge2.length() {
                    return Err(SceneError::at(
                        &at,
                        "the quad's edges are zero or parallel: it has no area",
                    ));
                }
                ShapeNode::Quad { corner, edge1, edge2 }
            }
            Shape::Disk { center, normal, radius, hole } => {
                let center = self.vec3(center)?;
                let normal = self.nonzero(normal, "the disk's normal")?;
                let radius = self.positive(radius, "radius")?;
                let hole = match hole {
                    Some(hole) => {
                        let value = self.non_negative(hole, "the disc's hole radius")?;
                        if value >= radius {
                            return Err(SceneError::at(
                                &hole.span,
                                format!(
                                    "the disc's hole radius {value} is not below its radius \
                                     {radius}: nothing would be left of it"
                                ),
                            ));
                        }
                        value
                    }
                    None => 0.0,
                };
                ShapeNode::Disk { center, normal, radius, hole }
            }
            Shape::Cylinder { base, cap, radius, open } => {
                let at = cap.span.clone();
                let (base, cap) = (self.vec3(base)?, self.vec3(cap)?);
                if base == cap {
                    return Err(SceneError::at(
                        &at,
                        "the cylinder's base and cap centres are the same point",
                    ));
                }
                let radius = self.positive(radius, "radius")?;
                if *open {
                    // The side alone: a cone with equal radii.
                    ShapeNode::Cone {
                        base,
                        base_radius: radius,
                        cap,
                        cap_radius: radius,
                        open: true,
                    }
                } else {
                    ShapeNode::Cylinder { base, cap, radius }
                }
            }
            Shape::Cone { base, base_radius, cap, cap_radius, open } => {
                // In written order: arguments may draw from a random stream.
                let base_at = base_radius.span.clone();
                let base = self.vec3(base)?;
                let base_radius = self.non_negative(base_radius, "the cone's base radius")?;
                let cap_at = cap.span.clone();
                let cap = self.vec3(cap)?;
                let cap_radius = self.non_negative(cap_radius, "the cone's cap radius")?;
                if base == cap {
                    return Err(SceneError::at(
                        &cap_at,
                        "the cone's base and cap centres are the same point",
                    ));
                }
                if base_radius == 0.0 && cap_radius == 0.0 {
                    return Err(SceneError::at(
                        &base_at,
                        "the cone's radii are both 0: it has no volume",
                    ));
                }
                ShapeNode::Cone { base, base_radius, cap, cap_radius, open: *open }
            }
            Shape::Torus { major, minor } => ShapeNode::Torus {
                major: self.positive(major, "the torus' major radius")?,
                minor: self.positive(minor, "the torus' minor radius")?,
            },
            Shape::Isosurface(isosurface) => {
                ShapeNode::Isosurface(Arc::new(self.isosurface(isosurface, &object.span)?))
            }
            Shape::Parametric(surface) => {
                ShapeNode::Parametric(Arc::new(self.parametric(surface, &object.span)?))
            }
            Shape::HeightField(field) => self.height_field(field, &object.span)?,
            Shape::SphereSweep { spline, count, points, tolerance } => {
                let points = self.listed_points(points)?;
                self.sphere_sweep(*spline, count, &points, tolerance.as_ref(), &object.span)?
            }
            Shape::Quadric { squares, products, linear, constant } => {
                self.quadric(squares, products, linear, constant)?
            }
            Shape::Poly { order, coefficients } => self.poly(order, coefficients)?,
            // POV-Ray's default threshold; the components are among the items.
            Shape::Blob => ShapeNode::Blob { threshold: 1.0, components: Vec::new() },
            Shape::Superellipsoid { exponents } => {
                let [e, n] = match self.value(exponents)? {
                    Value::Numbers(v) if v.len() == 2 => [v[0], v[1]],
                    // POV-Ray promotes a number to the vector <e, e> (cliche.pov).
                    Value::Float(e) => [e, e],
                    other => {
                        return Err(SceneError::at(
                            &exponents.span,
                            format!(
                                "a superellipsoid takes a 2-vector <e, n>, not {}",
                                other.kind()
                            ),
                        ));
                    }
                };
                if !(e > 0.0 && n > 0.0) {
                    return Err(SceneError::at(
                        &exponents.span,
                        format!("a superellipsoid's exponents <{e}, {n}> must be above 0"),
                    ));
                }
                let [e, n] = [single(e, &exponents.span)?, single(n, &exponents.span)?];
                ShapeNode::Superellipsoid { e, n }
            }
            Shape::Ovus { bottom, top } => self.ovus(bottom, top)?,
            Shape::Lemon { base, base_radius, cap, cap_radius, inner_radius, open } => {
                let arguments = [base, base_radius, cap, cap_radius, inner_radius];
                self.lemon(arguments, *open, &object.span)?
            }
            Shape::Prism { spline, sweep, heights, count, points, open } => {
                let points = self.listed_points(points)?;
                self.prism((*spline, *sweep), heights, count, &points, *open, &object.span)?
            }
            Shape::BicubicPatch(patch) => self.bicubic_patch(patch, &object.span)?,
            Shape::SmoothTriangle { corners, normals } => self.smooth_triangle(corners, normals)?,
            // Made of its triangles as its body reaches them (`mesh_items`, below).
            Shape::TriangleMesh { .. } => ShapeNode::Union(Vec::new()),
            Shape::Mesh2(mesh) => self.mesh2(mesh, &object.span)?,
            Shape::JuliaFractal(fractal) => self.julia_fractal(fractal)?,
            Shape::Lathe { spline, count, points } => {
                let points = self.listed_points(points)?;
                self.lathe(*spline, count, &points, &object.span)?
            }
            Shape::Sor { count, points, open } => {
                let points = self.listed_points(points)?;
                self.sor(count, &points, *open, &object.span)?
            }
            Shape::Polygon { count, points } => {
                let points = self.listed_points(points)?;
                self.polygon(count, &points, &object.span)?
            }
            Shape::BlobSphere { .. } | Shape::BlobCylinder { .. } => {
                return Err(SceneError::at(
                    &object.span,
                    "a blob's component stands only in a blob",
                ));
            }
            Shape::Mesh { file } => match self.value(file)? {
                // POV-Ray's `mesh { Declared_Mesh items }` (`.pov`): that object, as in
                // `object { }` (POV-Ray takes any object there).
                Value::Object(object) if self.dialect == Dialect::Pov => {
                    ShapeNode::Instance(object)
                }
                value => {
                    let name = text_of(value, file, "`mesh`")?;
                    ShapeNode::Mesh { path: resolve(&file.span.file.path, &name) }
                }
            },
            Shape::Text { font, string, thickness, offset } => {
                self.text_shape(font, string, thickness, offset, &span)?
            }
            Shape::Instance { of } => match self.value(of)? {
                Value::Object(object) => ShapeNode::Instance(object),
                // `object { DeclaredLight transforms }` (`.pov`): the light, moved by the
                // object's transforms as a light in an object is.
                Value::Light(light) => {
                    self.held_lights.push(((*light).clone(), span.clone()));
                    ShapeNode::Union(Vec::new())
                }
                other => {
                    let what = match &of.kind {
                        syntax::ExprKind::Ident(name) => format!("`{name}`"),
                        _ => "this".to_string(),
                    };
                    return Err(SceneError::at(
                        &of.span,
                        format!("{what} is {}, not an object", other.kind()),
                    ));
                }
            },
            Shape::Union => ShapeNode::Union(Vec::new()),
            Shape::Intersection => ShapeNode::Csg { op: CsgOp::Intersection, operands: Vec::new() },
            Shape::Difference => ShapeNode::Csg { op: CsgOp::Difference, operands: Vec::new() },
            Shape::Merge => ShapeNode::Csg { op: CsgOp::Merge, operands: Vec::new() },
        };
        let depth = match &shape {
            ShapeNode::Instance(target) => target.depth + 1,
            // A text's glyphs.
            ShapeNode::Union(glyphs) if !glyphs.is_empty() => 2,
            _ => 1,
        };
        self.count_objects(1, &object.span)?;
        // POV-Ray's modifiers on a wrapper (`object { T pigment { } }`) modify the texture the
        // wrapped object wears itself, if it has one: they start from its look.
        let worn = match &shape {
            ShapeNode::Instance(target) if self.dialect == Dialect::Pov => own_material(target)
                .map(|own| self.worn_looks.get(&address(own)).map(|(_, look)| look.clone())),
            _ => None,
        };
        let worn_space = match (&shape, &worn) {
            (ShapeNode::Instance(target), Some(Some(_))) => worn_space(target),
            _ => Affine3A::IDENTITY,
        };
        let mut node = ObjectNode { shape, material: None, transforms: Vec::new(), depth, span };
        self.looks.push(None);
        let worn_look = worn.clone().flatten();
        // A `texture` given to the wrapper is layered over the worn one, as POV-Ray's is.
        self.shapings.push(Shaping {
            textured: worn_look.is_some(),
            worn: worn_look,
            worn_space,
            ..Default::default()
        });
        let items = match &object.shape {
            Shape::TriangleMesh { triangles } => {
                self.mesh_items(triangles, &object.items, &mut node)
            }
            _ => self.exec(&object.items, &mut Body::Object(&mut node)),
        };
        let look = self.looks.pop().flatten();
        let shaping = self.shapings.pop().unwrap_or_default();
        items?;
        let moving = compose(&node.transforms);
        for (light, _) in &mut self.held_lights[held..] {
            light.moved_by(moving);
        }
        let flattened = moving.matrix3.determinant().abs() < FLATTENING_DETERMINANT;
        if flattened && self.dialect == Dialect::Pov {
            // POV-Ray draws an object scaled to (almost) nothing as the sliver it is
            // (swirlbox.pov's last box, `scale 5e-16`), which shows nothing: it is left out.
            let here = self.here(&object.span);
            self.warnings.push(format!(
                "{here:?}: warning: the transforms of this object flatten it (their determinant \
                 is {:e}): it shows nothing and is left out",
                moving.matrix3.determinant()
            ));
            node.shape = ShapeNode::Union(Vec::new());
            node.transforms.clear();
        }
        self.check_blob(&node.shape, &object.span)?;
        let material = look.map(|look| (self.look_material(&look, &object.span), look));
        if let (Some((material, _)), ShapeNode::Instance(target)) = (&material, &node.shape) {
            match worn {
                Some(Some(_)) => {
                    node.shape = ShapeNode::Instance(Arc::new(rewear(target, material.clone())))
                }
                Some(None) => {
                    let here = self.here(&object.span);
                    self.warnings.push(format!(
                        "{here:?}: warning: the wrapped object wears a material of its own that \
                         this object's texture, pigment, normal or finish cannot modify: they \
                         reach only its parts without one"
                    ));
                }
                None => {}
            }
        }
        if let Some((material, _)) = &material {
            // Laid in the space of all the object's transforms, which `clipped_by` splits
            // between the object and its clipping (`lay_textures` keeps it there).
            node.material = Some(material.clone());
        }
        let mut node = shaping.shaped(node);
        if let Some((material, look)) = material {
            node.material = Some(material.clone());
            if self.dialect == Dialect::Pov {
                self.made_look = Some((material, look));
            }
        }
        if node.depth > MAX_OBJECT_DEPTH {
            return Err(SceneError::at(
                &object.span,
                format!("objects nested more than {MAX_OBJECT_DEPTH} levels deep"),
            ));
        }
        if let ShapeNode::Csg { op, operands } = &node.shape {
            let what = match op {
                CsgOp::Intersection => "an intersection",
                CsgOp::Difference => "a difference",
                CsgOp::Merge => "a merge",
                CsgOp::Inverse => "an inverse",
                CsgOp::Clip => "a clipped object",
            };
            if operands.is_empty() {
                let message = format!("{what} of no operands: it would be empty");
                return Err(SceneError::at(&object.span, message));
            }
            if operands.len() > MAX_CSG_OPERANDS {
                return Err(SceneError::at(
                    &object.span,
                    format!(
                        "{what} of {} operands: at most {MAX_CSG_OPERANDS} are allowed (a ray is \
                         tested against every operand)",
                        operands.len()
                    ),
                ));
            }
            if self.csg_levels(&node) > MAX_CSG_DEPTH {
                return Err(SceneError::at(
                    &object.span,
                    format!(
                        "intersection, difference and merge nested more than {MAX_CSG_DEPTH} \
                         levels deep (counting the unions among their operands)"
                    ),
                ));
            }
        }
        Ok(node)
    }

    /// Counts `made` objects more, made for the object at `at`: a scene makes a bounded number.
    pub(super) fn count_objects(&mut self, made: u64, at: &Span) -> Result<(), SceneError> {
        self.objects_made += made;
        if self.objects_made > MAX_OBJECTS_MADE {
            return Err(SceneError::at(
                at,
                format!(
                    "the scene has made more than {MAX_OBJECTS_MADE} objects (does a loop end?)"
                ),
            ));
        }
        Ok(())
    }

    /// An object made to be a value (`#declare`d): a light in it would be placed once, where
    /// it is declared, not wherever the object is used, so it is refused.
    /// POV-Ray's `uv_mapping`, read with a warning: raydiance's surfaces carry no uv
    /// coordinates, so the texture stays laid in space as if it were not there.
    pub(super) fn warn_uv_mapping(&mut self, at: &Span) {
        let at = self.here(at);
        self.warnings.push(format!(
            "{at:?}: warning: `uv_mapping` is not honoured: raydiance's surfaces carry no uv \
             coordinates, so the texture is laid in space (the object's own coordinates) instead"
        ));
    }

    pub(super) fn unlit_object(
        &mut self,
        object: &syntax::Object,
    ) -> Result<ObjectNode, SceneError> {
        let held = self.held_lights.len();
        let node = self.object(object)?;
        // The look the declared object wears, kept for the wrappers that modify it.
        if let Some((material, look)) = self.made_look.take()
            && own_material(&node).is_some_and(|own| Arc::ptr_eq(own, &material))
        {
            self.worn_looks.insert(address(&material), (material, look));
        }
        if let Some((_, span)) = self.held_lights.get(held) {
            return Err(SceneError::at(
                span,
                "a light_source in a declared object is not supported: write the light in the \
                 object where it is placed in the scene",
            ));
        }
        Ok(node)
    }

    /// A box from two corners. POV-Ray draws a box whose corners are equal in one coordinate
    /// as the rectangle it is (`Orthographic_scene.pov`, `transmitfx.pov`): here a quad, with
    /// a warning; one equal in two or three coordinates is a line or a point and shows nothing:
    /// an empty union, with a warning. `.scn` refuses such a box.
    fn box_shape(
        &mut self,
        corner_a: Vec3,
        corner_b: Vec3,
        at: &Span,
    ) -> Result<ShapeNode, SceneError> {
        let size = corner_b - corner_a;
        let flat = size.cmpeq(Vec3::ZERO);
        if flat.bitmask() == 0 {
            return Ok(ShapeNode::Box { corner_a, corner_b });
        }
        if self.dialect == Dialect::Scn {
            return Err(SceneError::at(
                at,
                "the box's corners are equal in one coordinate: it has no volume",
            ));
        }
        let here = self.here(at);
        if flat.bitmask().count_ones() > 1 {
            self.warnings.push(format!(
                "{here:?}: warning: the box's corners are equal in more than one coordinate: it \
                 is a line or a point, and shows nothing (as in POV-Ray)"
            ));
            return Ok(ShapeNode::Union(Vec::new()));
        }
        self.warnings.push(format!(
            "{here:?}: warning: the box's corners are equal in one coordinate: it is drawn as \
             the rectangle it is (as in POV-Ray), a surface without an inside"
        ));
        let axis = flat.bitmask().trailing_zeros() as usize;
        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
        let edge = |i: usize| {
            let mut e = Vec3::ZERO;
            e[i] = size[i];
            e
        };
        Ok(ShapeNode::Quad { corner: corner_a, edge1: edge(u), edge2: edge(v) })
    }

    /// The levels of CSG operations that tracing `node` as an operand takes: one per CSG node and
    /// per union (a merge) on the way down to the deepest solid.
    fn csg_levels(&mut self, node: &ObjectNode) -> u32 {
        let below = |e: &mut Self, nodes: &[ObjectNode]| {
            nodes.iter().map(|n| e.csg_levels(n)).max().unwrap_or(0)
        };
        match node.shape.below() {
            Below::Operands(children) | Below::Children(children) => 1 + below(self, children),
            Below::Shared(target) => {
                let key = Arc::as_ptr(target) as usize;
                if let Some((_, levels)) = self.csg_levels.get(&key) {
                    return *levels;
                }
                let levels = self.csg_levels(target);
                self.csg_levels.insert(key, (target.clone(), levels));
                levels
            }
            Below::Nothing => 0,
        }
    }

    /// A radius that may be 0 (a cone's).
    pub(super) fn non_negative(
        &mut self,
        expr: &syntax::Expr,
        what: &str,
    ) -> Result<f32, SceneError> {
        let f = self.float(expr)?;
        if f < 0.0 || f.is_nan() {
            return Err(SceneError::at(
                &expr.span,
                format!("{what} {f} is negative: it must be 0 or more"),
            ));
        }
        super::expression::single(f, &expr.span)
    }

    /// A modifier of an object, or (in a union or CSG object) a child.
    pub(super) fn object_item(
        &mut self,
        item: &Item,
        node: &mut ObjectNode,
    ) -> Result<(), SceneError> {
        match item {
            Item::Material(m) if self.dialect == Dialect::Pov => {
                let mut look = self.pov_material(m)?;
                self.lay_given(node, &mut look, AppearanceKind::Texture);
                if let Some(slot) = self.looks.last_mut() {
                    *slot = Some(look);
                }
            }
            Item::Material(m) => node.material = Some(self.material(m, None)?),
            Item::MaterialName(name) => {
                let name = syntax::Expr::from(name.clone());
                node.material = Some(self.material_named(&name)?)
            }
            Item::Transform(t) => node.transforms.push(self.transform(t)?),
            // POV-Ray lets a light be part of an object; it moves with it.
            Item::Light { position, items, span } if self.dialect == Dialect::Pov => {
                let light = self.light_state(position, items)?;
                self.held_lights.push((light, span.clone()));
            }
            // POV-Ray's object modifiers: `hollow` and `double_illuminate` change nothing without
            // media and with two-sided shading; the others are not honoured, and say so.
            Item::PovParam { key, value: Some(value), .. } if key.name == "threshold" => {
                let ShapeNode::Blob { threshold, .. } = &mut node.shape else {
                    return Err(Self::misplaced(item, &Body::Object(node)));
                };
                *threshold = self.single(&value.value)?;
            }
            Item::Object(object) if matches!(node.shape, ShapeNode::Blob { .. }) => {
                let component = self.blob_component(object)?;
                if let ShapeNode::Blob { components, .. } = &mut node.shape {
                    components.push(component);
                }
            }
            Item::PovParam { key, value, .. } => {
                let on = match value {
                    Some(v) => self.number(&v.value, &format!("`{}`", key.name))? != 0.0,
                    None => true,
                };
                match key.name.as_str() {
                    // The roots of every polynomial are found robustly: POV-Ray's `sturm`
                    // asks for nothing more.
                    "hollow" | "double_illuminate" | "bounded_by" | "sturm" | "hierarchy" => {}
                    "inverse" => {
                        if let Some(shaping) = self.shapings.last_mut() {
                            shaping.inverse = !shaping.inverse;
                        }
                    }
                    "no_shadow" | "no_image" | "no_reflection" if on => {
                        let at = self.here(&key.span);
                        self.warnings.push(format!(
                            "{at:?}: warning: `{}` is not honoured: the object is seen, reflected \
                             and casts shadows",
                            key.name
                        ));
                    }
                    "no_shadow" | "no_image" | "no_reflection" => {}
                    "uv_mapping" => self.warn_uv_mapping(&key.span),
                    other => unreachable!("no object modifier `{other}`"),
                }
            }
            Item::Appearance(appearance) => {
                if self.dialect == Dialect::Scn {
                    let advice =
                        crate::lang::povray::message("normal", None).expect("`normal` has advice");
                    return Err(SceneError::at(&appearance.span, advice));
                }
                let worn = self.shapings.last_mut().and_then(|shaping| shaping.worn.take());
                // The object's look so far, or the one it wraps, lies in the object's space
                // (`placed`); the default one, not yet given, in the scene's.
                let (mut look, in_object_space) = match self.looks.last_mut().and_then(Option::take)
                {
                    Some(look) => (look, true),
                    None => match worn {
                        Some(worn) => (worn, true),
                        None => (self.default_look.clone(), false),
                    },
                };
                let under = look.clone();
                // The items apply where POV-Ray applies them: after the object's transforms
                // written so far.
                if let Some(placed) = self.placed(node).filter(|_| in_object_space) {
                    look.push_transform(appearance.kind, matrix_of(placed));
                }
                let result = self.apply_appearance(appearance, &mut look);
                self.lay_given(node, &mut look, appearance.kind);
                let texture = appearance.kind == AppearanceKind::Texture;
                let layered = match self.shapings.last_mut() {
                    Some(shaping) if texture => std::mem::replace(&mut shaping.textured, true),
                    _ => false,
                };
                if layered && result.is_ok() {
                    self.layer(&under, &mut look, &appearance.span);
                }
                if let Some(slot) = self.looks.last_mut() {
                    *slot = Some(look);
                }
                result?;
            }
            Item::ClippedBy { items, .. } => {
                let mut clip = ObjectNode {
                    shape: ShapeNode::Union(Vec::new()),
                    material: None,
                    transforms: Vec::new(),
                    depth: 1,
                    span: self.here(item.span()),
                };
                self.exec(items, &mut Body::Object(&mut clip))?;
                let ShapeNode::Union(by) = clip.shape else { unreachable!("made a union") };
                if by.is_empty() {
                    return Err(SceneError::at(item.span(), "`clipped_by` of no objects"));
                }
                if let Some(shaping) = self.shapings.last_mut() {
                    shaping.clips.push((node.transforms.len(), by));
                }
            }
            Item::Object(object) if children(&mut node.shape).is_some() => {
                let child = self.object(object)?;
                add_child(node, child);
            }
            Item::Value(expr) => match self.value(expr)? {
                // What a macro gives among an object's items: a material, or a child of a group
                // or CSG object.
                Value::Material(m) => node.material = Some(m),
                Value::Look(look) => {
                    let mut look = (*look).clone();
                    self.lay_given(node, &mut look, AppearanceKind::Texture);
                    if let Some(slot) = self.looks.last_mut() {
                        *slot = Some(look);
                    }
                }
                Value::Object(child) if children(&mut node.shape).is_some() => {
                    let child = super::instance(child, self.here(&expr.span));
                    add_child(node, child);
                }
                _ => return Err(Self::misplaced(item, &Body::Object(node))),
            },
            _ => return Err(Self::misplaced(item, &Body::Object(node))),
        }
        Ok(())
    }

    /// POV-Ray's layered textures: a `texture` over another shows the one under it through its
    /// pigment's filter and transmit, point by point (`Pigment::over`). Flattened into one look:
    /// the top one's finish applies to both (warned about, once a scene, where an object wears
    /// it: `look_material`); an opaque top covers the layer under it, as in POV-Ray.
    pub(super) fn layer(&mut self, under: &Look, over: &mut Look, span: &Span) {
        if over.pigment.is_opaque() {
            return;
        }
        // A texture layer replaced `over`'s mark with its own (none): an earlier flattening,
        // under it, is kept.
        over.finish_flattened_at = if under.finish != over.finish {
            Some(format!("{:?}", self.here(span)))
        } else {
            under.finish_flattened_at.clone()
        };
        over.pigment = over.pigment.over(&under.pigment);
    }

    pub(super) fn transform(&mut self, t: &syntax::Transform) -> Result<Transform, SceneError> {
        Ok(match &t.kind {
            TransformKind::Translate(e) => {
                Transform::Translate(self.transform_vector(e, "`translate`")?)
            }
            TransformKind::Rotate(e) => Transform::Rotate(self.transform_vector(e, "`rotate`")?),
            TransformKind::Scale(e) => self.scale(e)?,
            TransformKind::Matrix(e) => self.matrix(e)?,
            TransformKind::Value(e) => matrix_of(self.transform_value(e)?),
            TransformKind::Block(items) => matrix_of(self.transform_block(items, &t.span)?),
        })
    }

    /// A transform's vector: POV-Ray promotes a 2-vector to a vector with z 0 (`translate <1,
    /// 2>`).
    fn transform_vector(&mut self, expr: &syntax::Expr, what: &str) -> Result<Vec3, SceneError> {
        single_vector(self.promoted_vector(expr, what)?, &expr.span)
    }

    fn scale(&mut self, expr: &syntax::Expr) -> Result<Transform, SceneError> {
        let at = &expr.span;
        let mut s = self.transform_vector(expr, "`scale`")?;
        if s.cmpeq(Vec3::ZERO).any() && self.dialect == Dialect::Pov {
            // As POV-Ray does: a zero factor is changed to 1, with a warning.
            let here = self.here(at);
            self.warnings.push(format!(
                "{here:?}: warning: scale <{}, {}, {}> has a zero component, changed \
                 to 1 (as POV-Ray does)",
                s.x, s.y, s.z
            ));
            s = Vec3::select(s.cmpeq(Vec3::ZERO), Vec3::ONE, s);
        }
        if s.cmpeq(Vec3::ZERO).any() {
            let (x, y, z) = (s.x, s.y, s.z);
            return Err(SceneError::at(
                at,
                format!("scale <{x}, {y}, {z}> has a zero component: it flattens the object"),
            ));
        }
        Ok(Transform::Scale(s))
    }

    fn matrix(&mut self, expr: &syntax::Expr) -> Result<Transform, SceneError> {
        let at = &expr.span;
        let numbers = match self.value(expr)? {
            Value::Numbers(n) if n.len() == 12 => n,
            other => {
                return Err(SceneError::at(
                    at,
                    format!("`matrix` takes 12 numbers, not {}", other.kind()),
                ));
            }
        };
        let m: Vec<f32> = numbers.iter().map(|&f| single(f, at)).collect::<Result<_, _>>()?;
        let linear = Mat3::from_cols_slice(&m[..9]);
        if linear.determinant().abs() < 1e-12 {
            return Err(SceneError::at(at, "the matrix is singular: it flattens the object"));
        }
        Ok(Transform::Matrix { linear, translation: Vec3::new(m[9], m[10], m[11]) })
    }
}

/// POV-Ray's `inverse` and `clipped_by` of an object, applied once its items are read.
#[derive(Default)]
pub struct Shaping {
    inverse: bool,
    /// A `texture` has been given: another is layered over it.
    textured: bool,
    /// The look of the wrapped object (`object { T ... }`) that the wrapper's first texture,
    /// pigment, normal or finish modifies, until one does.
    worn: Option<Look>,
    /// The space that look lies in, in the wrapper's (`worn_space`): the identity elsewhere.
    pub(super) worn_space: Affine3A,
    /// Each `clipped_by`'s objects, with how many of the object's transforms stood before it:
    /// those move the object alone, the later ones the object and its clipping objects.
    clips: Vec<(usize, Vec<ObjectNode>)>,
}

impl Shaping {
    /// The object clipped, then turned inside out, as written.
    fn shaped(self, mut node: ObjectNode) -> ObjectNode {
        let mut placed = 0;
        for (before, by) in self.clips {
            let after = node.transforms.split_off(before - placed);
            placed = before;
            let span = node.span.clone();
            let depth = by.iter().map(|o| o.depth).max().unwrap_or(0).max(node.depth) + 1;
            let mut operands = vec![node];
            operands.extend(by);
            node = ObjectNode {
                shape: ShapeNode::Csg { op: CsgOp::Clip, operands },
                material: None,
                transforms: after,
                depth,
                span,
            };
        }
        if self.inverse {
            let (span, depth) = (node.span.clone(), node.depth + 1);
            node = ObjectNode {
                shape: ShapeNode::Csg { op: CsgOp::Inverse, operands: vec![node] },
                material: None,
                transforms: Vec::new(),
                depth,
                span,
            };
        }
        node
    }
}

/// The children of a group, or the operands of a CSG object: where the objects among its items
/// go. `None` for the other shapes, which take no objects.
pub(super) fn children(shape: &mut ShapeNode) -> Option<&mut Vec<ObjectNode>> {
    match shape {
        ShapeNode::Union(children) | ShapeNode::Csg { operands: children, .. } => Some(children),
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
        | ShapeNode::HeightField { .. }
        | ShapeNode::Instance(_) => None,
    }
}

fn add_child(node: &mut ObjectNode, child: ObjectNode) {
    node.depth = node.depth.max(child.depth + 1);
    if let Some(children) = children(&mut node.shape) {
        children.push(child);
    }
}

/// The material a node wears itself: its own, or down a chain of instances without one, the
/// instanced object's (POV-Ray copies a wrapped object's texture with it).
fn own_material(node: &ObjectNode) -> Option<&Arc<MaterialDesc>> {
    if node.material.is_some() {
        return node.material.as_ref();
    }
    let ShapeNode::Instance(target) = &node.shape else { return None };
    own_material(target)
}

/// `node` with `material` in place of the one it wears itself (`own_material`): the node that
/// wears it copied, and the instances down to it; their meshes are shared, not copied.
fn rewear(node: &ObjectNode, material: Arc<MaterialDesc>) -> ObjectNode {
    let mut copy = node.clone();
    if let (None, ShapeNode::Instance(target)) = (&node.material, &node.shape) {
        copy.shape = ShapeNode::Instance(Arc::new(rewear(target, material)));
    } else {
        copy.material = Some(material);
    }
    copy
}

/// A material's address: the key of `Evaluator::worn_looks`.
fn address(material: &Arc<MaterialDesc>) -> usize {
    Arc::as_ptr(material) as usize
}

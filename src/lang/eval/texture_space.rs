//! Where POV-Ray lays a texture (`.pov`): in the space of the object that is given it, as that
//! object stands when it is given, so that only the transforms written after it move it
//! (`docs/povray.md`, Object modifiers). The scene's builder lays a material in the space of
//! each shape that wears it, with all its transforms (`.scn`'s rule): here each `.pov` texture
//! is moved back by what that adds.

use std::collections::HashMap;
use std::sync::Arc;

use glam::Affine3A;

use super::object::children;
use super::transform::matrix_of;
use super::{Evaluator, Look};
use crate::diagnostic::{SceneError, Span};
use crate::graph::{Below, MaterialDesc, ObjectNode, Pattern, ShapeNode, compose};
use crate::lang::syntax::AppearanceKind;

/// The declared objects laid under a material, by the addresses of both (the `Arc`s kept so
/// that the addresses stay theirs): an object placed many times under one material is copied
/// once.
pub type Laid = HashMap<(usize, usize), (Arc<ObjectNode>, Arc<MaterialDesc>, Arc<ObjectNode>)>;

impl Evaluator {
    /// `node`, placed in the scene, with its parts laid as POV-Ray lays them: a part without a
    /// material of its own, moved by transforms of its own, wears its group's patterned
    /// material moved back by them, so that the material lies where its group was given it.
    pub(super) fn lay_textures(&mut self, node: &mut ObjectNode) -> Result<(), SceneError> {
        self.lay(node, None)
    }

    /// POV-Ray's default texture for `node`, placed in the scene without one: laid in the
    /// scene's space, not moved by the object's transforms.
    pub(super) fn default_look_of(&self, node: &ObjectNode) -> Look {
        let mut look = self.default_look.clone();
        self.lay_given(node, &mut look, AppearanceKind::Texture);
        look
    }

    /// Where POV-Ray lays what an object is given now, in the space its texture lies in (the
    /// object's, with all its transforms; in a wrapper that modifies the look of the object it
    /// wraps, that object's): the object's space as it stands now, so that only the transforms
    /// written after it move it. `None` where the two are the same.
    pub(super) fn placed(&self, node: &ObjectNode) -> Option<Affine3A> {
        let worn_space = self.shapings.last().map_or(Affine3A::IDENTITY, |s| s.worn_space);
        let placed = compose(&node.transforms) * worn_space;
        (placed != Affine3A::IDENTITY).then_some(placed)
    }

    /// `look`'s part that `kind` gives, laid as POV-Ray lays what `node` is given now
    /// (`placed`).
    pub(super) fn lay_given(&self, node: &ObjectNode, look: &mut Look, kind: AppearanceKind) {
        if let Some(placed) = self.placed(node) {
            look.push_transform(kind, matrix_of(placed.inverse()));
        }
    }

    fn lay(
        &mut self,
        node: &mut ObjectNode,
        inherited: Option<&Arc<MaterialDesc>>,
    ) -> Result<(), SceneError> {
        if let (None, Some(material)) = (&node.material, inherited)
            && is_patterned(material)
            && compose(&node.transforms) != Affine3A::IDENTITY
        {
            node.material = Some(Arc::new(moved(material, compose(&node.transforms).inverse())));
        }
        let worn = node.material.clone().or_else(|| inherited.cloned());
        if let ShapeNode::Instance(target) = &mut node.shape {
            if needs_laying(target, worn.as_ref()) {
                *target = self.laid(target, worn.as_ref(), &node.span)?;
            }
        } else if let Some(children) = children(&mut node.shape) {
            for child in children {
                self.lay(child, worn.as_ref())?;
            }
        }
        Ok(())
    }

    /// A copy of the declared `target` laid under `worn`, made once for both.
    /// The copy counts as the objects it copies, placed at `at`.
    fn laid(
        &mut self,
        target: &Arc<ObjectNode>,
        worn: Option<&Arc<MaterialDesc>>,
        at: &Span,
    ) -> Result<Arc<ObjectNode>, SceneError> {
        let key = (Arc::as_ptr(target) as usize, worn.map_or(0, |m| Arc::as_ptr(m) as usize));
        if let Some((_, _, laid)) = self.laid.get(&key) {
            return Ok(laid.clone());
        }
        self.count_objects(owned_nodes(target), at)?;
        let mut copy = (**target).clone();
        self.lay(&mut copy, worn)?;
        let copy = Arc::new(copy);
        if let Some(worn) = worn {
            self.laid.insert(key, (target.clone(), worn.clone(), copy.clone()));
        }
        Ok(copy)
    }
}

/// The space of the material `node` wears itself (`own_material`), in the space `node` is
/// placed in: its transforms, and down a chain of instances those of each.
pub(super) fn worn_space(node: &ObjectNode) -> Affine3A {
    let own = compose(&node.transforms);
    match (&node.material, &node.shape) {
        (None, ShapeNode::Instance(target)) => own * worn_space(target),
        _ => own,
    }
}

/// Whether laying `node` under `inherited` changes it: whether a part of it without a
/// material of its own is moved while it wears a patterned one.
fn needs_laying(node: &ObjectNode, inherited: Option<&Arc<MaterialDesc>>) -> bool {
    let worn = node.material.as_ref().or(inherited);
    if !worn.is_some_and(|material| is_patterned(material)) {
        return false;
    }
    if node.material.is_none() && compose(&node.transforms) != Affine3A::IDENTITY {
        return true;
    }
    match node.shape.below() {
        Below::Children(children) | Below::Operands(children) => {
            children.iter().any(|child| needs_laying(child, worn))
        }
        Below::Shared(target) => needs_laying(target, worn),
        Below::Nothing => false,
    }
}

/// The nodes a copy of `node` copies: itself and its parts, not the declared objects it shares.
fn owned_nodes(node: &ObjectNode) -> u64 {
    match node.shape.below() {
        Below::Children(parts) | Below::Operands(parts) => {
            1 + parts.iter().map(owned_nodes).sum::<u64>()
        }
        Below::Shared(_) | Below::Nothing => 1,
    }
}

/// Whether where a material lies changes it: a pattern in its colour or transparency, or bumps.
fn is_patterned(material: &MaterialDesc) -> bool {
    !matches!(material.diffuse.pattern, Pattern::Solid(_))
        || material.pigment.is_some()
        || material.normal.is_some()
}

/// `material` with its patterns and bumps moved by `moving` after their own transforms.
fn moved(material: &MaterialDesc, moving: Affine3A) -> MaterialDesc {
    let moving = matrix_of(moving);
    let mut material = material.clone();
    if !matches!(material.diffuse.pattern, Pattern::Solid(_)) {
        material.diffuse.transforms.push(moving);
    }
    if let Some(pigment) = &mut material.pigment {
        pigment.filter.transforms.push(moving);
        pigment.through.transforms.push(moving);
    }
    if let Some(normal) = &mut material.normal {
        normal.transforms.push(moving);
    }
    material
}

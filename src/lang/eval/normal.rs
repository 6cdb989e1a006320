//! POV-Ray's `normal { PATTERN AMOUNT ... }` (both dialects): bump mapping, read into a
//! `NormalNode` (`docs/language.md`, Bump mapping).

use super::pattern::{PatternState, block_colours, own_arguments};
use super::{Body, Evaluator};
use crate::diagnostic::SceneError;
use crate::graph::{FieldShape, NormalNode, NormalPattern, Transform};
use crate::lang::syntax::{Appearance, Item, MapKind, PatternKind};
use crate::lang::value::Value;
use crate::texture::DEFAULT_ACCURACY;

/// A pattern's amount in a normal when none is given (POV-Ray's).
const DEFAULT_AMOUNT: f32 = 0.5;

/// A normal's items as they are read.
pub struct NormalState {
    pattern: PatternState,
    transforms: Vec<Transform>,
    /// A declared normal named in it.
    base: Option<NormalNode>,
    /// A `bump_map`'s pattern.
    image: Option<NormalPattern>,
}

impl NormalNode {
    /// No perturbation.
    pub fn flat() -> NormalNode {
        NormalNode { pattern: NormalPattern::Average(Vec::new()), transforms: Vec::new() }
    }

    /// The shape of its pattern, where it has one (bumps or a normal_map's).
    fn shape(&self) -> Option<&FieldShape> {
        match &self.pattern {
            NormalPattern::Bumps { shape, .. } | NormalPattern::Map { shape, .. } => Some(shape),
            NormalPattern::Average(_) | NormalPattern::Image { .. } => None,
        }
    }
}

impl Evaluator {
    /// The bump mapping a `normal { }` makes, over `base`; `None`: none.
    pub(super) fn normal(
        &mut self,
        appearance: &Appearance,
        base: Option<&NormalNode>,
    ) -> Result<Option<NormalNode>, SceneError> {
        if appearance.items.is_empty() {
            // Read whole (a form raydiance does not render), or empty.
            self.warn_normal(&appearance.span);
            return Ok(base.cloned());
        }
        self.normal_of(&appearance.items, base)
    }

    /// The bump mapping `items` make, over `base`.
    pub(super) fn normal_of(
        &mut self,
        items: &[Item],
        base: Option<&NormalNode>,
    ) -> Result<Option<NormalNode>, SceneError> {
        let mut state = NormalState {
            pattern: PatternState::default(),
            transforms: Vec::new(),
            base: base.cloned(),
            image: None,
        };
        self.exec(items, &mut Body::Normal(&mut state))?;
        if let Some(pattern) = state.image {
            return Ok(Some(NormalNode { pattern, transforms: state.transforms }));
        }
        let Some((kind, arguments, at)) = state.pattern.word.clone() else {
            return Ok(state.base.map(|mut node| {
                node.transforms.extend(state.transforms);
                // `normal { N_Declared bump_size 2 }`: the declared bumps, by a new amount.
                if let (NormalPattern::Bumps { amount, .. }, Some(size)) =
                    (&mut node.pattern, state.pattern.bump_size)
                {
                    *amount = size;
                }
                node
            }));
        };
        // A new word over a declared normal's pattern changes only its type, as a pigment's
        // does (`field_shape`): its amount, accuracy and map stay unless given (a block
        // pattern's map is its own).
        let base = state.base.filter(|base| base.shape().is_some());
        state.pattern.base = base.as_ref().and_then(|base| base.shape().cloned());
        let (kept_amount, kept_slopes, kept_accuracy, kept_map) = match base.map(|b| b.pattern) {
            Some(NormalPattern::Bumps { amount, slopes, accuracy, .. }) => {
                (Some(amount), slopes, Some(accuracy), None)
            }
            Some(NormalPattern::Map { map, .. }) => (None, Vec::new(), None, Some(map)),
            _ => (None, Vec::new(), None, None),
        };
        let kept_map = kept_map.filter(|_| block_colours(kind).is_none());
        let amount = match (state.pattern.bump_size, arguments.get(own_arguments(kind))) {
            (Some(size), _) => size,
            (None, Some(a)) => self.single(&a.value)?,
            (None, None) => kept_amount.unwrap_or(DEFAULT_AMOUNT),
        };
        let accuracy = state.pattern.accuracy.or(kept_accuracy).unwrap_or(DEFAULT_ACCURACY);
        let average = kind == PatternKind::Average;
        let map = match &state.pattern.map {
            Some((map_kind, entries, _)) => Some(self.map_entries(*map_kind, entries, average)?),
            None => None,
        };
        let pattern = match map {
            Some(map) if average => match map.kind {
                MapKind::Normal => NormalPattern::Average(map.normals),
                MapKind::Pigment | MapKind::Texture | MapKind::Slope => {
                    return Err(SceneError::at(&at, "a normal's `average` takes a normal_map"));
                }
            },
            Some(map) => {
                let shape = Box::new(self.field_shape(kind, &arguments, &state.pattern, &at)?);
                match map.kind {
                    MapKind::Normal => NormalPattern::Map { shape, map: map.normals },
                    MapKind::Slope => {
                        NormalPattern::Bumps { shape, amount, slopes: map.slopes, accuracy }
                    }
                    MapKind::Pigment | MapKind::Texture => {
                        return Err(SceneError::at(
                            &at,
                            format!("a {} stands in a pigment or a texture", map.kind.word()),
                        ));
                    }
                }
            }
            None => {
                if state.pattern.color_map.is_some() {
                    return Err(SceneError::at(&at, "a color_map stands in a pigment"));
                }
                let shape = Box::new(self.field_shape(kind, &arguments, &state.pattern, &at)?);
                match kept_map {
                    Some(map) => NormalPattern::Map { shape, map },
                    None => NormalPattern::Bumps { shape, amount, slopes: kept_slopes, accuracy },
                }
            }
        };
        Ok(Some(NormalNode { pattern, transforms: state.transforms }))
    }

    pub(super) fn normal_item(
        &mut self,
        item: &Item,
        state: &mut NormalState,
    ) -> Result<(), SceneError> {
        if let Item::Pattern { .. } = item {
            // A new word over a declared normal's pattern keeps its transforms, as POV-Ray's
            // does (`normal_of`); over a bump_map or nothing, the ones written so far go.
            match state.base.as_mut().filter(|base| base.shape().is_some()) {
                Some(base) => {
                    let written = std::mem::take(&mut state.transforms);
                    state.transforms = std::mem::take(&mut base.transforms);
                    state.transforms.extend(written);
                }
                None => state.transforms.clear(),
            }
            state.image = None;
        }
        let warp = matches!(item, Item::PovParam { key, .. } if key.name == "warp");
        if self.pattern_item(item, &mut state.pattern)? {
            // The transforms written so far apply to the point after this warp, as a
            // pigment's do (a declared normal's warps are not read: it keeps its own).
            if warp
                && state.pattern.word.is_some()
                && let Some(last) = state.pattern.warps.pop()
            {
                let before = std::mem::take(&mut state.transforms);
                state.pattern.warp_after(&before, last);
            }
            return Ok(());
        }
        match item {
            Item::ImageMap { file, options, .. } => {
                state.image = Some(self.bump_image(file, options)?);
                state.pattern.word = None;
                state.transforms.clear();
            }
            Item::Transform(t) => {
                let transform = self.transform(t)?;
                state.transforms.push(transform);
            }
            Item::Value(expr) => match self.value(expr)? {
                Value::Normal(node) => {
                    state.base = node.map(|n| (*n).clone());
                    state.pattern.word = None;
                    state.image = None;
                    state.transforms.clear();
                }
                other => {
                    return Err(SceneError::at(
                        &expr.span,
                        format!("a normal names a declared normal, not {}", other.kind()),
                    ));
                }
            },
            _ => return Err(Self::misplaced(item, &Body::Normal(state))),
        }
        Ok(())
    }
}

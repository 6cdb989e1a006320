//! POV-Ray's `sky_sphere` (`.pov`): the environment light, from its pigment on the unit
//! direction (`docs/povray.md`, Sky).

use glam::Vec3;

use super::pigment::Pigment;
use super::{Body, Evaluator};
use crate::diagnostic::{SceneError, Span};
use crate::graph::{SkyDesc, TextureNode};
use crate::lang::syntax::{AppearanceKind, Item};
use crate::lang::value::Value;

impl Evaluator {
    /// `sky_sphere { items }`: the scene's environment light (one a scene, as in POV-Ray).
    pub(super) fn sky_sphere(&mut self, items: &[Item], span: &Span) -> Result<(), SceneError> {
        if self.sky.is_some() {
            return Err(SceneError::at(span, "a second sky_sphere (POV-Ray's scenes have one)"));
        }
        self.sky = Some(self.sky_desc(items, span)?);
        Ok(())
    }

    /// The sky that a `sky_sphere`'s items describe, declared or the scene's.
    pub(super) fn sky_desc(&mut self, items: &[Item], span: &Span) -> Result<SkyDesc, SceneError> {
        let mut sky = SkyDesc {
            pigment: TextureNode::solid(Vec3::ZERO),
            transforms: Vec::new(),
            emission: Vec3::ONE,
            span: self.here(span),
        };
        self.exec(items, &mut Body::Sky(&mut sky))?;
        Ok(sky)
    }

    /// An item of a `sky_sphere`: a declared sky (its pigment, transforms and emission, which
    /// the items after it change), a pigment (a layer over the sky so far, which shows through
    /// its filter and transmit, as POV-Ray layers them; the sky starts black, POV-Ray's default
    /// background), a transform, `emission`.
    pub(super) fn sky_item(&mut self, item: &Item, sky: &mut SkyDesc) -> Result<(), SceneError> {
        match item {
            Item::Value(expr) => match self.value(expr)? {
                Value::Sky(declared) => {
                    let span = sky.span.clone();
                    *sky = SkyDesc { span, ..(*declared).clone() };
                }
                other => {
                    return Err(SceneError::at(
                        &expr.span,
                        format!("a sky_sphere names a declared sky_sphere, not {}", other.kind()),
                    ));
                }
            },
            Item::Appearance(a) if a.kind == AppearanceKind::Pigment => {
                let layer = self.pigment(a, &Pigment::black())?;
                sky.pigment = match layer.is_opaque() {
                    true => layer.colour,
                    false => layer.over(&Pigment::opaque(sky.pigment.clone())).colour,
                };
            }
            Item::Transform(t) => sky.transforms.push(self.transform(t)?),
            Item::PovParam { key, value: Some(colour), .. } if key.name == "emission" => {
                sky.emission = self.pov_colour(colour)?.0;
            }
            _ => return Err(Self::misplaced(item, &Body::Sky(sky))),
        }
        Ok(())
    }
}

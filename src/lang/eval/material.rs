//! `material { ... }` and the texture nodes `diffuse` takes.

use std::sync::Arc;

use glam::Vec3;
use pest::iterators::Pair;

use super::{Evaluator, Source, resolve, string};
use crate::diagnostic::SceneError;
use crate::lang::parser::Rule;
use crate::lang::value::Value;
use crate::scene::graph::{MaterialDesc, Pattern, TextureNode};

impl Evaluator {
    pub(super) fn material(
        &self,
        src: &Source,
        pair: Pair<'_, Rule>,
        name: Option<&str>,
    ) -> Result<Arc<MaterialDesc>, SceneError> {
        let span = src.span(&pair);
        let mut items = pair.into_inner().skip(1).peekable();
        let base = match items.peek() {
            Some(p) if p.as_rule() == Rule::base_material => {
                let named = items.next().expect("peeked");
                Some(self.material_named(src, &named)?)
            }
            _ => None,
        };
        let mut items = items.peekable();
        if items.peek().is_none() && name.is_none() {
            if let Some(base) = base {
                return Ok(base); // `material { White }`: the declared material itself, shared
            }
        }
        let mut material = match base {
            Some(base) => MaterialDesc { name: None, span: span.clone(), ..(*base).clone() },
            None => MaterialDesc::new(span.clone()),
        };
        material.name = name.map(str::to_string);
        for item in items {
            let mut inner = item.into_inner();
            let key = inner.next().expect("key");
            let key_name = key.clone().into_inner().next().map_or(key.as_str(), |k| k.as_str());
            match key_name {
                "fresnel" => material.fresnel = true,
                "ior" => {
                    let expr = inner.next().expect("value");
                    material.ior = self.positive(src, expr, "ior")?;
                }
                "diffuse" => {
                    material.diffuse = self.texture_arg(src, inner.next().expect("value"))?;
                }
                _ => {
                    let colour = self.colour(src, inner.next().expect("value"))?;
                    match key_name {
                        "specular" => material.specular = colour,
                        "transmission" => material.transmission = colour,
                        _ => material.emission = colour,
                    }
                }
            }
        }
        let total = material.diffuse.max_value() + material.specular + material.transmission;
        if let Some(channel) = (0..3).find(|&c| total[c] > 1.0 + 1e-6) {
            let who = material
                .name
                .as_ref()
                .map_or("this material".to_string(), |n| format!("material `{n}`"));
            return Err(SceneError::at(
                &span,
                format!(
                    "{who} reflects more light than it receives: diffuse + specular + transmission = {} in the {} channel (at most 1)",
                    total[channel],
                    ["red", "green", "blue"][channel]
                ),
            ));
        }
        Ok(Arc::new(material))
    }

    /// A colour or a texture node, where `diffuse` takes one.
    pub(super) fn texture_arg(
        &self,
        src: &Source,
        pair: Pair<'_, Rule>,
    ) -> Result<TextureNode, SceneError> {
        let pair = match pair.as_rule() {
            Rule::texture_arg => pair.into_inner().next().expect("a texture or a colour"),
            _ => pair,
        };
        if pair.as_rule() == Rule::colour {
            // A declared texture's name reads as a colour expression.
            let value = pair.clone().into_inner().find(|p| p.as_rule() == Rule::expr);
            if let Some(Value::Texture(texture)) = value.map(|e| self.value(src, e)).transpose()? {
                return Ok((*texture).clone());
            }
            return Ok(TextureNode::solid(self.colour(src, pair)?));
        }
        let node = pair.into_inner().next().expect("one kind of texture");
        let kind = node.as_rule();
        let mut inner = node.into_inner().skip(1);
        let mut args = Vec::new();
        let mut transforms = Vec::new();
        let mut map = None;
        let (mut axis, mut octaves, mut turbulence) = (None, None, None);
        let mut path = None;
        for item in inner.by_ref() {
            match item.as_rule() {
                Rule::texture_arg => args.push(self.texture_arg(src, item)?),
                Rule::string => path = Some(resolve(&src.file.path, &string(&item))),
                Rule::transform => transforms.push(self.transform(src, item)?),
                Rule::color_map => {
                    let at = src.span(&item);
                    let takes_map =
                        matches!(kind, Rule::gradient | Rule::noise | Rule::marble | Rule::wood);
                    if !takes_map {
                        return Err(SceneError::at(
                            &at,
                            "`color_map` has no effect on this texture",
                        ));
                    }
                    let mut entries: Vec<(f32, Vec3)> = Vec::new();
                    for entry in item.into_inner().filter(|e| e.as_rule() == Rule::map_entry) {
                        let mut parts = entry.into_inner();
                        let position_pair = parts.next().expect("position");
                        let position_at = src.span(&position_pair);
                        let position = self.float(src, position_pair)? as f32;
                        let colour = self.colour(src, parts.next().expect("colour"))?;
                        let previous = entries.last().map_or(0.0, |e| e.0);
                        if !(previous..=1.0).contains(&position) {
                            return Err(SceneError::at(
                                &position_at,
                                format!(
                                    "color_map position {position} must be in [0, 1] and not below the one before"
                                ),
                            ));
                        }
                        entries.push((position, colour));
                    }
                    if map.replace(entries).is_some() {
                        return Err(SceneError::at(&at, "a second color_map"));
                    }
                }
                _ => {
                    let mut parts = item.into_inner();
                    let key = parts.next().expect("key");
                    let key_at = src.span(&key);
                    let value = parts.next().expect("value");
                    let applies = match key.as_str() {
                        "axis" => matches!(kind, Rule::stripes | Rule::gradient),
                        "octaves" => matches!(kind, Rule::noise | Rule::marble | Rule::wood),
                        _ => matches!(kind, Rule::marble | Rule::wood),
                    };
                    if !applies {
                        return Err(SceneError::at(
                            &key_at,
                            format!("`{}` has no effect on this texture", key.as_str()),
                        ));
                    }
                    match key.as_str() {
                        "axis" => axis = Some(self.nonzero(src, value, "the axis")?),
                        "octaves" => octaves = Some(self.integer(src, value, 1, 16)? as u32),
                        _ => {
                            let at = src.span(&value);
                            let t = self.float(src, value)? as f32;
                            if t < 0.0 {
                                return Err(SceneError::at(
                                    &at,
                                    format!("turbulence {t} is negative"),
                                ));
                            }
                            turbulence = Some(t);
                        }
                    }
                }
            }
        }
        // Black to white when no map is given.
        let map = map
            .filter(|m| !m.is_empty())
            .unwrap_or_else(|| vec![(0.0, Vec3::ZERO), (1.0, Vec3::ONE)]);
        let mut args = args.into_iter().map(Box::new);
        let mut arg = || args.next().expect("the grammar gives the arguments");
        let octaves = octaves.unwrap_or(4);
        let turbulence = turbulence.unwrap_or(0.0);
        let pattern = match kind {
            Rule::checker => Pattern::Checker(arg(), arg()),
            Rule::stripes => Pattern::Stripes { a: arg(), b: arg(), axis: axis.unwrap_or(Vec3::X) },
            Rule::gradient => Pattern::Gradient { axis: axis.unwrap_or(Vec3::Y), map },
            Rule::noise => Pattern::Noise { octaves, map },
            Rule::marble => Pattern::Marble { turbulence, octaves, map },
            Rule::wood => Pattern::Wood { turbulence, octaves, map },
            Rule::image_map => Pattern::Image { path: path.expect("the grammar gives a file") },
            _ => Pattern::Mix { a: arg(), b: arg(), t: arg() },
        };
        Ok(TextureNode { pattern, transforms })
    }

    pub(super) fn material_named(
        &self,
        src: &Source,
        pair: &Pair<'_, Rule>,
    ) -> Result<Arc<MaterialDesc>, SceneError> {
        let ident = pair.clone().into_inner().next().unwrap_or_else(|| pair.clone());
        match self.lookup(src, &ident)? {
            Value::Material(m) => Ok(m),
            other => Err(src.error(
                &ident,
                format!("`{}` is {}, not a material", ident.as_str(), other.kind()),
            )),
        }
    }
}

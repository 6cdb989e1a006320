//! POV-Ray's pigment (`.pov`): a colour and how much light passes through it at each point,
//! its filter (tinted by the colour) and transmit (not tinted), patterned as the colour is and
//! interpolated with it between a map's entries, as POV-Ray does.

use glam::Vec3;

use crate::graph::{FieldShape, Pattern, TextureMap, TextureNode, Transform, Warp};

/// A pigment: three textures of one pattern and transforms: the colour, the filter and
/// filter + transmit (grey). Kept as filter and filter + transmit so that layering and the
/// material make what they need of them exactly, by products (`Pattern::Mix`).
#[derive(Debug, Clone, PartialEq)]
pub struct Pigment {
    pub colour: TextureNode,
    pub filter: TextureNode,
    pub through: TextureNode,
}

/// A color_map's entry: its position and POV-Ray's colour there (filter and transmit are 0 in
/// `.scn`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stop {
    pub position: f32,
    pub colour: Vec3,
    pub filter: f32,
    pub transmit: f32,
}

impl Pigment {
    /// A plain colour with its filter and transmit.
    pub fn solid(colour: Vec3, filter: f32, transmit: f32) -> Pigment {
        Pigment {
            colour: TextureNode::solid(colour),
            filter: TextureNode::solid(Vec3::splat(filter)),
            through: TextureNode::solid(Vec3::splat(filter + transmit)),
        }
    }

    /// POV-Ray's default pigment.
    pub fn black() -> Pigment {
        Pigment::solid(Vec3::ZERO, 0.0, 0.0)
    }

    /// An opaque pigment of a texture's colours.
    pub fn opaque(colour: TextureNode) -> Pigment {
        Pigment { colour, ..Pigment::black() }
    }

    /// The pigment of a color_map's stop.
    pub fn of_stop(stop: &Stop) -> Pigment {
        Pigment::solid(stop.colour, stop.filter, stop.transmit)
    }

    /// Whether it lets no light through anywhere.
    pub fn is_opaque(&self) -> bool {
        self.through.max_value().max_element() <= 0.0
    }

    /// The most light it lets through anywhere (filter + transmit).
    pub fn most_through(&self) -> f32 {
        self.through.max_value().max_element().min(1.0)
    }

    /// Moves the pattern (all three textures alike).
    pub fn push_transform(&mut self, transform: Transform) {
        for node in [&mut self.colour, &mut self.filter, &mut self.through] {
            node.transforms.push(transform);
        }
    }

    pub fn set_transforms(&mut self, transforms: Vec<Transform>) {
        self.filter.transforms.clone_from(&transforms);
        self.through.transforms.clone_from(&transforms);
        self.colour.transforms = transforms;
    }

    /// The pigment evaluated where `warp` moves each point (all three textures alike); the
    /// transforms pushed after it apply before it, as POV-Ray's do.
    pub fn warped(self, warp: Warp) -> Pigment {
        let wrap = |node: TextureNode| match node.pattern {
            // A solid colour is the same anywhere (an opaque pigment's filter and through).
            Pattern::Solid(_) => node,
            _ => TextureNode {
                pattern: Pattern::Warped { warp, node: Box::new(node) },
                transforms: Vec::new(),
            },
        };
        Pigment {
            colour: wrap(self.colour),
            filter: wrap(self.filter),
            through: wrap(self.through),
        }
    }

    /// The pigment of a pattern through a map of pigments: `pattern` makes the pattern of a
    /// map of textures; the filter and through maps take the same pattern (solid 0 where every
    /// entry is opaque, so an opaque pigment costs nothing more at each hit).
    pub fn mapped(
        entries: Vec<(f32, Pigment)>,
        pattern: impl Fn(TextureMap) -> Pattern,
    ) -> Pigment {
        let opaque = entries.iter().all(|(_, p)| p.is_opaque());
        let part = |part: fn(&Pigment) -> &TextureNode| -> TextureMap {
            entries.iter().map(|(t, p)| (*t, part(p).clone())).collect()
        };
        let node = |pattern| TextureNode { pattern, transforms: Vec::new() };
        let colour = node(pattern(part(|p| &p.colour)));
        if opaque {
            return Pigment::opaque(colour);
        }
        Pigment {
            colour,
            filter: node(pattern(part(|p| &p.filter))),
            through: node(pattern(part(|p| &p.through))),
        }
    }

    /// This pigment's pattern through a new map (POV-Ray's `pigment { P_Declared pigment_map
    /// { ... } }`): the pattern, its warps and the transforms around each kept; `None` where it
    /// is not a pattern through a map (a plain colour, an image, an average).
    pub fn remapped(&self, entries: Vec<(f32, Pigment)>) -> Option<Pigment> {
        // The warps from the outside in, each with the transforms around it.
        let mut warps = Vec::new();
        let mut node = &self.colour;
        while let Pattern::Warped { warp, node: inner } = &node.pattern {
            warps.push((*warp, node.transforms.clone()));
            node = inner;
        }
        let Pattern::Field { shape, .. } = &node.pattern else { return None };
        let mut pigment =
            Pigment::mapped(entries, |map| Pattern::Field { shape: shape.clone(), map });
        pigment.set_transforms(node.transforms.clone());
        for (warp, transforms) in warps.into_iter().rev() {
            pigment = pigment.warped(warp);
            pigment.set_transforms(transforms);
        }
        Some(pigment)
    }

    /// The shape of this pigment's pattern where it is a pattern through a map, not warped
    /// after it is made (a `pigment { P_Declared warp { } }`).
    pub fn pattern_shape(&self) -> Option<&FieldShape> {
        match &self.colour.pattern {
            Pattern::Field { shape, .. } => Some(shape),
            _ => None,
        }
    }

    /// This pattern through a map with its shape replaced (a new pattern word over it), its map
    /// and transforms kept.
    pub fn reshaped(mut self, shape: &FieldShape) -> Pigment {
        for node in [&mut self.colour, &mut self.filter, &mut self.through] {
            if let Pattern::Field { shape: own, .. } = &mut node.pattern {
                **own = shape.clone();
            }
        }
        self
    }

    /// This pigment over `under` (POV-Ray's layered textures): where this one lets light
    /// through (filter + transmit), the one under it shows; their light through multiplies.
    /// The filter's tint of the layer under it is not kept (the colours mix).
    pub fn over(&self, under: &Pigment) -> Pigment {
        let product = |a: &TextureNode, b: &TextureNode| mix(&solid(0.0), a, b);
        Pigment {
            // under × through + this × (1 - through).
            colour: mix(&self.colour, &under.colour, &self.through),
            filter: product(&under.filter, &self.through),
            through: product(&under.through, &self.through),
        }
    }
}

fn solid(v: f32) -> TextureNode {
    TextureNode::solid(Vec3::splat(v))
}

/// a (1 - t) + b t, t grey (as `Pattern::Mix` reads it); a colour where all three are one, so
/// that plain pigments stay plain.
fn mix(a: &TextureNode, b: &TextureNode, t: &TextureNode) -> TextureNode {
    if let (Pattern::Solid(a), Pattern::Solid(b), Pattern::Solid(t)) =
        (&a.pattern, &b.pattern, &t.pattern)
    {
        let t = t.dot(Vec3::splat(1.0 / 3.0)).clamp(0.0, 1.0);
        return TextureNode::solid(*a * (1.0 - t) + *b * t);
    }
    let pattern =
        Pattern::Mix { a: Box::new(a.clone()), b: Box::new(b.clone()), t: Box::new(t.clone()) };
    TextureNode { pattern, transforms: Vec::new() }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::texture::Texture;

    fn at(node: &TextureNode, p: Vec3) -> Vec3 {
        Texture::new(node, &mut |_| unreachable!("no image")).unwrap().eval(p)
    }

    /// Layers: the top's colour where it is opaque, the bottom's where it is clear, and the
    /// light through multiplies, point by point.
    #[test]
    fn a_layer_shows_the_one_under_it_where_it_lets_light_through() {
        let stripes = |a: Pigment, b: Pigment| {
            Pigment::mapped(vec![(0.0, a), (1.0, b)], |map| Pattern::Stripes {
                a: Box::new(map[0].1.clone()),
                b: Box::new(map[1].1.clone()),
                axis: Vec3::X,
            })
        };
        let top = stripes(Pigment::solid(Vec3::X, 0.0, 0.0), Pigment::solid(Vec3::ONE, 0.0, 1.0));
        let under = Pigment::solid(Vec3::Z, 0.5, 0.25);
        let layered = top.over(&under);
        let (opaque, clear) = (Vec3::new(0.5, 0.0, 0.0), Vec3::new(1.5, 0.0, 0.0));
        assert_eq!(at(&layered.colour, opaque), Vec3::X);
        assert_eq!(at(&layered.colour, clear), Vec3::Z);
        assert_eq!(at(&layered.through, opaque), Vec3::ZERO);
        assert_eq!(at(&layered.through, clear), Vec3::splat(0.75));
        assert_eq!(at(&layered.filter, clear), Vec3::splat(0.5));
        assert!(!layered.is_opaque() && top.over(&Pigment::black()).most_through() == 0.0);
    }
}

//! Media as the scene gives them: `.scn`'s `medium { }` (in a material) and `atmosphere { }`,
//! POV-Ray's `interior { ior fade_distance fade_power fade_color media }`, `media { }` and
//! `fog { }` (`docs/language.md`, Media; `docs/povray.md`, Interiors, media and fog).

use std::sync::Arc;

use glam::Vec3;

use super::Evaluator;
use crate::diagnostic::{SceneError, Span};
use crate::graph::{GroundDesc, MediumDesc};
use crate::lang::syntax::{Colour, Item};
use crate::lang::value::Value;

/// POV-Ray's `interior { }`: the index of refraction, and what fills the object.
#[derive(Debug, Clone, PartialEq)]
pub struct Interior {
    pub ior: f32,
    /// `fade_distance` (0: no fade) and `fade_color`.
    pub fade_distance: f32,
    pub fade_colour: Vec3,
    /// Its `media { }`, summed.
    pub media: Option<MediumDesc>,
    pub span: Option<Span>,
}

impl Default for Interior {
    fn default() -> Self {
        Interior { ior: 1.0, fade_distance: 0.0, fade_colour: Vec3::ZERO, media: None, span: None }
    }
}

impl Interior {
    /// The medium inside: the fade as Beer–Lambert absorption, sigma_a = (1 - fade_color) /
    /// fade_distance (light crossing fade_distance keeps exp(-1) of what fade_color does not
    /// keep), with the media's coefficients added.
    pub fn medium(&self) -> Option<Arc<MediumDesc>> {
        let span = self.span.clone()?;
        let fade = (self.fade_distance > 0.0).then(|| MediumDesc {
            absorption: (Vec3::ONE - self.fade_colour.min(Vec3::ONE)) / self.fade_distance,
            scattering: Vec3::ZERO,
            emission: Vec3::ZERO,
            anisotropy: 0.0,
            ground: None,
            span,
        });
        let medium = match (fade, &self.media) {
            // POV-Ray's media are even (ground fog is a fog's): they add to the fade.
            (Some(fade), Some(media)) => together(&fade, media),
            (Some(only), None) => only,
            (None, Some(only)) => only.clone(),
            (None, None) => return None,
        };
        Some(Arc::new(medium))
    }
}

/// Two media filling the same space: their coefficients add; the phase function is the one
/// whose g is the mean of theirs weighted by how much each scatters. Their densities must be
/// the same: a ground fog adds only to ground fog of the same layer.
fn together_checked(a: &MediumDesc, b: &MediumDesc) -> Result<MediumDesc, SceneError> {
    if a.ground != b.ground {
        return Err(SceneError::at(
            &b.span,
            "this medium fills the same space as a ground fog of another layer (or as an even \
             one): media of different densities cannot be combined yet",
        ));
    }
    Ok(MediumDesc { ground: a.ground, ..together(a, b) })
}

/// `together_checked` for media of the same density.
fn together(a: &MediumDesc, b: &MediumDesc) -> MediumDesc {
    let (sa, sb) = (a.scattering.element_sum(), b.scattering.element_sum());
    let anisotropy =
        if sa + sb > 0.0 { (a.anisotropy * sa + b.anisotropy * sb) / (sa + sb) } else { 0.0 };
    MediumDesc {
        absorption: a.absorption + b.absorption,
        scattering: a.scattering + b.scattering,
        emission: a.emission + b.emission,
        anisotropy,
        ground: a.ground,
        span: a.span.clone(),
    }
}

/// Henyey–Greenstein g with the mean cosine of POV-Ray's Mie phase functions (`scattering`
/// types 2 and 3): its (0.5 + 4.5 x^8) and (0.5 + 16.5 x^32), x = (1 + cos) / 2, have mean
/// cosines 2/5 and 8/17.
const MIE_HAZY_G: f32 = 0.4;
const MIE_MURKY_G: f32 = 8.0 / 17.0;

impl Evaluator {
    /// `medium { absorption C scattering C emission C anisotropy g }`, or the atmosphere's.
    pub(super) fn medium(&mut self, items: &[Item], span: &Span) -> Result<MediumDesc, SceneError> {
        let mut medium = self.empty_medium(span);
        for item in items {
            if let Item::PovParam { key, value: Some(up), items } = item
                && key.name == "ground"
            {
                let [Item::Value(offset), Item::Value(falloff)] = &items[..] else {
                    unreachable!("the grammar gives ground its three values")
                };
                let up = self.nonzero(&up.value, "ground's up")?.normalize();
                let offset = super::expression::single(self.float(offset)?, &offset.span)?;
                let falloff = self.positive(falloff, "ground's falloff")?;
                medium.ground = Some(GroundDesc { up, offset, falloff });
                continue;
            }
            let (key, value) = self.keyed(item, "in a medium")?;
            match key {
                "absorption" => medium.absorption = self.colour(value)?,
                "scattering" => medium.scattering = self.colour(value)?,
                "emission" => medium.emission = self.colour(value)?,
                "anisotropy" => medium.anisotropy = self.anisotropy(value)?,
                other => unreachable!("the grammar gives a medium no `{other}`"),
            }
        }
        Ok(medium)
    }

    /// `atmosphere { }`, POV-Ray's `fog { }` or scene-wide `media { }`: added to what fills
    /// the scene already. An atmosphere that emits where it extinguishes nothing would glow
    /// without end along rays that leave the scene.
    pub(super) fn add_atmosphere(&mut self, medium: MediumDesc) -> Result<(), SceneError> {
        let sum = match &self.atmosphere {
            Some(before) => together_checked(before, &medium)?,
            None => medium,
        };
        let sigma = sum.absorption + sum.scattering;
        if (0..3).any(|c| sum.emission[c] > 0.0 && sigma[c] <= 0.0) {
            return Err(SceneError::at(
                &sum.span,
                "a medium filling the scene that emits must absorb or scatter in the same \
                 channels (`absorption` or `scattering`), or rays that leave the scene would \
                 gather its emission without end",
            ));
        }
        self.atmosphere = Some(sum);
        Ok(())
    }

    /// POV-Ray's `fog { distance D color C }`: light fades to C as exp(-d / D), as it does
    /// through a medium that absorbs 1 / D and emits C / D per unit length (`docs/povray.md`).
    pub(super) fn pov_fog(&mut self, items: &[Item], span: &Span) -> Result<(), SceneError> {
        let mut distance = None;
        let mut colour = Vec3::ZERO;
        let (mut ground, mut offset, mut alt, mut up) = (false, 0.0, 1.0, Vec3::Y);
        for item in items {
            match item {
                Item::Value(expr) => {
                    let value = self.value(expr)?;
                    let (rgb, _, transmit) = super::appearance::pov_colour(value, &expr.span)?;
                    colour = rgb;
                    if transmit > 0.0 {
                        self.warn(
                            &expr.span,
                            "a fog's transmit is not rendered: it fades to \
                                               its colour alone",
                        );
                    }
                }
                Item::Transform(_) => {}
                _ => {
                    let (key, value) = self.keyed(item, "in a fog")?;
                    match key {
                        "distance" => distance = Some(self.positive(&value.value, "distance")?),
                        "fog_type" => {
                            ground = match self.number(&value.value, "`fog_type`")? {
                                1.0 => false,
                                2.0 => true,
                                other => {
                                    return Err(SceneError::at(
                                        &value.span,
                                        format!(
                                            "fog_type {other}: POV-Ray's fog types are 1 \
                                             (constant) and 2 (ground fog)"
                                        ),
                                    ));
                                }
                            }
                        }
                        "fog_offset" => {
                            offset =
                                super::expression::single(self.float(&value.value)?, &value.span)?
                        }
                        "fog_alt" => alt = self.positive(&value.value, "fog_alt")?,
                        "up" => up = self.nonzero(&value.value, "the fog's up")?.normalize(),
                        "turbulence" | "octaves" | "turb_depth" | "omega" | "lambda" => {
                            self.warn(&value.span, "a fog's turbulence is not rendered")
                        }
                        other => unreachable!("the grammar gives a fog no `{other}`"),
                    }
                }
            }
        }
        let Some(distance) = distance else {
            return Err(SceneError::at(
                span,
                "a fog needs its `distance` (over which it thickens)",
            ));
        };
        let mut fog = self.empty_medium(span);
        fog.absorption = Vec3::splat(1.0 / distance);
        fog.emission = colour / distance;
        fog.ground = ground.then_some(GroundDesc { up, offset, falloff: alt });
        self.add_atmosphere(fog)
    }

    /// POV-Ray's `media { absorption C emission C scattering { type, C eccentricity e } }`.
    pub(super) fn pov_media(
        &mut self,
        items: &[Item],
        span: &Span,
    ) -> Result<MediumDesc, SceneError> {
        let mut medium = self.empty_medium(span);
        for item in items {
            match item {
                // A declared media, the items after it added to it.
                Item::Value(expr) => match self.value(expr)? {
                    Value::Media(declared) => medium = together_checked(&medium, &declared)?,
                    other => {
                        return Err(SceneError::at(
                            &expr.span,
                            format!("a media names a declared media, not {}", other.kind()),
                        ));
                    }
                },
                Item::Transform(_) => {} // a homogeneous medium is the same moved
                Item::PovParam { key, value, items } => match key.name.as_str() {
                    "absorption" => medium.absorption = self.pov_rgb(value, &key.span)?,
                    "emission" => medium.emission = self.pov_rgb(value, &key.span)?,
                    "scattering" => self.scattering(value, items, &mut medium, &key.span)?,
                    "density" => self.warn(
                        &key.span,
                        "a media's `density` is not rendered: \
                                                       the medium is homogeneous",
                    ),
                    // How POV-Ray samples its media; here sampling is unbiased.
                    "method" | "intervals" | "samples" | "confidence" | "variance" | "ratio"
                    | "jitter" | "aa_threshold" | "aa_level" => {}
                    other => unreachable!("the grammar gives a media no `{other}`"),
                },
                _ => return Err(Self::misplaced(item, &super::Body::Scene)),
            }
        }
        Ok(medium)
    }

    /// `scattering { type, C [eccentricity e] [extinction x] }`.
    fn scattering(
        &mut self,
        kind: &Option<Colour>,
        items: &[Item],
        medium: &mut MediumDesc,
        at: &Span,
    ) -> Result<(), SceneError> {
        let kind_expr = &kind.as_ref().expect("the grammar gives a scattering type").value;
        let kind = self.number(kind_expr, "the scattering type")?;
        let mut eccentricity = 0.0;
        for item in items {
            let (key, value) = self.keyed(item, "in a scattering")?;
            match key {
                "colour" => medium.scattering = self.pov_rgb(&Some(value.clone()), at)?,
                "eccentricity" => eccentricity = self.anisotropy(value)?,
                "extinction" => {
                    if self.number(&value.value, "`extinction`")? != 1.0 {
                        self.warn(
                            &value.span,
                            "`extinction` is not honoured: scattering \
                                                dims light as much as it scatters",
                        );
                    }
                }
                other => unreachable!("the grammar gives a scattering no `{other}`"),
            }
        }
        medium.anisotropy = match kind {
            1.0 => 0.0,
            2.0 | 3.0 | 4.0 => {
                let (name, g) = match kind as u32 {
                    2 => ("Mie hazy", MIE_HAZY_G),
                    3 => ("Mie murky", MIE_MURKY_G),
                    _ => ("Rayleigh", 0.0),
                };
                self.warn(
                    &kind_expr.span,
                    &format!(
                        "{name} scattering is rendered with the Henyey–Greenstein phase \
                         function of the same mean cosine (g = {g:.2})"
                    ),
                );
                g
            }
            5.0 => eccentricity,
            other => {
                return Err(SceneError::at(
                    &kind_expr.span,
                    format!(
                        "scattering type {other}: POV-Ray's types are 1 (isotropic), 2 (Mie \
                         hazy), 3 (Mie murky), 4 (Rayleigh) and 5 (Henyey–Greenstein)"
                    ),
                ));
            }
        };
        Ok(())
    }

    /// POV-Ray's `interior { }` item into `interior`.
    pub(super) fn interior_item(
        &mut self,
        item: &Item,
        interior: &mut Interior,
    ) -> Result<(), SceneError> {
        match item {
            Item::PovParam { key, items, .. } if key.name == "media" => {
                let media = self.pov_media(items, &key.span)?;
                interior.media = Some(match &interior.media {
                    Some(before) => together_checked(before, &media)?,
                    None => media,
                });
                interior.span.get_or_insert_with(|| self.here(&key.span));
            }
            Item::PovParam { key, value: Some(v), .. } => match key.name.as_str() {
                "ior" => interior.ior = self.positive(&v.value, "ior")?,
                "fade_distance" => {
                    interior.fade_distance = self.positive(&v.value, "fade_distance")?;
                    interior.span.get_or_insert_with(|| self.here(&key.span));
                }
                "fade_power" => {
                    self.warn(
                        &key.span,
                        "`fade_power` is not honoured: the fade is Beer–Lambert's \
                                          exponential absorption (`docs/povray.md`)",
                    );
                }
                "fade_color" | "fade_colour" => {
                    let value = self.value(&v.value)?;
                    interior.fade_colour = super::appearance::pov_colour(value, &v.span)?.0;
                }
                "dispersion" => self.warn(
                    &key.span,
                    "`dispersion` is not rendered: one index \
                                                      of refraction serves every colour",
                ),
                "dispersion_samples" | "caustics" => {}
                other => unreachable!("the grammar gives an interior no `{other}`"),
            },
            Item::Value(expr) => match self.value(expr)? {
                Value::Interior(declared) => *interior = (*declared).clone(),
                other => {
                    return Err(SceneError::at(
                        &expr.span,
                        format!("an interior names a declared interior, not {}", other.kind()),
                    ));
                }
            },
            _ => return Err(Self::misplaced(item, &super::Body::Interior(interior))),
        }
        Ok(())
    }

    fn empty_medium(&self, span: &Span) -> MediumDesc {
        MediumDesc {
            absorption: Vec3::ZERO,
            scattering: Vec3::ZERO,
            emission: Vec3::ZERO,
            anisotropy: 0.0,
            ground: None,
            span: self.here(span),
        }
    }

    /// A keyed item's key and value.
    fn keyed<'i>(&self, item: &'i Item, place: &str) -> Result<(&'i str, &'i Colour), SceneError> {
        match item {
            Item::PovParam { key, value: Some(value), .. } => Ok((key.name.as_str(), value)),
            _ => Err(SceneError::at(
                item.span(),
                format!("{} cannot stand {place}", item.describe()),
            )),
        }
    }

    /// A POV-Ray colour's red, green and blue.
    fn pov_rgb(&mut self, colour: &Option<Colour>, at: &Span) -> Result<Vec3, SceneError> {
        let Some(colour) = colour else {
            return Err(SceneError::at(at, "expected a colour"));
        };
        let value = self.value(&colour.value)?;
        Ok(super::appearance::pov_colour(value, &colour.span)?.0)
    }

    /// Henyey–Greenstein's g: in (-1, 1).
    fn anisotropy(&mut self, value: &Colour) -> Result<f32, SceneError> {
        let g = self.number(&value.value, "the anisotropy")?;
        if !(g > -1.0 && g < 1.0) {
            return Err(SceneError::at(
                &value.span,
                format!("anisotropy {g} is outside (-1, 1): -1 and 1 would scatter along one line"),
            ));
        }
        Ok(g as f32)
    }

    fn warn(&mut self, span: &Span, message: &str) {
        let at = self.here(span);
        self.warnings.push(format!("{at:?}: warning: {message}"));
    }
}

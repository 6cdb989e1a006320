//! Tone mapping: linear HDR values to 8-bit display values, as `docs/tonemapping.md` states. Pure
//! functions over an `Image`; exposure first, then normalisation, clamping, the curve, and
//! quantisation round(255 c').

use std::fmt;
use std::str::FromStr;

use glam::Vec3;

use crate::image::Image;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Operator {
    /// min(c, 1)
    Clamp,
    /// c / M
    Equalize,
    /// min(c, V) / V
    EqualizeClamp,
    /// (c / M)^(1/gamma)
    Gamma,
    /// (min(c, V) / V)^(1/gamma)
    ClampGamma,
    /// Reinhard et al. 2002, global operator on luminance.
    Reinhard,
    /// Narkowicz's fit of the ACES filmic curve, then the sRGB transfer function.
    Aces,
}

impl Operator {
    pub const ALL: [Operator; 7] = [
        Operator::Clamp,
        Operator::Equalize,
        Operator::EqualizeClamp,
        Operator::Gamma,
        Operator::ClampGamma,
        Operator::Reinhard,
        Operator::Aces,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Operator::Clamp => "clamp",
            Operator::Equalize => "equalize",
            Operator::EqualizeClamp => "equalize-clamp",
            Operator::Gamma => "gamma",
            Operator::ClampGamma => "clamp-gamma",
            Operator::Reinhard => "reinhard",
            Operator::Aces => "aces",
        }
    }
}

impl fmt::Display for Operator {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Operator {
    type Err = ToneMapError;

    fn from_str(s: &str) -> Result<Self, ToneMapError> {
        Operator::ALL
            .into_iter()
            .find(|op| op.name() == s)
            .ok_or_else(|| ToneMapError::Operator { name: s.to_string() })
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct ToneMap {
    pub op: Operator,
    /// Threshold V of the clamping operators.
    pub v: f32,
    pub gamma: f32,
    /// Exposure in stops: values are multiplied by 2^exposure first.
    pub exposure: f32,
    /// Reinhard's white luminance (default: the largest scaled luminance).
    pub white: Option<f32>,
}

impl Default for ToneMap {
    fn default() -> Self {
        ToneMap { op: Operator::ClampGamma, v: 1.0, gamma: 2.2, exposure: 0.0, white: None }
    }
}

impl ToneMap {
    /// The parameters the operator uses, as `v 1, gamma 2.2, exposure 0`.
    pub fn used(&self) -> String {
        let mut used = match self.op {
            Operator::Clamp | Operator::Equalize | Operator::Aces => Vec::new(),
            Operator::EqualizeClamp => vec![format!("v {}", self.v)],
            Operator::Gamma => vec![format!("gamma {}", self.gamma)],
            Operator::ClampGamma => vec![format!("v {}", self.v), format!("gamma {}", self.gamma)],
            Operator::Reinhard => match self.white {
                Some(white) => vec![format!("white {white}")],
                None => vec!["white: the largest luminance".to_string()],
            },
        };
        used.push(format!("exposure {}", self.exposure));
        used.join(", ")
    }

    /// Checks the parameters; the message names the bad value.
    pub fn validate(&self) -> Result<(), ToneMapError> {
        if !(self.v.is_finite() && self.v > 0.0) {
            return Err(ToneMapError::V(self.v));
        }
        if !(self.gamma.is_finite() && self.gamma > 0.0) {
            return Err(ToneMapError::Gamma(self.gamma));
        }
        if !self.exposure.is_finite() {
            return Err(ToneMapError::Exposure(self.exposure));
        }
        if let Some(w) = self.white.filter(|w| !(w.is_finite() && *w > 0.0)) {
            return Err(ToneMapError::White(w));
        }
        Ok(())
    }
}

/// A tone-mapping operator unknown, or a parameter out of its range.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ToneMapError {
    #[error(
        "unknown operator `{name}` (expected one of {})",
        Operator::ALL.map(Operator::name).join(", ")
    )]
    Operator { name: String },
    #[error("--v {0} must be a positive number")]
    V(f32),
    #[error("--gamma {0} must be a positive number")]
    Gamma(f32),
    #[error("--exposure {0} must be a finite number")]
    Exposure(f32),
    #[error("--white {0} must be a positive number")]
    White(f32),
}

/// Display values in [0, 1] per pixel. Components that are not finite take no part in the
/// image's statistics: +inf stands for the largest finite component, NaN and -inf for 0.
pub fn tonemap(image: &Image, params: &ToneMap) -> Vec<Vec3> {
    let scale = params.exposure.exp2();
    let finite = |c: f32| if c.is_finite() { c * scale } else { 0.0 };
    let largest_finite =
        image.pixels.iter().map(|p| p.map(finite).max_element()).fold(0.0, f32::max);
    let exposed: Vec<Vec3> = image
        .pixels
        .iter()
        .map(|p| p.map(|c| if c == f32::INFINITY { largest_finite } else { finite(c) }))
        .map(|p| p.max(Vec3::ZERO))
        .collect();
    let largest = exposed.iter().map(|p| p.max_element()).fold(0.0, f32::max);
    // Dividing by the largest component of an all-black image: leave it black.
    let m = if largest > 0.0 { largest } else { 1.0 };
    let inverse_gamma = 1.0 / params.gamma;
    let unit = |c: Vec3| c.clamp(Vec3::ZERO, Vec3::ONE);
    match params.op {
        Operator::Clamp => exposed.iter().map(|&c| unit(c)).collect(),
        Operator::Equalize => exposed.iter().map(|&c| unit(c / m)).collect(),
        Operator::EqualizeClamp => {
            exposed.iter().map(|&c| unit(c.min(Vec3::splat(params.v)) / params.v)).collect()
        }
        Operator::Gamma => exposed.iter().map(|&c| unit(c / m).powf(inverse_gamma)).collect(),
        Operator::ClampGamma => exposed
            .iter()
            .map(|&c| unit(c.min(Vec3::splat(params.v)) / params.v).powf(inverse_gamma))
            .collect(),
        Operator::Reinhard => reinhard(&exposed, params.white),
        Operator::Aces => exposed.iter().map(|&c| unit(aces(c)).map(srgb_transfer)).collect(),
    }
}

/// How many pixels have a component that is not finite (`tonemap` clamps them).
pub fn non_finite_pixels(image: &Image) -> usize {
    image.pixels.iter().filter(|p| !p.is_finite()).count()
}

/// round(255 c') per channel.
pub fn quantise(display: &[Vec3]) -> Vec<[u8; 3]> {
    display
        .iter()
        .map(|c| c.to_array().map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as u8))
        .collect()
}

/// Luminance of linear sRGB/Rec. 709 primaries (ITU-R BT.709 weights).
pub fn luminance(c: Vec3) -> f32 {
    c.dot(Vec3::new(0.2126, 0.7152, 0.0722))
}

/// A warning when `image` would show black or nearly so with the default operator (PNG output):
/// 99 % of its pixels below 4 % of white once tone-mapped, with how dark and what to try.
pub fn darkness_warning(image: &Image) -> Option<String> {
    // (10/255)^2.2: the default operator shows this luminance as 10 of 255.
    const DARK: f32 = 8.0e-4;
    let mut luminances: Vec<f32> =
        image.pixels.iter().map(|&c| luminance(c)).filter(|l| l.is_finite()).collect();
    let brightest = luminances.iter().copied().fold(0.0, f32::max);
    if brightest <= 0.0 {
        return Some(
            "warning: the image is black: every pixel is 0. Objects without a `material` are \
             black (its parameters default to 0); is every light blocked, or facing away; is the \
             camera inside an object?"
                .to_string(),
        );
    }
    let rank = luminances.len() * 99 / 100;
    let (_, &mut percentile, _) = luminances.select_nth_unstable_by(rank, f32::total_cmp);
    (percentile < DARK).then(|| {
        format!(
            "warning: the image is almost black: 99% of its pixels have luminance below \
             {percentile:.2e} (the brightest {brightest:.2e}), under 4% of white once tone-mapped. \
             If the lights are too weak for the scene's size (a light_source's power falls off as \
             1/r²: at distance 10 it needs 100 times the power that lights a surface at distance \
             1), raise their power; or brighten the image: `raydiance tonemap OUT.exr -o OUT.png \
             --exposure 6`"
        )
    })
}

/// Reinhard's global operator: L = 0.18 / Lavg * Lw with Lavg the log-average luminance,
/// Ld = L (1 + L / Lwhite^2) / (1 + L), colour scaled by Ld / Lw, then clamped.
fn reinhard(pixels: &[Vec3], white: Option<f32>) -> Vec<Vec3> {
    let n = pixels.len().max(1) as f64;
    let log_sum: f64 = pixels.iter().map(|&c| f64::from(1e-6 + luminance(c)).ln()).sum();
    let log_average = (log_sum / n).exp() as f32;
    let key = 0.18 / log_average;
    let largest = pixels.iter().map(|&c| key * luminance(c)).fold(0.0, f32::max);
    let white = white.unwrap_or(largest);
    let white2 = if white > 0.0 { white * white } else { f32::INFINITY };
    pixels
        .iter()
        .map(|&c| {
            let lw = luminance(c);
            if lw <= 0.0 {
                return Vec3::ZERO;
            }
            let l = key * lw;
            let ld = l * (1.0 + l / white2) / (1.0 + l);
            (c * (ld / lw)).clamp(Vec3::ZERO, Vec3::ONE)
        })
        .collect()
}

/// Narkowicz 2015, "ACES Filmic Tone Mapping Curve".
fn aces(x: Vec3) -> Vec3 {
    let (a, b, c, d, e) = (2.51, 0.03, 2.43, 0.59, 0.14);
    (x * (a * x + b)) / (x * (c * x + d) + e)
}

/// The sRGB transfer function (IEC 61966-2-1) from linear to encoded values.
pub fn srgb_transfer(c: f32) -> f32 {
    if c <= 0.003_130_8 { 12.92 * c } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tiny() -> Image {
        Image { width: 2, height: 1, pixels: vec![Vec3::new(4.5, 0.0, 0.0), Vec3::splat(0.9)] }
    }

    fn bytes(op: Operator, v: f32) -> Vec<[u8; 3]> {
        quantise(&tonemap(&tiny(), &ToneMap { op, v, ..ToneMap::default() }))
    }

    #[test]
    fn the_spec_example_maps_to_the_listed_values() {
        assert_eq!(bytes(Operator::Clamp, 1.0), [[255, 0, 0], [230, 230, 230]]);
        assert_eq!(bytes(Operator::Equalize, 1.0), [[255, 0, 0], [51, 51, 51]]);
        assert_eq!(bytes(Operator::EqualizeClamp, 2.0), [[255, 0, 0], [115, 115, 115]]);
        assert_eq!(bytes(Operator::Gamma, 1.0), [[255, 0, 0], [123, 123, 123]]);
        assert_eq!(bytes(Operator::ClampGamma, 1.0), [[255, 0, 0], [243, 243, 243]]);
    }

    #[test]
    fn exposure_doubles_before_the_curve() {
        let image = Image { width: 1, height: 1, pixels: vec![Vec3::splat(0.25)] };
        let at = |exposure| {
            tonemap(&image, &ToneMap { op: Operator::Clamp, exposure, ..ToneMap::default() })[0]
        };
        assert_eq!(at(1.0), Vec3::splat(0.5));
        assert_eq!(at(-1.0), Vec3::splat(0.125));
    }

    #[test]
    fn filmic_operators_are_monotonic_and_bounded() {
        let ramp: Vec<Vec3> = (0..200).map(|i| Vec3::splat(i as f32 * 0.05)).collect();
        let image = Image { width: ramp.len(), height: 1, pixels: ramp };
        for op in [Operator::Reinhard, Operator::Aces] {
            let out = tonemap(&image, &ToneMap { op, ..ToneMap::default() });
            assert!(out.windows(2).all(|w| w[1].x >= w[0].x), "{op} is monotonic");
            assert!(
                out.iter()
                    .all(|c| c.is_finite() && c.min_element() >= 0.0 && c.max_element() <= 1.0)
            );
            assert_eq!(out[0], Vec3::ZERO, "{op}: black stays black");
        }
        // With the default white point the brightest pixel maps to exactly 1 (Reinhard 2002, eq. 4).
        let out = tonemap(&image, &ToneMap { op: Operator::Reinhard, ..ToneMap::default() });
        assert!((out[199].x - 1.0).abs() < 1e-5);
    }

    #[test]
    fn operator_names_round_trip() {
        for op in Operator::ALL {
            assert_eq!(op.name().parse::<Operator>(), Ok(op));
        }
        let unknown = "filmic".parse::<Operator>().unwrap_err();
        assert_eq!(unknown, ToneMapError::Operator { name: "filmic".into() });
        assert!(unknown.to_string().contains("expected one of clamp"));
    }
}

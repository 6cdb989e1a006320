//! AOVs (arbitrary output variables): what the camera sees at the first surface with a lobe
//! that has a density, the delta lobes of perfect mirrors and smooth glass followed on the way
//! (what a denoiser needs: the wall seen in a mirror, not the mirror). Written beside the
//! beauty as extra EXR channels, named as Mitsuba's `aov` integrator names them when each AOV
//! is named after its type: `albedo.R`, `normal.X`, `depth.T`, `position.X`, ...
//!
//! They are taken from the beauty's own camera samples (`camera_sample`: the same positions in
//! the pixel and on the lens, the same share of a split render) and averaged with the film's
//! weights (each sample of a pixel counts alike), so a pixel's AOV is filtered as its beauty is.

use std::fmt;
use std::str::FromStr;

use glam::Vec3;
use rayon::prelude::*;

use crate::geometry::offset_origin;
use crate::material::{LobeFlags, TransportMode};
use crate::ray::Ray;
use crate::region::Region;
use crate::sampling::Sampler;
use crate::scene::{Scene, camera_samples};

/// Bytes a pixel takes for each channel of AOVs while rendering: its row's value, then its
/// plane's.
pub const BYTES_PER_CHANNEL: u64 = 4 + 4;

/// One output variable.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Aov {
    /// The directional albedo of the surface's lobes with a density, estimated by sampling
    /// them (exactly `diffuse` on a Lambertian surface), plus the radiance the surface emits
    /// towards the camera, each channel at most 1 (a light is its colour, as renderers give
    /// emitters to denoisers); black where nothing is hit.
    Albedo,
    /// The unit shading normal, world space, in the shape's own orientation (outwards for
    /// closed solids).
    Normal,
    /// The distance the camera ray travelled to the surface, through the mirrors and glass on
    /// the way; 0 where nothing is hit.
    Depth,
    /// The surface point, world space; 0 where nothing is hit.
    Position,
}

impl Aov {
    pub const ALL: [Aov; 4] = [Aov::Albedo, Aov::Normal, Aov::Depth, Aov::Position];

    pub fn name(self) -> &'static str {
        match self {
            Aov::Albedo => "albedo",
            Aov::Normal => "normal",
            Aov::Depth => "depth",
            Aov::Position => "position",
        }
    }

    /// Its EXR channels, with Mitsuba's suffixes.
    pub fn channels(self) -> &'static [&'static str] {
        match self {
            Aov::Albedo => &["albedo.R", "albedo.G", "albedo.B"],
            Aov::Normal => &["normal.X", "normal.Y", "normal.Z"],
            Aov::Depth => &["depth.T"],
            Aov::Position => &["position.X", "position.Y", "position.Z"],
        }
    }

    /// Its value seen by one camera sample, channel by channel.
    fn values(self, seen: &Seen) -> &[f32] {
        match self {
            Aov::Albedo => seen.albedo.as_ref(),
            Aov::Normal => seen.normal.as_ref(),
            Aov::Depth => std::slice::from_ref(&seen.depth),
            Aov::Position => seen.position.as_ref(),
        }
    }
}

/// The AOVs asked for, a set: each once, in the order of `Aov::ALL` (the order of their
/// channels in a file, whatever the order they were asked in).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct AovList(u8);

impl AovList {
    pub fn new(aovs: impl IntoIterator<Item = Aov>) -> AovList {
        AovList(aovs.into_iter().fold(0, |set, aov| set | AovList::bit(aov)))
    }

    fn bit(aov: Aov) -> u8 {
        1 << aov as u8
    }

    pub fn contains(self, aov: Aov) -> bool {
        self.0 & AovList::bit(aov) != 0
    }

    pub fn is_empty(&self) -> bool {
        self.0 == 0
    }

    pub fn iter(&self) -> impl Iterator<Item = Aov> + '_ {
        Aov::ALL.into_iter().filter(|aov| self.contains(*aov))
    }

    /// The channels of every AOV, in order.
    pub fn channels(&self) -> impl Iterator<Item = &'static str> + '_ {
        self.iter().flat_map(|aov| aov.channels().iter().copied())
    }

    /// The AOVs whose channels are all among `names` (a file's), or the name of a channel
    /// missing from an AOV found only in part.
    pub fn in_channels(names: &[String]) -> Result<AovList, &'static str> {
        let mut found = Vec::new();
        for aov in Aov::ALL {
            let (present, missing): (Vec<&str>, Vec<&str>) =
                aov.channels().iter().partition(|channel| names.iter().any(|n| n == *channel));
            match (present.is_empty(), missing.first()) {
                (true, _) => {}
                (false, None) => found.push(aov),
                (false, Some(missing)) => return Err(missing),
            }
        }
        Ok(AovList::new(found))
    }
}

impl fmt::Display for AovList {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        let names: Vec<&str> = self.iter().map(Aov::name).collect();
        f.write_str(&names.join(","))
    }
}

/// A list of AOVs that names one that is not, or one twice.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum AovListError {
    /// The name, printable.
    #[error("unknown AOV `{0}` (expected albedo, normal, depth or position, separated by commas)")]
    Unknown(String),
    #[error("the AOV `{0}` is named twice")]
    Twice(&'static str),
}

/// `albedo,normal,depth,position`, any of them in any order.
impl FromStr for AovList {
    type Err = AovListError;

    fn from_str(text: &str) -> Result<AovList, AovListError> {
        let mut aovs = AovList::default();
        for name in text.split(',').map(str::trim) {
            let Some(aov) = Aov::ALL.into_iter().find(|aov| aov.name() == name) else {
                return Err(AovListError::Unknown(crate::diagnostic::printable(name)));
            };
            if aovs.contains(aov) {
                return Err(AovListError::Twice(aov.name()));
            }
            aovs = AovList::new(aovs.iter().chain([aov]));
        }
        Ok(aovs)
    }
}

/// The AOVs of an image or of a crop of it: one plane of values per channel
/// (`AovList::channels`), rows top to bottom.
#[derive(Debug, Clone, PartialEq)]
pub struct AovImage {
    pub list: AovList,
    pub width: usize,
    pub height: usize,
    pub planes: Vec<Vec<f32>>,
}

impl AovImage {
    /// Each channel's name and plane.
    pub fn channels(&self) -> impl Iterator<Item = (&'static str, &[f32])> + '_ {
        self.list.channels().zip(self.planes.iter().map(Vec::as_slice))
    }

    /// The plane of channel `name`, if the image has it.
    pub fn plane(&self, name: &str) -> Option<&[f32]> {
        self.channels().find(|(channel, _)| *channel == name).map(|(_, plane)| plane)
    }
}

/// What one camera sample sees where it stops.
#[derive(Debug, Clone, Copy, Default)]
struct Seen {
    albedo: Vec3,
    normal: Vec3,
    depth: f32,
    position: Vec3,
}

/// Follows the camera ray through delta lobes (one of reflection and refraction, chosen as the
/// integrators choose) to the first surface with a lobe with a density, or with no lobe at all,
/// or where `max_depth` delta bounces end the path; what it sees there. Nothing is seen (all
/// zero) where the ray leaves the scene.
fn seen(scene: &Scene, mut ray: Ray, sampler: &mut Sampler) -> Seen {
    let mut depth = 0.0;
    for bounce in 0..=scene.settings.max_depth {
        let Some(hit) = scene.intersect(&ray) else { break };
        depth += hit.t;
        let wo = -Vec3::from(ray.dir);
        let material = scene.material(hit.primitive, hit.point);
        let bsdf = material.bsdf(hit.shading_normal, TransportMode::Radiance);
        let flags = bsdf.flags();
        let u_lobe = sampler.next_1d();
        let u = sampler.next_2d();
        if flags.is_delta()
            && !flags.is_non_delta()
            && bounce < scene.settings.max_depth
            && let Some(sample) = bsdf.sample(wo, u_lobe, u, LobeFlags::DELTA)
        {
            ray = Ray::new(offset_origin(&hit, sample.wi), sample.wi);
            continue;
        }
        let reflected = bsdf
            .sample(wo, u_lobe, u, LobeFlags::NON_DELTA)
            .map_or(Vec3::ZERO, |sample| sample.weight);
        let albedo = (reflected + material.emitted(hit.normal, wo)).min(Vec3::ONE);
        return Seen { albedo, normal: hit.shading_normal, depth, position: hit.point };
    }
    Seen::default()
}

/// The AOVs of `list` over the region's crop: in each pixel, the mean over the first `taken`
/// samples of its share, those the beauty's film holds (`Film::samples`). Rows in parallel; the
/// same values whatever the thread count.
pub fn render(scene: &Scene, region: &Region, taken: u32, list: &AovList) -> AovImage {
    let (x0, y0) = (region.crop.x0 as usize, region.crop.y0 as usize);
    let (width, height) = (region.crop.width() as usize, region.crop.height() as usize);
    let layout = region.layout();
    let channels = list.channels().count();
    let rows: Vec<Vec<f32>> = (0..height)
        .into_par_iter()
        .map(|row| {
            let mut values = Vec::with_capacity(width * channels);
            let mut sum = vec![0f64; channels];
            for column in 0..width {
                sum.fill(0.0);
                let share = layout.samples_of((row * width + column) as u64);
                let indices = share.start..share.end.min(share.start.saturating_add(taken));
                let count = indices.len();
                let pixel = camera_samples(scene, x0 + column, y0 + row);
                for index in indices {
                    let (ray, mut sampler) = pixel.sample(index);
                    // Where no light reaches the film, every AOV is 0, as the beauty is.
                    let Some(ray) = ray else { continue };
                    let seen = seen(scene, ray, &mut sampler);
                    let sample = list.iter().flat_map(|aov| aov.values(&seen).iter().copied());
                    for (sum, value) in sum.iter_mut().zip(sample) {
                        // A value that is not a number counts as 0, as a dropped beauty sample.
                        *sum += if value.is_finite() { f64::from(value) } else { 0.0 };
                    }
                }
                let scale = 1.0 / count.max(1) as f64;
                values.extend(sum.iter().map(|s| (s * scale) as f32));
            }
            values
        })
        .collect();
    let mut planes = vec![Vec::with_capacity(width * height); channels];
    for row in &rows {
        for pixel in row.chunks_exact(channels.max(1)) {
            for (plane, value) in planes.iter_mut().zip(pixel) {
                plane.push(*value);
            }
        }
    }
    AovImage { list: *list, width, height, planes }
}

/// Sums of AOVs weighted by sample counts, to merge parts: each plane's means times the
/// samples of each pixel, in f64 (as the film's sums).
#[derive(Debug, Clone)]
pub struct AovSums {
    pub list: AovList,
    pub sums: Vec<Vec<f64>>,
}

impl AovSums {
    pub fn new(list: AovList, pixels: usize) -> AovSums {
        let sums = list.channels().map(|_| vec![0.0; pixels]).collect();
        AovSums { list, sums }
    }

    /// The means, given each pixel's sample count.
    pub fn image(&self, width: usize, height: usize, counts: &[u32]) -> AovImage {
        let planes = self
            .sums
            .iter()
            .map(|plane| {
                let means = plane.iter().zip(counts);
                means.map(|(sum, count)| (sum / f64::from((*count).max(1))) as f32).collect()
            })
            .collect();
        AovImage { list: self.list, width, height, planes }
    }
}

//! The environment light (pbrt's infinite lights, Mitsuba's `envmap`): radiance arriving from
//! infinitely far away, by direction. A constant sky is sampled uniformly over the sphere; a
//! textured one (POV-Ray's `sky_sphere`) by a piecewise-constant density over cells of equal
//! (θ, φ) extent, each cell's probability in proportion to its mean radiance times its solid
//! angle, uniform by solid angle inside it.

use std::f32::consts::PI;

use glam::{Mat3, Vec2, Vec3};

use crate::geometry::Frame;
use crate::sampling::{concentric_disk, uniform_sphere};
use crate::texture::Texture;

/// Cells of the textured sky's density: θ (from +y, POV-Ray's up) by φ.
const THETA_CELLS: usize = 64;
const PHI_CELLS: usize = 128;
/// Radiance looks per cell side when the density is built (so a cell's mean sees features
/// smaller than the cell).
const LOOKS: usize = 2;
/// The share of the mean cell weight every cell gets at least: no direction where the sky may
/// shine has zero density, which photon emission (sampled from the sky alone) needs to be
/// unbiased.
const FLOOR: f32 = 0.01;

#[derive(Debug, Clone)]
pub struct Environment {
    sky: Sky,
    /// The sphere bounding what photons must reach: they leave a disc of this radius, facing
    /// the scene, at this distance from its centre.
    centre: Vec3,
    radius: f32,
}

#[derive(Debug, Clone)]
enum Sky {
    Constant(Vec3),
    /// A pigment evaluated on the unit direction turned into the sky's own space, times a
    /// multiplier, with its sampling density.
    Textured {
        pigment: Box<Texture>,
        to_sky: Mat3,
        emission: Vec3,
        cells: Cells,
    },
}

/// The textured sky's density: the cumulative distribution of the rows (θ), and of the cells
/// within each row (φ), each cell's probability in proportion to its mean radiance times its
/// solid angle; and the sky's ∫ L dω estimated from the same means. (A row, then a cell in it:
/// each of the two sample values keeps enough bits to place the direction inside its cell.)
#[derive(Debug, Clone)]
struct Cells {
    rows: Vec<f32>,
    columns: Vec<Vec<f32>>,
    integral: Vec3,
    /// cos θ at the edges between rows, decreasing.
    inner_edges: Vec<f32>,
}

/// One direction sampled from the environment: where it comes from, the radiance arriving
/// along it and its solid-angle density.
#[derive(Debug, Clone, Copy)]
pub struct SkySample {
    pub wi: Vec3,
    pub le: Vec3,
    pub pdf: f32,
}

impl Environment {
    /// A sky of radiance `le` everywhere, lighting what lies within the sphere (`centre`,
    /// `radius`).
    pub fn constant(le: Vec3, centre: Vec3, radius: f32) -> Self {
        Environment { sky: Sky::Constant(le), centre, radius }
    }

    /// A sky whose radiance towards direction d is `pigment` at `to_sky` d (normalised) times
    /// `emission`.
    pub fn textured(
        pigment: Texture,
        to_sky: Mat3,
        emission: Vec3,
        centre: Vec3,
        radius: f32,
    ) -> Self {
        let cells = Cells::new(|wi| radiance(&pigment, to_sky, emission, wi));
        let pigment = Box::new(pigment);
        Environment { sky: Sky::Textured { pigment, to_sky, emission, cells }, centre, radius }
    }

    /// The sphere its photons enter (centre, radius): they leave a disc across it.
    pub fn sphere(&self) -> (Vec3, f32) {
        (self.centre, self.radius)
    }

    /// Radiance arriving from direction `wi` (a unit vector pointing at the sky).
    pub fn le(&self, wi: Vec3) -> Vec3 {
        match &self.sky {
            Sky::Constant(le) => *le,
            Sky::Textured { pigment, to_sky, emission, .. } => {
                radiance(pigment, *to_sky, *emission, wi)
            }
        }
    }

    /// ∫ L dω over the sphere.
    pub fn integral(&self) -> Vec3 {
        match &self.sky {
            Sky::Constant(le) => 4.0 * PI * *le,
            Sky::Textured { cells, .. } => cells.integral,
        }
    }

    /// Power the sky sends into the bounding sphere: through the disc of radius R facing each
    /// direction, π R² ∫ L dω (pbrt's infinite lights).
    pub fn power_rgb(&self) -> Vec3 {
        PI * self.radius * self.radius * self.integral()
    }

    /// A direction towards the sky from `u`; `None` where the density is zero.
    pub fn sample(&self, u: Vec2) -> Option<SkySample> {
        let (wi, pdf) = match &self.sky {
            Sky::Constant(_) => (uniform_sphere(u), 1.0 / (4.0 * PI)),
            Sky::Textured { cells, .. } => cells.sample(u)?,
        };
        Some(SkySample { wi, le: self.le(wi), pdf })
    }

    /// The solid-angle density with which `sample` returns `wi`.
    pub fn pdf(&self, wi: Vec3) -> f32 {
        match &self.sky {
            Sky::Constant(_) => 1.0 / (4.0 * PI),
            Sky::Textured { cells, .. } => cells.pdf(wi),
        }
    }

    /// A photon's start from `u_point` (on the disc) and `u_direction` (the direction it comes
    /// from): a point uniform on the disc of radius R facing the sampled direction, at distance
    /// R from the centre, travelling inwards, with power L π R² / pdf (of which `share` is
    /// this photon's); `None` where the density is zero.
    pub fn sample_photon(
        &self,
        u_point: Vec2,
        u_direction: Vec2,
        share: f32,
    ) -> Option<(Vec3, Vec3, Vec3)> {
        let SkySample { wi, le, pdf } = self.sample(u_direction)?;
        let disc = concentric_disk(u_point) * self.radius;
        let frame = Frame::from_normal(wi);
        let origin =
            self.centre + self.radius * wi + frame.to_world(Vec3::new(disc.x, disc.y, 0.0));
        let power = le * PI * self.radius * self.radius / pdf * share;
        Some((origin, -wi, power))
    }
}

/// A textured sky's radiance from `wi`: the pigment on the unit sphere of the sky's own space.
fn radiance(pigment: &Texture, to_sky: Mat3, emission: Vec3, wi: Vec3) -> Vec3 {
    pigment.eval((to_sky * wi).normalize_or_zero()) * emission
}

/// The direction at (θ, φ), θ from +y.
fn direction(cos_theta: f32, phi: f32) -> Vec3 {
    let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    Vec3::new(sin_theta * phi.cos(), cos_theta, sin_theta * phi.sin())
}

/// cos θ at the top edge of row `row` (θ = row π / rows).
fn row_cos(row: usize) -> f32 {
    (row as f32 * PI / THETA_CELLS as f32).cos()
}

/// The solid angle of a cell of row `row`.
fn cell_solid_angle(row: usize) -> f32 {
    (row_cos(row) - row_cos(row + 1)) * 2.0 * PI / PHI_CELLS as f32
}

impl Cells {
    fn new(le: impl Fn(Vec3) -> Vec3) -> Self {
        let mut weights = Vec::with_capacity(THETA_CELLS);
        let mut integral = Vec3::ZERO;
        for row in 0..THETA_CELLS {
            let solid_angle = cell_solid_angle(row);
            let mut row_weights = Vec::with_capacity(PHI_CELLS);
            for column in 0..PHI_CELLS {
                let mut mean = Vec3::ZERO;
                for (i, j) in (0..LOOKS).flat_map(|i| (0..LOOKS).map(move |j| (i, j))) {
                    let t = (i as f32 + 0.5) / LOOKS as f32;
                    let cos = row_cos(row) + t * (row_cos(row + 1) - row_cos(row));
                    let phi = (column as f32 + (j as f32 + 0.5) / LOOKS as f32) * 2.0 * PI
                        / PHI_CELLS as f32;
                    mean += le(direction(cos, phi)).max(Vec3::ZERO);
                }
                mean /= (LOOKS * LOOKS) as f32;
                integral += mean * solid_angle;
                row_weights.push(mean.element_sum() / 3.0 * solid_angle);
            }
            weights.push(row_weights);
        }
        let total: f32 = weights.iter().flatten().sum();
        // The floor is shared by solid angle, so that a black sky samples uniformly.
        let floor = FLOOR * total.max(f32::MIN_POSITIVE) / (4.0 * PI);
        let columns: Vec<Vec<f32>> = weights
            .iter()
            .enumerate()
            .map(|(row, w)| cumulative(w.iter().map(|w| w + floor * cell_solid_angle(row))))
            .collect();
        let rows = cumulative(columns.iter().map(|c| c[PHI_CELLS - 1]));
        let inner_edges = (1..THETA_CELLS).map(row_cos).collect();
        Cells { rows, columns, integral, inner_edges }
    }

    /// A direction from `u`: `u.x` chooses the row and places it in the row, `u.y` the cell in
    /// it and the place in the cell; with its density.
    fn sample(&self, u: Vec2) -> Option<(Vec3, f32)> {
        let (row, along_theta, p_row) = choose(&self.rows, u.x)?;
        let (column, along_phi, p_column) = choose(&self.columns[row], u.y)?;
        let cos = row_cos(row) + along_theta * (row_cos(row + 1) - row_cos(row));
        let phi = (column as f32 + along_phi) * 2.0 * PI / PHI_CELLS as f32;
        Some((direction(cos, phi), p_row * p_column / cell_solid_angle(row)))
    }

    fn pdf(&self, wi: Vec3) -> f32 {
        // The row by comparing cos θ with the rows' edges, as `sample` placed it (acos would
        // move directions near the poles across an edge).
        let row = self.inner_edges.partition_point(|&cos| cos > wi.y);
        let phi = wi.z.atan2(wi.x).rem_euclid(2.0 * PI);
        let column = ((phi / (2.0 * PI) * PHI_CELLS as f32) as usize).min(PHI_CELLS - 1);
        probability(&self.rows, row) * probability(&self.columns[row], column)
            / cell_solid_angle(row)
    }
}

/// The running sums of `weights`.
fn cumulative(weights: impl Iterator<Item = f32>) -> Vec<f32> {
    weights
        .scan(0.0, |sum, w| {
            *sum += w;
            Some(*sum)
        })
        .collect()
}

/// The probability of entry `i` of the distribution whose running sums are `cdf`.
fn probability(cdf: &[f32], i: usize) -> f32 {
    let below = if i == 0 { 0.0 } else { cdf[i - 1] };
    (cdf[i] - below) / cdf[cdf.len() - 1]
}

/// The entry of the distribution `cdf` that `u` chooses, where `u` falls within it (in [0, 1]),
/// and its probability; `None` if it has none.
fn choose(cdf: &[f32], u: f32) -> Option<(usize, f32, f32)> {
    let total = cdf[cdf.len() - 1];
    let target = u * total;
    let i = cdf.partition_point(|&c| c <= target).min(cdf.len() - 1);
    let below = if i == 0 { 0.0 } else { cdf[i - 1] };
    let width = cdf[i] - below;
    (width > 0.0).then(|| (i, ((target - below) / width).clamp(0.0, 1.0), width / total))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::graph::{Pattern, TextureNode};
    use crate::sampling::Sampler;

    /// A sky bright towards +y and a spot towards +x: `gradient y` with a sharp map.
    fn gradient_sky() -> Environment {
        let map = vec![
            (0.0, Vec3::splat(0.05)),
            (0.8, Vec3::new(0.2, 0.4, 1.0)),
            (1.0, Vec3::splat(8.0)),
        ];
        let node = TextureNode {
            pattern: Pattern::Gradient { axis: Vec3::Y, map },
            transforms: Vec::new(),
        };
        let pigment = Texture::new(&node, &mut |_| unreachable!("no image")).unwrap();
        Environment::textured(pigment, Mat3::IDENTITY, Vec3::ONE, Vec3::ZERO, 1.0)
    }

    /// The density integrates to 1 over the sphere (midpoint rule in θ and φ, ten points a
    /// cell side, none on a cell's edge).
    #[test]
    fn the_density_integrates_to_one() {
        for sky in [gradient_sky(), Environment::constant(Vec3::ONE, Vec3::ZERO, 1.0)] {
            let (n_theta, n_phi) = (10 * THETA_CELLS, 10 * PHI_CELLS);
            let (d_theta, d_phi) = (PI / n_theta as f32, 2.0 * PI / n_phi as f32);
            let mut sum = 0.0f64;
            for i in 0..n_theta {
                let theta = (i as f32 + 0.5) * d_theta;
                for j in 0..n_phi {
                    let phi = (j as f32 + 0.5) * d_phi;
                    let pdf = sky.pdf(direction(theta.cos(), phi));
                    sum += f64::from(pdf * theta.sin() * d_theta * d_phi);
                }
            }
            assert!((sum - 1.0).abs() < 1e-3, "∫ pdf = {sum}");
        }
    }

    /// Every sampled direction's density is what `pdf` says for it, and L / pdf averages to
    /// ∫ L dω (the estimator photon emission relies on).
    #[test]
    fn samples_have_the_density_pdf_gives_and_estimate_the_integral() {
        let sky = gradient_sky();
        let n = 200_000;
        let (mut estimate, mut differing) = (Vec3::ZERO, 0);
        for i in 0..n {
            let s = sky.sample(Sampler::new(5, i, 0).next_2d()).expect("a sample");
            // Rounding may put a direction on a cell's edge in the neighbouring cell.
            differing += usize::from((s.pdf - sky.pdf(s.wi)).abs() > 1e-3 * s.pdf);
            estimate += s.le / s.pdf;
        }
        assert!(differing < 20, "{differing} of {n} samples have another density than pdf's");
        estimate /= n as f32;
        let mut quadrature = Vec3::ZERO;
        let (n_cos, n_phi) = (2000, 8);
        for i in 0..n_cos {
            for j in 0..n_phi {
                let cos = -1.0 + 2.0 * (i as f32 + 0.5) / n_cos as f32;
                let phi = 2.0 * PI * (j as f32 + 0.5) / n_phi as f32;
                quadrature += sky.le(direction(cos, phi));
            }
        }
        quadrature *= 4.0 * PI / (n_cos * n_phi) as f32;
        let error = ((estimate - quadrature) / quadrature).abs().max_element();
        assert!(error < 0.01, "L / pdf averages {estimate}, ∫ L = {quadrature}");
        let cells = ((sky.integral() - quadrature) / quadrature).abs().max_element();
        assert!(cells < 0.02, "the cells' integral {} against {quadrature}", sky.integral());
    }
}

//! Perlin's improved gradient noise (2002) and what POV-Ray's patterns build on it: noise in
//! [0, 1], vector noise, turbulence (a sum of octaves) and a random number per lattice cell. All
//! deterministic (a fixed permutation), the noises continuous everywhere.

use glam::{IVec3, Vec3};

/// A fixed permutation of 0..256 (Perlin's reference table), doubled to avoid wrapping.
const PERMUTATION: [u8; 256] = [
    151, 160, 137, 91, 90, 15, 131, 13, 201, 95, 96, 53, 194, 233, 7, 225, 140, 36, 103, 30, 69,
    142, 8, 99, 37, 240, 21, 10, 23, 190, 6, 148, 247, 120, 234, 75, 0, 26, 197, 62, 94, 252, 219,
    203, 117, 35, 11, 32, 57, 177, 33, 88, 237, 149, 56, 87, 174, 20, 125, 136, 171, 168, 68, 175,
    74, 165, 71, 134, 139, 48, 27, 166, 77, 146, 158, 231, 83, 111, 229, 122, 60, 211, 133, 230,
    220, 105, 92, 41, 55, 46, 245, 40, 244, 102, 143, 54, 65, 25, 63, 161, 1, 216, 80, 73, 209, 76,
    132, 187, 208, 89, 18, 169, 200, 196, 135, 130, 116, 188, 159, 86, 164, 100, 109, 198, 173,
    186, 3, 64, 52, 217, 226, 250, 124, 123, 5, 202, 38, 147, 118, 126, 255, 82, 85, 212, 207, 206,
    59, 227, 47, 16, 58, 17, 182, 189, 28, 42, 223, 183, 170, 213, 119, 248, 152, 2, 44, 154, 163,
    70, 221, 153, 101, 155, 167, 43, 172, 9, 129, 22, 39, 253, 19, 98, 108, 110, 79, 113, 224, 232,
    178, 185, 112, 104, 218, 246, 97, 228, 251, 34, 242, 193, 238, 210, 144, 12, 191, 179, 162,
    241, 81, 51, 145, 235, 249, 14, 239, 107, 49, 192, 214, 31, 181, 199, 106, 157, 184, 84, 204,
    176, 115, 121, 50, 45, 127, 4, 150, 254, 138, 236, 205, 93, 222, 114, 67, 29, 24, 72, 243, 141,
    128, 195, 78, 66, 215, 61, 156, 180,
];

fn hash(i: i32) -> usize {
    PERMUTATION[(i & 255) as usize] as usize
}

/// Gradient noise in about [-1, 1], 0 at integer lattice points.
pub fn perlin(p: Vec3) -> f32 {
    let cell = p.floor();
    let f = p - cell;
    let (x, y, z) = (cell.x as i32, cell.y as i32, cell.z as i32);
    // Quintic fade 6t^5 - 15t^4 + 10t^3: continuous second derivative.
    let fade = |t: f32| t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
    let (u, v, w) = (fade(f.x), fade(f.y), fade(f.z));
    let gradient = |ix: i32, iy: i32, iz: i32, d: Vec3| {
        let h = hash(ix + hash(iy + hash(iz) as i32) as i32) & 15;
        // The 12 edge directions of a cube (and 4 repeats), as in Perlin 2002.
        let a = if h < 8 { d.x } else { d.y };
        let b = if h < 4 {
            d.y
        } else if h == 12 || h == 14 {
            d.x
        } else {
            d.z
        };
        (if h & 1 == 0 { a } else { -a }) + (if h & 2 == 0 { b } else { -b })
    };
    let lerp = |t: f32, a: f32, b: f32| a + t * (b - a);
    let corner = |dx: i32, dy: i32, dz: i32| {
        gradient(x + dx, y + dy, z + dz, f - Vec3::new(dx as f32, dy as f32, dz as f32))
    };
    lerp(
        w,
        lerp(
            v,
            lerp(u, corner(0, 0, 0), corner(1, 0, 0)),
            lerp(u, corner(0, 1, 0), corner(1, 1, 0)),
        ),
        lerp(
            v,
            lerp(u, corner(0, 0, 1), corner(1, 0, 1)),
            lerp(u, corner(0, 1, 1), corner(1, 1, 1)),
        ),
    )
}

/// Fractal Brownian motion: `octaves` of noise, each at twice the frequency and half the
/// amplitude of the one before, mapped to [0, 1].
pub fn fbm(p: Vec3, octaves: u32) -> f32 {
    let (mut sum, mut amplitude, mut total, mut frequency) = (0.0, 1.0, 0.0, 1.0);
    for _ in 0..octaves {
        sum += amplitude * perlin(p * frequency);
        total += amplitude;
        amplitude *= 0.5;
        frequency *= 2.0;
    }
    (0.5 + 0.5 * sum / total).clamp(0.0, 1.0)
}

/// POV-Ray's `Noise`: gradient noise mapped to [0, 1], 0.5 on the lattice.
pub fn noise(p: Vec3) -> f32 {
    (0.5 + 0.5 * perlin(p)).clamp(0.0, 1.0)
}

/// Three independent noises in about [-1, 1] (POV-Ray's `DNoise`): the lattice is shifted for
/// each component so they do not correlate.
pub fn vector_noise(p: Vec3) -> Vec3 {
    Vec3::new(
        perlin(p + Vec3::new(31.416, -47.853, 12.793)),
        perlin(p + Vec3::new(-7.274, 93.127, -53.91)),
        perlin(p + Vec3::new(61.71, 17.34, -83.59)),
    )
}

/// POV-Ray's turbulence parameters: `octaves` of noise, each `lambda` times the frequency and
/// `omega` times the amplitude of the one before.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Octaves {
    pub octaves: u32,
    pub omega: f32,
    pub lambda: f32,
}

impl Octaves {
    /// POV-Ray's defaults: `octaves 6 omega 0.5 lambda 2`.
    pub const DEFAULT: Octaves = Octaves { octaves: 6, omega: 0.5, lambda: 2.0 };

    /// The sum of `noise` over the octaves (POV-Ray's `Turbulence`): about 1 on average with
    /// the defaults.
    pub fn scalar(&self, p: Vec3) -> f32 {
        self.sum(p, 0.0, noise)
    }

    /// The sum of `vector_noise` over the octaves (POV-Ray's `DTurbulence`), a displacement.
    pub fn vector(&self, p: Vec3) -> Vec3 {
        self.sum(p, Vec3::ZERO, vector_noise)
    }

    fn sum<T: std::ops::Add<Output = T> + std::ops::Mul<f32, Output = T>>(
        &self,
        p: Vec3,
        zero: T,
        f: impl Fn(Vec3) -> T,
    ) -> T {
        let (mut sum, mut amplitude, mut frequency) = (zero, 1.0, 1.0);
        for _ in 0..self.octaves.max(1) {
            sum = sum + f(p * frequency) * amplitude;
            amplitude *= self.omega;
            frequency *= self.lambda;
        }
        sum
    }
}

/// A random number in [0, 1) for lattice cell `cell` and stream `k`: the same for every point of
/// the cell (`cells`, the feature points of `crackle`).
pub fn cell_random(cell: IVec3, k: u32) -> f32 {
    let mut h = (cell.x as u32).wrapping_mul(0x8da6_b343)
        ^ (cell.y as u32).wrapping_mul(0xd816_3841)
        ^ (cell.z as u32).wrapping_mul(0xcb1a_b31f)
        ^ k.wrapping_mul(0x1656_67b1);
    // A 32-bit finaliser (murmur3's): every input bit moves every output bit.
    h ^= h >> 16;
    h = h.wrapping_mul(0x85eb_ca6b);
    h ^= h >> 13;
    h = h.wrapping_mul(0xc2b2_ae35);
    h ^= h >> 16;
    (h >> 8) as f32 / (1u32 << 24) as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn turbulence_is_the_weighted_sum_of_its_octaves() {
        let p = Vec3::new(0.37, 1.21, -2.4);
        let two = Octaves { octaves: 2, omega: 0.3, lambda: 3.0 };
        assert!((two.scalar(p) - (noise(p) + 0.3 * noise(p * 3.0))).abs() < 1e-6);
        let d = two.vector(p) - (vector_noise(p) + vector_noise(p * 3.0) * 0.3);
        assert!(d.length() < 1e-6);
        // The default sum is about 1 on average (POV-Ray's scale for marble and wood).
        let mean = (0..4000)
            .map(|i| Octaves::DEFAULT.scalar(Vec3::new(i as f32 * 0.173, i as f32 * 0.071, 0.3)))
            .sum::<f32>()
            / 4000.0;
        assert!((mean - 1.0).abs() < 0.1, "mean {mean}");
    }

    #[test]
    fn cell_random_is_uniform_and_constant_in_a_cell() {
        let mut counts = [0u32; 10];
        for i in 0..10_000 {
            let v = cell_random(IVec3::new(i % 37, i / 37, -i), 3);
            assert!((0.0..1.0).contains(&v));
            counts[(v * 10.0) as usize] += 1;
        }
        // 1000 expected per bin; 5 standard deviations is about 150.
        assert!(counts.iter().all(|&c| (850..1150).contains(&c)), "{counts:?}");
        assert_ne!(cell_random(IVec3::ZERO, 0), cell_random(IVec3::ZERO, 1), "streams differ");
    }

    #[test]
    fn noise_is_bounded_deterministic_and_continuous() {
        let mut previous = fbm(Vec3::ZERO, 4);
        for i in 1..20000 {
            let p =
                Vec3::new(i as f32 * 1e-3, (i as f32 * 7e-4).sin() * 3.0, -2.5 + i as f32 * 3e-4);
            let value = fbm(p, 4);
            assert!((0.0..=1.0).contains(&value));
            assert_eq!(value, fbm(p, 4));
            // Steps of about 1e-3 change the value by little: no jumps at cell boundaries.
            assert!((value - previous).abs() < 0.05, "jump at {p}: {previous} -> {value}");
            previous = value;
        }
        assert_eq!(perlin(Vec3::new(3.0, -2.0, 5.0)), 0.0, "zero on the lattice");
    }

    #[test]
    fn noise_varies() {
        let values: Vec<f32> = (0..1000).map(|i| fbm(Vec3::splat(i as f32 * 0.137), 4)).collect();
        let (lo, hi) = values.iter().fold((1.0f32, 0.0f32), |(lo, hi), v| (lo.min(*v), hi.max(*v)));
        assert!(hi - lo > 0.3, "{lo}..{hi}");
    }
}

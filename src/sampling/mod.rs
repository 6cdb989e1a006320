//! Deterministic random streams and the warps that turn uniform samples into directions and points.

mod sampler;
mod warp;

pub use sampler::{PixelSampler, Sampler};
pub use warp::{
    concentric_disk, concentric_disk_of, cosine_hemisphere, cosine_hemisphere_of, uniform_sphere,
    uniform_triangle, uniform_triangle_of,
};

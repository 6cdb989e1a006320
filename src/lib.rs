//! raydiance: a physically based renderer for a POV-Ray-like scene language.
//!
//! Data flows one way: text --`lang`--> `SceneGraph` --`scene::build`--> `Scene`
//! --`render`--> `Film` --> image files --> `tonemap`.
#![forbid(unsafe_code)]

pub mod aabb;
pub mod accel;
pub mod animation;
pub mod aov;
pub mod bench;
pub mod camera;
pub mod denoise;
pub mod diagnostic;
pub mod digest;
pub mod film;
pub mod function;
pub mod geometry;
pub mod graph;
pub mod image;
pub mod input;
pub mod integrator;
pub mod job;
pub mod lanes;
pub mod lang;
pub mod light;
pub mod material;
pub mod medium;
pub mod mesh;
pub mod photon;
mod pipeline;
pub mod preview;
pub mod progress;
pub mod projection;
pub mod ray;
pub mod region;
pub mod render;
pub mod sampling;
pub mod scene;
pub mod snapshot;
pub mod split;
pub mod texture;
pub mod threads;
pub mod tonemap;

pub use pipeline::{
    FilmTooLarge, LoadError, MAX_DEPTH, MAX_RESOLUTION, MAX_SAMPLES, MergeReport, OutputFormat,
    RenderRequest, RequestError, ToneMapFileError, check, load, load_with_digest, merge_files,
    tonemap_file, write_image, write_render,
};

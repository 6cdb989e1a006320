//! raydiance: a physically based renderer for a POV-Ray-like scene language.
#![forbid(unsafe_code)]

pub mod diagnostic;
pub mod image;
pub mod lang;
pub mod scene;

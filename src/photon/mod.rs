//! Photon mapping's parts: photons shared out among the lights (`emission`).

mod emission;

pub use emission::{Emission, MAX_PHOTONS};

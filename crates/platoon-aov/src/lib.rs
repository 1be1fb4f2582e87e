//! platoon-aov: what a frame writes beside its beauty, and the denoisers those outputs guide.
//!
//! - [`aov`]: the arbitrary output variables (albedo, normal, position, depth, ids, sample count
//!   and variance) and how each is rendered and composed into a film's layers; [`cryptomatte`],
//!   [`light_pass`] (Cycles' direct/indirect split), [`motion`] (vectors from the scene's
//!   previous pose) and [`hit_geometry`] (what a first hit was, for motion and temporal reuse);
//! - [`denoise`]: à-trous, temporal accumulation and OIDN, run on the assembled frame;
//! - [`Crop`]: the region of the film a frame renders, which the outputs above share.
//!
//! It knows the scene, the flattened scene and films, and nothing of methods, balancers or
//! devices; the core re-exports its modules where they were (`platoon_core::frame::aov`...,
//! `platoon_core::denoise`, `platoon_core::frame::Crop`).

pub mod aov;
mod crop;
pub mod cryptomatte;
pub mod denoise;
pub mod hit_geometry;
pub mod light_pass;
pub mod motion;

pub use crop::{Crop, Region};

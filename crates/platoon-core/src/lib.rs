//! platoon-core: everything of the renderer that is not Vulkan.
//!
//! The scene graph ([`scene`]), its loaders ([`gltf_load`], [`cornell`]), the environment
//! ([`environment`]), the CPU-side BVHs ([`bvh`]), the flattening of a posed scene into plain
//! GPU-ready arrays ([`gpu_scene`]) and the image outputs ([`output`]). The tracer crate consumes
//! [`gpu_scene::GpuScene`] and knows nothing of glTF.

pub mod animation;
pub mod balance;
pub mod bvh;
pub mod camera;
pub mod cornell;
pub mod environment;
pub mod error;
pub mod fault;
pub mod features;
pub mod floating_origin;
pub mod frame;
pub mod gltf_load;
pub mod gpu_scene;
pub mod output;
pub mod renderer;
pub mod replay;
pub mod scene;
pub mod tangents;

pub use error::{Error, Result};
pub use features::FeatureSet;
pub use scene::Scene;

#[cfg(test)]
mod tests {
    /// The test profile keeps overflow checks on (Cargo.toml): hostile inputs rely on them.
    #[test]
    #[should_panic(expected = "overflow")]
    fn overflow_checks_are_on_in_tests() {
        let x: u8 = std::hint::black_box(255);
        std::hint::black_box(x + 1);
    }
}

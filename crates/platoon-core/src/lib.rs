//! platoon-core: everything of the renderer that is not Vulkan, grouped by stage.
//!
//! - [`scene`]: the scene graph, its loaders (glTF, the built-in Cornell box), animation,
//!   cameras, the environment and the floating origin: the crate `platoon-scene`, re-exported
//!   here with its [`error`], [`input`] (reading a user's files) and [`byte_size`];
//! - [`flatten`]: a posed scene made into the plain GPU-ready arrays of [`flatten::GpuScene`]
//!   (BVHs, materials and textures, lights and their selection CDF, the feature set) and the
//!   CPU's ray queries over them: the crate `platoon-accel`, re-exported here;
//! - [`frame`]: frame parameters and the bands of pixels a tracer renders: the frame contract,
//!   crate `platoon-frame`, re-exported here; its outputs beside the beauty (`frame::aov`,
//!   `cryptomatte`, `light_pass`, `motion`, `hit_geometry`, `Crop`) and the [`denoise`]rs they
//!   guide are the crate `platoon-aov`, re-exported where they were;
//! - [`method`]: the rendering methods (IGI, vertex links, layered hit buffers) and the list of
//!   the built-in ones (`method::registry`); what renders a frame, how a method is chosen and
//!   the reference method (path tracing) are the frame contract's, re-exported there;
//! - [`balance`]: the line balancers and the replay of recorded costs: the crate
//!   `platoon-balance`, re-exported here;
//! - [`measure`]: summaries of measurements (platoon-balance's);
//! - [`output`]: films and image files, and [`colour`] (exposure and view transforms): the crate
//!   `platoon-image`, re-exported here.
//!
//! Built on this one: a living scene (the game's edits, the double-buffered updater, the frame
//! driver) is the crate `platoon-live`, frames split between processes (MPI ranks) the crate
//! `platoon-distribute`. The tracer crate consumes [`flatten::GpuScene`] and knows nothing of glTF.

pub mod method;

pub use platoon_frame::frame;

pub use platoon_accel as flatten;
pub use platoon_aov::denoise;
pub use platoon_balance as balance;
pub use platoon_balance::measure;
pub use platoon_scene as scene;
pub use platoon_scene::{byte_size, error, input};

pub use platoon_image as output;
pub use platoon_image::colour;

pub use error::{Error, Result};
pub use flatten::features::SceneFeatures;
pub use method::variant::KernelVariant;
pub use method::Method;
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

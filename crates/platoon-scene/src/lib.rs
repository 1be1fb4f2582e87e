//! platoon-scene: the scene: the graph a game or a file describes (`graph.rs`, `nodes.rs`,
//! `mesh.rs`, posed by `pose.rs`; all re-exported here), where it comes from (glTF, the
//! built-in Cornell box), how it moves (animation, cameras, the floating origin) and its distant
//! light; with the errors every layer of platoon returns (`error`), the reading of a user's
//! files (`input`) and sizes in bytes for people (`byte_size`). platoon-core re-exports it as
//! `platoon_core::scene`; nothing here knows BVHs, frames or Vulkan.

pub mod byte_size;
pub mod error;
pub mod input;

pub mod animation;
pub mod camera;
pub mod cornell;
pub mod environment;
pub mod floating_origin;
pub mod gltf_load;
mod graph;
mod merge;
mod mesh;
mod nodes;
pub mod placeable;
pub mod placement;
mod pose;
mod subdivide;
pub mod tangents;
pub mod texture_levels;

pub use error::{Error, Result};
pub use graph::*;
pub use mesh::*;
pub use nodes::*;
pub use placement::Placement;
pub use pose::*;

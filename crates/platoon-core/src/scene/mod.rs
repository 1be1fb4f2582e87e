//! The scene: the graph a game or a file describes (`graph.rs`, re-exported here), where it comes from (glTF,
//! the built-in Cornell box), how it moves (animation, cameras, the floating origin) and its
//! distant light.

pub mod animation;
pub mod camera;
pub mod cornell;
pub mod environment;
pub mod floating_origin;
pub mod gltf_load;
mod graph;
mod merge;
pub mod placeable;
pub mod placement;
mod subdivide;
pub mod tangents;

pub use graph::*;
pub use placement::Placement;

//! The scene: the graph a game or a file describes (`graph.rs`, `nodes.rs`, `mesh.rs`, posed by
//! `pose.rs`; all re-exported here), where it comes from (glTF,
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
mod mesh;
mod nodes;
pub mod placeable;
pub mod placement;
mod pose;
mod subdivide;
pub mod tangents;
pub mod texture_levels;

pub use graph::*;
pub use mesh::*;
pub use nodes::*;
pub use placement::Placement;
pub use pose::*;

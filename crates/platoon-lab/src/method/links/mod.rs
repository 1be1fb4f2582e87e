//! Vertex links' measuring: the update stage by stage (`bench`), the walk across a room with
//! links regenerated and revalidated (`walk`), and `platoon bench links` (`command`).

pub mod bench;
pub mod command;
pub mod walk;

//! Spherical layered hit buffers (Insu Yu's thesis; `../shared/briefs/lhb.md`, issue 23): for a
//! set of directions, an orthographic buffer of the whole scene per direction whose every pixel
//! lists the surfaces along it; indirect rays are answered by a lookup in the buffer of the
//! nearest direction instead of a traversal.
//!
//! The method (`Lhb`, its options `LhbOptions`) and its CPU parts: [`directions`] (the
//! icosahedral, octahedral and Halton sets), [`directional_map`] (any direction to its nearest
//! buffer direction, exact), [`frame`] (the scene's bounding sphere and each direction's view),
//! [`tables`] (what every tracer uploads: frame, views, map, placed triangles, their digests),
//! [`oracle`] (buffers built by rays, what the devices' rasterizer is tested against), [`raster`]
//! (the rasterizer's algorithm on the CPU: edge functions, the top-left rule, plane depth, a
//! capacity with overflow counted) and [`lookup`] (a ray answered by the buffers, the reference
//! of the kernels' lookups). The device side is the tracer's `method/lhb/` and shaders/lhb/;
//! measured in docs/LHB.md.

mod build_report;
pub use build_report::LhbBuild;
pub mod directional_map;
pub mod directions;
pub mod frame;
mod kind;
pub mod lookup;
pub use kind::LhbKind;
mod method;
mod options;
pub mod oracle;
mod prepared;
pub mod raster;
pub mod tables;

pub use options::{
    LhbOptions, RasterVariant, FRAME_MARGIN, MAX_BOUNCES, MAX_BYTES, MAX_RESOLUTION,
};
pub use prepared::Lhb;

/// A flattened scene of `mesh` alone, at the origin (the tests' scenes).
#[cfg(test)]
fn one_mesh(mesh: crate::scene::Mesh) -> crate::flatten::GpuScene {
    let mut node = crate::scene::Node::new("mesh");
    node.mesh = Some(0);
    let scene = crate::scene::Scene {
        nodes: vec![node],
        meshes: vec![std::sync::Arc::new(mesh)],
        materials: vec![crate::scene::Material::default()],
        ..Default::default()
    };
    crate::flatten::GpuScene::build(&scene, &scene.pose(0.0), None).unwrap()
}

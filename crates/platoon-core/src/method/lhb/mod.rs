//! Spherical layered hit buffers (Insu Yu's thesis; `../shared/briefs/lhb.md`, issue 23): for a
//! set of directions, an orthographic buffer of the whole scene per direction whose every pixel
//! lists the surfaces along it; indirect rays are answered by a lookup in the buffer of the
//! nearest direction instead of a traversal.
//!
//! Built so far: [`directions`] (the icosahedral, octahedral and Halton sets) and
//! [`directional_map`] (any direction to its nearest buffer direction, exact). To come: the
//! buffers' frame, the compute rasterizer and its ray oracle, the lookups, `--method lhb`.

pub mod directional_map;
pub mod directions;

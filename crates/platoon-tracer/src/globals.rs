//! The root block the kernel reaches through the push constants: addresses of every scene
//! array plus the per-render parameters. Mirrors `Globals` in shaders/scene.glsl (std430).

use bytemuck::{Pod, Zeroable};

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub(crate) struct Globals {
    pub vertices: u64,
    pub tri_pos: u64,
    pub triangles: u64,
    pub tri_lights: u64,
    pub blas: u64,
    pub tlas: u64,
    pub instances: u64,
    pub materials: u64,
    pub textures: u64,
    pub texels: u64,
    pub lights: u64,
    pub light_cdf: u64,
    pub env_texels: u64,
    pub env_marginal: u64,
    pub env_conditional: u64,
    pub accum: u64,
    pub stats: u64,
    pub _pad: [u32; 2],
    pub cam_origin: [f32; 4],
    pub cam_right: [f32; 4],
    pub cam_up: [f32; 4],
    pub cam_forward: [f32; 4],
    pub env_color: [f32; 4],
    pub dims: [u32; 4],
    pub counts: [u32; 4],
    pub params: [u32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub(crate) struct Push {
    pub globals: u64,
    pub y0: u32,
    pub y1: u32,
    pub sample_begin: u32,
    pub sample_end: u32,
    pub stride: u32,
    pub _pad: u32,
}

const _: () = assert!(std::mem::size_of::<Globals>() == 144 + 8 * 16);

//! The root block the kernel reaches through the push constants: addresses of every scene
//! array plus the per-render parameters. Mirrors `Globals` in shaders/scene.glsl (std430).

use bytemuck::{Pod, Zeroable};
use platoon_core::frame::FrameParams;

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

impl Globals {
    /// This block with the camera, frame parameters and per-frame buffers of one render.
    pub fn for_frame(&self, params: &FrameParams, accum: u64, stats: u64) -> Globals {
        let mut g = *self;
        g.accum = accum;
        g.stats = stats;
        let cam = &params.camera;
        let m = cam.camera_to_world;
        let right = m.x_axis.truncate().normalize();
        let up = m.y_axis.truncate().normalize();
        let forward = -m.z_axis.truncate().normalize();
        let tan_half = (cam.yfov * 0.5).tan();
        let aspect = params.width as f32 / params.height.max(1) as f32;
        let origin = m.w_axis.truncate();
        g.cam_origin = [origin.x, origin.y, origin.z, cam.aperture_radius];
        g.cam_right = [right.x, right.y, right.z, tan_half * aspect];
        g.cam_up = [up.x, up.y, up.z, tan_half];
        g.cam_forward = [forward.x, forward.y, forward.z, cam.focus_distance];
        g.dims[0] = params.width;
        g.dims[1] = params.height;
        g.params = [
            params.max_depth.max(1),
            params.frame,
            params.seed,
            params.rr_depth,
        ];
        g
    }
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

//! The root block the kernel reaches through the push constants: addresses of every scene
//! array plus the per-render parameters. Mirrors `Globals` in shaders/scene.glsl (std430).

use bytemuck::{Pod, Zeroable};
use platoon_core::flatten::arrays::SceneArray;
use platoon_core::frame::{kernel_word_names, FrameParams, LOOP_WORDS, OPTION_WORDS};

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
    /// The rendering method's buffers (`MethodPasses::prepare`; IGI's VPLs, per-pixel texels and
    /// gathering vertices), 0 where a method has none.
    pub method_buffers: [u64; 4],
    /// COLOR_0 and TEXCOORD_1 (an empty array when the scene has neither).
    pub vertex_extras: u64,
    pub cam_origin: [f32; 4],
    pub cam_right: [f32; 4],
    pub cam_up: [f32; 4],
    pub cam_forward: [f32; 4],
    pub env_color: [f32; 4],
    pub dims: [u32; 4],
    pub counts: [u32; 4],
    pub params: [u32; 4],
    /// The scene's bounding sphere (centre, radius).
    pub scene_sphere: [f32; 4],
    /// The frame's first pixel in the image its camera frames, and that image's size
    /// (`FrameParams::crop`; the frame's own size without one).
    pub crop: [u32; 4],
}

impl Globals {
    /// The field holding `array`'s buffer device address (its `globals_field` in the table).
    pub fn address_mut(&mut self, array: SceneArray) -> &mut u64 {
        use SceneArray::*;
        match array {
            Vertices => &mut self.vertices,
            TrianglePositions => &mut self.tri_pos,
            Triangles => &mut self.triangles,
            TriangleLights => &mut self.tri_lights,
            Blas => &mut self.blas,
            Tlas => &mut self.tlas,
            Instances => &mut self.instances,
            Materials => &mut self.materials,
            Textures => &mut self.textures,
            Texels => &mut self.texels,
            Lights => &mut self.lights,
            LightCdf => &mut self.light_cdf,
            EnvTexels => &mut self.env_texels,
            EnvMarginal => &mut self.env_marginal,
            EnvConditional => &mut self.env_conditional,
            VertexExtras => &mut self.vertex_extras,
        }
    }

    /// This block with the camera, frame parameters and per-frame buffers of one render.
    pub fn for_frame(
        &self,
        params: &FrameParams,
        accum: u64,
        stats: u64,
        method_buffers: [u64; 4],
    ) -> Globals {
        let mut g = *self;
        g.accum = accum;
        g.stats = stats;
        g.method_buffers = method_buffers;
        let cam = &params.camera;
        let crop = params.image_crop();
        let b = cam.basis(crop.image_width, crop.image_height);
        g.cam_origin = b.origin.extend(cam.aperture_radius).to_array();
        g.cam_right = b.right.extend(b.tan_half_x).to_array();
        g.cam_up = b.up.extend(b.tan_half_y).to_array();
        g.cam_forward = b.forward.extend(cam.focus_distance).to_array();
        g.dims[0] = params.width;
        g.dims[1] = params.height;
        g.crop = [crop.x, crop.y, crop.image_width, crop.image_height];
        g.params = [params.frame, 0, 0, 0];
        g
    }
}

/// Push-constant words a rendering method has for its options (`Push::method`; its shaders
/// name them).
pub const METHOD_WORDS: usize = 9;

/// A method's push words: `first`, then zeros.
pub fn method_words(first: &[u32]) -> [u32; METHOD_WORDS] {
    let mut words = [0; METHOD_WORDS];
    words[..first.len()].copy_from_slice(first);
    words
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct Push {
    pub globals: u64,
    /// Lines dispatched, and the pixels among them rendered (row-major indices).
    pub y0: u32,
    pub y1: u32,
    pub pixel_begin: u32,
    pub pixel_end: u32,
    pub sample_begin: u32,
    pub sample_end: u32,
    pub stride: u32,
    /// The words the kernel reads of the frame's options and path loop
    /// (`FrameParams::kernel_words`, then zeros), read through the accessors
    /// `frame_words_glsl` writes.
    pub frame_words: [u32; FRAME_WORDS],
    /// The rendering method's words (`MethodPasses::push_words`; its shaders name them).
    pub method: [u32; METHOD_WORDS],
}

impl Push {
    /// The words every pass of a frame of `params` reads the same: the root block's address
    /// `globals`, the frame's words and the method's own; the band's lines, pixels and
    /// samples are left for its passes.
    pub fn of_frame(params: &FrameParams, globals: u64, method: [u32; METHOD_WORDS]) -> Push {
        let mut frame_words = [0; FRAME_WORDS];
        for (word, value) in frame_words.iter_mut().zip(params.kernel_words()) {
            *word = value;
        }
        Push {
            globals,
            frame_words,
            method,
            ..Push::default()
        }
    }
}

/// Push words for what the kernel reads of the frame's options and path loop: room for two
/// more without a new block.
pub const FRAME_WORDS: usize = 8;
const _: () = assert!(OPTION_WORDS.len() + LOOP_WORDS.len() <= FRAME_WORDS);

/// Where the kernel includes `frame_words_glsl` from (after the push block,
/// shaders/common/scene.glsl): a source made here, not a file of shaders/.
pub(crate) const FRAME_WORDS_INCLUDE: &str = "generated/frame_words.glsl";

/// The GLSL accessor of each word of the frame, by its name in `OPTION_WORDS` and
/// `LOOP_WORDS` (`uint NAME()`, or `float NAME()` for an f32), reading `pc.frame_words`.
pub(crate) fn frame_words_glsl() -> String {
    let mut glsl = String::from(
        "// Made by crates/platoon-tracer/src/globals.rs (frame_words_glsl) from the frame's\n\
         // words, OPTION_WORDS and LOOP_WORDS of crates/platoon-frame/src/frame/.\n",
    );
    for (i, (name, float)) in kernel_word_names().enumerate() {
        let read = format!("pc.frame_words[{i}]");
        let (ty, value) = match float {
            true => ("float", format!("uintBitsToFloat({read})")),
            false => ("uint", read),
        };
        glsl.push_str(&format!("{ty} {name}() {{ return {value}; }}\n"));
    }
    glsl
}

const _: () = assert!(std::mem::size_of::<Globals>() == 176 + 10 * 16);
// Must match the push-constant block of shaders/scene.glsl.
const _: () = assert!(std::mem::size_of::<Push>() == 104);

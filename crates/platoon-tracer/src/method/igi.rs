//! IGI on one device (platoon_core::method::igi): the frame's VPL buffer, the gathering vertices,
//! the texels a filtered gather leaves for the filters after assembly, and its three kernels
//! (shaders/igi/): the first pass that shoots the VPLs, then per sample a camera pass and gather
//! passes. Every tracer shoots the same set (a pure function of scene, frame and seed), so no
//! VPLs cross between devices.

use std::time::Duration;

use ash::vk;
use gpu_allocator::MemoryLocation;
use platoon_core::frame::{FrameParams, PixelData, Span};
use platoon_core::method::igi::{IgiOptions, IgiTexel, IgiVertex, Vpl};

use super::{ensure, MethodPasses, Recorder};
use crate::buffer::GpuBuffer;
use crate::dispatch::record_dispatch;
use crate::globals::{method_words, Push, METHOD_WORDS};
use crate::gpu::Gpu;
use crate::Result;

const EMIT: &str = "igi/emit.comp";
const CAMERA: &str = "igi/camera.comp";
const GATHER: &str = "igi/gather.comp";

const VPL_BYTES: u64 = std::mem::size_of::<Vpl>() as u64;
const TEXEL_BYTES: u64 = std::mem::size_of::<IgiTexel>() as u64;
const VERTEX_BYTES: u64 = std::mem::size_of::<IgiVertex>() as u64;
/// VPLs one gather pass takes per pixel: 128 shadow rays of up to ~500 BVH steps stay within
/// llvmpipe's 65535 loop iterations per invocation (shaders/igi/camera.comp). The same on every
/// device, so that the sums add in the same order whatever the split.
const GATHER_CHUNK: u32 = 128;
/// `Push::method`'s words the gather passes' VPL range takes (shaders/igi/igi.glsl).
const VPL_FIRST: usize = 6;
const VPL_END: usize = 7;

#[derive(Default)]
pub(crate) struct IgiPasses {
    vpls: Option<GpuBuffer>,
    /// Texels of every pixel of the frame (host-visible: read back in place).
    texels: Option<GpuBuffer>,
    /// The gathering vertex of every pixel's current sample.
    vertices: Option<GpuBuffer>,
}

fn options(params: &FrameParams) -> IgiOptions {
    *params
        .method
        .state::<IgiOptions>()
        .expect("IGI's passes render IGI's frames")
}

impl MethodPasses for IgiPasses {
    fn kernels(&self, _params: &FrameParams, _cpu: bool) -> Vec<&'static str> {
        vec![EMIT, CAMERA, GATHER]
    }

    /// The VPL, texel and vertex buffers (Globals' method buffers 0, 1 and 2).
    fn prepare(&mut self, gpu: &mut Gpu, params: &FrameParams) -> Result<[u64; 4]> {
        let o = options(params);
        let pixels = params.width as u64 * params.height as u64;
        let vpls = ensure(
            gpu,
            &mut self.vpls,
            "igi vpls",
            o.slots() as u64 * VPL_BYTES,
            MemoryLocation::GpuOnly,
        )?;
        let texels = if o.filtered() {
            ensure(
                gpu,
                &mut self.texels,
                "igi texels",
                pixels * TEXEL_BYTES,
                MemoryLocation::GpuToCpu,
            )?
        } else {
            0
        };
        let vertices = ensure(
            gpu,
            &mut self.vertices,
            "igi vertices",
            pixels * VERTEX_BYTES,
            MemoryLocation::GpuOnly,
        )?;
        Ok([vpls, texels, vertices, 0])
    }

    /// Paths, bounces, minimum distance, downsampling, the interleaving tile; the gather
    /// passes fill in their VPL range.
    fn push_words(&self, params: &FrameParams) -> [u32; METHOD_WORDS] {
        let o = options(params);
        method_words(&[
            o.paths,
            o.bounces,
            o.min_distance.to_bits(),
            o.downsample,
            o.interleave[0],
            o.interleave[1],
        ])
    }

    /// A filtered gather adds onto the span's texels.
    fn clears(&self, params: &FrameParams, span: Span) -> Vec<(vk::Buffer, u64, u64)> {
        match &self.texels {
            Some(b) if options(params).filtered() => vec![(
                b.buffer,
                span.begin as u64 * TEXEL_BYTES,
                span.len() as u64 * TEXEL_BYTES,
            )],
            _ => Vec::new(),
        }
    }

    /// A sample at a time: its gather passes follow each camera pass.
    fn samples_per_pass(&self, _params: &FrameParams) -> u32 {
        1
    }

    /// Shoots the frame's VPLs. (The next dispatch's barrier makes them visible to the gather.)
    fn begin_band(&mut self, rec: &mut Recorder, push: &Push) -> Result<Duration> {
        let groups = options(rec.params).paths.div_ceil(64);
        rec.dispatch(EMIT, push, (groups, 1))
    }

    /// The camera pass, then the gather passes over the VPLs a chunk at a time, in one
    /// submission.
    fn pass(&mut self, rec: &mut Recorder, push: &Push, groups: (u32, u32)) -> Result<Duration> {
        let o = options(rec.params);
        let (camera, gather) = (rec.kernel(CAMERA)?, rec.kernel(GATHER)?);
        let chunk = GATHER_CHUNK * o.subsets();
        let slots = o.slots();
        rec.gpu.timed(|d, cb| unsafe {
            record_dispatch(d, cb, camera, push, groups);
            let mut first = 0;
            while first < slots {
                let end = (first + chunk).min(slots);
                let mut chunk = *push;
                chunk.method[VPL_FIRST] = first;
                chunk.method[VPL_END] = end;
                record_dispatch(d, cb, gather, &chunk, groups);
                first = end;
            }
        })
    }

    /// The span's texels, after the gather (none unless the gather is filtered).
    fn per_pixel(&mut self, params: &FrameParams, span: Span) -> PixelData {
        if !options(params).filtered() {
            return PixelData::default();
        }
        let Some(b) = self.texels.as_mut() else {
            return PixelData::default();
        };
        PixelData::of_span::<IgiTexel>(b.mapped(), span)
    }

    fn destroy(&mut self, gpu: &mut Gpu) {
        for mut b in [self.vpls.take(), self.texels.take(), self.vertices.take()]
            .into_iter()
            .flatten()
        {
            gpu.destroy_buffer(&mut b);
        }
    }
}

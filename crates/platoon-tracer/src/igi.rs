//! IGI on one device (crates/platoon-core/src/igi): the frame's VPL buffer, the texels a
//! filtered gather leaves for the filters after assembly, and the first pass that shoots the
//! VPLs (shaders/igi/emit.comp). Every tracer shoots the same set (a pure function of scene,
//! frame and seed), so no VPLs cross between devices.

use std::time::Duration;

use ash::vk;
use gpu_allocator::MemoryLocation;
use platoon_core::frame::{FrameParams, Span};
use platoon_core::igi::IgiTexel;

use crate::buffer::GpuBuffer;
use crate::dispatch::{record_dispatch, timestamp};
use crate::globals::Push;
use crate::kernel::{EMIT_VPLS, GATHER};
use crate::tracer::Tracer;
use crate::{Error, Result};

const VPL_BYTES: u64 = std::mem::size_of::<platoon_core::igi::Vpl>() as u64;
const TEXEL_BYTES: u64 = std::mem::size_of::<IgiTexel>() as u64;
const VERTEX_BYTES: u64 = std::mem::size_of::<platoon_core::igi::IgiVertex>() as u64;
/// VPLs one gather pass takes per pixel: 128 shadow rays of up to ~500 BVH steps stay within
/// llvmpipe's 65535 loop iterations per invocation (shaders/igi/camera.comp). The same on every
/// device, so that the sums add in the same order whatever the split.
const GATHER_CHUNK: u32 = 128;

#[derive(Default)]
pub(crate) struct IgiBuffers {
    vpls: Option<GpuBuffer>,
    /// Texels of every pixel of the frame (host-visible: read back in place).
    texels: Option<GpuBuffer>,
    /// The gathering vertex of every pixel's current sample.
    vertices: Option<GpuBuffer>,
}

impl IgiBuffers {
    pub fn destroy(
        &mut self,
        device: &ash::Device,
        allocator: &mut gpu_allocator::vulkan::Allocator,
    ) {
        for b in [
            self.vpls.as_mut(),
            self.texels.as_mut(),
            self.vertices.as_mut(),
        ]
        .into_iter()
        .flatten()
        {
            b.destroy(device, allocator);
        }
        *self = IgiBuffers::default();
    }
}

/// A buffer of at least `size` bytes in `slot`, replaced when too small.
fn ensure(
    tracer: &mut Tracer,
    which: fn(&mut IgiBuffers) -> &mut Option<GpuBuffer>,
    name: &str,
    size: u64,
    location: MemoryLocation,
) -> Result<u64> {
    let device = tracer.ctx.device.clone();
    if let Some(b) = which(&mut tracer.igi).as_ref() {
        if b.size >= size {
            return Ok(b.address);
        }
    }
    tracer.wait_idle()?;
    if let Some(mut old) = which(&mut tracer.igi).take() {
        old.destroy(&device, &mut tracer.allocator);
    }
    let usage = vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST;
    let b = GpuBuffer::new(&device, &mut tracer.allocator, name, size, usage, location)?;
    let address = b.address;
    *which(&mut tracer.igi) = Some(b);
    Ok(address)
}

impl Tracer {
    /// The addresses of the VPL, texel and vertex buffers for `params` (zeros when not IGI).
    pub(crate) fn igi_addresses(&mut self, params: &FrameParams) -> Result<[u64; 3]> {
        let Some(o) = params.igi else {
            return Ok([0; 3]);
        };
        let pixels = params.width as u64 * params.height as u64;
        o.validate().map_err(Error::Invalid)?;
        if params.output != platoon_core::frame::Output::Radiance {
            return Err(Error::Invalid("IGI renders radiance only".into()));
        }
        let vpls = ensure(
            self,
            |b| &mut b.vpls,
            "igi vpls",
            o.slots() as u64 * VPL_BYTES,
            MemoryLocation::GpuOnly,
        )?;
        let vertices = ensure(
            self,
            |b| &mut b.vertices,
            "igi vertices",
            pixels * VERTEX_BYTES,
            MemoryLocation::GpuOnly,
        )?;
        let texels = if o.filtered() {
            ensure(
                self,
                |b| &mut b.texels,
                "igi texels",
                pixels * TEXEL_BYTES,
                MemoryLocation::GpuToCpu,
            )?
        } else {
            0
        };
        Ok([vpls, texels, vertices])
    }

    /// The span's texels as (buffer, offset, size) when the gather is filtered: what the band
    /// clears before its first pass.
    pub(crate) fn igi_texel_range(
        &self,
        params: &FrameParams,
        span: Span,
    ) -> Option<(vk::Buffer, u64, u64)> {
        if !params.igi.is_some_and(|o| o.filtered()) {
            return None;
        }
        let b = self.igi.texels.as_ref()?;
        Some((
            b.buffer,
            span.begin as u64 * TEXEL_BYTES,
            span.len() as u64 * TEXEL_BYTES,
        ))
    }

    /// Shoots the frame's VPLs; returns the device time. (The next dispatch's barrier makes
    /// them visible to the gather.)
    pub(crate) fn emit_vpls(&mut self, params: &FrameParams, push: &Push) -> Result<Duration> {
        let Some(o) = params.igi else {
            return Ok(Duration::ZERO);
        };
        let mut defines = self.kernel_defines(params);
        defines.push(EMIT_VPLS);
        let kernel = self.kernel(defines)?;
        let query_pool = self.query_pool;
        let groups = o.paths.div_ceil(64);
        self.submit(|d, cb| unsafe {
            timestamp(d, cb, query_pool, 0);
            record_dispatch(d, cb, kernel, push, (groups, 1));
            timestamp(d, cb, query_pool, 1);
        })?;
        self.timestamps()
    }

    /// One sample of every pixel of the dispatch: the camera pass, then the gather passes over
    /// the VPLs a chunk at a time, in one submission; returns the device time.
    pub(crate) fn igi_sample(
        &mut self,
        params: &FrameParams,
        push: &Push,
        groups: (u32, u32),
    ) -> Result<Duration> {
        let Some(o) = params.igi else {
            return Ok(Duration::ZERO);
        };
        let mut defines = self.kernel_defines(params);
        let camera = self.kernel(defines.clone())?;
        defines.push(GATHER);
        let gather = self.kernel(defines)?;
        let chunk = GATHER_CHUNK * o.subsets();
        let slots = o.slots();
        let query_pool = self.query_pool;
        self.submit(|d, cb| unsafe {
            timestamp(d, cb, query_pool, 0);
            record_dispatch(d, cb, camera, push, groups);
            let mut first = 0;
            while first < slots {
                let end = (first + chunk).min(slots);
                let chunk = Push {
                    vpl_first: first,
                    vpl_end: end,
                    ..*push
                };
                record_dispatch(d, cb, gather, &chunk, groups);
                first = end;
            }
            timestamp(d, cb, query_pool, 1);
        })?;
        self.timestamps()
    }

    /// The span's texels, after the gather (empty unless the gather is filtered).
    pub(crate) fn read_texels(&mut self, params: &FrameParams, span: Span) -> Vec<IgiTexel> {
        if !params.igi.is_some_and(|o| o.filtered()) {
            return Vec::new();
        }
        let Some(b) = self.igi.texels.as_mut() else {
            return Vec::new();
        };
        let bytes = &b.mapped()
            [span.begin as usize * TEXEL_BYTES as usize..span.end as usize * TEXEL_BYTES as usize];
        bytemuck::pod_collect_to_vec(bytes)
    }

    /// Push-constant fields of IGI's options (zeros when not IGI).
    pub(crate) fn igi_push(params: &FrameParams, push: &mut Push) {
        if let Some(o) = params.igi {
            push.vpl_paths = o.paths;
            push.vpl_bounces = o.bounces;
            push.vpl_min_distance = o.min_distance;
            push.igi_downsample = o.downsample;
            push.igi_tile = o.interleave;
        }
    }
}

//! Light reuse on one device (`platoon_core::method::path::light_reuse`): the previous frame's
//! reservoirs of the whole image, with its camera and the reuse's settings, uploaded once a
//! frame (method buffer 2, read by the path kernels with LIGHT_REUSE), and the reservoirs the
//! frame's first vertices leave (method buffer 3, three vec4s a pixel of the frame), which the
//! band carries back per pixel.

use std::sync::Arc;

use gpu_allocator::MemoryLocation;
use platoon_core::frame::{FrameParams, PixelData, Span};
use platoon_core::method::path::light_reuse::{ReservoirHistory, ReservoirRecord};

use super::ensure;
use crate::buffer::GpuBuffer;
use crate::gpu::Gpu;
use crate::Result;

/// Bytes of a pixel's reservoir.
const RECORD_BYTES: usize = std::mem::size_of::<ReservoirRecord>();

#[derive(Default)]
pub(crate) struct LightReusePasses {
    history: Option<GpuBuffer>,
    reservoirs: Option<GpuBuffer>,
    /// The history (and first sample) the buffer holds: uploaded once a frame.
    uploaded: Option<(Arc<ReservoirHistory>, u32)>,
}

/// The history block light_reuse.glsl reads (its ReuseHistory): sizes and settings, the
/// previous frame's camera, then its reservoirs.
fn history_block(h: &ReservoirHistory, params: &FrameParams) -> Vec<u8> {
    let (width, height) = if h.has_frame() {
        (h.width, h.height)
    } else {
        (0, 0)
    };
    let b = h.camera.basis(width.max(1), height.max(1));
    let orthographic = if h.camera.orthographic.is_some() {
        1.0
    } else {
        0.0
    };
    let mut bytes = Vec::with_capacity(96 + h.records.len() * RECORD_BYTES);
    let size = [width, height, params.first_sample, h.options.neighbours];
    bytes.extend_from_slice(bytemuck::cast_slice(&size));
    let cap = (h.options.history
        * params
            .method
            .path()
            .resampled_light
            .map_or(1, |r| r.candidates.max(1))) as f32;
    let vec4s = [
        [h.options.radius, cap, 0.0, 0.0],
        b.origin.extend(0.0).to_array(),
        b.right.extend(b.tan_half_x).to_array(),
        b.up.extend(b.tan_half_y).to_array(),
        b.forward.extend(orthographic).to_array(),
    ];
    bytes.extend_from_slice(bytemuck::cast_slice(&vec4s));
    if width > 0 {
        bytes.extend_from_slice(bytemuck::cast_slice(&h.records));
    }
    bytes
}

impl LightReusePasses {
    /// Uploads the frame's history and sizes the reservoirs; the two buffers' addresses.
    pub fn prepare(&mut self, gpu: &mut Gpu, params: &FrameParams) -> Result<[u64; 2]> {
        let Some(history) = params.method.path().reused_light(params.output) else {
            return Ok([0; 2]);
        };
        let fresh = !self
            .uploaded
            .as_ref()
            .is_some_and(|(h, first)| Arc::ptr_eq(h, history) && *first == params.first_sample);
        let mut history_address = self.history.as_ref().map_or(0, |b| b.address);
        if fresh {
            let bytes = history_block(history, params);
            history_address = ensure(
                gpu,
                &mut self.history,
                "light reuse history",
                bytes.len() as u64,
                MemoryLocation::CpuToGpu,
            )?;
            let b = self.history.as_mut().expect("ensured just above");
            b.mapped()[..bytes.len()].copy_from_slice(&bytes);
            self.uploaded = Some((Arc::clone(history), params.first_sample));
        }
        let pixels = params.width as u64 * params.height as u64;
        let reservoirs = ensure(
            gpu,
            &mut self.reservoirs,
            "light reuse reservoirs",
            pixels.max(1) * RECORD_BYTES as u64,
            MemoryLocation::GpuToCpu,
        )?;
        Ok([history_address, reservoirs])
    }

    /// The span's reservoirs (after the band's last submission), one a pixel.
    pub fn reservoirs(&mut self, params: &FrameParams, span: Span) -> PixelData {
        if params.method.path().reused_light(params.output).is_none() {
            return PixelData::default();
        }
        let Some(b) = self.reservoirs.as_mut() else {
            return PixelData::default();
        };
        PixelData::of_span::<ReservoirRecord>(b.mapped(), span)
    }

    pub fn destroy(&mut self, gpu: &mut Gpu) {
        for mut b in [self.history.take(), self.reservoirs.take()]
            .into_iter()
            .flatten()
        {
            gpu.destroy_buffer(&mut b);
        }
        self.uploaded = None;
    }
}

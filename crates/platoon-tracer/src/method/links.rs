//! Vertex links on one device (platoon_core::method::links): the frames of the update, whose
//! pixels are rays (shooting) or elements (lighting), and the image frames that read the
//! solution. Their data arrive in the frame's job, shared by every tracer; each is uploaded once
//! (kept while the next frame names the same one).

use std::sync::Arc;
use std::time::Duration;

use gpu_allocator::MemoryLocation;
use platoon_core::frame::{FrameParams, PixelData, Span};
use platoon_core::method::links::job::ElementRays;
use platoon_core::method::links::{ElementAlbedo, Job, Links, ShotHit, Solution};

use super::{ensure, MethodPasses, Recorder};
use crate::buffer::GpuBuffer;
use crate::globals::{Push, METHOD_WORDS};
use crate::gpu::Gpu;
use crate::Result;

const SHOOT: &str = "links/shoot.comp";
const LIGHT: &str = "links/light.comp";
const CAMERA: &str = "links/camera.comp";

/// Samples an image pass adds per pixel at most: camera paths of many bounces in big scenes
/// stay within llvmpipe's loop limit (the path megakernel's fallback is not here).
const CAMERA_SAMPLES_PER_PASS: u32 = 4;

#[derive(Default)]
pub(crate) struct LinksPasses {
    /// Elements (shooting, lighting) or irradiance (image).
    first: Option<GpuBuffer>,
    /// Directions (shooting) or the element table (image).
    second: Option<GpuBuffer>,
    /// What shooting and lighting frames leave per pixel (host-visible: read back in place).
    output: Option<GpuBuffer>,
    /// The job whose data the buffers hold.
    uploaded: Option<Job>,
}

fn links(params: &FrameParams) -> &Links {
    params
        .method
        .state::<Links>()
        .expect("vertex links' passes render vertex links' frames")
}

fn job(params: &FrameParams) -> &Job {
    links(params)
        .job
        .as_ref()
        .expect("validated: a links frame has its job")
}

fn same_job(a: &Job, b: &Job) -> bool {
    match (a, b) {
        (Job::Shoot(x), Job::Shoot(y)) | (Job::Light(x), Job::Light(y)) => Arc::ptr_eq(x, y),
        (Job::Render(x), Job::Render(y)) => Arc::ptr_eq(x, y),
        _ => false,
    }
}

fn upload(gpu: &mut Gpu, slot: &mut Option<GpuBuffer>, name: &str, bytes: &[u8]) -> Result<u64> {
    let address = ensure(
        gpu,
        slot,
        name,
        (bytes.len() as u64).max(16),
        MemoryLocation::GpuOnly,
    )?;
    let buffer = slot.as_ref().expect("just ensured").buffer;
    gpu.write_buffers(&[(buffer, 0, bytes)])?;
    Ok(address)
}

impl LinksPasses {
    /// The elements, and the directions (shooting) or the fans (lighting, `fans` non-empty).
    fn upload_elements(&mut self, gpu: &mut Gpu, rays: &ElementRays) -> Result<[u64; 2]> {
        let second: &[u8] = if rays.fans.is_empty() {
            bytemuck::cast_slice(&rays.directions)
        } else {
            bytemuck::cast_slice(&rays.fans)
        };
        Ok([
            upload(
                gpu,
                &mut self.first,
                "links elements",
                bytemuck::cast_slice(&rays.elements),
            )?,
            upload(gpu, &mut self.second, "links directions or fans", second)?,
        ])
    }

    fn upload_solution(&mut self, gpu: &mut Gpu, s: &Solution) -> Result<[u64; 2]> {
        Ok([
            upload(
                gpu,
                &mut self.first,
                "links irradiance",
                bytemuck::cast_slice(&s.irradiance),
            )?,
            upload(
                gpu,
                &mut self.second,
                "links table",
                bytemuck::cast_slice(&s.table),
            )?,
        ])
    }
}

impl MethodPasses for LinksPasses {
    fn kernels(&self, params: &FrameParams, _cpu: bool) -> Vec<&'static str> {
        match job(params) {
            Job::Shoot(_) => vec![SHOOT],
            Job::Light(_) => vec![LIGHT],
            Job::Render(_) => vec![CAMERA],
        }
    }

    /// Shooting and lighting: elements, directions, the per-pixel output; image frames:
    /// irradiance and the element table.
    fn prepare(&mut self, gpu: &mut Gpu, params: &FrameParams) -> Result<[u64; 4]> {
        let job = job(params);
        let fresh = !self.uploaded.as_ref().is_some_and(|old| same_job(old, job));
        let address = |b: &Option<GpuBuffer>| b.as_ref().map_or(0, |b| b.address);
        let [first, second] = match job {
            Job::Shoot(rays) | Job::Light(rays) if fresh => self.upload_elements(gpu, rays)?,
            Job::Render(s) if fresh => self.upload_solution(gpu, s)?,
            _ => [address(&self.first), address(&self.second)],
        };
        self.uploaded = Some(job.clone());
        let output = match job {
            Job::Render(_) => 0,
            _ => ensure(
                gpu,
                &mut self.output,
                "links output",
                params.width as u64 * params.height as u64 * 16,
                MemoryLocation::GpuToCpu,
            )?,
        };
        Ok([first, second, output, 0])
    }

    /// The frame's element count (shooting, lighting) and whether they are single rays; or the
    /// solution's instance count, table
    /// length and element count (image).
    fn push_words(&self, params: &FrameParams) -> [u32; METHOD_WORDS] {
        let mut words = [0; METHOD_WORDS];
        match job(params) {
            Job::Shoot(rays) | Job::Light(rays) => {
                words[0] = rays.elements.len() as u32;
                words[1] = rays.single_rays as u32;
            }
            Job::Render(s) => {
                words[0] = s.instances;
                words[1] = s.table.len() as u32;
                words[2] = s.irradiance.len() as u32;
            }
        }
        words
    }

    fn samples_per_pass(&self, params: &FrameParams) -> u32 {
        let n = params.samples_per_pass.max(1);
        match job(params) {
            Job::Render(_) => n.min(CAMERA_SAMPLES_PER_PASS),
            _ => n,
        }
    }

    fn pass(&mut self, rec: &mut Recorder, push: &Push, groups: (u32, u32)) -> Result<Duration> {
        let entry = self.kernels(rec.params, false)[0];
        rec.dispatch(entry, push, groups)
    }

    /// A shooting frame's hits, a lighting frame's albedos.
    fn per_pixel(&mut self, params: &FrameParams, span: Span) -> PixelData {
        let job = job(params);
        if matches!(job, Job::Render(_)) {
            return PixelData::default();
        }
        let Some(b) = self.output.as_mut() else {
            return PixelData::default();
        };
        match job {
            Job::Shoot(_) => PixelData::of_span::<ShotHit>(b.mapped(), span),
            _ => PixelData::of_span::<ElementAlbedo>(b.mapped(), span),
        }
    }

    fn destroy(&mut self, gpu: &mut Gpu) {
        for mut b in [self.first.take(), self.second.take(), self.output.take()]
            .into_iter()
            .flatten()
        {
            gpu.destroy_buffer(&mut b);
        }
        self.uploaded = None;
    }
}

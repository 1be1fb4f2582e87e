//! The dispatch of one band of pixels: clear it (or start it from the sums of earlier samples),
//! have the frame's rendering method (`method::MethodPasses`) add its passes of samples with GPU
//! timestamps around each and end the band, copy it back with its per-line counters and what the method leaves
//! per pixel.

use std::time::{Duration, Instant};

use ash::vk;
use platoon_core::frame::{Band, BandTracer, FrameParams, Span, TracerError, ValidatedFrame};

use crate::globals::{Globals, Push};
use crate::gpu::record_copy_to_host;
use crate::method::{passes_of, MethodPasses, Recorder};
use crate::tracer::Tracer;
use crate::Result;

impl Tracer {
    /// Renders lines [y0, y1) of the frame at `params.spp` samples per pixel (fewer, in whole
    /// passes, when `params.options.time_limit` runs out first; the band says how many).
    pub fn render(
        &mut self,
        params: &FrameParams,
        y0: u32,
        y1: u32,
        progress: &mut dyn FnMut(u32),
    ) -> Result<Band> {
        self.render_strided(params, y0, y1, 1, progress)
    }

    /// Renders the pixels of `span` (which may start and end within a line).
    pub fn render_span(
        &mut self,
        params: &FrameParams,
        span: Span,
        progress: &mut dyn FnMut(u32),
    ) -> Result<Band> {
        self.render_pixels(params, span, 1, progress)
    }

    /// Renders lines y0, y0 + stride, ... below y1 (interleaved lines). The band's sums cover
    /// [y0, y1) with the lines not rendered left at zero.
    pub fn render_strided(
        &mut self,
        params: &FrameParams,
        y0: u32,
        y1: u32,
        stride: u32,
        progress: &mut dyn FnMut(u32),
    ) -> Result<Band> {
        let y1 = y1.min(params.height);
        let span = Span::lines(params.width, y0.min(y1), y1);
        self.render_pixels(params, span, stride, progress)
    }

    /// Renders `span`, of its lines only the first and every `stride`-th after it: for a
    /// caller who renders bands on the tracer directly, its frame checked first.
    fn render_pixels(
        &mut self,
        params: &FrameParams,
        span: Span,
        stride: u32,
        progress: &mut dyn FnMut(u32),
    ) -> Result<Band> {
        params.check().map_err(crate::Error::Invalid)?;
        self.render_checked(params, span, stride, progress)
    }

    /// The same for a frame whose rules passed (a renderer's `ValidatedFrame`, or checked by
    /// `render_pixels`): what the device refuses of it is what only the device knows (the
    /// scene's lights).
    fn render_checked(
        &mut self,
        params: &FrameParams,
        span: Span,
        stride: u32,
        progress: &mut dyn FnMut(u32),
    ) -> Result<Band> {
        let method = params.method.unit();
        method
            .check_scene(&self.features)
            .map_err(crate::Error::Invalid)?;
        // The method's device side is taken out while it records, and kept for the next band.
        let name = method.name();
        let mut passes = self
            .methods
            .remove(name)
            .unwrap_or_else(|| passes_of(&params.method));
        let band = self.render_with(passes.as_mut(), params, span, stride, progress);
        self.methods.insert(name, passes);
        band
    }

    fn render_with(
        &mut self,
        method: &mut dyn MethodPasses,
        params: &FrameParams,
        span: Span,
        stride: u32,
        progress: &mut dyn FnMut(u32),
    ) -> Result<Band> {
        let stride = stride.max(1);
        let (width, height) = (params.width, params.height);
        let pixels = width * height;
        let span = Span::new(span.begin.min(pixels), span.end.min(pixels));
        let span = Span::new(span.begin.min(span.end), span.end);
        let (y0, y1) = (span.first_line(width), span.end_line(width));
        self.ensure_frame_buffers(width, height)?;
        let defines = self.kernel_defines(params);
        let scene = self
            .scene
            .descriptors
            .as_ref()
            .expect("created with the tracer");
        // Compiling a kernel variant happens once; it is not part of the band's time.
        let kernels = method
            .kernels(params, self.gpu.ctx.info.cpu)
            .iter()
            .map(|&entry| Ok((entry, self.gpu.kernel((entry, defines.clone()), scene)?)))
            .collect::<Result<Vec<_>>>()?;
        let wall = Instant::now();
        let (accum, stats, readback) = match &self.frame_buffers {
            Some((_, _, a, s, r)) => ((a.buffer, a.address), (s.buffer, s.address), r.buffer),
            None => unreachable!("frame buffers were just created"),
        };

        let method_buffers = method.prepare(&mut self.gpu, params)?;
        let g = self
            .scene
            .globals
            .for_frame(params, accum.1, stats.1, method_buffers);
        self.globals_buffer.mapped()[..std::mem::size_of::<Globals>()]
            .copy_from_slice(bytemuck::bytes_of(&g));
        let globals_address = self.globals_buffer.address;

        // One vec4 per pixel.
        let band_offset = span.begin as u64 * 16;
        let band_size = span.len() as u64 * 16;
        let mut band = Band {
            span,
            ..Default::default()
        };
        if band_size == 0 {
            return Ok(band);
        }
        let compute_barrier = |d: &ash::Device,
                               cb: vk::CommandBuffer,
                               src: vk::PipelineStageFlags,
                               src_access: vk::AccessFlags| unsafe {
            let barrier = vk::MemoryBarrier::default()
                .src_access_mask(src_access)
                .dst_access_mask(vk::AccessFlags::SHADER_READ | vk::AccessFlags::SHADER_WRITE);
            d.cmd_pipeline_barrier(
                cb,
                src,
                vk::PipelineStageFlags::COMPUTE_SHADER,
                vk::DependencyFlags::empty(),
                &[barrier],
                &[],
                &[],
            );
        };
        // The band starts from the earlier samples' sums when the frame continues them.
        let start = match &params.film.accumulated {
            Some(sums) => {
                // (Its length is the frame's: `FrameParams::check`.)
                let range = span.begin as usize..span.end as usize;
                // The kernels leave pixels flagged converged (w = 2, PIXEL_CONVERGED in
                // shaders/path/path.glsl) as they are.
                let flag = |i: usize| match &params.film.converged {
                    Some(c) if c[i] => 2.0,
                    _ => 0.0,
                };
                Some(
                    range
                        .map(|i| [sums[i][0], sums[i][1], sums[i][2], flag(i)])
                        .collect::<Vec<_>>(),
                )
            }
            None => None,
        };
        if let Some(rows) = &start {
            self.gpu
                .write_buffers(&[(accum.0, band_offset, bytemuck::cast_slice(rows))])?;
        }
        // What the method's passes add onto is cleared with the rest.
        let clears = method.clears(params, span);
        self.gpu.submit(|d, cb| unsafe {
            if start.is_none() {
                d.cmd_fill_buffer(cb, accum.0, band_offset, band_size, 0);
            }
            d.cmd_fill_buffer(cb, stats.0, 0, vk::WHOLE_SIZE, 0);
            for &(buffer, offset, size) in &clears {
                d.cmd_fill_buffer(cb, buffer, offset, size, 0);
            }
            compute_barrier(
                d,
                cb,
                vk::PipelineStageFlags::TRANSFER,
                vk::AccessFlags::TRANSFER_WRITE,
            );
        })?;

        let push = Push {
            y0,
            y1,
            pixel_begin: span.begin,
            pixel_end: span.end,
            stride,
            // What a method's first pass may key its work by, besides frame and seed.
            sample_begin: params.first_sample,
            sample_end: params.first_sample,
            ..Push::of_frame(params, globals_address, method.push_words(params))
        };
        let Some((_, _, _, stats_buffer, _)) = self.frame_buffers.as_mut() else {
            unreachable!("frame buffers were just created")
        };
        let mut rec = Recorder {
            params,
            gpu: &mut self.gpu,
            kernels,
            defines,
            scene,
            stats: stats_buffer,
            fallbacks: 0,
            globals: &mut self.globals_buffer,
            globals_block: g,
        };
        band.gpu_time += method.begin_band(&mut rec, &push)?;

        let spp = params.spp;
        let per_pass = method.samples_per_pass(params);
        let groups = rec.band_groups(&push);
        let mut begin = 0;
        let mut pass_start = Duration::ZERO;
        // Under a time limit the first pass takes one sample and each next one at most twice
        // the last (up to a whole pass), as many as the time left allows at the last pass's
        // pace: a limit shorter than a whole pass ends after a sample, not a pass (issue 41,
        // defect 6). How the samples are cut into passes leaves the sums' bits as they are.
        let mut next = if params.options.time_limit.is_some() {
            1
        } else {
            per_pass
        };
        while begin < spp {
            let end = (begin + next).min(spp);
            let push = Push {
                sample_begin: params.first_sample.wrapping_add(begin),
                sample_end: params.first_sample.wrapping_add(end),
                ..push
            };
            band.gpu_time += method.pass(&mut rec, &push, groups)?;
            let taken = end - begin;
            begin = end;
            progress(end);
            if crate::stop::requested() {
                break;
            }
            let elapsed = wall.elapsed();
            let pass = elapsed - pass_start;
            pass_start = elapsed;
            if let Some(limit) = params.options.time_limit {
                let per_sample = pass.as_secs_f64() / taken as f64;
                let left = limit.saturating_sub(elapsed).as_secs_f64();
                let fits = (left / per_sample.max(1e-9)).min(u32::MAX as f64) as u32;
                next = (2 * taken).min(per_pass).min(fits);
                if next == 0 {
                    break;
                }
            }
        }
        band.samples = begin;
        let push = Push {
            sample_begin: params.first_sample,
            sample_end: params.first_sample.wrapping_add(begin),
            ..push
        };
        band.gpu_time += method.end_band(&mut rec, &push)?;
        band.kernel_fallbacks = rec.fallbacks;

        // The sums into the readback buffer; the counters (host-visible) made visible too.
        self.gpu.submit(|d, cb| unsafe {
            record_copy_to_host(d, cb, accum.0, band_offset, readback, band_size)
        })?;

        let Some((_, _, _, stats_buf, readback_buf)) = self.frame_buffers.as_mut() else {
            unreachable!()
        };
        let data: &[[f32; 4]] = bytemuck::cast_slice(&readback_buf.mapped()[..band_size as usize]);
        band.sums = data.iter().map(|p| [p[0], p[1], p[2]]).collect();
        let counters: &[u32] = bytemuck::cast_slice(stats_buf.mapped());
        band.rejected_samples = counters[0] as u64;
        band.line_rays = counters[4 + y0 as usize..4 + y1 as usize]
            .iter()
            .map(|&r| r as u64)
            .collect();
        band.rays = band.line_rays.iter().sum();
        band.per_pixel = method.per_pixel(params, span);
        band.method_report = method.report(counters);
        band.wall_time = wall.elapsed();
        Ok(band)
    }
}

impl BandTracer for Tracer {
    fn render_band(
        &mut self,
        frame: &ValidatedFrame,
        span: Span,
        progress: &mut dyn FnMut(u32),
    ) -> std::result::Result<Band, TracerError> {
        self.render_checked(frame, span, 1, progress)
            .map_err(|e| Box::new(e) as TracerError)
    }

    fn apply_commit(
        &mut self,
        commit: &platoon_core::flatten::commit::Commit,
    ) -> std::result::Result<u64, TracerError> {
        Tracer::apply_commit(self, commit)
            .map(|s| s.bytes)
            .map_err(|e| Box::new(e) as TracerError)
    }
    fn messages(&self) -> Vec<String> {
        self.validation_messages()
    }
    fn filter_atrous(
        &mut self,
        film: &platoon_core::output::Film,
        guides: &platoon_core::denoise::Guides,
    ) -> std::result::Result<platoon_core::output::Film, TracerError> {
        self.filter_atrous_timed(film, guides)
            .map(|(film, _)| film)
            .map_err(|e| Box::new(e) as TracerError)
    }
}

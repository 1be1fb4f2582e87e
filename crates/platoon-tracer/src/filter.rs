//! The à-trous denoiser on this device (shaders/denoise/atrous.comp): a whole assembled frame
//! and its guides in, the filtered frame out. The CPU filter (`platoon_core::denoise::atrous`)
//! is its reference; on the device its 25 taps of five iterations run in the kernel's lanes,
//! where the CPU's cores are what a game's update needs.

use std::time::Duration;

use gpu_allocator::MemoryLocation;
use platoon_core::denoise::Guides;
use platoon_core::output::Film;

use crate::dispatch::record_dispatch;
use crate::globals::{Globals, Push, METHOD_WORDS};
use crate::method::ensure;
use crate::tracer::Tracer;
use crate::Result;

const ENTRY: &str = "denoise/atrous.comp";
/// The kernel's planes (its header lists them), a vec4 per pixel each.
const PLANES: u64 = 5;
/// Holes 1, 2, 4, 8, 16, as the CPU filter's.
const ITERATIONS: u32 = 5;
const GROUP: u32 = 64;

impl Tracer {
    /// `film` filtered by the edge-avoiding à-trous wavelet filter with `guides` (of the same
    /// size), and the device time it took.
    pub fn filter_atrous_timed(
        &mut self,
        film: &Film,
        guides: &Guides,
    ) -> Result<(Film, Duration)> {
        let n = film.width as usize * film.height as usize;
        if guides.albedo.len() != n
            || guides.normal.len() != n
            || guides.depth.len() != n
            || guides.variance.as_ref().is_some_and(|v| v.len() != n)
        {
            return Err(crate::Error::Invalid(format!(
                "the denoiser's guides hold {} pixels, the frame {}x{}",
                guides.depth.len(),
                film.width,
                film.height
            )));
        }
        if n == 0 {
            return Ok((film.clone(), Duration::ZERO));
        }
        let plane = n as u64 * 16;
        let address = ensure(
            &mut self.gpu,
            &mut self.filter_planes,
            "denoiser planes",
            PLANES * plane,
            MemoryLocation::GpuOnly,
        )?;
        let buffer = self
            .filter_planes
            .as_ref()
            .expect("ensured just above")
            .buffer;
        // The history's variance where it has one; negative: the kernel's window estimates it.
        let given = |i: usize| match &guides.variance {
            Some(v) if !v[i].is_nan() => v[i],
            _ => -1.0,
        };
        let colour: Vec<[f32; 4]> = film
            .pixels
            .iter()
            .enumerate()
            .map(|(i, c)| [c[0], c[1], c[2], given(i)])
            .collect();
        let albedo: Vec<[f32; 4]> = (0..n)
            .map(|i| {
                let a = guides.albedo[i];
                [a[0], a[1], a[2], guides.depth[i]]
            })
            .collect();
        let normal: Vec<[f32; 4]> = guides
            .normal
            .iter()
            .map(|v| [v[0], v[1], v[2], 0.0])
            .collect();
        self.gpu.write_buffers(&[
            (buffer, 0, bytemuck::cast_slice(&colour)),
            (buffer, 2 * plane, bytemuck::cast_slice(&albedo)),
            (buffer, 3 * plane, bytemuck::cast_slice(&normal)),
        ])?;

        // The scene's addresses stay; method buffer 0 names the planes. A band rewrites the
        // block before its own passes.
        let mut g: Globals = self.scene.globals;
        g.method_buffers = [address, 0, 0, 0];
        self.globals_buffer.mapped()[..std::mem::size_of::<Globals>()]
            .copy_from_slice(bytemuck::bytes_of(&g));
        let scene = self
            .scene
            .descriptors
            .as_ref()
            .expect("created with the tracer");
        let defines = crate::memory::defines(&self.scene.paths);
        let kernel = self.gpu.kernel((ENTRY, defines), scene)?;
        let push = |words: [u32; 6]| {
            let mut method = [0u32; METHOD_WORDS];
            method[..6].copy_from_slice(&words);
            Push {
                globals: self.globals_buffer.address,
                method,
                ..Default::default()
            }
        };
        let (w, h) = (film.width, film.height);
        let mut stages = vec![push([0, 0, w, h, 0, 1])];
        for i in 0..ITERATIONS {
            // Stage 0 left the frame in plane 1; each iteration writes the other plane.
            let (source, destination) = if i % 2 == 0 { (1, 0) } else { (0, 1) };
            stages.push(push([1, 0, w, h, source, 0]));
            stages.push(push([2, 1 << i, w, h, source, destination]));
        }
        let last = if ITERATIONS % 2 == 1 { 0 } else { 1 };
        let groups = (n as u32).div_ceil(GROUP);
        let time = self.gpu.timed(|d, cb| unsafe {
            for push in &stages {
                record_dispatch(d, cb, kernel, push, (groups, 1));
            }
        })?;
        // read_buffer's copy waits for the kernels' writes (record_copy_to_host's barrier).
        let bytes = self.gpu.read_buffer(buffer, last * plane, plane)?;
        let out: &[[f32; 4]] = bytemuck::cast_slice(&bytes);
        Ok((
            Film {
                width: w,
                height: h,
                pixels: out.iter().map(|p| [p[0], p[1], p[2]]).collect(),
            },
            time,
        ))
    }
}

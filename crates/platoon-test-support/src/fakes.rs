//! Tracers for the tests of renderers (platoon-schedule) and ranks (platoon-distribute): CPU
//! fakes whose pixels are a function of the pixel, the frame and the film they continue.

use std::sync::Arc;
use std::time::Duration;

use platoon_frame::flatten::commit::Commit;
use platoon_frame::frame::{Band, BandTracer, Span, TracerError, ValidatedFrame};

/// A CPU tracer whose pixels are a fixed function of (x, y, frame) added onto the
/// accumulated sums, as the kernel continues them; `slowness` sets its speed.
pub struct Fake {
    pub slowness: u64,
}

impl BandTracer for Fake {
    fn render_band(
        &mut self,
        p: &ValidatedFrame,
        span: Span,
        _: &mut dyn FnMut(u32),
    ) -> Result<Band, TracerError> {
        let first = span.first_line(p.width);
        let mut line_rays = vec![0; (span.end_line(p.width) - first) as usize];
        let mut sums = Vec::new();
        for i in span.begin..span.end {
            let (x, y) = (i % p.width, i / p.width);
            let before = p
                .film
                .accumulated
                .as_ref()
                .map_or([0.0; 3], |a| a[i as usize]);
            let done = p.film.converged.as_ref().is_some_and(|c| c[i as usize]);
            let add = if done {
                0.0
            } else {
                (x * 7 + y * 13 + p.frame) as f32 * 0.1
            };
            sums.push(before.map(|v| v + add));
            line_rays[(y - first) as usize] += if y < p.height / 2 { 1 } else { 8 };
        }
        let rays = line_rays.iter().sum::<u64>();
        std::thread::sleep(Duration::from_micros(rays * self.slowness * 3));
        Ok(Band {
            span,
            sums,
            rays,
            line_rays,
            wall_time: Duration::from_micros(rays * self.slowness * 3),
            ..Default::default()
        })
    }
}

/// A tracer that keeps the headers of the commits it applied.
pub struct Keeping(pub Arc<std::sync::Mutex<Vec<u32>>>);

impl BandTracer for Keeping {
    fn render_band(
        &mut self,
        p: &ValidatedFrame,
        span: Span,
        progress: &mut dyn FnMut(u32),
    ) -> Result<Band, TracerError> {
        Fake { slowness: 0 }.render_band(p, span, progress)
    }
    fn apply_commit(&mut self, c: &Commit) -> Result<u64, TracerError> {
        self.0.lock().unwrap().push(c.header.lights);
        Ok(c.arrays.iter().map(|a| a.data.len() as u64).sum())
    }
}

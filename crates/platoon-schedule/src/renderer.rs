//! The frame loop over many tracers: each frame the balancer cuts the pixels into one band per
//! tracer, every tracer renders its band on its own thread (with stealing, its head and what
//! it claims of the bands' tails: `balance::steal`), the core assembles the image. A tracer
//! that fails (device lost, timeout, error) is dropped, its lines are rendered by the
//! survivors in the same frame (`rounds`), and the failure is reported once.

use std::sync::Arc;
use std::time::{Duration, Instant};

pub use crate::outcome::{RenderError, TracerFailure, TracerStats};
use crate::rounds::{check_cover, piece_overhead, planned_round, stolen_round, Gathered};
use crate::workers::Worker;
use platoon_frame::balance::steal::{unstolen_seconds, ClaimBoard, Stealing};
use platoon_frame::balance::steal_history::StealHistory;
use platoon_frame::balance::{idle_fraction, Balancer, FrameMeasure, TracerFrame};
use platoon_frame::denoise::{DeviceFilter, Guides};
use platoon_frame::flatten::commit::Commit;
use platoon_frame::frame::{
    assemble, gather_sums, Band, BandTracer, FrameParams, MethodReport, PixelData, Span,
    ValidatedFrame,
};
use platoon_frame::output::Film;

pub struct FrameResult {
    pub film: Film,
    /// Each pixel's radiance sum (with `FrameParams::accumulated` when the frame continued
    /// one): what a film accumulating over frames keeps.
    pub sums: Vec<[f32; 3]>,
    /// Samples each pixel holds: the least of the bands' (below `FrameParams::spp` when a
    /// time limit ended the frame's band early).
    pub spp: u32,
    pub tracers: Vec<TracerStats>,
    /// Rays traced in each line of the frame (its cost map, as the balancer saw it).
    pub line_rays: Vec<u64>,
    /// sum_i (T_max - T_i) / (n T_max) over the tracers' planned bands.
    pub idle_fraction: f64,
    /// Tracers that failed during this frame (each is reported in exactly one frame).
    pub failures: Vec<TracerFailure>,
    pub wall_time: Duration,
    pub rejected_samples: u64,
    /// Megakernel passes finished by the streaming kernels (`Band::kernel_fallbacks`).
    pub kernel_fallbacks: u32,
    /// What the bands left per pixel (`Band::per_pixel`), in pixel order; empty when nothing.
    pub per_pixel: PixelData,
    /// What the method reported on the band of the frame's first pixels (`Band::method_report`).
    pub method_report: MethodReport,
}

pub struct Renderer<T: BandTracer + Send + 'static> {
    /// Surviving tracers with their original indices, each on its own thread.
    tracers: Vec<(usize, Worker<T>)>,
    balancer: Box<dyn Balancer>,
    failures: Vec<TracerFailure>,
    /// The bands of the last frame, for a frame that keeps them.
    last_bands: Vec<Span>,
    /// Whether a band's tail may be taken by others (`balance::steal`), and how it is cut.
    stealing: Option<Stealing>,
    /// What the frames so far tell stealing: line costs, a piece's overhead, the idle to
    /// expect without it.
    history: StealHistory,
}

impl<T: BandTracer + Send + 'static> DeviceFilter for Renderer<T> {
    fn atrous(&mut self, film: &Film, guides: &Guides) -> Result<Film, String> {
        self.filter_atrous(film, guides)
    }
}

impl<T: BandTracer + Send + 'static> Renderer<T> {
    /// The renderer of `tracers`, its frames cut by `balancer` (and stolen as it says,
    /// `Balancer::stealing`).
    pub fn new(tracers: Vec<T>, balancer: Box<dyn Balancer>) -> Renderer<T> {
        let stealing = balancer.stealing();
        Renderer {
            tracers: tracers
                .into_iter()
                .enumerate()
                .map(|(i, t)| (i, Worker::start(i, t)))
                .collect(),
            balancer,
            failures: Vec::new(),
            last_bands: Vec::new(),
            stealing,
            history: StealHistory::default(),
        }
    }

    /// Lets tracers done with their band take the unstarted chunks of others' tails in the
    /// same frame (`balance::steal`); None: each renders its band alone. The image is the
    /// same bits either way.
    pub fn set_stealing(&mut self, stealing: Option<Stealing>) {
        self.stealing = stealing;
    }

    pub fn balancer_name(&self) -> &'static str {
        self.balancer.name()
    }

    /// Cuts the next frames with `balancer` (which learns the tracers' speeds afresh), and
    /// steals as it says.
    pub fn set_balancer(&mut self, balancer: Box<dyn Balancer>) {
        self.stealing = balancer.stealing();
        self.balancer = balancer;
    }

    /// Original indices of the tracers still working.
    pub fn alive(&self) -> Vec<usize> {
        self.tracers.iter().map(|(i, _)| *i).collect()
    }

    /// Every failure so far.
    pub fn failures(&self) -> &[TracerFailure] {
        &self.failures
    }

    /// The surviving tracers, for reuse under another balancer.
    pub fn into_tracers(self) -> Vec<T> {
        self.tracers
            .into_iter()
            .filter_map(|(_, w)| w.into_tracer())
            .collect()
    }

    /// `f` of every surviving tracer, between frames (device names, kernel defines, messages).
    pub fn with_tracers<R>(&self, mut f: impl FnMut(&mut T) -> R) -> Vec<R> {
        self.tracers
            .iter()
            .filter_map(|(_, w)| w.lock().map(|mut t| f(&mut t)))
            .collect()
    }

    /// `film` filtered by the à-trous kernel on the first surviving tracer's device: one device
    /// filters the whole assembled frame, so the image does not depend on the split.
    pub fn filter_atrous(&self, film: &Film, guides: &Guides) -> Result<Film, String> {
        let (index, worker) = self
            .tracers
            .first()
            .ok_or("no tracer left to filter the frame on")?;
        let mut tracer = worker
            .lock()
            .ok_or_else(|| format!("tracer {index} panicked"))?;
        tracer
            .filter_atrous(film, guides)
            .map_err(|e| format!("filtering the frame on tracer {index}: {e}"))
    }

    /// Gives every tracer the next generation of the scene (`commit`: what changed since the
    /// one they hold), before the frame that renders it; returns each survivor's (tracer, bytes
    /// uploaded). A tracer that fails to apply it is dropped and reported like one that fails
    /// to render: the others render its lines, on the new generation.
    pub fn apply_commit(
        &mut self,
        commit: &Arc<Commit>,
        frame: u32,
    ) -> Result<Vec<(usize, u64)>, RenderError> {
        // Each tracer applies it on its own thread, as each renders its band.
        for (_, worker) in &self.tracers {
            worker.start_commit(commit);
        }
        let results: Vec<Result<u64, String>> = self
            .tracers
            .iter()
            .map(|(_, w)| w.committed().map_err(|e| e.to_string()))
            .collect();
        let mut uploaded = Vec::with_capacity(results.len());
        for (slot, result) in results.into_iter().enumerate().rev() {
            let id = self.tracers[slot].0;
            match result {
                Ok(bytes) => uploaded.push((id, bytes)),
                Err(message) => {
                    self.failures.push(TracerFailure {
                        tracer: id,
                        frame,
                        message: format!("applying a scene commit: {message}"),
                    });
                    self.tracers.remove(slot);
                    self.balancer.remove_tracer(slot);
                }
            }
        }
        uploaded.reverse();
        if self.tracers.is_empty() {
            return Err(RenderError::NoTracers(
                "every tracer failed to apply the scene commit".into(),
            ));
        }
        Ok(uploaded)
    }

    pub fn render_frame(&mut self, params: &FrameParams) -> Result<FrameResult, RenderError> {
        self.render_frame_planned(params, true)
    }

    /// Renders a frame as `render_frame` does; `progress` hears the samples each pixel holds
    /// as passes end when one tracer renders it (several render their bands at once: no one
    /// count says how far the frame is).
    pub fn render_frame_with_progress(
        &mut self,
        params: &FrameParams,
        progress: &mut dyn FnMut(u32),
    ) -> Result<FrameResult, RenderError> {
        let planned = self.plan(params, true)?;
        self.render_bands(params, planned, true, progress)
    }

    /// Renders a frame, cut anew by the balancer when `rebalance`, else in the last frame's
    /// bands (when they still fit: same frame size, same tracers). The balancer learns from the
    /// frame either way.
    pub fn render_frame_planned(
        &mut self,
        params: &FrameParams,
        rebalance: bool,
    ) -> Result<FrameResult, RenderError> {
        let planned = self.plan(params, rebalance)?;
        self.render_bands(params, planned, true, &mut |_| {})
    }

    /// The frame's bands: cut anew when `rebalance`, else the last frame's when they fit.
    fn plan(&mut self, params: &FrameParams, rebalance: bool) -> Result<Vec<Span>, RenderError> {
        if self.tracers.is_empty() {
            return Err(RenderError::NoTracers("every tracer has failed".into()));
        }
        let pixels = params.width * params.height;
        let planned = if rebalance || !self.last_bands_fit(pixels) {
            self.balancer
                .plan(params.width, params.height, self.tracers.len())
        } else {
            self.last_bands.clone()
        };
        self.last_bands = planned.clone();
        Ok(planned)
    }

    /// Renders a side pass of a frame (a denoiser's guides): in the last frame's bands when
    /// they fit, else in equal ones, and the balancer neither cuts it nor learns from it, so
    /// the beauty's cut stays the beauty's.
    pub fn render_side_pass(&mut self, params: &FrameParams) -> Result<FrameResult, RenderError> {
        if self.tracers.is_empty() {
            return Err(RenderError::NoTracers("every tracer has failed".into()));
        }
        let pixels = params.width * params.height;
        let bands = if self.last_bands_fit(pixels) {
            self.last_bands.clone()
        } else {
            let n = self.tracers.len() as u64;
            let at = |k: u64| (pixels as u64 * k / n) as u32;
            (0..n).map(|k| Span::new(at(k), at(k + 1))).collect()
        };
        self.render_bands(params, bands, false, &mut |_| {})
    }

    fn last_bands_fit(&self, pixels: u32) -> bool {
        self.last_bands.len() == self.tracers.len()
            && self.last_bands.last().is_some_and(|b| b.end == pixels)
    }

    /// Renders `planned` (a band per tracer), the lost bands of failed tracers by the
    /// survivors; the balancer observes the frame when `learn`.
    fn render_bands(
        &mut self,
        params: &FrameParams,
        planned: Vec<Span>,
        learn: bool,
        progress: &mut dyn FnMut(u32),
    ) -> Result<FrameResult, RenderError> {
        let start = Instant::now();
        let part = self.render_part(params, planned, learn, (0, params.height), progress)?;
        Ok(frame_of(params, part, start))
    }

    /// Renders the pixels `span` of the frame `params` (a rank's share of a frame split
    /// between machines, `platoon-distribute`): the balancer cuts it between the tracers as it
    /// would a frame of the lines the span touches, and learns from it. The bands come back
    /// as they are, for whoever assembles the frame.
    pub fn render_within(
        &mut self,
        params: &FrameParams,
        span: Span,
    ) -> Result<PartResult, RenderError> {
        if self.tracers.is_empty() {
            return Err(RenderError::NoTracers("every tracer has failed".into()));
        }
        let w = params.width;
        let window = (span.first_line(w), span.end_line(w));
        let base = window.0 * w;
        let planned = self
            .balancer
            .plan(w, window.1 - window.0, self.tracers.len())
            .into_iter()
            .map(|s| {
                let at = |p: u32| (p + base).clamp(span.begin, span.end);
                Span::new(at(s.begin), at(s.end))
            })
            .collect();
        self.render_part(params, planned, true, window, &mut |_| {})
    }

    /// The bands of `planned` rendered (failed tracers' by the survivors); the balancer,
    /// when `learn`, observes them as a frame of the lines `window` (y0, y1).
    fn render_part(
        &mut self,
        params: &FrameParams,
        planned: Vec<Span>,
        learn: bool,
        window: (u32, u32),
        progress: &mut dyn FnMut(u32),
    ) -> Result<PartResult, RenderError> {
        let params = &Arc::new(ValidatedFrame::new(params.clone()).map_err(RenderError::Invalid)?);
        let mut g = Gathered::new(&self.tracers, &planned);
        // The first round: the planned bands, their tails shared when stealing; each
        // tracer's time in it, for idle and for the balancer.
        let mut times = match self.board(params, &planned) {
            Some(board) => stolen_round(&self.tracers, board, params, &mut g),
            None => planned_round(&self.tracers, &planned, params, &mut g, progress),
        };
        self.recover(params, &mut g, &mut times)?;
        check_cover(&planned, &g.done)?;

        let Gathered {
            mut stats,
            done,
            failures: new_failures,
            claimed,
            ..
        } = g;
        stats.retain(|s| self.tracers.iter().any(|(id, _)| *id == s.tracer));
        let max = times.iter().copied().fold(0.0, f64::max);
        for (s, t) in stats.iter_mut().zip(&times) {
            s.idle = Duration::from_secs_f64(max - t);
        }
        // A frame with a failure measured a split that no longer exists: learn nothing from it.
        if learn && new_failures.is_empty() {
            let (y0, y1) = window;
            let base = y0 * params.width;
            let all_costs: Vec<f64> = line_rays_of(params, &done)
                .iter()
                .map(|&r| r as f64)
                .collect();
            let line_costs = &all_costs[y0 as usize..y1 as usize];
            let observed: Vec<TracerFrame> = stats
                .iter()
                .zip(&times)
                .map(|(s, &t)| TracerFrame {
                    span: Span::new(s.span.begin - base, s.span.end - base),
                    seconds: claimed
                        .iter()
                        .find(|c| c.tracer == s.tracer)
                        .map_or(t, |c| {
                            unstolen_seconds(&all_costs, params.width, s.span, &c.spans(), t)
                        }),
                })
                .collect();
            self.balancer.observe(&FrameMeasure {
                width: params.width,
                height: y1 - y0,
                tracers: &observed,
                line_costs,
            });
            let unstolen: Vec<f64> = observed.iter().map(|t| t.seconds).collect();
            let overhead = piece_overhead(&all_costs, params.width, &claimed);
            self.history.learn(
                all_costs,
                times.iter().copied().fold(0.0, f64::max),
                idle_fraction(&unstolen),
                overhead,
            );
        }
        self.failures.extend(new_failures.iter().cloned());
        Ok(PartResult {
            bands: done,
            idle_fraction: idle_fraction(&times),
            tracers: stats,
            failures: new_failures,
        })
    }

    /// Drops the tracers that failed and has the survivors render what they lost, in this
    /// same frame, until nothing is lost (or no tracer is left: an error naming every failure).
    fn recover(
        &mut self,
        params: &Arc<ValidatedFrame>,
        g: &mut Gathered,
        times: &mut Vec<f64>,
    ) -> Result<(), RenderError> {
        loop {
            // Highest slot first, so that lower slots keep their meaning.
            g.dead.sort_unstable_by_key(|&slot| std::cmp::Reverse(slot));
            for slot in g.dead.drain(..) {
                self.tracers.remove(slot);
                self.balancer.remove_tracer(slot);
                times.remove(slot);
            }
            if g.lost.is_empty() {
                return Ok(());
            }
            if self.tracers.is_empty() {
                self.failures.extend(g.failures.iter().cloned());
                let why: Vec<String> = g
                    .failures
                    .iter()
                    .map(|f| format!("tracer {}: {}", f.tracer, f.message))
                    .collect();
                return Err(RenderError::NoTracers(why.join("; ")));
            }
            let n = self.tracers.len() as u64;
            let mut shares: Vec<Span> = std::mem::take(&mut g.lost)
                .iter()
                .flat_map(|lost| {
                    let len = lost.len() as u64;
                    let at = move |k: u64| lost.begin + (len * k / n) as u32;
                    (0..n).map(move |k| Span::new(at(k), at(k + 1)))
                })
                .filter(|s| !s.is_empty())
                .collect();
            while !shares.is_empty() {
                let round: Vec<Span> = (0..self.tracers.len())
                    .map(|_| shares.pop().unwrap_or_default())
                    .collect();
                planned_round(&self.tracers, &round, params, g, &mut |_| {});
                if !g.dead.is_empty() {
                    g.lost.append(&mut shares);
                    break;
                }
            }
        }
    }

    /// The claim board of `planned` when this renderer steals, the frame may be split and
    /// stealing pays (`StealHistory::board`).
    fn board(&self, params: &FrameParams, planned: &[Span]) -> Option<ClaimBoard> {
        let stealing = self.stealing.as_ref()?;
        if self.tracers.len() < 2 || params.check_split(2).is_err() {
            return None;
        }
        self.history
            .board(stealing, planned, params.width, params.height)
    }
}

/// What the tracers rendered of a part of a frame (all of it, or a rank's span): the bands
/// as they came back.
#[derive(Debug, Default)]
pub struct PartResult {
    pub bands: Vec<Band>,
    pub tracers: Vec<TracerStats>,
    /// sum_i (T_max - T_i) / (n T_max) over the tracers' planned bands.
    pub idle_fraction: f64,
    pub failures: Vec<TracerFailure>,
}

/// Rays traced in each line of the frame from its bands, a line cut between two bands counted
/// by both, each for its pixels.
pub fn line_rays_of(params: &FrameParams, bands: &[Band]) -> Vec<u64> {
    let mut line_rays = vec![0u64; params.height as usize];
    for b in bands {
        let first = b.span.first_line(params.width) as usize;
        for (k, r) in b.line_rays.iter().enumerate() {
            if let Some(l) = line_rays.get_mut(first + k) {
                *l += r;
            }
        }
    }
    line_rays
}

/// The frame from bands covering it: the method's pass over the whole frame (what needs
/// neighbours across band edges), then the image and what the bands counted; its wall time
/// from `start`.
pub fn frame_of(params: &FrameParams, part: PartResult, start: Instant) -> FrameResult {
    let PartResult {
        bands: mut done,
        tracers,
        idle_fraction,
        failures,
    } = part;
    params.method.unit().finish(params, &mut done);
    FrameResult {
        film: assemble(params, &done),
        sums: gather_sums(params, &done),
        spp: done
            .iter()
            .map(|b| b.spp(params))
            .min()
            .unwrap_or(params.spp),
        line_rays: line_rays_of(params, &done),
        per_pixel: per_pixel_in_order(&mut done),
        method_report: first_report(&done),
        idle_fraction,
        rejected_samples: done.iter().map(|b| b.rejected_samples).sum(),
        kernel_fallbacks: done.iter().map(|b| b.kernel_fallbacks).sum(),
        tracers,
        failures,
        wall_time: start.elapsed(),
    }
}

/// The method's report of the band that starts first (every tracer builds what a method's
/// report describes the same; its counts are that band's).
pub fn first_report(bands: &[Band]) -> MethodReport {
    bands
        .iter()
        .filter(|b| !b.method_report.is_empty())
        .min_by_key(|b| b.span.begin)
        .map(|b| b.method_report.clone())
        .unwrap_or_default()
}

/// The bands' `per_pixel` data joined in pixel order (taken out of them).
pub fn per_pixel_in_order(bands: &mut [Band]) -> PixelData {
    let mut order: Vec<usize> = (0..bands.len()).collect();
    order.sort_by_key(|&i| bands[i].span.begin);
    let mut joined = PixelData::default();
    for i in order {
        joined.append(std::mem::take(&mut bands[i].per_pixel));
    }
    joined
}

#[cfg(test)]
mod tests {
    use super::*;
    use platoon_frame::balance::{by_name, NAMES};
    use platoon_frame::frame::TracerError;
    use platoon_frame::scene::camera::Camera;
    use platoon_test_support::fakes::Fake;
    use platoon_test_support::fault::FaultInjector;

    /// A fake that, when `refuse`, fails every scene commit, as a lost device would.
    struct Committing {
        fake: Fake,
        refuse: bool,
    }

    impl BandTracer for Committing {
        fn render_band(
            &mut self,
            p: &ValidatedFrame,
            span: Span,
            progress: &mut dyn FnMut(u32),
        ) -> Result<Band, TracerError> {
            self.fake.render_band(p, span, progress)
        }

        fn apply_commit(
            &mut self,
            _: &platoon_frame::flatten::commit::Commit,
        ) -> Result<u64, TracerError> {
            if self.refuse {
                return Err("device lost".into());
            }
            Ok(0)
        }
    }

    #[test]
    fn a_tracer_that_cannot_apply_a_commit_is_dropped_and_the_frame_still_completes() {
        let tracers: Vec<Committing> = [false, true, false]
            .map(|refuse| Committing {
                fake: Fake { slowness: 1 },
                refuse,
            })
            .into();
        let mut r = Renderer::new(tracers, by_name("cost-aware").unwrap());
        let uploaded = r.apply_commit(&Arc::new(Commit::default()), 3).unwrap();
        assert_eq!(uploaded, vec![(0, 0), (2, 0)]);
        assert_eq!(r.alive(), vec![0, 2]);
        assert_eq!(r.failures().len(), 1);
        assert_eq!((r.failures()[0].tracer, r.failures()[0].frame), (1, 3));
        assert!(r.failures()[0].message.contains("device lost"));
        let frame = r.render_frame(&params(3)).unwrap();
        assert_eq!(frame.tracers.iter().map(|t| t.pixels).sum::<u32>(), 160);
    }

    fn params(frame: u32) -> FrameParams {
        let mut p = FrameParams::new(
            4,
            40,
            1,
            Camera::look_at(glam::Vec3::Z, glam::Vec3::ZERO, 1.0),
        );
        p.frame = frame;
        p
    }

    /// A frame that breaks a tracer's rules is refused once, before any tracer renders it:
    /// every tracer stays, and the next frame renders.
    #[test]
    fn a_wrong_frame_is_refused_and_drops_no_tracer() {
        let mut r = Renderer::new(
            vec![Fake { slowness: 1 }, Fake { slowness: 1 }],
            by_name("cost-aware").unwrap(),
        );
        let mut wrong = params(0);
        wrong.path_loop.rr_survival = 0.0;
        match r.render_frame(&wrong) {
            Err(RenderError::Invalid(e)) => assert!(e.contains("survival"), "{e}"),
            other => panic!("{:?}", other.map(|f| f.tracers.len())),
        }
        assert_eq!(r.alive(), vec![0, 1]);
        assert!(r.failures().is_empty());
        assert!(r.render_frame(&params(1)).is_ok());
    }

    #[test]
    fn every_balancer_assembles_the_same_frame() {
        let reference = Renderer::new(vec![Fake { slowness: 1 }], by_name("none").unwrap())
            .render_frame(&params(0))
            .unwrap()
            .film;
        for name in NAMES {
            let mut r = Renderer::new(
                vec![
                    Fake { slowness: 1 },
                    Fake { slowness: 2 },
                    Fake { slowness: 3 },
                ],
                by_name(name).unwrap(),
            );
            for _ in 0..3 {
                let f = r.render_frame(&params(0)).unwrap();
                assert_eq!(f.film, reference, "{name}");
                assert_eq!(f.tracers.iter().map(|s| s.pixels).sum::<u32>(), 160);
                assert!(f.idle_fraction >= 0.0 && f.idle_fraction < 1.0);
            }
        }
    }

    #[test]
    fn a_frame_that_does_not_rebalance_keeps_the_last_bands() {
        let fakes = vec![Fake { slowness: 1 }, Fake { slowness: 3 }];
        let mut r = Renderer::new(fakes, by_name("perfect").unwrap());
        let bands = |f: &FrameResult| f.tracers.iter().map(|t| t.span).collect::<Vec<_>>();
        let first = r.render_frame(&params(0)).unwrap();
        // Perfect moves the cut after the first frame (the tracers' speeds differ 3 to 1)...
        let kept = r.render_frame_planned(&params(1), false).unwrap();
        assert_eq!(bands(&kept), bands(&first));
        let moved = r.render_frame_planned(&params(2), true).unwrap();
        assert_ne!(bands(&moved), bands(&first));
        // ...and a kept cut is still the whole frame, the same image.
        let reference = Renderer::new(vec![Fake { slowness: 1 }], by_name("none").unwrap())
            .render_frame(&params(1))
            .unwrap()
            .film;
        assert_eq!(kept.film, reference);
    }

    #[test]
    fn a_failing_tracer_loses_no_lines_and_is_reported_once() {
        let tracers = vec![
            FaultInjector::healthy(Fake { slowness: 1 }),
            FaultInjector::failing_from(Fake { slowness: 1 }, 2),
            FaultInjector::healthy(Fake { slowness: 1 }),
        ];
        let mut r = Renderer::new(tracers, by_name("cost-aware").unwrap());
        let mut reported = Vec::new();
        for frame in 0..6 {
            let f = r.render_frame(&params(frame)).unwrap();
            let expected = Renderer::new(vec![Fake { slowness: 1 }], by_name("none").unwrap())
                .render_frame(&params(frame))
                .unwrap()
                .film;
            assert_eq!(f.film, expected, "frame {frame} incomplete");
            reported.extend(f.failures);
            assert_eq!(f.tracers.len(), if frame < 2 { 3 } else { 2 });
        }
        assert_eq!(reported.len(), 1);
        assert_eq!((reported[0].tracer, reported[0].frame), (1, 2));
        assert_eq!(r.alive(), vec![0, 2]);
    }

    /// Long tails of small chunks, so that the fakes' frames are mostly claimed.
    fn greedy() -> Stealing {
        Stealing {
            tail: 0.5,
            chunk: 0.02,
            reserve: 0,
            guide: 1.0,
            work_per_overhead: 0.0,
            pieces_worth: 0.0,
        }
    }

    #[test]
    fn stealing_renders_the_same_frame_under_every_balancer() {
        for frame in 0..3 {
            let reference = Renderer::new(vec![Fake { slowness: 1 }], by_name("none").unwrap())
                .render_frame(&params(frame))
                .unwrap()
                .film;
            for name in NAMES {
                for tracers in 1..=3u64 {
                    let fakes = (1..=tracers).map(|s| Fake { slowness: s }).collect();
                    let mut r = Renderer::new(fakes, by_name(name).unwrap());
                    r.set_stealing(Some(greedy()));
                    for _ in 0..2 {
                        let f = r.render_frame(&params(frame)).unwrap();
                        assert_eq!(f.film, reference, "{name}, {tracers} tracers");
                        assert_eq!(f.tracers.iter().map(|s| s.pixels).sum::<u32>(), 160);
                        let claimed: u32 = f.tracers.iter().map(|s| s.pieces).sum();
                        assert_eq!(claimed > 0, tracers > 1, "{name}, {tracers} tracers");
                    }
                }
            }
        }
    }

    #[test]
    fn a_slow_tracers_tail_is_taken_by_the_fast_ones() {
        // An equal split of tracers 1 and 4 times as slow: the fast one runs out first.
        let fakes = vec![Fake { slowness: 1 }, Fake { slowness: 4 }];
        let mut r = Renderer::new(fakes, by_name("none").unwrap());
        r.set_stealing(Some(greedy()));
        let f = r.render_frame(&params(0)).unwrap();
        assert!(f.tracers[0].stolen > 0, "{:?}", f.tracers);
        assert_eq!(f.tracers[1].stolen, 0, "{:?}", f.tracers);
        assert!(f.tracers[0].pixels > f.tracers[1].pixels, "{:?}", f.tracers);
    }

    #[test]
    fn a_tracer_dying_with_a_claimed_chunk_loses_no_pixel() {
        for after in 0..3 {
            // Band 0 of a frame is the head, later ones claimed pieces.
            let tracers = vec![
                FaultInjector::healthy(Fake { slowness: 1 }),
                FaultInjector::failing_at_band_of_frame(Fake { slowness: 1 }, after),
                FaultInjector::healthy(Fake { slowness: 2 }),
            ];
            let mut r = Renderer::new(tracers, by_name("cost-aware").unwrap());
            r.set_stealing(Some(greedy()));
            let mut reference = Renderer::new(vec![Fake { slowness: 1 }], by_name("none").unwrap());
            for frame in 0..6 {
                let f = r.render_frame(&params(frame)).unwrap();
                let expected = reference.render_frame(&params(frame)).unwrap().film;
                assert_eq!(f.film, expected, "dying after {after} bands, frame {frame}");
                if f.failures.is_empty() {
                    assert_eq!(f.tracers.iter().map(|s| s.pixels).sum::<u32>(), 160);
                }
            }
            assert_eq!(r.alive(), vec![0, 2], "dying after {after} bands");
            assert_eq!(r.failures().len(), 1);
        }
    }

    #[test]
    fn all_tracers_failing_is_an_error_not_a_partial_frame() {
        let tracers = vec![FaultInjector::failing_from(Fake { slowness: 1 }, 0)];
        let mut r = Renderer::new(tracers, by_name("none").unwrap());
        assert!(r.render_frame(&params(0)).is_err());
    }

    /// A frame's per-pixel records come out in pixel order whatever order its bands came back
    /// in (what makes the world cache and the reservoirs the same for any split).
    #[test]
    fn per_pixel_records_join_in_pixel_order() {
        #[repr(C)]
        #[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
        struct Pixel(u32);
        impl platoon_frame::frame::PixelRecord for Pixel {
            const KIND: &'static str = "test.pixel";
        }
        let band = |begin: u32, end: u32| Band {
            span: Span::new(begin, end),
            per_pixel: PixelData::of(&(begin..end).map(Pixel).collect::<Vec<_>>()),
            ..Default::default()
        };
        let mut bands = vec![band(6, 9), band(0, 2), band(2, 6)];
        let joined = per_pixel_in_order(&mut bands);
        let expected: Vec<Pixel> = (0..9).map(Pixel).collect();
        assert_eq!(joined.records::<Pixel>().unwrap(), &expected[..]);
        assert!(bands.iter().all(|b| b.per_pixel.is_empty()), "taken out");
    }
}

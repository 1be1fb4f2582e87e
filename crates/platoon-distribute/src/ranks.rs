//! A frame over ranks, each with a renderer of its own devices. Per frame: rank 0's balancer
//! cuts the frame into one span per rank and scatters each rank its share (the span, the
//! frame's fingerprint, and the accumulated sums and converged mask of the span when the
//! frame continues a film); every rank renders its share on its devices, cut between them by
//! its own balancer (`Renderer::render_within`); the bands and timings are gathered on rank 0,
//! which assembles the frame and lets its balancer learn each rank's speed. A rank whose
//! devices all failed reports so; rank 0 renders its share itself in the same frame and gives
//! it no more. Scene commits are rank 0's, broadcast.

use std::rc::Rc;
use std::sync::Arc;
use std::time::{Duration, Instant};

use super::share::{decode_reply, encode_reply, share, unshare, Reply};
use super::wire::{self, Reader, WireError, Writer};
use super::Collective;
use platoon_core::balance::{idle_fraction, Balancer, FrameMeasure, TracerFrame};
use platoon_core::flatten::commit::Commit;
use platoon_core::frame::{BandTracer, FrameParams, Span};
use platoon_core::output::Film;
use platoon_schedule::renderer::{
    frame_of, line_rays_of, FrameResult, PartResult, RenderError, Renderer, TracerStats,
};

#[derive(Debug, thiserror::Error)]
pub enum RankError {
    #[error(transparent)]
    Render(#[from] RenderError),
    #[error(transparent)]
    Wire(#[from] WireError),
    /// A rank prepared the frame otherwise than rank 0 (other arguments, another scene file).
    #[error("rank {rank} prepared a different frame than rank 0 (its arguments, scene or build differ): {message}")]
    Mismatch { rank: usize, message: String },
    #[error("{0}")]
    Refused(String),
}

/// What crossed between the ranks for one frame or commit, as rank 0 saw it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Communication {
    /// Bytes rank 0 sent to the other ranks (shares, commits).
    pub sent: u64,
    /// Bytes it received from them (bands, timings).
    pub received: u64,
    /// Time this rank spent moving the bytes (the exchanges, after every rank is ready).
    pub time: Duration,
    /// Time it waited for the other ranks to finish their shares (load imbalance, not
    /// communication).
    pub waiting: Duration,
}

/// One rank's part in a frame.
#[derive(Clone, Debug)]
pub struct RankStats {
    pub rank: usize,
    /// The share rank 0's balancer gave it.
    pub span: Span,
    /// Its time for the share (its devices' frame), what the balancer learns from.
    pub wall_time: Duration,
    /// Its devices' parts.
    pub tracers: Vec<TracerStats>,
}

/// A frame over the ranks.
pub struct RankFrame {
    /// On rank 0 the frame; on the other ranks a frame of zeros of the same size (the image is
    /// rank 0's), with their own devices' statistics.
    pub frame: FrameResult,
    /// Rank 0: each rank's part, in rank order (ranks given nothing left out).
    pub ranks: Vec<RankStats>,
    pub communication: Communication,
    /// What failed in this frame, said once: devices dropped on a rank, ranks left without
    /// devices.
    pub failures: Vec<String>,
}

pub struct RankRenderer<T: BandTracer + Send + 'static> {
    local: Renderer<T>,
    group: Rc<dyn Collective>,
    /// Rank 0's: cuts the frame between the ranks still rendering.
    balancer: Box<dyn Balancer>,
    alive: Vec<usize>,
}

impl<T: BandTracer + Send + 'static> RankRenderer<T> {
    /// This rank's renderer over its devices (`local`, with its own balancer), in `group`;
    /// `balancer` cuts frames between the ranks (used on rank 0).
    pub fn new(
        local: Renderer<T>,
        group: Rc<dyn Collective>,
        balancer: Box<dyn Balancer>,
    ) -> RankRenderer<T> {
        let alive = (0..group.size()).collect();
        RankRenderer {
            local,
            group,
            balancer,
            alive,
        }
    }

    pub fn rank(&self) -> usize {
        self.group.rank()
    }
    pub fn ranks(&self) -> usize {
        self.group.size()
    }
    /// Rank 0: the ranks still given shares.
    pub fn alive(&self) -> &[usize] {
        &self.alive
    }
    pub fn balancer_name(&self) -> &'static str {
        self.balancer.name()
    }
    pub fn group(&self) -> &Rc<dyn Collective> {
        &self.group
    }
    /// This rank's own devices.
    pub fn local(&self) -> &Renderer<T> {
        &self.local
    }
    pub fn local_mut(&mut self) -> &mut Renderer<T> {
        &mut self.local
    }

    /// Brings every rank's devices to the next generation: rank 0's `commit` is broadcast and
    /// applied everywhere (the others' `commit` is ignored: what they render is rank 0's
    /// scene). A rank whose devices all fail to apply it ends with an error.
    pub fn apply_commit(
        &mut self,
        commit: &Arc<Commit>,
        frame: u32,
    ) -> Result<Communication, RankError> {
        let root = self.rank() == 0;
        let mut bytes = Vec::new();
        if root {
            let mut w = Writer::default();
            wire::put_commit(&mut w, commit);
            bytes = w.0;
        }
        let began = Instant::now();
        let got = self.group.broadcast(bytes);
        let time = began.elapsed();
        let commit = if root {
            commit.clone()
        } else {
            let mut r = Reader::new(&got);
            let c = wire::get_commit(&mut r)?;
            r.finish()?;
            Arc::new(c)
        };
        self.local.apply_commit(&commit, frame)?;
        let others = self.ranks().saturating_sub(1) as u64;
        Ok(Communication {
            sent: if root { got.len() as u64 * others } else { 0 },
            received: if root { 0 } else { got.len() as u64 },
            time,
            waiting: Duration::ZERO,
        })
    }

    /// Renders the frame `params` over the ranks. Every rank calls it with the same `params`
    /// (the fingerprint checks it); rank 0 gets the frame.
    pub fn render_frame(&mut self, params: &FrameParams) -> Result<RankFrame, RankError> {
        let start = Instant::now();
        if params.options.time_limit.is_some() && self.ranks() > 1 {
            return Err(RankError::Refused(
                "a time limit renders on one device: shares cut at different times would \
                 break the image's independence from the split"
                    .into(),
            ));
        }
        let root = self.rank() == 0;
        let mut comm = Communication::default();
        let shares = if root { self.plan(params) } else { Vec::new() };
        // The fingerprint formats every setting of the frame: once, not once per rank.
        let print = if root { wire::fingerprint(params) } else { 0 };
        let parts: Vec<Vec<u8>> = shares.iter().map(|&s| share(params, print, s)).collect();
        comm.sent = parts.iter().skip(1).map(|p| p.len() as u64).sum();
        let began = Instant::now();
        let mine = self.group.scatter(parts);
        comm.time += began.elapsed();
        if !root {
            comm.received += mine.len() as u64;
        }

        let began = Instant::now();
        let reply = match unshare(params, &mine) {
            Err(message) => Reply::Mismatch(message),
            Ok((span, _)) if span.is_empty() => Reply::Done {
                seconds: Duration::ZERO,
                part: PartResult::default(),
            },
            Ok((span, p)) => match self.local.render_within(&p, span) {
                Ok(part) => Reply::Done {
                    seconds: began.elapsed(),
                    part,
                },
                Err(e) => Reply::Lost(e.to_string()),
            },
        };
        // What this rank keeps of its reply, for a rank other than 0 to return.
        let (mismatch, own_devices, own_failures) = match &reply {
            Reply::Done { part, .. } => (
                None,
                part.tracers.clone(),
                device_failures(self.rank(), part),
            ),
            Reply::Lost(m) => (
                None,
                Vec::new(),
                vec![format!("rank {}: every device failed: {m}", self.rank())],
            ),
            Reply::Mismatch(m) => (Some(m.clone()), Vec::new(), Vec::new()),
        };
        let bytes = encode_reply(&reply);
        let began = Instant::now();
        self.group.barrier();
        comm.waiting = began.elapsed();
        let began = Instant::now();
        let replies = self.group.gather(bytes);
        comm.time += began.elapsed();
        if !root {
            if let Some(message) = mismatch {
                return Err(RankError::Mismatch {
                    rank: self.rank(),
                    message,
                });
            }
            return Ok(RankFrame {
                frame: zeros(params, own_devices, start),
                ranks: Vec::new(),
                communication: comm,
                failures: own_failures,
            });
        }
        comm.received = replies.iter().skip(1).map(|r| r.len() as u64).sum();
        self.assemble(params, &shares, replies, comm, start)
    }

    /// The share of every rank (empty for ranks no longer rendering).
    fn plan(&mut self, params: &FrameParams) -> Vec<Span> {
        let cut = self
            .balancer
            .plan(params.width, params.height, self.alive.len());
        let mut shares = vec![Span::default(); self.ranks()];
        for (&rank, span) in self.alive.iter().zip(cut) {
            shares[rank] = span;
        }
        shares
    }

    /// Rank 0: the frame from every rank's reply; lost shares rendered here.
    fn assemble(
        &mut self,
        params: &FrameParams,
        shares: &[Span],
        replies: Vec<Vec<u8>>,
        communication: Communication,
        start: Instant,
    ) -> Result<RankFrame, RankError> {
        let mut bands = Vec::new();
        let mut ranks = Vec::new();
        let mut failures = Vec::new();
        let mut lost: Vec<(usize, Span)> = Vec::new();
        for (rank, bytes) in replies.iter().enumerate() {
            match decode_reply(bytes)? {
                Reply::Mismatch(message) => return Err(RankError::Mismatch { rank, message }),
                Reply::Lost(message) => {
                    failures.push(format!(
                        "rank {rank} lost every device and renders no more; rank 0 rendered \
                         its share: {message}"
                    ));
                    lost.push((rank, shares[rank]));
                }
                Reply::Done { seconds, part } => {
                    failures.extend(device_failures(rank, &part));
                    if self.alive.contains(&rank) {
                        ranks.push(RankStats {
                            rank,
                            span: shares[rank],
                            wall_time: seconds,
                            tracers: part.tracers,
                        });
                    }
                    bands.extend(part.bands);
                }
            }
        }
        for &(rank, span) in &lost {
            if let Some(slot) = self.alive.iter().position(|&r| r == rank) {
                self.alive.remove(slot);
                self.balancer.remove_tracer(slot);
            }
            if !span.is_empty() {
                let part = self.local.render_within(params, span)?;
                failures.extend(device_failures(0, &part));
                bands.extend(part.bands);
            }
        }
        let times: Vec<f64> = ranks.iter().map(|r| r.wall_time.as_secs_f64()).collect();
        // A frame with a lost rank measured a split that no longer exists.
        if lost.is_empty() {
            let line_costs: Vec<f64> = line_rays_of(params, &bands)
                .iter()
                .map(|&r| r as f64)
                .collect();
            let observed: Vec<TracerFrame> = ranks
                .iter()
                .map(|r| TracerFrame {
                    span: r.span,
                    seconds: r.wall_time.as_secs_f64(),
                })
                .collect();
            self.balancer.observe(&FrameMeasure {
                width: params.width,
                height: params.height,
                tracers: &observed,
                line_costs: &line_costs,
            });
        }
        let max = times.iter().copied().fold(0.0, f64::max);
        let per_rank: Vec<TracerStats> = ranks
            .iter()
            .map(|r| TracerStats {
                tracer: r.rank,
                span: r.span,
                pixels: r.tracers.iter().map(|t| t.pixels).sum(),
                gpu_time: r.tracers.iter().map(|t| t.gpu_time).sum(),
                wall_time: r.wall_time,
                idle: Duration::from_secs_f64(max - r.wall_time.as_secs_f64()),
                rays: r.tracers.iter().map(|t| t.rays).sum(),
                pieces: r.tracers.iter().map(|t| t.pieces).sum(),
                stolen: r.tracers.iter().map(|t| t.stolen).sum(),
            })
            .collect();
        let part = PartResult {
            bands,
            tracers: per_rank,
            idle_fraction: idle_fraction(&times),
            failures: Vec::new(),
        };
        Ok(RankFrame {
            frame: frame_of(params, part, start),
            ranks,
            communication,
            failures,
        })
    }
}

/// Devices dropped on `rank` during its share, one line each.
fn device_failures(rank: usize, part: &PartResult) -> Vec<String> {
    part.failures
        .iter()
        .map(|f| {
            format!(
                "rank {rank}: device {} failed in frame {} and was dropped; its lines were \
                 rendered by the rank's other devices: {}",
                f.tracer, f.frame, f.message
            )
        })
        .collect()
}

/// What a rank other than 0 returns: a frame of the right size holding nothing.
fn zeros(params: &FrameParams, tracers: Vec<TracerStats>, start: Instant) -> FrameResult {
    let pixels = params.width as usize * params.height as usize;
    FrameResult {
        film: Film {
            width: params.width,
            height: params.height,
            pixels: vec![[0.0; 3]; pixels],
        },
        sums: vec![[0.0; 3]; pixels],
        spp: params.spp,
        tracers,
        line_rays: vec![0; params.height as usize],
        idle_fraction: 0.0,
        failures: Vec::new(),
        wall_time: start.elapsed(),
        rejected_samples: 0,
        kernel_fallbacks: 0,
        per_pixel: Default::default(),
        method_report: Default::default(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::local::LocalGroup;
    use platoon_core::balance::{by_name, NAMES};
    use platoon_core::scene::camera::Camera;
    use platoon_test_support::fakes::{Fake, Keeping};
    use platoon_test_support::fault::FaultInjector;

    fn params(frame: u32) -> FrameParams {
        let camera = Camera::look_at(glam::Vec3::Z, glam::Vec3::ZERO, 1.0);
        let mut p = FrameParams::new(7, 30, 1, camera);
        p.frame = frame;
        p
    }

    fn bits(f: &Film) -> Vec<u32> {
        f.pixels.iter().flatten().map(|v| v.to_bits()).collect()
    }

    /// Runs `body` on every rank of a group whose rank r has `devices[r]` tracers (built by
    /// `tracer(rank, device)`), each rank on its own thread; rank 0's result first.
    fn over_ranks<T, R>(
        devices: &[usize],
        balancers: (&str, &str),
        tracer: impl Fn(usize, usize) -> T + Sync,
        body: impl Fn(&mut RankRenderer<T>) -> R + Sync,
    ) -> Vec<R>
    where
        T: BandTracer + Send + 'static,
        R: Send,
    {
        let group = LocalGroup::new(devices.len());
        std::thread::scope(|s| {
            let handles: Vec<_> = group
                .into_iter()
                .zip(devices)
                .map(|(g, &n)| {
                    let (tracer, body) = (&tracer, &body);
                    s.spawn(move || {
                        let rank = g.rank();
                        let local = Renderer::new(
                            (0..n).map(|d| tracer(rank, d)).collect(),
                            by_name(balancers.1).unwrap(),
                        );
                        let mut r =
                            RankRenderer::new(local, Rc::new(g), by_name(balancers.0).unwrap());
                        body(&mut r)
                    })
                })
                .collect();
            handles.into_iter().map(|h| h.join().unwrap()).collect()
        })
    }

    fn reference(p: &FrameParams) -> Film {
        Renderer::new(vec![Fake { slowness: 1 }], by_name("none").unwrap())
            .render_frame(p)
            .unwrap()
            .film
    }

    #[test]
    fn every_balancer_at_both_levels_gives_the_one_process_image() {
        for (i, ranks) in [vec![1], vec![2, 1], vec![1, 3, 2]].iter().enumerate() {
            for (k, name) in NAMES.iter().enumerate() {
                let local = NAMES[(k + i) % NAMES.len()];
                let films = over_ranks(
                    ranks,
                    (name, local),
                    |rank, d| Fake {
                        slowness: 1 + (rank + d) as u64 % 3,
                    },
                    |r| {
                        (0..3)
                            .map(|f| {
                                let frame = r.render_frame(&params(f)).unwrap();
                                (
                                    bits(&frame.frame.film),
                                    frame.frame.line_rays.iter().sum::<u64>(),
                                )
                            })
                            .collect::<Vec<_>>()
                    },
                );
                for (f, (film, rays)) in films[0].iter().enumerate() {
                    let want = reference(&params(f as u32));
                    assert_eq!(*film, bits(&want), "{ranks:?} {name}/{local} frame {f}");
                    assert_eq!(*rays, 7 * 15 + 7 * 15 * 8, "{ranks:?} {name}");
                }
            }
        }
    }

    #[test]
    fn a_frame_continuing_sums_gets_each_rank_its_share_of_them() {
        let mut p = params(2);
        let before: Vec<[f32; 3]> = (0..7 * 30).map(|i| [i as f32, 1.5, -2.0]).collect();
        p.film.accumulated = Some(before.into());
        p.film.converged = Some((0..7 * 30).map(|i| i % 5 == 0).collect::<Vec<_>>().into());
        let films = over_ranks(
            &[2, 1, 2],
            ("cost-aware", "perfect"),
            |_, _| Fake { slowness: 1 },
            |r| bits(&r.render_frame(&p).unwrap().frame.film),
        );
        assert_eq!(films[0], bits(&reference(&p)));
    }

    #[test]
    fn a_rank_that_loses_its_devices_is_dropped_and_its_share_rendered_by_rank_0() {
        let results = over_ranks(
            &[1, 2, 1],
            ("perfect", "none"),
            |rank, _| {
                if rank == 1 {
                    FaultInjector::failing_from(Fake { slowness: 1 }, 1)
                } else {
                    FaultInjector::healthy(Fake { slowness: 1 })
                }
            },
            |r| {
                (0..4)
                    .map(|f| {
                        let frame = r.render_frame(&params(f)).unwrap();
                        (bits(&frame.frame.film), frame.failures, r.alive().to_vec())
                    })
                    .collect::<Vec<_>>()
            },
        );
        let failures: Vec<&String> = results[0].iter().flat_map(|f| &f.1).collect();
        assert_eq!(failures.len(), 1, "{failures:?}");
        assert!(
            failures[0].contains("rank 1 lost every device"),
            "{failures:?}"
        );
        for (f, (film, _, alive)) in results[0].iter().enumerate() {
            assert_eq!(*film, bits(&reference(&params(f as u32))), "frame {f}");
            let want: &[usize] = if f < 1 { &[0, 1, 2] } else { &[0, 2] };
            assert_eq!(alive, want, "frame {f}");
        }
    }

    #[test]
    fn a_rank_with_other_settings_stops_the_job_with_a_clear_error() {
        let results = over_ranks(
            &[1, 1],
            ("none", "none"),
            |_, _| Fake { slowness: 1 },
            |r| {
                let mut p = params(0);
                p.options.seed = r.rank() as u32;
                r.render_frame(&p).map(|_| ()).map_err(|e| e.to_string())
            },
        );
        for r in &results {
            let e = r.as_ref().unwrap_err();
            assert!(e.contains("rank 1 prepared a different frame"), "{e}");
        }
    }

    #[test]
    fn every_rank_applies_rank_0s_commit() {
        let seen: Vec<Arc<std::sync::Mutex<Vec<u32>>>> =
            (0..3).map(|_| Default::default()).collect();
        let comms = over_ranks(
            &[1, 1, 1],
            ("none", "none"),
            |rank, _| Keeping(seen[rank].clone()),
            |r| {
                let mut c = Commit::default();
                c.header.lights = 10 + r.rank() as u32;
                c.arrays.push(platoon_core::flatten::commit::ArrayCommit {
                    array: 1,
                    len: 8,
                    ranges: vec![(0, 8)],
                    data: vec![r.rank() as u8; 8],
                });
                r.apply_commit(&Arc::new(c), 1).unwrap()
            },
        );
        for s in &seen {
            assert_eq!(*s.lock().unwrap(), vec![10]);
        }
        assert!(comms[0].sent > 16 && comms[0].sent == comms[1].received * 2);
    }
}

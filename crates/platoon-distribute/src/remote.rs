//! Ranks as tracers of rank 0's frame driver (the game loop over MPI): a [`RankTracer`] is one
//! rank seen as a `BandTracer`, so the driver's renderer, balancer, commits, side passes and
//! failure handling work unchanged with one tracer per rank. Rank 0's own devices are a
//! [`LocalRank`]: a renderer of their own cutting each band between them; another rank's are a
//! [`RemoteRank`]: the band's parameters (`params.rs`) sent to it, the band sent back, the
//! commits forwarded. Each other rank runs [`serve`] over its devices until rank 0 ends. The
//! messages are point to point ([`Link`]), from the renderer's threads at once.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use super::params::{get_params, put_params};
use super::wire::{self, Reader, WireError, Writer};
use platoon_core::flatten::commit::Commit;
use platoon_core::frame::{Band, BandTracer, FrameParams, Span, TracerError, ValidatedFrame};
use platoon_schedule::renderer::{
    first_report, line_rays_of, per_pixel_in_order, PartResult, Renderer,
};

/// Messages between rank 0 and another rank, callable from several threads at once (MPI
/// started with MPI_THREAD_MULTIPLE; channels for ranks as threads).
pub trait Link: Send + Sync {
    fn send(&self, to: usize, bytes: Vec<u8>);
    fn receive(&self, from: usize) -> Vec<u8>;
}

/// What this process's remote ranks have exchanged so far (what `bench game --mpi` reports
/// per frame): bytes each way and the time on the wire (round trips less the rank's render).
#[derive(Debug, Default)]
pub struct Traffic {
    pub sent: AtomicU64,
    pub received: AtomicU64,
    pub wire_nanos: AtomicU64,
    pub messages: AtomicU64,
}

pub static TRAFFIC: Traffic = Traffic {
    sent: AtomicU64::new(0),
    received: AtomicU64::new(0),
    wire_nanos: AtomicU64::new(0),
    messages: AtomicU64::new(0),
};

const END: u8 = 0;
const BAND: u8 = 1;
const COMMIT: u8 = 2;

/// One rank as a tracer of rank 0's renderer.
pub enum RankTracer<T: BandTracer + Send + 'static> {
    Local(LocalRank<T>),
    Remote(RemoteRank),
}

impl<T: BandTracer + Send + 'static> BandTracer for RankTracer<T> {
    fn render_band(
        &mut self,
        params: &ValidatedFrame,
        span: Span,
        progress: &mut dyn FnMut(u32),
    ) -> Result<Band, TracerError> {
        match self {
            RankTracer::Local(t) => t.render_band(params, span, progress),
            RankTracer::Remote(t) => t.render_band(params, span, progress),
        }
    }
    fn apply_commit(&mut self, commit: &Commit) -> Result<u64, TracerError> {
        match self {
            RankTracer::Local(t) => t.apply_commit(commit),
            RankTracer::Remote(t) => t.apply_commit(commit),
        }
    }
    fn messages(&self) -> Vec<String> {
        match self {
            RankTracer::Local(t) => t.messages(),
            RankTracer::Remote(_) => Vec::new(),
        }
    }
}

/// Rank 0's own devices as one tracer: each band cut between them by their renderer.
pub struct LocalRank<T: BandTracer + Send + 'static>(pub Renderer<T>);

impl<T: BandTracer + Send + 'static> BandTracer for LocalRank<T> {
    fn render_band(
        &mut self,
        params: &ValidatedFrame,
        span: Span,
        _: &mut dyn FnMut(u32),
    ) -> Result<Band, TracerError> {
        let start = Instant::now();
        let part = self.0.render_within(params, span)?;
        Ok(merge(params, span, part, start.elapsed()))
    }
    fn apply_commit(&mut self, commit: &Commit) -> Result<u64, TracerError> {
        let uploaded = self.0.apply_commit(&Arc::new(commit.clone()), 0)?;
        Ok(uploaded.first().map_or(0, |u| u.1))
    }
    fn messages(&self) -> Vec<String> {
        self.0.with_tracers(|t| t.messages()).concat()
    }
}

/// The bands a rank's devices rendered of `span`, as one band of it.
fn merge(params: &FrameParams, span: Span, part: PartResult, wall: Duration) -> Band {
    let mut bands = part.bands;
    bands.sort_by_key(|b| b.span.begin);
    let lines = span.first_line(params.width) as usize..span.end_line(params.width) as usize;
    let line_rays = line_rays_of(params, &bands)[lines].to_vec();
    Band {
        span,
        sums: bands.iter().flat_map(|b| b.sums.iter().copied()).collect(),
        samples: bands.first().map_or(0, |b| b.samples),
        rays: bands.iter().map(|b| b.rays).sum(),
        line_rays,
        rejected_samples: bands.iter().map(|b| b.rejected_samples).sum(),
        kernel_fallbacks: bands.iter().map(|b| b.kernel_fallbacks).sum(),
        method_report: first_report(&bands),
        gpu_time: bands.iter().map(|b| b.gpu_time).sum(),
        per_pixel: per_pixel_in_order(&mut bands),
        wall_time: wall,
    }
}

/// Another rank's devices, reached through `link`.
pub struct RemoteRank {
    link: Arc<dyn Link>,
    rank: usize,
}

impl RemoteRank {
    pub fn new(link: Arc<dyn Link>, rank: usize) -> RemoteRank {
        RemoteRank { link, rank }
    }

    /// Sends `request`, waits for the answer; the time on the wire is the round trip less
    /// the time the rank says it worked (the answer's first 8 bytes).
    fn ask(&self, request: Vec<u8>) -> Result<Vec<u8>, TracerError> {
        let start = Instant::now();
        let sent = request.len() as u64;
        self.link.send(self.rank, request);
        let answer = self.link.receive(self.rank);
        let round = start.elapsed();
        let mut r = Reader::new(&answer);
        let worked = r.duration()?;
        TRAFFIC.sent.fetch_add(sent, Ordering::Relaxed);
        TRAFFIC
            .received
            .fetch_add(answer.len() as u64, Ordering::Relaxed);
        TRAFFIC.wire_nanos.fetch_add(
            round.saturating_sub(worked).as_nanos() as u64,
            Ordering::Relaxed,
        );
        TRAFFIC.messages.fetch_add(1, Ordering::Relaxed);
        Ok(answer)
    }

    fn answer<'a>(&self, answer: &'a [u8]) -> Result<Reader<'a>, TracerError> {
        let mut r = Reader::new(answer);
        r.duration()?;
        if r.u8()? != 0 {
            return Err(format!("rank {}: {}", self.rank, r.string()?).into());
        }
        Ok(r)
    }
}

impl BandTracer for RemoteRank {
    fn render_band(
        &mut self,
        params: &ValidatedFrame,
        span: Span,
        _: &mut dyn FnMut(u32),
    ) -> Result<Band, TracerError> {
        let mut w = Writer::default();
        w.u8(BAND);
        w.span(span);
        put_params(&mut w, params, span)?;
        let answer = self.ask(w.0)?;
        let mut r = self.answer(&answer)?;
        let band = wire::get_band(&mut r)?;
        r.finish()?;
        Ok(band)
    }
    fn apply_commit(&mut self, commit: &Commit) -> Result<u64, TracerError> {
        let mut w = Writer::default();
        w.u8(COMMIT);
        wire::put_commit(&mut w, commit);
        let answer = self.ask(w.0)?;
        let mut r = self.answer(&answer)?;
        Ok(r.u64()?)
    }
}

impl Drop for RemoteRank {
    /// Ends the rank's `serve`.
    fn drop(&mut self) {
        self.link.send(self.rank, vec![END]);
    }
}

/// Another rank's side: renders the bands and applies the commits rank 0 sends, on `local`,
/// until rank 0 ends (its `RemoteRank` dropped). A band or commit that fails is answered with
/// the error (rank 0's renderer then drops this rank and renders its lines elsewhere).
pub fn serve<T: BandTracer + Send + 'static>(
    local: &mut Renderer<T>,
    link: &dyn Link,
) -> Result<(), WireError> {
    loop {
        let request = link.receive(0);
        let start = Instant::now();
        let mut r = Reader::new(&request);
        let mut w = Writer::default();
        let outcome: Result<Vec<u8>, String> = match r.u8()? {
            END => return Ok(()),
            BAND => {
                let span = r.span()?;
                let params = get_params(&mut r, span)?;
                r.finish()?;
                local
                    .render_within(&params, span)
                    .map(|part| {
                        let band = merge(&params, span, part, start.elapsed());
                        let mut b = Writer::default();
                        wire::put_band(&mut b, &band);
                        b.0
                    })
                    .map_err(|e| e.to_string())
            }
            COMMIT => {
                let commit = wire::get_commit(&mut r)?;
                r.finish()?;
                local
                    .apply_commit(&Arc::new(commit), 0)
                    .map(|up| up.first().map_or(0, |u| u.1).to_le_bytes().to_vec())
                    .map_err(|e| e.to_string())
            }
            k => return Err(WireError(format!("unknown request {k}"))),
        };
        w.duration(start.elapsed());
        match outcome {
            Ok(body) => {
                w.u8(0);
                w.0.extend_from_slice(&body);
            }
            Err(message) => {
                w.u8(1);
                w.str(&message);
            }
        }
        link.send(0, w.0);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::local::LocalLink;
    use platoon_core::balance::{by_name, NAMES, STEALING_NAMES};
    use platoon_core::output::Film;
    use platoon_core::scene::camera::Camera;
    use platoon_test_support::fakes::{Fake, Keeping};

    fn params(frame: u32) -> FrameParams {
        let camera = Camera::look_at(glam::Vec3::Z, glam::Vec3::ZERO, 1.0);
        let mut p = FrameParams::new(9, 31, 2, camera);
        p.frame = frame;
        p
    }

    fn bits(f: &Film) -> Vec<u32> {
        f.pixels.iter().flatten().map(|v| v.to_bits()).collect()
    }

    /// Rank 0's renderer over itself (`local` devices) and `others.len()` ranks served on
    /// threads (rank r with `others[r - 1]` devices); `body` drives it.
    fn with_ranks<T: BandTracer + Send + 'static, R>(
        local: Vec<T>,
        others: Vec<Vec<T>>,
        balancer: &str,
        body: impl FnOnce(&mut Renderer<RankTracer<T>>) -> R,
    ) -> R {
        let links = LocalLink::new(others.len() + 1);
        std::thread::scope(|s| {
            for (rank, devices) in others.into_iter().enumerate() {
                let link = links[rank + 1].clone();
                s.spawn(move || {
                    let mut r = Renderer::new(devices, by_name("perfect").unwrap());
                    serve(&mut r, link.as_ref()).unwrap();
                });
            }
            let mut tracers = vec![RankTracer::Local(LocalRank(Renderer::new(
                local,
                by_name("cost-aware").unwrap(),
            )))];
            for rank in 1..links.len() {
                let link: Arc<dyn Link> = links[0].clone();
                tracers.push(RankTracer::Remote(RemoteRank::new(link, rank)));
            }
            let mut renderer = Renderer::new(tracers, by_name(balancer).unwrap());
            let out = body(&mut renderer);
            drop(renderer);
            out
        })
    }

    #[test]
    fn ranks_as_tracers_render_the_one_process_image_under_every_balancer() {
        for name in NAMES.into_iter().chain(STEALING_NAMES) {
            let messages = TRAFFIC.messages.load(Ordering::Relaxed);
            let (mut pieces, mut remote_pieces) = (0, 0);
            let films = with_ranks(
                vec![Fake { slowness: 1 }],
                vec![
                    vec![Fake { slowness: 2 }, Fake { slowness: 1 }],
                    vec![Fake { slowness: 3 }],
                ],
                name,
                |r| {
                    (0..3)
                        .map(|f| {
                            let mut p = params(f);
                            if f == 2 {
                                // A frame continuing a film: each rank gets its span's sums.
                                let sums: Vec<[f32; 3]> =
                                    (0..9 * 31).map(|i| [i as f32, 2.0, 0.25]).collect();
                                p.film.accumulated = Some(sums.into());
                            }
                            let frame = r.render_frame(&p).unwrap();
                            assert_eq!(frame.line_rays.iter().sum::<u64>(), 9 * 15 + 9 * 16 * 8);
                            pieces += frame.tracers.iter().map(|t| t.pieces).sum::<u32>();
                            let remote = frame.tracers.iter().filter(|t| t.tracer > 0);
                            remote_pieces += remote.map(|t| t.pieces as u64).sum::<u64>();
                            (bits(&frame.film), p)
                        })
                        .collect::<Vec<_>>()
                },
            );
            for (f, (film, p)) in films.iter().enumerate() {
                let reference = Renderer::new(vec![Fake { slowness: 0 }], by_name("none").unwrap())
                    .render_frame(p)
                    .unwrap();
                assert_eq!(*film, bits(&reference.film), "{name} frame {f}");
            }
            // A piece a remote rank claims is one more band asked of it: a message each way.
            assert_eq!(pieces > 0, name.ends_with("+steal"), "{name}");
            let asked = TRAFFIC.messages.load(Ordering::Relaxed) - messages;
            assert!(asked >= 2 * 3 + remote_pieces, "{name}: {asked}");
        }
    }

    #[test]
    fn commits_reach_every_rank_and_are_counted() {
        let seen: Vec<Arc<std::sync::Mutex<Vec<u32>>>> =
            (0..3).map(|_| Default::default()).collect();
        let before = TRAFFIC.sent.load(Ordering::Relaxed);
        let uploaded = with_ranks(
            vec![Keeping(seen[0].clone())],
            vec![
                vec![Keeping(seen[1].clone())],
                vec![Keeping(seen[2].clone())],
            ],
            "none",
            |r| {
                let mut c = Commit::default();
                c.header.lights = 5;
                c.arrays.push(platoon_core::flatten::commit::ArrayCommit {
                    array: 0,
                    len: 4,
                    ranges: vec![(0, 4)],
                    data: vec![9; 4],
                });
                r.apply_commit(&Arc::new(c), 1).unwrap()
            },
        );
        for s in &seen {
            assert_eq!(*s.lock().unwrap(), vec![5]);
        }
        assert_eq!(uploaded, vec![(0, 4), (1, 4), (2, 4)]);
        assert!(TRAFFIC.sent.load(Ordering::Relaxed) > before);
    }

    #[test]
    fn a_rank_whose_devices_fail_is_dropped_by_rank_0s_renderer() {
        for balancer in ["perfect", "perfect+steal"] {
            a_rank_fails(balancer);
        }
    }

    /// Rank 1's devices fail from frame 1 on (with stealing, whatever piece it holds then).
    fn a_rank_fails(balancer: &str) {
        use platoon_test_support::fault::FaultInjector;
        let (films, alive) = with_ranks(
            vec![FaultInjector::healthy(Fake { slowness: 1 })],
            vec![
                vec![FaultInjector::failing_from(Fake { slowness: 1 }, 1)],
                vec![FaultInjector::healthy(Fake { slowness: 1 })],
            ],
            balancer,
            |r| {
                let films: Vec<Vec<u32>> = (0..3)
                    .map(|f| bits(&r.render_frame(&params(f)).unwrap().film))
                    .collect();
                (films, r.alive())
            },
        );
        for (f, film) in films.iter().enumerate() {
            let reference = Renderer::new(vec![Fake { slowness: 0 }], by_name("none").unwrap())
                .render_frame(&params(f as u32))
                .unwrap();
            assert_eq!(*film, bits(&reference.film), "{balancer}, frame {f}");
        }
        assert_eq!(alive, vec![0, 2], "{balancer}");
    }
}

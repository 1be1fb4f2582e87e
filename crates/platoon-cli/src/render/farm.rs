//! `platoon render --mpi-frames A..B`: a render farm over an MPI job. Rank 0 deals the frames
//! to the ranks as they finish (`platoon::distributed::Session::deal`); each rank renders
//! whole frames on its own devices and writes them atomically (the output folder is shared),
//! saying `frame N: ok ... (rank R)` for each; rank 0 totals the ranks' counts at the end.

use std::path::Path;
use std::time::Instant;

use anyhow::{Context as _, Result};
use platoon::animation::frame_path;

use super::frames::{Frames, Job, Tally};

pub(super) fn run(frames: &mut Frames, job: &Job, out: &Path, todo: Vec<i64>) -> Result<Tally> {
    let session = frames
        .setup
        .session
        .clone()
        .context("--mpi-frames runs in an MPI job")?;
    let rank = session.rank();
    let (mut rendered, mut failed) = (0u64, 0u64);
    for f in session.deal(todo) {
        let path = frame_path(out, f);
        let began = Instant::now();
        match frames.render(job, f, &path, &mut |_| {}) {
            Ok(()) => println!(
                "frame {f}: ok, {} in {:.2} s (rank {rank})",
                path.display(),
                began.elapsed().as_secs_f64()
            ),
            Err(e) => {
                failed += 1;
                println!("frame {f}: failed on rank {rank}: {e:#}");
            }
        }
        rendered += 1;
    }
    let mine = [rendered, failed].map(u64::to_le_bytes).concat();
    let counts = session.gather(mine);
    let mut tally = Tally {
        rendered: 0,
        failed: 0,
    };
    for (r, c) in counts.iter().enumerate() {
        let n = |k: usize| u64::from_le_bytes(c[k * 8..k * 8 + 8].try_into().expect("8 bytes"));
        eprintln!("  rank {r}: {} frame(s), {} failed", n(0), n(1));
        tally.rendered += n(0);
        tally.failed += n(1);
    }
    Ok(tally)
}

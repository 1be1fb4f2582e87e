//! `platoon render --mpi-frames A..B`: a render farm over an MPI job. Rank 0 deals the frames
//! to the ranks as they finish (`platoon::distributed::Session::deal`); each rank renders
//! whole frames on its own devices and writes them atomically (the output folder is shared),
//! saying `frame N: ok ... (rank R)` for each; rank 0 totals the ranks' counts at the end.

use std::path::Path;
use std::rc::Rc;
use std::time::Instant;

use anyhow::Result;
use platoon::animation::frame_path;
use platoon::distributed::Session;

use super::frame_log::FrameLog;

/// Renders the frames of `todo` this rank is dealt with `render` (frame, its file), saying
/// each one's fate; rank 0 returns every rank's (frames rendered, failed).
pub(super) fn run(
    session: &Rc<dyn Session>,
    todo: Vec<i64>,
    out: &Path,
    log: FrameLog,
    mut render: impl FnMut(i64, &Path) -> Result<()>,
) -> Result<(u64, u64)> {
    let rank = session.rank();
    let (mut rendered, mut failed) = (0u64, 0u64);
    for f in session.deal(todo) {
        let path = frame_path(out, f);
        let began = Instant::now();
        match render(f, &path) {
            Ok(()) => println!(
                "{}",
                log.ok(f, &path, began.elapsed().as_secs_f64(), Some(rank))
            ),
            Err(e) => {
                failed += 1;
                println!("{}", log.failed(f, &e, Some(rank)));
            }
        }
        rendered += 1;
    }
    let mine = [rendered, failed].map(u64::to_le_bytes).concat();
    let counts = session.gather(mine);
    let mut total = (0, 0);
    for (r, c) in counts.iter().enumerate() {
        let n = |k: usize| u64::from_le_bytes(c[k * 8..k * 8 + 8].try_into().expect("8 bytes"));
        eprintln!("  rank {r}: {} frame(s), {} failed", n(0), n(1));
        total.0 += n(0);
        total.1 += n(1);
    }
    Ok(total)
}

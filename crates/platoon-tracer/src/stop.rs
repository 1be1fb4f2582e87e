//! A process-wide request to end renders early (Ctrl-C in the CLI): every band stops after its
//! current pass and keeps the samples it has, as a time limit stops it. A frame of several
//! bands then holds bands of different sample counts, each averaged over its own (the image is
//! an unbiased estimate either way, its noise uneven).

use std::sync::atomic::{AtomicBool, Ordering};

static REQUESTED: AtomicBool = AtomicBool::new(false);

/// Asks every band rendering now or later to stop after its current pass.
pub fn request() {
    REQUESTED.store(true, Ordering::SeqCst);
}

/// Whether a stop was asked for.
pub fn requested() -> bool {
    REQUESTED.load(Ordering::SeqCst)
}

/// Withdraws the request (renders after it take all their samples again).
pub fn clear() {
    REQUESTED.store(false, Ordering::SeqCst);
}

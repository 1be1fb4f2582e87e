//! What a long load shows: a spinner on standard error naming the stage and its time so far
//! (reading the scene, building its BVHs, uploading it), cleared when the stage ends. A scene of
//! millions of triangles takes seconds in each (docs/PERFORMANCE.md, "Scenes of production
//! size"). Nothing is drawn where standard error is not a terminal (indicatif's rule).

use std::time::Duration;

use indicatif::{ProgressBar, ProgressStyle};

/// Runs `f` under a spinner saying `what`.
pub(super) fn during<T>(what: &str, f: impl FnOnce() -> T) -> T {
    let spinner = ProgressBar::new_spinner();
    spinner.set_style(
        ProgressStyle::with_template("{spinner} {msg} ({elapsed})").expect("a valid template"),
    );
    spinner.set_message(what.to_string());
    spinner.enable_steady_tick(Duration::from_millis(120));
    let r = f();
    spinner.finish_and_clear();
    r
}

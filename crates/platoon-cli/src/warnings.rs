//! Where the library's warnings go in the CLI: standard error, one line each, as `warning: ...`
//! (the library logs them through `log`; an embedding application routes them its own way).

use std::io::Write as _;

struct Stderr;

impl log::Log for Stderr {
    fn enabled(&self, metadata: &log::Metadata) -> bool {
        metadata.level() <= log::Level::Warn
    }

    fn log(&self, record: &log::Record) {
        if !self.enabled(record.metadata()) {
            return;
        }
        let level = match record.level() {
            log::Level::Error => "error",
            _ => "warning",
        };
        // One write: under mpirun the ranks' pieces of a line would interleave.
        let _ = std::io::stderr().write_all(format!("{level}: {}\n", record.args()).as_bytes());
    }

    fn flush(&self) {}
}

/// Sends the library's warnings and errors to standard error.
pub fn to_stderr() {
    static LOGGER: Stderr = Stderr;
    if log::set_logger(&LOGGER).is_ok() {
        log::set_max_level(log::LevelFilter::Warn);
    }
}

//! What is wrong with a request, naming the option (a `Request` field's name); a render
//! stopped before its end.

use std::fmt;

/// What is wrong with a request: the option (a `Request` field's name) and the problem.
#[derive(Clone, Debug, PartialEq)]
pub struct RequestError {
    pub option: &'static str,
    pub problem: String,
}

impl fmt::Display for RequestError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.option, self.problem)
    }
}

impl std::error::Error for RequestError {}

/// A render stopped by a stop request (`platoon_tracer::stop`, Ctrl-C) whose samples were not
/// kept (a progressive render's call).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interrupted;

impl fmt::Display for Interrupted {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "interrupted: the samples of this call were not kept")
    }
}

impl std::error::Error for Interrupted {}

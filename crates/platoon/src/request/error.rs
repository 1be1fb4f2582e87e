//! What is wrong with a request, naming the option (a `Request` field's name).

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

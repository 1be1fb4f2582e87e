//! A render request's errors as the command line says them: the option written as the flag
//! that sets it (`max_depth` as `--max-depth`, `transparent_film` as `--film-transparent`),
//! the request's table's flag where it has the option.

use platoon::request::options;
use platoon::RequestError;

/// `e` with its option written as its flag.
pub fn as_flags(e: RequestError) -> anyhow::Error {
    let flag = match (options::option(e.option), e.option) {
        (Some(o), _) => o.flag.to_string(),
        // Options outside the table, whose flags say them another way.
        (None, "adaptive") => "adaptive-threshold".into(),
        (None, "aovs") => "aov".into(),
        (None, option) => option.replace('_', "-"),
    };
    anyhow::anyhow!("--{flag}: {}", e.problem)
}

/// The same for an error that may hold a request's.
pub fn any_as_flags(e: anyhow::Error) -> anyhow::Error {
    match e.downcast::<RequestError>() {
        Ok(e) => as_flags(e),
        Err(e) => e,
    }
}

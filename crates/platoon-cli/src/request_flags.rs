//! A render request's errors as the command line says them: the option written as the flag
//! that sets it (`max_depth` as `--max-depth`).

use platoon::RequestError;

/// `e` with its option written as its flag.
pub fn as_flags(e: RequestError) -> anyhow::Error {
    let flag = match e.option {
        "adaptive" => "adaptive-threshold",
        "aovs" => "aov",
        "denoiser" => "denoise",
        option => option,
    };
    anyhow::anyhow!("--{}: {}", flag.replace('_', "-"), e.problem)
}

/// The same for an error that may hold a request's.
pub fn any_as_flags(e: anyhow::Error) -> anyhow::Error {
    match e.downcast::<RequestError>() {
        Ok(e) => as_flags(e),
        Err(e) => e,
    }
}

//! The messages of a frame over ranks: rank 0's share to each rank (the frame's fingerprint,
//! the span, the film it continues there) and each rank's reply (its bands and timings, or why
//! it has none).

use std::time::Duration;

use super::wire::{self, Reader, WireError, Writer};
use platoon_core::frame::{FrameParams, Span};
use platoon_schedule::renderer::PartResult;

/// What a rank answers for its share.
pub(super) enum Reply {
    Done {
        seconds: Duration,
        part: PartResult,
    },
    /// Its devices all failed: its share is rank 0's to render.
    Lost(String),
    /// Its frame is not rank 0's: the job must stop.
    Mismatch(String),
}

/// Rank 0's message to a rank: the frame's fingerprint (`print`, `wire::fingerprint` of
/// `params`, made once for all ranks), the rank's span and, when the frame continues a film,
/// its sums and converged mask there.
pub(super) fn share(params: &FrameParams, print: u64, span: Span) -> Vec<u8> {
    let mut w = Writer::default();
    w.u64(print);
    w.span(span);
    wire::put_film_span(&mut w, params, span);
    w.0
}

/// A rank's span and its frame: `params` with the share's film. Err when the fingerprint
/// differs (the rank prepared another frame) or the message is malformed.
pub(super) fn unshare(params: &FrameParams, bytes: &[u8]) -> Result<(Span, FrameParams), String> {
    let mut r = Reader::new(bytes);
    let read = |r: &mut Reader| -> Result<(u64, Span), WireError> { Ok((r.u64()?, r.span()?)) };
    let (print, span) = read(&mut r).map_err(|e| e.to_string())?;
    if print != wire::fingerprint(params) {
        return Err("the frame's settings differ".into());
    }
    let mut p = params.clone();
    wire::get_film_span(&mut r, &mut p, span).map_err(|e| e.to_string())?;
    r.finish().map_err(|e| e.to_string())?;
    Ok((span, p))
}

pub(super) fn encode_reply(reply: &Reply) -> Vec<u8> {
    let mut w = Writer::default();
    match reply {
        Reply::Done { seconds, part } => {
            w.u8(0);
            w.duration(*seconds);
            w.f64(part.idle_fraction);
            w.u32(part.bands.len() as u32);
            for b in &part.bands {
                wire::put_band(&mut w, b);
            }
            w.u32(part.tracers.len() as u32);
            for t in &part.tracers {
                wire::put_tracer_stats(&mut w, t);
            }
            w.u32(part.failures.len() as u32);
            for f in &part.failures {
                wire::put_failure(&mut w, f);
            }
        }
        Reply::Lost(m) => {
            w.u8(1);
            w.str(m);
        }
        Reply::Mismatch(m) => {
            w.u8(2);
            w.str(m);
        }
    }
    w.0
}

pub(super) fn decode_reply(bytes: &[u8]) -> Result<Reply, WireError> {
    let mut r = Reader::new(bytes);
    let kind = r.u8()?;
    let reply = match kind {
        0 => {
            let seconds = r.duration()?;
            let idle_fraction = r.f64()?;
            let bands = (0..r.u32()?)
                .map(|_| wire::get_band(&mut r))
                .collect::<Result<_, _>>()?;
            let tracers = (0..r.u32()?)
                .map(|_| wire::get_tracer_stats(&mut r))
                .collect::<Result<_, _>>()?;
            let failures = (0..r.u32()?)
                .map(|_| wire::get_failure(&mut r))
                .collect::<Result<_, _>>()?;
            Reply::Done {
                seconds,
                part: PartResult {
                    bands,
                    tracers,
                    idle_fraction,
                    failures,
                },
            }
        }
        1 => Reply::Lost(r.string()?),
        2 => Reply::Mismatch(r.string()?),
        k => return Err(WireError(format!("unknown reply {k}"))),
    };
    r.finish()?;
    Ok(reply)
}

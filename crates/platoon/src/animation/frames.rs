//! Which frames a render farm task renders and where each goes: frame ranges as Blender and
//! Cycles users write them (`1..48`, `1..48:2`, both ends included), `#` patterns for the
//! frame number, and a task's share of a range chosen by a job-array index.

use std::path::{Path, PathBuf};
use std::str::FromStr;

use anyhow::{bail, Context as _, Result};

/// Frames `first..=last` every `step`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FrameRange {
    pub first: i64,
    pub last: i64,
    pub step: i64,
}

impl FromStr for FrameRange {
    type Err = String;

    /// `A`, `A..B` or `A..B:STEP` (B included).
    fn from_str(s: &str) -> Result<FrameRange, String> {
        let bad = || format!("{s:?} is not a frame range: A, A..B or A..B:STEP (B included)");
        let number = |t: &str| t.trim().parse::<i64>().map_err(|_| bad());
        let (span, step) = match s.split_once(':') {
            Some((span, step)) => (span, number(step)?),
            None => (s, 1),
        };
        let (first, last) = match span.split_once("..") {
            Some((a, b)) => (number(a)?, number(b)?),
            None => (number(span)?, number(span)?),
        };
        if step < 1 {
            return Err(format!("{s:?}: the step must be at least 1"));
        }
        if last < first {
            return Err(format!("{s:?}: the last frame comes before the first"));
        }
        Ok(FrameRange { first, last, step })
    }
}

impl FrameRange {
    pub fn frames(&self) -> Vec<i64> {
        (self.first..=self.last)
            .step_by(self.step as usize)
            .collect()
    }

    /// The frames of chunk `index` (from 0) when the range is cut into chunks of `chunk`
    /// frames: a farm task's share.
    pub fn chunk(&self, chunk: usize, index: usize) -> Result<Vec<i64>> {
        if chunk == 0 {
            bail!("--chunk must be at least 1");
        }
        let frames = self.frames();
        let chunks = frames.len().div_ceil(chunk);
        if index >= chunks {
            bail!(
                "task index {index} is past the {chunks} chunk(s) of {chunk} frame(s) in frames \
                 {}..{}:{} (indices count from 0)",
                self.first,
                self.last,
                self.step
            );
        }
        Ok(frames.chunks(chunk).nth(index).unwrap_or_default().to_vec())
    }
}

/// The task index a farm scheduler gave this process in the environment variable `name`
/// (Slurm's `SLURM_ARRAY_TASK_ID`, a Kubernetes indexed job's `JOB_COMPLETION_INDEX`, ...).
pub fn task_index(name: &str) -> Result<usize> {
    let value = std::env::var(name)
        .map_err(|_| anyhow::anyhow!("--task-index {name}: the environment variable is not set"))?;
    value.trim().parse::<usize>().with_context(|| {
        format!("--task-index {name}: {value:?} is not a task index (a whole number from 0)")
    })
}

/// Where frame `frame` goes: the last run of `#` in the file name replaced by the frame
/// number padded with zeros to the run's width (`shot_####.exr`, frame 7: `shot_0007.exr`);
/// a name without `#` gets `_####` before its extension.
pub fn frame_path(pattern: &Path, frame: i64) -> PathBuf {
    let name = pattern
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let name = if name.contains('#') {
        name
    } else {
        match name.rsplit_once('.') {
            Some((stem, ext)) => format!("{stem}_####.{ext}"),
            None => format!("{name}_####"),
        }
    };
    let end = name.rfind('#').map_or(0, |i| i + 1);
    let start = name[..end].trim_end_matches('#').len();
    let width = end - start;
    let number = if frame < 0 {
        format!("-{:0width$}", frame.unsigned_abs(), width = width)
    } else {
        format!("{frame:0width$}")
    };
    pattern.with_file_name(format!("{}{number}{}", &name[..start], &name[end..]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_parse_as_blender_writes_them() {
        let r: FrameRange = "1..48:2".parse().unwrap();
        assert_eq!(r.frames().len(), 24);
        assert_eq!(*r.frames().last().unwrap(), 47);
        assert_eq!("5".parse::<FrameRange>().unwrap().frames(), vec![5]);
        assert_eq!("-2..1".parse::<FrameRange>().unwrap().frames().len(), 4);
        for bad in ["", "3..1", "1..5:0", "a..b", "1..5:x"] {
            assert!(bad.parse::<FrameRange>().is_err(), "{bad}");
        }
    }

    #[test]
    fn chunks_cover_the_range_once() {
        let r: FrameRange = "1..10".parse().unwrap();
        let all: Vec<i64> = (0..4).flat_map(|i| r.chunk(3, i).unwrap()).collect();
        assert_eq!(all, r.frames());
        assert_eq!(r.chunk(3, 3).unwrap(), vec![10]);
        assert!(r.chunk(3, 4).is_err());
        assert!(r.chunk(0, 0).is_err());
    }

    #[test]
    fn frame_numbers_fill_the_last_run_of_hashes() {
        let p = |s: &str, f| frame_path(Path::new(s), f).display().to_string();
        assert_eq!(p("out/shot_####.exr", 7), "out/shot_0007.exr");
        assert_eq!(p("out/v#/shot_##.png", 123), "out/v#/shot_123.png");
        assert_eq!(p("shot.exr", 12), "shot_0012.exr");
        assert_eq!(p("a##b##.exr", 3), "a##b03.exr");
        assert_eq!(p("f_###.exr", -4), "f_-004.exr");
    }
}

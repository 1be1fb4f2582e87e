//! A still's checkpoint (`OUT.checkpoint` beside its image): what a render that ended short of
//! its samples (Ctrl-C, `--time-limit`) had summed, so that `--resume` continues it bit for
//! bit, its samples taken in the same order into the same sums as one uninterrupted render's.
//! One device only: there every pixel holds the same samples when a pass ends (bands of
//! several devices stop at different passes). The file: a first line naming the format, a JSON
//! line (the settings' key, size, samples), then the sums as little-endian f32 RGB, row-major.

use std::path::{Path, PathBuf};

use anyhow::{bail, Context as _, Result};
use platoon::core::frame::FrameParams;

const MAGIC: &str = "platoon checkpoint 1";

pub(super) struct Checkpoint {
    /// What the render was: the settings and scene a continuation must have too.
    pub key: String,
    pub width: u32,
    pub height: u32,
    /// Samples per pixel in `sums`.
    pub spp: u32,
    pub sums: Vec<[f32; 3]>,
}

/// The checkpoint of the image `out`.
pub(super) fn path_of(out: &Path) -> PathBuf {
    let mut name = out.as_os_str().to_owned();
    name.push(".checkpoint");
    PathBuf::from(name)
}

/// The key of a render of `params` (every sample it asks for, from the first) of a scene whose
/// content hash is `scene`, with `sampling`: two renders of one key take the same samples.
pub(super) fn key(params: &FrameParams, scene: u64, sampling: &str) -> String {
    let mut p = params.clone();
    p.first_sample = 0;
    p.options.time_limit = None;
    let settings = platoon::distribute::wire::fingerprint(&p);
    format!("{settings:016x}-{scene:016x}-{sampling}")
}

impl Checkpoint {
    pub(super) fn write(&self, path: &Path) -> Result<()> {
        let header = serde_json::json!({
            "key": self.key, "width": self.width, "height": self.height, "spp": self.spp,
        });
        let mut bytes = format!("{MAGIC}\n{header}\n").into_bytes();
        bytes.extend(self.sums.iter().flatten().flat_map(|v| v.to_le_bytes()));
        platoon::core::output::write_bytes(path, &bytes)?;
        Ok(())
    }

    pub(super) fn read(path: &Path) -> Result<Checkpoint> {
        let bytes = std::fs::read(path)
            .with_context(|| format!("{}: no checkpoint to resume from", path.display()))?;
        let bad = |what: &str| anyhow::anyhow!("{}: not a checkpoint ({what})", path.display());
        let mut lines = bytes.splitn(3, |&b| b == b'\n');
        if lines.next() != Some(MAGIC.as_bytes()) {
            return Err(bad("its first line"));
        }
        let header: serde_json::Value = lines
            .next()
            .and_then(|h| serde_json::from_slice(h).ok())
            .ok_or_else(|| bad("its settings"))?;
        let number = |k: &str| {
            header[k]
                .as_u64()
                .and_then(|v| u32::try_from(v).ok())
                .ok_or_else(|| bad(k))
        };
        let (width, height, spp) = (number("width")?, number("height")?, number("spp")?);
        let data = lines.next().unwrap_or(&[]);
        if data.len() != width as usize * height as usize * 12 {
            return Err(bad("its sums are cut short"));
        }
        let values: Vec<f32> = data
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes(b.try_into().expect("4 bytes")))
            .collect();
        Ok(Checkpoint {
            key: header["key"].as_str().ok_or_else(|| bad("key"))?.into(),
            width,
            height,
            spp,
            sums: values.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect(),
        })
    }

    /// Whether `params` (of the key `key`) may continue from it, and if not why.
    pub(super) fn check(&self, path: &Path, key: &str, params: &FrameParams) -> Result<()> {
        if self.key != key || (self.width, self.height) != (params.width, params.height) {
            bail!(
                "{}: made by other settings or another scene (size, samples, seed, camera, \
                 method...): resume with the settings it was made with, or delete it",
                path.display()
            );
        }
        if self.spp >= params.spp {
            bail!(
                "{}: holds {} samples a pixel already, as many as --spp {}",
                path.display(),
                self.spp,
                params.spp
            );
        }
        Ok(())
    }
}

/// With `--resume`: `params` turned into the rest of the render the checkpoint of `out`
/// began (its first sample the checkpoint's count, its film the checkpoint's sums); the
/// samples it holds.
pub(super) fn resume(out: &Path, params: &mut FrameParams, key: &str) -> Result<u32> {
    let path = path_of(out);
    let c = Checkpoint::read(&path)?;
    c.check(&path, key, params)?;
    params.first_sample = c.spp;
    params.spp -= c.spp;
    params.film.accumulated = Some(c.sums.into());
    Ok(c.spp)
}

/// After the render of `out` (`asked` samples a pixel, `reached` of them in `sums`): a
/// checkpoint when it ended short, none when it is whole. Returns what to tell the user.
pub(super) fn keep(
    out: &Path,
    key: String,
    params: &FrameParams,
    asked: u32,
    reached: u32,
    sums: &[[f32; 3]],
    one_device: bool,
) -> Result<Option<String>> {
    let path = path_of(out);
    if reached >= asked {
        if path.exists() {
            std::fs::remove_file(&path)
                .with_context(|| format!("{}: cannot remove", path.display()))?;
        }
        return Ok(None);
    }
    if !one_device {
        return Ok(Some(
            "no checkpoint: the devices' bands stopped at different passes (a render on one \
             device can be resumed)"
                .into(),
        ));
    }
    Checkpoint {
        key,
        width: params.width,
        height: params.height,
        spp: reached,
        sums: sums.to_vec(),
    }
    .write(&path)?;
    Ok(Some(format!(
        "{} holds its {reached} samples a pixel: the same command with --resume renders the \
         other {}",
        path.display(),
        asked - reached
    )))
}

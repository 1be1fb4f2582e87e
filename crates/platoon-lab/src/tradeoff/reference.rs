//! The converged reference a sweep is measured against: platoon's own MIS render at many
//! samples, cached on disk under a key of everything that decides its pixels, or a file given
//! by the user (another renderer's, say), checked before any sweep starts.

use std::hash::{Hash, Hasher};
use std::path::{Path, PathBuf};

use anyhow::{bail, Context as _, Result};
use platoon_core::frame::FrameParams;
use platoon_core::output::{read_exr, write_image, Film};
use platoon_tracer::{Tracer, TracerOptions};

use platoon::Prepared;

/// Seed offset of platoon's reference, so that its samples are independent of every sweep
/// render's (a reference sharing their random numbers would hide part of their error).
const SEED_OFFSET: u32 = 0x5eed_0001;

pub struct Reference {
    pub film: Film,
    pub path: PathBuf,
    pub spp: Option<u32>,
    /// Read from the cache (or the user's file) rather than rendered now.
    pub loaded: bool,
}

/// Where platoon's reference of `base` (the sweep's frame) at `spp` samples is cached.
pub fn cache_path(prepared: &Prepared, base: &FrameParams, spp: u32) -> Result<PathBuf> {
    let mut h = std::collections::hash_map::DefaultHasher::new();
    prepared.gpu.content_hash().hash(&mut h);
    platoon_tracer::sources_hash()?.hash(&mut h);
    let c = &base.camera;
    let camera: Vec<u32> = c
        .camera_to_world
        .to_cols_array()
        .iter()
        .chain(&[c.yfov, c.aperture_radius, c.focus_distance])
        .chain(c.orthographic.iter().flatten())
        .map(|v| v.to_bits())
        .collect();
    (
        base.width,
        base.height,
        base.options.seed,
        spp,
        base.path_loop.max_depth,
        base.path_loop.rr_depth,
        camera,
    )
        .hash(&mut h);
    Ok(platoon_tracer::cache_dir()
        .join("references")
        .join(format!("reference-{:016x}.exr", h.finish())))
}

/// platoon's reference: from the cache, or rendered now (`progress` gets the samples done).
pub fn platoon_reference(
    prepared: &Prepared,
    base: &FrameParams,
    spp: u32,
    progress: &mut dyn FnMut(u32),
) -> Result<Reference> {
    let path = cache_path(prepared, base, spp)?;
    if path.is_file() {
        if let Ok(film) = check(&path, base.width, base.height) {
            return Ok(Reference {
                film,
                path,
                spp: Some(spp),
                loaded: true,
            });
        }
    }
    let mut params = base.clone();
    params.spp = spp;
    params.options.seed = base.options.seed.wrapping_add(SEED_OFFSET);
    let mut tracer = Tracer::new(&TracerOptions::default(), &prepared.gpu)?;
    let band = tracer
        .render(&params, 0, params.height, progress)
        .context("rendering the reference")?;
    let film = platoon_core::frame::assemble(&params, &[band]);
    if film.count_non_finite() > 0 {
        bail!("the reference render has non-finite pixels");
    }
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("{}: cannot create the cache folder", dir.display()))?;
    }
    let meta = vec![
        ("platoon_reference_spp".to_string(), spp.to_string()),
        ("seed".to_string(), params.options.seed.to_string()),
    ];
    write_image(&path, &film, &meta)?;
    Ok(Reference {
        film,
        path,
        spp: Some(spp),
        loaded: false,
    })
}

/// A reference file the user gave: an EXR of the sweep's size with finite pixels.
pub fn user_reference(path: &Path, width: u32, height: u32) -> Result<Reference> {
    Ok(Reference {
        film: check(path, width, height)?,
        path: path.to_path_buf(),
        spp: None,
        loaded: true,
    })
}

fn check(path: &Path, width: u32, height: u32) -> Result<Film> {
    if !path.is_file() {
        bail!("{}: the reference does not exist", path.display());
    }
    let (film, _) =
        read_exr(path).with_context(|| format!("{}: reading the reference", path.display()))?;
    if (film.width, film.height) != (width, height) {
        bail!(
            "{}: the reference is {}x{}, the sweep renders {width}x{height} (pass --width {} \
             --height {} or another reference)",
            path.display(),
            film.width,
            film.height,
            film.width,
            film.height
        );
    }
    let bad = film.count_non_finite();
    if bad > 0 {
        bail!(
            "{}: the reference has {bad} non-finite pixels",
            path.display()
        );
    }
    Ok(film)
}

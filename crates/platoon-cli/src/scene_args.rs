//! The scene arguments every command that loads a scene shares.

use std::path::PathBuf;

use anyhow::Result;
use glam::Vec3;
use platoon::core::scene::texture_levels::{TextureLod, TextureOptions};
use platoon::EnvChoice;

#[derive(clap::Args)]
pub struct SceneArgs {
    /// glTF scene (.gltf or .glb); the built-in Cornell box when omitted.
    pub scene: Option<PathBuf>,
    /// Equirectangular environment map (.exr or .hdr).
    #[arg(long, conflicts_with = "env_color")]
    pub env: Option<PathBuf>,
    /// Constant environment radiance, as R,G,B.
    #[arg(long, value_parser = parse_rgb)]
    pub env_color: Option<Vec3>,
    /// A factor on the environment's radiance (Cycles' world strength).
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    pub env_strength: f32,
    /// Turns the environment map about +Y by this many degrees, counter-clockwise seen from
    /// above (by whole texel columns).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub env_rotation: f32,
    /// Animation time in seconds.
    #[arg(long, default_value_t = 0.0)]
    pub time: f32,
    /// Read buffers and textures whose URI is absolute or leads out of the scene's folder
    /// (refused by default, as glTF viewers do).
    #[arg(long)]
    pub allow_external_files: bool,
    /// The material variant to render (KHR_materials_variants; `platoon info` lists a file's).
    #[arg(long)]
    pub variant: Option<String>,
    /// How textures are read: `off` (the image itself: unbiased, aliased in the distance until
    /// enough samples land) or `ray-cone` (mip maps made at load, the level chosen by the
    /// camera path's ray cone: less noise and aliasing, blurred at grazing angles).
    #[arg(long, default_value = "off", value_parser = TextureLod::parse)]
    pub texture_lod: TextureLod,
    /// Device memory all textures together may take (bytes, or 512M, 2G...), mip levels
    /// included: past it the largest are halved until they fit (the metadata says how often).
    #[arg(long, value_parser = crate::bytes_arg::parse_bytes)]
    pub texture_budget: Option<u64>,
}

impl SceneArgs {
    pub fn load(&self) -> Result<platoon::core::Scene> {
        platoon::load_scene_with(self.scene.as_deref(), &self.load_options())
    }

    /// How the glTF file is read.
    pub fn load_options(&self) -> platoon::core::scene::gltf_load::LoadOptions {
        platoon::core::scene::gltf_load::LoadOptions {
            allow_external_files: self.allow_external_files,
            variant: self.variant.clone(),
            textures: TextureOptions {
                lod: self.texture_lod,
                budget: self.texture_budget,
            },
        }
    }

    /// The scene loaded and prepared with the arguments' light and time (and the rest of
    /// `PrepareOptions` at their defaults: the scene's first camera, a pinhole).
    pub fn prepare(&self) -> Result<platoon::Prepared> {
        platoon::prepare(
            self.load()?,
            &platoon::PrepareOptions {
                env: self.env_choice(),
                env_light: self.env_light(),
                time: self.time,
                ..Default::default()
            },
        )
    }

    /// Its strength and rotation.
    pub fn env_light(&self) -> platoon::EnvLight {
        platoon::EnvLight {
            strength: self.env_strength,
            rotation: self.env_rotation,
        }
    }

    /// The distant light the arguments ask for.
    pub fn env_choice(&self) -> EnvChoice {
        match (&self.env, self.env_color) {
            (Some(p), _) => EnvChoice::File(p.clone()),
            (None, Some(c)) => EnvChoice::Color(c),
            _ => EnvChoice::Scene,
        }
    }
}

/// Comma-separated numbers.
fn numbers(s: &str) -> Result<Vec<f32>, String> {
    s.split(',')
        .map(|p| p.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .map_err(|e| format!("{s}: {e}"))
}

/// A point or vector given as X,Y,Z.
pub fn parse_xyz(s: &str) -> Result<Vec3, String> {
    let v = numbers(s)?;
    match v.as_slice() {
        [x, y, z] if v.iter().all(|c| c.is_finite()) => Ok(Vec3::new(*x, *y, *z)),
        _ => Err(format!("{s}: expected three finite numbers X,Y,Z")),
    }
}

fn parse_rgb(s: &str) -> Result<Vec3, String> {
    let v = numbers(s)?;
    match v.as_slice() {
        [r, g, b] => Ok(Vec3::new(*r, *g, *b)),
        [c] => Ok(Vec3::splat(*c)),
        _ => Err(format!("{s}: expected R,G,B")),
    }
}

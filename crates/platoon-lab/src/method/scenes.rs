//! The scenes the methods' benches share (`platoon bench links`, `bench lhb`): the Cornell
//! box cut into quads, the generated conference room, CesiumMan, a furnished tea room.

use anyhow::{bail, Context as _, Result};
use glam::Vec3;
use platoon::{EnvChoice, PrepareOptions};

/// A scene of the bench: its name, what it is, and how it is made.
pub struct MethodScene {
    pub name: String,
    pub what: String,
    pub scene: platoon::core::Scene,
    pub env: EnvChoice,
}

/// The named scenes: `boxN` (the Cornell box, every face N x N quads), `conference` (the
/// generated conference room), `cesium` (CesiumMan from the shared data, under a grey sky),
/// `tearoomN` (a furnished room, walls N x N quads, teapots from the shared data).
pub fn scenes(names: &[String], shared: &std::path::Path) -> Result<Vec<MethodScene>> {
    names
        .iter()
        .map(|name| {
            if let Some(cells) = name.strip_prefix("box").and_then(|n| n.parse().ok()) {
                return Ok(MethodScene {
                    name: name.clone(),
                    what: format!("Cornell box, every face {cells}x{cells} quads"),
                    scene: platoon::core::scene::cornell::tessellated(cells),
                    env: EnvChoice::Scene,
                });
            }
            if let Some(cells) = name.strip_prefix("tearoom").and_then(|n| n.parse().ok()) {
                let teapot = shared_scene(shared, "teapot.gltf")?;
                return Ok(MethodScene {
                    name: name.clone(),
                    what: format!(
                        "a tea room: walls {cells}x{cells} quads, six tables, chairs, teapots"
                    ),
                    scene: crate::tearoom::tearoom(&teapot, cells)?,
                    env: EnvChoice::Scene,
                });
            }
            let (what, file, env) = match name.as_str() {
                "conference" => {
                    let scene =
                        crate::generated::load(&platoon_scenegen::conference_room(), "conference")?;
                    return Ok(MethodScene {
                        name: name.clone(),
                        what: "the generated conference room".into(),
                        scene,
                        env: EnvChoice::Scene,
                    });
                }
                "cesium" => (
                    "CesiumMan under a grey sky",
                    "CesiumMan.glb",
                    EnvChoice::Color(Vec3::splat(0.8)),
                ),
                _ => {
                    bail!("unknown bench scene {name:?}: boxN, conference, cesium, tearoomN")
                }
            };
            Ok(MethodScene {
                name: name.clone(),
                what: what.into(),
                scene: shared_scene(shared, file)?,
                env,
            })
        })
        .collect()
}

/// The scene `file` of the shared data's scenes/ folder (`shared`), or why it is not there.
pub fn shared_scene(shared: &std::path::Path, file: &str) -> Result<platoon::core::Scene> {
    let path = shared.join("scenes").join(file);
    if !path.is_file() {
        bail!("{}: not found (--shared names the folder)", path.display());
    }
    platoon::load_scene(Some(&path))
}

impl MethodScene {
    /// The scene prepared for rendering (flattened, its BVHs built).
    pub fn prepare(&self) -> Result<platoon::Prepared> {
        platoon::prepare(
            self.scene.clone(),
            &PrepareOptions {
                env: self.env.clone(),
                ..Default::default()
            },
        )
        .with_context(|| format!("preparing {}", self.name))
    }
}

//! `platoon info`: a scene's contents and the kernel it compiles to.

use anyhow::Result;
use platoon::PrepareOptions;

use crate::scene_args::SceneArgs;

pub fn run(scene: SceneArgs) -> Result<()> {
    let loaded = scene.load()?;
    let prepared = platoon::prepare(
        loaded,
        &PrepareOptions {
            env: scene.env_choice(),
            time: scene.time,
            ..Default::default()
        },
    )?;
    print!("{}", crate::bench::describe(&prepared));
    Ok(())
}

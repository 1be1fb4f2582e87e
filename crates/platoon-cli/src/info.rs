//! `platoon info`: a scene's contents and the kernel it compiles to.

use anyhow::Result;

use crate::scene_args::SceneArgs;

pub fn run(scene: SceneArgs) -> Result<()> {
    let prepared = scene.prepare()?;
    print!("{}", crate::bench::describe(&prepared));
    Ok(())
}

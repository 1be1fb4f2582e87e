//! Scenes `platoon-scenegen` generates, loaded as a user's exported file is: written to a
//! temporary glb and read by the glTF loader (the benches measure the loader's scene, not a
//! shortcut around it).

use anyhow::Result;
use platoon_core::scene::Scene;

/// `data` as the loader reads it from `{name}.glb`.
pub fn load(data: &platoon_scenegen::SceneData, name: &str) -> Result<Scene> {
    let dir = tempfile::tempdir()?;
    let path = dir.path().join(format!("{name}.glb"));
    std::fs::write(&path, platoon_scenegen::to_glb(data))?;
    platoon::load_scene(Some(&path))
}

//! The library's loader resolves a scene's separate files against the folder of the path as
//! given, a bare file name included (its folder is the current directory). One test in its own
//! process: it changes the current directory.

use std::path::Path;

use platoon_scene::gltf_load;

#[test]
fn a_bare_file_name_and_every_other_form_find_the_scenes_files() {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path().canonicalize().unwrap();
    let scene_dir = platoon_scenegen::twins::write_scene_folders(&root).unwrap();
    let forms = [
        (scene_dir.clone(), "scene.gltf"),
        (scene_dir.clone(), "./scene.gltf"),
        (root.join("other"), "../scene/scene.gltf"),
        (root.clone(), "link/scene.gltf"),
        (root.join("link"), "scene.gltf"),
    ];
    for (cwd, name) in forms {
        std::env::set_current_dir(&cwd).unwrap();
        let scene = gltf_load::load(Path::new(name))
            .unwrap_or_else(|e| panic!("{name} from {}: {e}", cwd.display()));
        assert_eq!(scene.textures.len(), 1, "{name}");
        assert_eq!(scene.textures[0].width, 4);
    }
    let absolute = scene_dir.join("scene.gltf");
    assert!(gltf_load::load(&absolute).is_ok());
}

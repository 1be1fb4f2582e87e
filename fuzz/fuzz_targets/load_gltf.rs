//! Fuzzes the glTF loader and everything a loaded scene goes through before a device sees it
//! (posing, BVH builds, flattening, light selection). Any panic is a bug: the loader's own
//! panic guard is bypassed (`load_from_slice`) so that a panic is found, not hidden.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use platoon_core::scene::gltf_load::{load_from_slice, LoadOptions};
use platoon_core::flatten::GpuScene;

fuzz_target!(|data: &[u8]| {
    // External URIs resolve in an empty folder: nothing outside the input is read.
    let base = Path::new("/nonexistent-platoon-fuzz");
    let Ok(scene) = load_from_slice(Path::new("fuzz.glb"), data, base, &LoadOptions::default())
    else {
        return;
    };
    let posed = scene.pose(0.5);
    let _ = posed.bounds();
    let _ = GpuScene::build(&scene, &posed, None);
});

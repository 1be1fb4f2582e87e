//! The image is a pure function of (scene, pixel, sample, frame, seed): bit-identical across
//! runs and across any split of the frame into bands.

#[path = "../common/mod.rs"]
mod common;

use common::*;
use platoon::core::balance::{line_bands, proportional};
use platoon::core::frame::{FrameParams, Span};
use platoon::tracer::Sampling;

fn cesium() -> platoon::Prepared {
    let scene = platoon::load_scene(Some(&shared("scenes/CesiumMan.glb"))).unwrap();
    prepare(
        scene,
        platoon::EnvChoice::File(shared("envmaps/forest.exr")),
    )
}

#[test]
fn same_seed_gives_identical_images_and_other_seeds_differ() {
    let prepared = prepare(
        platoon::core::scene::cornell::scene(),
        platoon::EnvChoice::Scene,
    );
    let mut tracer = tracer(&prepared, Sampling::Mis);
    let mut params = FrameParams::new(24, 24, 8, prepared.camera);
    let a = render_with(&mut tracer, &params);
    let b = render_with(&mut tracer, &params);
    assert_eq!(a, b);
    // A fresh device gives the same bits too.
    let c = render(&prepared, &params, Sampling::Mis);
    assert_eq!(a, c);
    params.seed = 1;
    let d = render_with(&mut tracer, &params);
    assert_ne!(a, d);
    params.seed = 0;
    params.frame = 1;
    assert_ne!(a, render_with(&mut tracer, &params));
}

#[test]
fn any_band_split_gives_the_same_bits() {
    for prepared in [
        prepare(
            platoon::core::scene::cornell::scene(),
            platoon::EnvChoice::Scene,
        ),
        cesium(),
    ] {
        let mut tracer = tracer(&prepared, Sampling::Mis);
        let params = FrameParams::new(20, 30, 6, prepared.camera);
        let whole =
            platoon::render_bands(&mut tracer, &params, &[Span::lines(20, 0, 30)], &mut |_| {})
                .unwrap();
        for parts in [2, 3, 7] {
            let split = platoon::render_bands(
                &mut tracer,
                &params,
                &line_bands(20, &proportional(30, &vec![1.0; parts])),
                &mut |_| {},
            )
            .unwrap();
            assert_eq!(whole.film, split.film, "{parts} bands differ from one");
            assert_eq!(whole.rays(), split.rays());
        }
        // Uneven bands, out of order, cut within lines (the cost-aware balancer cuts to the
        // pixel).
        let odd = platoon::render_bands(
            &mut tracer,
            &params,
            &[
                Span::new(17 * 20 + 3, 600),
                Span::new(0, 7),
                Span::new(7, 21),
                Span::new(21, 17 * 20 + 3),
            ],
            &mut |_| {},
        )
        .unwrap();
        assert_eq!(whole.film, odd.film);
        assert_eq!(whole.rays(), odd.rays());
        assert_no_validation_messages(&tracer);
    }
}

#[test]
fn interleaved_passes_give_the_contiguous_image() {
    let prepared = cesium();
    let mut tracer = tracer(&prepared, Sampling::Mis);
    let params = FrameParams::new(12, 17, 3, prepared.camera);
    let whole = tracer.render(&params, 0, 17, &mut |_| {}).unwrap();
    let mut sums = vec![[0.0f32; 3]; whole.sums.len()];
    for k in 0..3 {
        let pass = tracer
            .render_strided(&params, k, 17, 3, &mut |_| {})
            .unwrap();
        for (i, s) in pass.sums.iter().enumerate() {
            let line = k as usize + i / 12;
            if (line - k as usize).is_multiple_of(3) {
                sums[i + k as usize * 12] = *s;
            }
        }
    }
    assert!(sums == whole.sums);
    assert_no_validation_messages(&tracer);
}

#[test]
fn texel_buffers_storage_buffers_and_device_addresses_give_the_same_bits() {
    use platoon::tracer::MemoryPath;
    init();
    for prepared in [
        prepare(
            platoon::core::scene::cornell::scene(),
            platoon::EnvChoice::Scene,
        ),
        cesium(),
    ] {
        let params = FrameParams::new(20, 20, 4, prepared.camera);
        let paths = [
            (MemoryPath::TexelBuffers, "TEXEL_"),
            (MemoryPath::StorageBuffers, "SSBO_"),
            (MemoryPath::DeviceAddress, ""),
        ];
        let films: Vec<_> = paths
            .into_iter()
            .map(|(memory, prefix)| {
                let mut t = tracer_reading(&prepared.gpu, memory);
                let defines = t.kernel_defines(&params);
                let bound = |p: &str| defines.iter().filter(|d| d.starts_with(p)).count();
                // Every array of these small scenes fits the texel and storage limits.
                let arrays = platoon::tracer::SCENE_ARRAYS.len();
                let expected = if prefix.is_empty() { 0 } else { arrays };
                assert_eq!(bound("TEXEL_") + bound("SSBO_"), expected, "{memory:?}");
                if !prefix.is_empty() {
                    assert_eq!(bound(prefix), arrays, "{memory:?}");
                }
                let film = render_with(&mut t, &params);
                assert_no_validation_messages(&t);
                film
            })
            .collect();
        assert!(films[0] == films[1], "texel and storage buffers differ");
        assert!(
            films[0] == films[2],
            "texel buffers and device addresses differ"
        );
    }
}

//! The image is a pure function of (scene, pixel, sample, frame, seed): bit-identical across
//! runs and across any split of the frame into bands.

#[path = "../common/mod.rs"]
mod common;

use common::*;
use platoon::core::balance::{line_bands, proportional};
use platoon::core::frame::{FrameParams, Span};
use platoon::core::method::path::{PathKernel, ResampledLight};
use platoon::tracer::{Sampling, TracerOptions};

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
    params.options.seed = 1;
    let d = render_with(&mut tracer, &params);
    assert_ne!(a, d);
    params.options.seed = 0;
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
        for kernel in [PathKernel::Mega, PathKernel::Streaming] {
            let mut params = FrameParams::new(20, 30, 6, prepared.camera);
            params.method = in_kernel(&params.method, kernel);
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
        }
        assert_no_validation_messages(&tracer);
    }
}

/// Resampled direct light (issue 43) among the many-light hall's panels and sconces: a
/// pixel's candidates are its own random numbers, so any split gives the same bits, on both
/// path kernels.
#[test]
fn resampled_direct_light_gives_the_same_bits_for_any_split() {
    let prepared = prepare(
        load_generated(&platoon_scenegen::many_lights::many_lights()),
        platoon::EnvChoice::Scene,
    );
    let mut tracer = tracer(&prepared, Sampling::Mis);
    for kernel in [PathKernel::Mega, PathKernel::Streaming] {
        let mut params = FrameParams::new(24, 16, 2, prepared.camera);
        params.method = in_kernel(&params.method, kernel);
        params.method.path_mut().unwrap().resampled_light = Some(ResampledLight::new(8));
        let whole =
            platoon::render_bands(&mut tracer, &params, &[Span::lines(24, 0, 16)], &mut |_| {})
                .unwrap();
        let split = platoon::render_bands(
            &mut tracer,
            &params,
            &line_bands(24, &proportional(16, &[1.0, 2.0, 1.0])),
            &mut |_| {},
        )
        .unwrap();
        assert!(
            whole.film == split.film,
            "{kernel:?}: 3 bands differ from one"
        );
        assert_eq!(whole.film.count_non_finite(), 0);
        // It is the resampling kernel: another image than one light drawn by power.
        params.method.path_mut().unwrap().resampled_light = None;
        let plain =
            platoon::render_bands(&mut tracer, &params, &[Span::lines(24, 0, 16)], &mut |_| {})
                .unwrap();
        assert!(
            plain.film != whole.film,
            "{kernel:?}: resampling changed nothing"
        );
    }
    assert_no_validation_messages(&tracer);
}

#[test]
fn interleaved_passes_give_the_contiguous_image() {
    let prepared = cesium();
    let mut tracer = tracer(&prepared, Sampling::Mis);
    for kernel in [PathKernel::Mega, PathKernel::Streaming] {
        let mut params = FrameParams::new(12, 17, 3, prepared.camera);
        params.method = in_kernel(&params.method, kernel);
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
        assert!(
            sums == whole.sums,
            "{}: interleaved lines differ",
            kernel.name()
        );
    }
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

#[test]
fn the_streaming_path_tracer_gives_the_megakernels_bits_with_any_number_of_slots() {
    // Fewer slots than pixels: a slot takes pixel after pixel as it finishes them (claimed by
    // an atomic counter, so in no fixed order), and partly filled SIMD groups everywhere.
    for prepared in [
        prepare(
            platoon::core::scene::cornell::scene(),
            platoon::EnvChoice::Scene,
        ),
        cesium(),
    ] {
        let mut params = FrameParams::new(20, 30, 6, prepared.camera);
        params.method = in_kernel(&params.method, PathKernel::Mega);
        let mut mega_tracer = tracer(&prepared, Sampling::Mis);
        let mega = mega_tracer.render(&params, 0, 30, &mut |_| {}).unwrap();
        params.method = in_kernel(&params.method, PathKernel::Streaming);
        for slots in [1, 7, 64, 600, 5000] {
            init();
            let options = TracerOptions {
                validation: true,
                stream_slots: Some(slots),
                ..Default::default()
            };
            let mut tracer = platoon::tracer::Tracer::new(&options, &prepared.gpu).unwrap();
            let streamed = tracer.render(&params, 0, 30, &mut |_| {}).unwrap();
            assert!(
                streamed.sums == mega.sums,
                "{slots} slots: the image differs"
            );
            // The same rays, counted on the same lines (what the balancers weigh lines by).
            assert_eq!(
                streamed.line_rays, mega.line_rays,
                "{slots} slots: other rays"
            );
            assert_eq!(streamed.rejected_samples, 0);
            assert_no_validation_messages(&tracer);
        }
    }
}

#[test]
fn the_streaming_path_tracer_continues_a_sum_as_one_longer_render() {
    use platoon::core::balance::by_name;
    use platoon::schedule::renderer::Renderer;
    let prepared = cesium();
    let mut renderer = Renderer::new(
        vec![tracer(&prepared, Sampling::Mis)],
        by_name("none").unwrap(),
    );
    let mut params = FrameParams::new(16, 12, 5, prepared.camera);
    params.method = in_kernel(&params.method, PathKernel::Streaming);
    let whole = renderer.render_frame(&params).unwrap().sums;
    // 2 samples, then 3 more onto their sums.
    params.spp = 2;
    let first = renderer.render_frame(&params).unwrap().sums;
    params.spp = 3;
    params.first_sample = 2;
    params.film.accumulated = Some(first.into());
    let rest = renderer.render_frame(&params).unwrap().sums;
    assert!(rest == whole, "continuing the sum changed the bits");
}

#[test]
fn the_quick_build_of_big_meshes_renders_the_reinserted_trees_image() {
    // Issue 59: static meshes past QUICK_BUILD_TRIANGLES are built by binned SAH instead of
    // obvhs' reinserted PLOC. Both trees hold the same triangles, so camera rays find the same
    // surfaces: the emitters seen directly are the same bits. What does change is the order of
    // the triangles in the leaves, and with it the order of the emissive triangles in the light
    // list, so next-event estimation draws other lights for the same numbers: the full paths
    // agree within noise (the pixels' mean difference within 4 standard errors).
    use platoon::core::flatten::bvh::BuildQuality;
    use platoon::core::flatten::static_merge::StaticMerge;
    use platoon::core::flatten::GpuScene;
    let prepared = prepare(
        load_generated(&platoon_scenegen::bench::cornell_cut(16)),
        platoon::EnvChoice::Scene,
    );
    let scene = &prepared.scene;
    let levels = StaticMerge::of_scene(scene).apply(scene, prepared.posed.clone());
    let build = |quality| {
        GpuScene::build_at(scene, &levels, scene.environment.as_ref(), Some(quality)).unwrap()
    };
    let (fine, quick) = (build(BuildQuality::Static), build(BuildQuality::Quick));
    assert!(fine.blas_nodes != quick.blas_nodes, "the same tree twice");
    let mut params = FrameParams::new(32, 32, 16, prepared.camera);
    let image = |g: &GpuScene, params: &FrameParams| {
        let mut t = tracer_reading(g, Default::default());
        render_with(&mut t, params)
    };
    params.path_loop.max_depth = 1;
    assert!(
        image(&fine, &params) == image(&quick, &params),
        "camera rays found other surfaces"
    );
    params.path_loop.max_depth = 6;
    let (a, b) = (image(&fine, &params), image(&quick, &params));
    let (d, err) = mean_and_stderr(
        a.pixels
            .iter()
            .zip(&b.pixels)
            .map(|(p, q)| luminance(*p) - luminance(*q)),
    );
    assert!(d.abs() < 4.0 * err, "mean difference {d} +- {err}");
    assert!(
        err < 0.02 * mean(&a),
        "too noisy to tell: {err} against {}",
        mean(&a)
    );
}

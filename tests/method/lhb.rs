//! Layered hit buffers (issue 23): the devices' buffers equal the ray oracle's, whatever the
//! rasterizer variant, however large the triangles and however many; the indirect light converges towards
//! the path tracer's as directions and resolution grow; one and three tracers give the same
//! bits.

#[path = "../common/mod.rs"]
mod common;

use common::*;
use platoon::core::balance::by_name;
use platoon::core::flatten::GpuScene;
use platoon::core::frame::{FrameParams, MethodReport, Span};
use platoon::core::method::lhb::directions::DirectionSet;
use platoon::core::method::lhb::oracle::{buffer_by_rays, on_an_edge, Layer};
use platoon::core::method::lhb::{Lhb, LhbBuild, LhbOptions, RasterVariant};
use platoon::core::Method;
use platoon::devices::{create_tracers, DeviceSpec};
use platoon::schedule::renderer::Renderer;
use platoon::tracer::{Sampling, Tracer};

fn cornell() -> platoon::Prepared {
    prepare(
        platoon::core::scene::cornell::scene(),
        platoon::EnvChoice::Scene,
    )
}

fn options(directions: &str, resolution: u32) -> LhbOptions {
    LhbOptions {
        directions: DirectionSet::parse(directions).unwrap(),
        resolution,
        ..Default::default()
    }
}

/// Per direction, per texel, a buffer's layers.
type Lists = Vec<Vec<Vec<Layer>>>;

/// Renders one small frame with `o` on `tracer` (which builds the buffers) and returns the
/// band's report with the buffers' lists, per direction and texel, sorted as the oracle's.
fn device_lists(
    tracer: &mut Tracer,
    g: &GpuScene,
    prepared: &platoon::Prepared,
    o: LhbOptions,
) -> (MethodReport, Lists, Lhb) {
    let lhb = Lhb::prepared(o, g);
    let mut params = FrameParams::new(8, 8, 1, prepared.camera);
    params.method = Method::new(lhb.clone());
    let band = tracer
        .render_span(&params, Span::lines(8, 0, 8), &mut |_| {})
        .expect("render");
    assert_no_validation_messages(tracer);
    let buffers = tracer.method_buffers("lhb").unwrap();
    let words = |b: &[u8]| -> Vec<u32> {
        b.chunks_exact(4)
            .map(|w| u32::from_le_bytes([w[0], w[1], w[2], w[3]]))
            .collect()
    };
    let work = words(&buffers[0]);
    let layers: Vec<[u32; 2]> = words(&buffers[1])
        .chunks_exact(2)
        .map(|l| [l[0], l[1]])
        .collect();
    let lists = lhb
        .tables
        .as_ref()
        .unwrap()
        .device_lists(&o, &work, &layers);
    (band.method_report, lists, lhb)
}

/// Compares every `step`-th direction's device lists with the oracle's: (texels the same,
/// texels differing at a centre on an edge). Panics on any other difference.
fn compare_with_oracle(
    g: &GpuScene,
    lhb: &Lhb,
    lists: &[Vec<Vec<Layer>>],
    step: usize,
) -> (usize, usize) {
    let t = lhb.tables.as_ref().unwrap();
    let r = lhb.options.resolution;
    let (mut same, mut exempt) = (0, 0);
    for (d, view) in t.views.iter().enumerate().step_by(step) {
        let oracle = buffer_by_rays(g, &t.frame, view, r);
        for (k, (want, got)) in oracle.iter().zip(&lists[d]).enumerate() {
            let equal = want.len() == got.len()
                && want.iter().zip(got).all(|(w, g)| {
                    (w.instance, w.triangle) == (g.instance, g.triangle)
                        && (w.depth - g.depth).abs() <= 1e-5 * w.depth.abs().max(1.0)
                });
            let texel = (k as u32 % r, k as u32 / r);
            if equal {
                same += 1;
            } else if on_an_edge(
                g,
                &t.frame,
                view,
                r,
                &[want.clone(), got.clone()].concat(),
                texel,
            ) {
                exempt += 1;
            } else {
                panic!("direction {d}, texel {texel:?}: rays {want:?}, device {got:?}");
            }
        }
    }
    (same, exempt)
}

#[test]
fn the_devices_buffers_list_what_the_rays_find_with_either_rasterizer() {
    let scene = platoon::core::scene::cornell::tessellated(3);
    let prepared = prepare(scene, platoon::EnvChoice::Scene);
    let g = &prepared.gpu;
    let mut tracer = tracer(&prepared, Sampling::Mis);
    for variant in [RasterVariant::Capacity, RasterVariant::Exact] {
        let o = LhbOptions {
            variant,
            ..options("ico80", 48)
        };
        let (report, lists, lhb) = device_lists(&mut tracer, g, &prepared, o);
        println!("{variant:?}: {}", report_line(&report));
        assert_eq!(report_line_lost(&report), 0, "{report:?}");
        let (same, exempt) = compare_with_oracle(g, &lhb, &lists, 7);
        println!("{variant:?}: {same} texels the same, {exempt} on edges");
        assert!(exempt * 50 < same, "{exempt} of {same} on edges");
        // Every direction holds layers: the rasterizer reached them all.
        assert!(lists.iter().all(|d| d.iter().any(|t| !t.is_empty())));
    }
}

fn report_line(r: &MethodReport) -> String {
    (r.value::<LhbBuild>()).expect("the build's report").line()
}

fn report_line_lost(r: &MethodReport) -> u64 {
    (r.value::<LhbBuild>()).expect("the build's report").lost
}

/// A quad of two triangles seen by the four octahedral directions facing it at 512 x 512: each
/// triangle's box spans over 100,000 texels, past llvmpipe's 65,535 loop iterations an
/// invocation (one thread testing them all would stop short, silently). The blocks on the queue
/// rasterize them, and the lists equal the oracle's.
#[test]
fn triangles_covering_the_buffer_are_rasterized_whole() {
    use platoon::core::scene::{Material, Mesh};
    let mut mesh = Mesh::default();
    platoon::core::scene::cornell::push_grid(
        &mut mesh,
        [
            glam::Vec3::new(-1.0, -1.0, 0.0),
            glam::Vec3::new(1.0, -1.0, 0.0),
            glam::Vec3::new(1.0, 1.0, 0.0),
            glam::Vec3::new(-1.0, 1.0, 0.0),
        ],
        0,
        1,
    );
    let scene = scene_of(
        vec![(mesh, glam::Vec3::ZERO, 1.0)],
        vec![Material::default()],
        glam::Vec3::new(0.0, 0.0, 4.0),
        glam::Vec3::ZERO,
        0.8,
    );
    let prepared = prepare(scene, platoon::EnvChoice::Scene);
    let g = &prepared.gpu;
    let mut tracer = tracer(&prepared, Sampling::Mis);
    let o = LhbOptions {
        layers: 2,
        ..options("oct8", 512)
    };
    let (report, lists, lhb) = device_lists(&mut tracer, g, &prepared, o);
    println!("{}", report_line(&report));
    let covered: usize = lists.iter().flatten().filter(|t| !t.is_empty()).count();
    let (same, exempt) = compare_with_oracle(g, &lhb, &lists, 1);
    println!("{covered} texels covered; {same} the same, {exempt} on edges");
    assert!(covered > 200_000, "{covered}");
    assert!(exempt * 100 < same);
}

/// A million triangles (the Cornell box with every face cut into 183 x 183 quads, each a few
/// hundredths of a texel at 64 x 64): the exact rasterizer's lists equal the oracle's in two of
/// the twenty icosahedral directions.
#[test]
fn a_million_triangles_rasterize_as_the_rays_find() {
    let prepared = prepare(
        platoon::core::scene::cornell::tessellated(183),
        platoon::EnvChoice::Scene,
    );
    let g = &prepared.gpu;
    assert!(g.triangles.len() >= 1_000_000, "{}", g.triangles.len());
    let mut tracer = tracer(&prepared, Sampling::Mis);
    let o = LhbOptions {
        variant: RasterVariant::Exact,
        ..options("ico20", 64)
    };
    let (report, lists, lhb) = device_lists(&mut tracer, g, &prepared, o);
    println!("{} triangles: {}", g.triangles.len(), report_line(&report));
    let (same, exempt) = compare_with_oracle(g, &lhb, &lists, 10);
    println!("{same} texels the same, {exempt} on edges");
    assert!(exempt * 50 < same, "{exempt} of {same} on edges");
}

/// The Cornell box is Lambertian: with B lookup bounces, layered hit buffers estimate what the
/// path tracer does with paths of B + 2 segments. Their indirect light (the render minus the
/// same paths cut after their first vertex's direct light) approaches the path tracer's as
/// directions and resolution grow.
#[test]
fn lhb_indirect_light_converges_to_the_path_tracers_with_directions_and_resolution() {
    let prepared = cornell();
    let mut tracer = tracer(&prepared, Sampling::Mis);
    let mut params = FrameParams::new(32, 32, 4096, prepared.camera);
    let bounces = LhbOptions::default().bounces;
    params.path_loop.max_depth = bounces + 2;
    let full = render_with(&mut tracer, &params);
    params.path_loop.max_depth = 2;
    let reference = minus(&full, &render_with(&mut tracer, &params));
    params.spp = 256;
    params.options.seed = 1;
    let mut errors = Vec::new();
    for (set, r) in [("ico20", 16), ("ico80", 64), ("ico320", 128)] {
        let o = LhbOptions {
            variant: RasterVariant::Exact,
            ..options(set, r)
        };
        params.method = Method::new(Lhb::prepared(o, &prepared.gpu));
        params.path_loop.max_depth = platoon::core::frame::DEFAULT_MAX_DEPTH;
        let lit = render_with(&mut tracer, &params);
        // The same paths cut after the first vertex's direct light: the same random numbers,
        // so the difference holds none of the direct light's noise.
        params.path_loop.max_depth = 2;
        let indirect = minus(&lit, &render_with(&mut tracer, &params));
        errors.push((set, r, rmse(&indirect, &reference), mean(&indirect)));
    }
    let m = mean(&reference);
    println!("path-traced indirect: mean {m:.4} (of {:.4})", mean(&full));
    for (set, r, e, mi) in &errors {
        println!("{set:>8} at {r:3}^2: indirect RMSE {e:.4}, mean {mi:.4}");
    }
    assert!(m > 0.15 * mean(&full), "the box has indirect light to find");
    let (_, _, last_error, last_mean) = errors[errors.len() - 1];
    assert!(
        (last_mean - m).abs() < 0.03 * m,
        "mean {last_mean} vs {m}: {errors:?}"
    );
    // Falling towards the noise of 256 samples (about 0.003: the error of the same estimator
    // with traversals instead of lookups).
    for w in errors.windows(2) {
        assert!(w[1].2 < w[0].2 * 1.05, "error does not fall: {errors:?}");
    }
    assert!(last_error < 0.5 * errors[0].2, "{errors:?}");
}

#[test]
fn lhb_frames_are_bit_identical_for_one_and_three_tracers() {
    init();
    let prepared = cornell();
    let spec: DeviceSpec = "lavapipe:1,1,1".parse().unwrap();
    let mut tracers = create_tracers(&spec, &prepared.gpu, true, Sampling::Mis).unwrap();
    let mut one = tracer(&prepared, Sampling::Mis);
    for variant in [RasterVariant::Capacity, RasterVariant::Exact] {
        let o = LhbOptions {
            variant,
            bounces: 3,
            cone: 2.0,
            ..options("ico80", 32)
        };
        let mut params = FrameParams::new(24, 20, 2, prepared.camera);
        params.method = Method::new(Lhb::prepared(o, &prepared.gpu));
        let reference = render_with(&mut one, &params);
        assert!(mean(&reference) > 0.0, "{o:?}: black");
        assert!(
            render_with(&mut one, &params) == reference,
            "{o:?}: rerun differs"
        );
        let mut renderer = Renderer::new(tracers, by_name("cost-aware").unwrap());
        for frame in 0..3 {
            let f = renderer.render_frame(&params).unwrap();
            assert!(f.film == reference, "{o:?}, frame {frame}: image differs");
            assert_eq!(f.rejected_samples, 0);
        }
        tracers = renderer.into_tracers();
    }
    for t in &tracers {
        assert_no_validation_messages(t);
    }
}

/// Living scenes: CesiumMan walking across the tessellated Cornell box, a generation a step. A
/// tracer keeping the layers of what did not move (the room) and rasterizing the man again each
/// frame renders the bits of one rebuilding every buffer every frame; from the second step on
/// it reuses the kept part, adding one instance.
#[test]
fn keeping_what_did_not_move_renders_the_bits_of_rebuilding_every_frame() {
    use platoon::drive::Updater;
    let man = platoon::load_scene(Some(&shared("scenes/CesiumMan.glb"))).unwrap();
    let (scene, node) = platoon::drive::walk::walk_in_a_room(&man, 6).unwrap();
    let camera =
        platoon::core::scene::camera::Camera::from_scene(&scene, &scene.pose(0.0), None).unwrap();
    let mut updater = Updater::new(scene, 0.0, glam::DVec3::ZERO).unwrap();
    let mut kept = tracer_reading(updater.flattened(), Default::default());
    let mut rebuilt = tracer_reading(updater.flattened(), Default::default());
    let o = options("ico80", 64);
    let mut previous: Option<std::sync::Arc<platoon::core::method::lhb::tables::Tables>> = None;
    for step in 0..4 {
        if step > 0 {
            for e in platoon::drive::walk::walk_edits(node, step) {
                updater.apply(e).unwrap();
            }
            let generation = updater.update().unwrap();
            kept.apply_commit(&generation.commit).unwrap();
            rebuilt.apply_commit(&generation.commit).unwrap();
        }
        let g = updater.flattened();
        let lhb = Lhb::prepared_after(o, g, previous.as_deref());
        let tables = lhb.tables.clone().unwrap();
        if let Some(p) = &previous {
            assert_eq!(p.frame, tables.frame, "the frame moved");
        }
        let mut params = FrameParams::new(16, 16, 2, camera);
        params.method = Method::new(lhb.clone());
        let band = kept
            .render_span(&params, Span::lines(16, 0, 16), &mut |_| {})
            .unwrap();
        let built = report_line(&band.method_report);
        println!("step {step}: {built}");
        assert_eq!(report_line_lost(&band.method_report), 0);
        let image = render_with(&mut kept, &params);
        params.method = Method::new(Lhb {
            options: LhbOptions { rebuild: true, ..o },
            ..lhb
        });
        assert!(
            render_with(&mut rebuilt, &params) == image,
            "step {step}: keeping what did not move changed the image"
        );
        if step >= 2 {
            assert!(built.starts_with("kept part reused, 1 moving"), "{built}");
        }
        previous = Some(tables);
    }
    assert_no_validation_messages(&kept);
}

/// The game loop: with the synchronous update each new generation of the walk gets its tables
/// (in the first generation's frame) before its first frame, and the frames render on two
/// tracers without NaN or a device message.
#[test]
fn the_game_loop_prepares_each_generation_of_a_walk() {
    use platoon::drive::{DriverOptions, FrameDriver, GiUpdate, Pipeline};
    init();
    let man = platoon::load_scene(Some(&shared("scenes/CesiumMan.glb"))).unwrap();
    let (scene, node) = platoon::drive::walk::walk_in_a_room(&man, 6).unwrap();
    let camera =
        platoon::core::scene::camera::Camera::from_scene(&scene, &scene.pose(0.0), None).unwrap();
    let (pipeline, first) = Pipeline::new(scene, 0.0, glam::DVec3::ZERO).unwrap();
    let spec: DeviceSpec = "lavapipe:1,1".parse().unwrap();
    let tracers = create_tracers(&spec, &first, true, Sampling::Mis).unwrap();
    let mut options = DriverOptions::new(16, 16);
    options.method = Method::new(Lhb::new(options_for_the_loop()));
    options.gi_update = GiUpdate::Synchronous;
    let mut d = FrameDriver::with_update_tracers(
        pipeline,
        &first,
        tracers,
        Vec::new(),
        by_name("cost-aware").unwrap(),
        options,
    )
    .unwrap();
    let mut stats = Vec::new();
    for frame in 0..6 {
        if frame < 3 {
            for e in platoon::drive::walk::walk_edits(node, frame + 1) {
                d.scene().push(e).unwrap();
            }
        }
        let out = d.frame(camera).unwrap();
        stats.extend(out.finished.map(|f| f.stats));
    }
    while let Some(f) = d.finish().unwrap() {
        stats.push(f.stats);
    }
    let gis: Vec<_> = stats.iter().map(|s| s.gi.clone().unwrap()).collect();
    let generations: Vec<u64> = gis.iter().map(|g| g.generation).collect();
    println!("generations {generations:?}");
    assert!(generations.windows(2).all(|w| w[0] <= w[1]));
    assert_eq!(*generations.last().unwrap(), 3);
    assert!(gis.iter().all(|g| g.age == 0));
    let frames: Vec<_> = gis
        .iter()
        .map(|g| {
            g.method
                .state::<Lhb>()
                .unwrap()
                .tables
                .clone()
                .unwrap()
                .frame
        })
        .collect();
    assert!(frames.iter().all(|f| *f == frames[0]), "the frame moved");
    for s in &stats {
        assert_eq!(s.rejected_samples, 0);
        assert!(s.device_messages.is_empty(), "{:?}", s.device_messages);
    }
}

fn options_for_the_loop() -> LhbOptions {
    LhbOptions {
        layers: 8,
        ..options("ico20", 32)
    }
}

/// The kernels' lookup answers rays as the CPU's (`lookup.rs`, over the ray oracle's buffers):
/// 4096 rays from random points inside the tessellated Cornell box in random directions,
/// without jitter, through a probe frame (a pixel a ray). They may differ only where the
/// device's lists differ from the oracle's (texel centres on edges) or where the two round a
/// projection into neighbouring texels.
#[test]
fn the_devices_lookups_answer_as_the_cpus() {
    use platoon::core::method::lhb::lookup::Buffers;
    use platoon::core::method::lhb::FRAME_MARGIN;
    let prepared = prepare(
        platoon::core::scene::cornell::tessellated(2),
        platoon::EnvChoice::Scene,
    );
    let g = &prepared.gpu;
    let mut tracer = tracer(&prepared, Sampling::Mis);
    for variant in [RasterVariant::Capacity, RasterVariant::Exact] {
        let o = LhbOptions {
            cone: 0.0,
            variant,
            ..options("ico80", 32)
        };
        let cpu = Buffers::by_rays(g, o.directions, o.resolution, FRAME_MARGIN);
        let mut s = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 40) as f32 / (1u64 << 24) as f32
        };
        let queries: Vec<[f32; 8]> = (0..4096)
            .map(|_| {
                let x = glam::Vec3::new(next(), next(), next()) * 4.95 + 0.3;
                let z = 1.0 - 2.0 * next();
                let phi = std::f32::consts::TAU * next();
                let r = (1.0 - z * z).max(0.0).sqrt();
                [x.x, x.y, x.z, r * phi.cos(), r * phi.sin(), z, 0.0, 0.0]
            })
            .collect();
        let tables = Lhb::prepared(o, g).tables.unwrap().with_queries(&queries);
        let eps = 1e-5 * tables.frame.radius;
        let mut params = FrameParams::new(64, 64, 1, prepared.camera);
        params.method = Method::new(Lhb {
            options: o,
            tables: Some(std::sync::Arc::new(tables)),
            previous: None,
        });
        let band = tracer
            .render_span(&params, Span::lines(64, 0, 64), &mut |_| {})
            .expect("probe");
        assert_no_validation_messages(&tracer);
        let (mut agree, mut found) = (0, 0);
        for (q, got) in queries.iter().zip(&band.sums) {
            let (x, d) = (
                glam::Vec3::new(q[0], q[1], q[2]),
                glam::Vec3::new(q[3], q[4], q[5]),
            );
            let want = cpu.lookup(x, d, (0.0, 0.0), eps).map(|h| h.point);
            let got = (got[0] < 1e29).then(|| glam::Vec3::from(*got));
            found += got.is_some() as u32;
            agree += match (want, got) {
                (None, None) => 1,
                (Some(w), Some(g)) if (w - g).length() < 1e-3 => 1,
                _ => 0,
            };
        }
        println!("{variant:?}: {agree} of 4096 lookups as the CPU's, {found} found a surface");
        assert!(found > 3000, "{found}");
        assert!(agree >= 4086, "{agree} of 4096");
    }
}

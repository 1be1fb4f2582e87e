//! `platoon bench kernel`: samples/s, rays/s and BVH build times of the built-in scenes, the cost
//! of interleaved lines and the CPU comparison of BVH layouts.

use std::time::Duration;

use anyhow::Result;
use platoon::core::flatten::GpuScene;
use platoon::core::frame::FrameParams;
use platoon::tracer::{Tracer, TracerOptions};

use platoon::core::measure::median;
use platoon::{prepare, PrepareOptions, Prepared};

struct Measure {
    samples_per_s: f64,
    rays_per_s: f64,
    seconds: f64,
}

impl Measure {
    fn print(&self, label: &str) {
        let (s, r) = (self.samples_per_s / 1e6, self.rays_per_s / 1e6);
        println!("{label:<40} {s:>12.3} {r:>12.3} {:>9.3}", self.seconds);
    }
}

fn measure(tracer: &mut Tracer, params: &FrameParams, repeat: u32) -> Result<Measure> {
    let mut warm = params.clone();
    warm.spp = 1;
    tracer.render(&warm, 0, warm.height, &mut |_| {})?;
    let mut times = Vec::new();
    let mut rays = Vec::new();
    for _ in 0..repeat {
        let band = tracer.render(params, 0, params.height, &mut |_| {})?;
        let t = band.wall_time.as_secs_f64();
        times.push(t);
        rays.push(band.rays as f64 / t);
    }
    let t = median(times);
    let samples = params.width as f64 * params.height as f64 * params.spp as f64;
    Ok(Measure {
        samples_per_s: samples / t,
        rays_per_s: median(rays),
        seconds: t,
    })
}

fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

/// `platoon bench kernel`'s settings.
#[derive(clap::Args)]
pub struct KernelArgs {
    /// Samples per pixel of each measured render.
    #[arg(long, default_value_t = 16)]
    spp: u32,
    #[arg(long, default_value_t = 0)]
    device: usize,
    /// Repetitions of each measurement (the median is reported).
    #[arg(long, default_value_t = 3)]
    repeat: u32,
}

pub fn run(a: &KernelArgs) -> Result<()> {
    let (spp, device, repeat) = (a.spp, a.device, a.repeat.max(1));
    let options = TracerOptions {
        device,
        ..Default::default()
    };
    println!("platoon bench kernel: {spp} spp per render, median of {repeat}, 256x256");
    let cornell = prepare(
        platoon::core::scene::cornell::scene(),
        &PrepareOptions::default(),
    )?;
    let mut tracer = Tracer::new(&options, &cornell.gpu)?;
    println!("device: {}", tracer.device_info().name);
    println!(
        "{:<40} {:>12} {:>12} {:>9}",
        "scene", "Msamples/s", "Mrays/s", "seconds"
    );
    // Camera rays only (max depth 1: the emitters seen directly) against full paths.
    for (label, depth) in [
        ("cornell box, camera rays only", Some(1)),
        ("cornell box, depth 8", Some(8)),
        ("cornell box, unbounded", None),
    ] {
        let mut params = FrameParams::new(256, 256, spp, cornell.camera);
        if let Some(d) = depth {
            params.max_depth = d;
        }
        let m = measure(&mut tracer, &params, repeat)?;
        m.print(label);
    }
    drop(tracer);

    // Contiguous bands against interleaved lines: what interleaving costs in coherence.
    let layout = platoon_lab::balance_bench::Options {
        width: 192,
        height: 144,
        spp,
        ..Default::default()
    };
    let one = platoon::devices::DeviceSpec::Indices(vec![device]);
    for stride in [2, 3] {
        let (c, i) = platoon_lab::balance_bench::coherence(&layout, &one, stride, repeat)?;
        println!("outdoor 192x144, {stride} interleaved passes vs one band: {:.3} s vs {:.3} s ({:+.1}%)", i, c, 100.0 * (i / c - 1.0));
    }

    let dir = tempfile::tempdir()?;
    for (label, unique) in [
        ("sphere field 100k, instanced", false),
        ("sphere field 100k, unique", true),
    ] {
        let path = dir.path().join(format!("field-{unique}.glb"));
        std::fs::write(
            &path,
            platoon_scenegen::to_glb(&platoon_scenegen::sphere_field(4, unique)),
        )?;
        let p = prepare(
            platoon::load_scene(Some(&path))?,
            &PrepareOptions::default(),
        )?;
        let mut tracer = Tracer::new(&options, &p.gpu)?;
        let mut params = FrameParams::new(256, 256, spp, p.camera);
        measure(&mut tracer, &params, repeat)?.print(label);
        params.max_depth = 1;
        measure(&mut tracer, &params, repeat)?.print(&format!("{label}, camera rays"));
        print_build_times(&p.gpu, label);
        if unique {
            compare_layouts(&p);
            refit_row(&p);
        }
    }
    Ok(())
}

/// Refitting against rebuilding the 16 distinct meshes of the 100k field, each deformed by a
/// wave (one thread: the refit of one mesh is one sweep).
fn refit_row(p: &Prepared) {
    use platoon::core::flatten::refit::MeshBvh;
    use std::time::Instant;
    let meshes: Vec<_> = p.posed.meshes.iter().map(|m| (**m).clone()).collect();
    let triangles: usize = meshes.iter().map(|m| m.indices.len()).sum();
    let mut bvhs: Vec<MeshBvh> = meshes.iter().map(MeshBvh::build).collect();
    let (mut refit, mut rebuild) = (Vec::new(), Vec::new());
    for frame in 0..5 {
        let moved: Vec<_> = meshes
            .iter()
            .map(|m| {
                let mut m = m.clone();
                for v in &mut m.positions {
                    v.y += 0.02 * (3.0 * v.x + 0.7 * frame as f32).sin();
                }
                m
            })
            .collect();
        let t = Instant::now();
        for (b, m) in bvhs.iter_mut().zip(&moved) {
            assert!(b.refit(m), "same triangles");
        }
        refit.push(t.elapsed().as_secs_f64());
        let t = Instant::now();
        for m in &moved {
            std::hint::black_box(platoon::core::flatten::bvh::build_mesh_bvh(m));
        }
        rebuild.push(t.elapsed().as_secs_f64());
    }
    let (refit, rebuild) = (median(refit), median(rebuild));
    println!(
        "BVH refit, {triangles} triangles in 16 meshes (leaf boxes included, 1 thread): {:.2} ms = {:.1} M triangles/s; rebuild {:.2} ms: {:.0}x",
        refit * 1e3,
        triangles as f64 / refit / 1e6,
        rebuild * 1e3,
        rebuild / refit
    );
}

/// BVH2 against CWBVH on the CPU (platoon_lab::layout_bench).
fn compare_layouts(p: &Prepared) {
    let (c, triangles, rays) = platoon_lab::layout_bench::on_prepared(p);
    println!(
        "BVH layouts on the CPU (1 thread, {} triangles, {} rays; same hits: {}):",
        triangles, rays, c.hits_agree
    );
    println!(
        "  BVH2:  {:>6.2} Mrays/s, nodes {:>6.2} MB, build {:>6.1} ms",
        c.bvh2_rays_per_s / 1e6,
        c.bvh2_node_bytes as f64 / 1e6,
        ms(c.bvh2_build)
    );
    println!(
        "  CWBVH: {:>6.2} Mrays/s, nodes {:>6.2} MB, build {:>6.1} ms",
        c.cwbvh_rays_per_s / 1e6,
        c.cwbvh_node_bytes as f64 / 1e6,
        ms(c.cwbvh_build)
    );
}

fn print_build_times(g: &GpuScene, label: &str) {
    println!(
        "  BVH build ({label}): {} triangles, bottom level {:.1} ms, top level {:.2} ms",
        g.triangle_count,
        ms(g.build_times.meshes),
        ms(g.build_times.instances)
    );
}

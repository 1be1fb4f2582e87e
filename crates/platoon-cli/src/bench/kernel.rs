//! `platoon bench kernel`: samples/s and rays/s of the bench scenes (platoon_lab::scene_bench)
//! with each of the path tracer's kernels, BVH build times, the cost of interleaved lines and
//! the CPU comparison of BVH layouts.

use std::time::Duration;

use anyhow::Result;
use platoon::core::flatten::GpuScene;
use platoon::core::frame::FrameParams;
use platoon::tracer::{Tracer, TracerOptions};

use platoon::core::measure::median;
use platoon::core::method::path::{PathKernel, PathTracing};
use platoon::core::Method;
use platoon::{prepare, PrepareOptions, Prepared};
use platoon_lab::scene_bench;

struct Measure {
    samples_per_s: f64,
    rays_per_s: f64,
    seconds: f64,
}

/// Renders `params` with each of `kernels`, `repeat` times in turn after a warm-up render of
/// each (the kernel compiles are not timed); the median of each.
fn measure(
    tracer: &mut Tracer,
    params: &FrameParams,
    kernels: &[PathKernel],
    repeat: u32,
) -> Result<Vec<Measure>> {
    let with = |kernel: PathKernel| FrameParams {
        method: Method::new(PathTracing {
            kernel,
            ..params.method.path().clone()
        }),
        ..params.clone()
    };
    for &k in kernels {
        let mut warm = with(k);
        warm.spp = 1;
        tracer.render(&warm, 0, warm.height, &mut |_| {})?;
    }
    let mut times = vec![Vec::new(); kernels.len()];
    let mut rays = vec![Vec::new(); kernels.len()];
    for _ in 0..repeat {
        for (i, &k) in kernels.iter().enumerate() {
            let band = tracer.render(&with(k), 0, params.height, &mut |_| {})?;
            let t = band.wall_time.as_secs_f64();
            times[i].push(t);
            rays[i].push(band.rays as f64 / t);
        }
    }
    let samples = params.width as f64 * params.height as f64 * params.spp as f64;
    Ok(times
        .into_iter()
        .zip(rays)
        .map(|(t, r)| {
            let t = median(t);
            Measure {
                samples_per_s: samples / t,
                rays_per_s: median(r),
                seconds: t,
            }
        })
        .collect())
}

fn print_row(label: &str, m: &[Measure]) {
    print!("{label:<44}");
    for k in m {
        print!(
            " {:>8.3} {:>8.3} {:>7.3}",
            k.samples_per_s / 1e6,
            k.rays_per_s / 1e6,
            k.seconds
        );
    }
    if m.len() == 2 {
        print!(" {:>7.2}x", m[0].seconds / m[1].seconds);
    }
    println!();
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
    /// The path tracer's kernels to measure, in turn (mega, spt), comma-separated.
    #[arg(long, default_value = "mega,spt", value_delimiter = ',', value_parser = parse_kernel)]
    kernels: Vec<PathKernel>,
    /// The folder of the shared test data (CesiumMan and courtyard.exr for the last row).
    #[arg(long, default_value_os_t = platoon_lab::shared::dir())]
    shared: std::path::PathBuf,
}

fn parse_kernel(s: &str) -> Result<PathKernel, String> {
    PathKernel::by_name(s).ok_or_else(|| format!("unknown kernel {s}: mega or spt"))
}

pub fn run(a: &KernelArgs) -> Result<()> {
    let (spp, device, repeat) = (a.spp, a.device, a.repeat.max(1));
    let options = TracerOptions {
        device,
        ..Default::default()
    };
    let kernels = &a.kernels;
    println!("platoon bench kernel: {spp} spp per render, median of {repeat}, 256x256");
    let dir = tempfile::tempdir()?;
    let mut names: Vec<String> = scene_bench::NAMES.iter().map(|s| s.to_string()).collect();
    if !a.shared.join("scenes/CesiumMan.glb").is_file() {
        println!("(no {}: CesiumMan left out)", a.shared.display());
        names.retain(|n| n != "cesium");
    }
    let scenes = scene_bench::scenes(dir.path(), &a.shared, &names)?;
    print!("{:<44}", "scene");
    for k in kernels {
        print!(
            " {:>8} {:>8} {:>7}",
            format!("{} Ms/s", k.name()),
            "Mrays/s",
            "s"
        );
    }
    if kernels.len() == 2 {
        print!(
            " {:>8}",
            format!("{}/{}", kernels[1].name(), kernels[0].name())
        );
    }
    println!();
    for scene in &scenes {
        // Scenes of many nodes also with an instance per node: what merging the objects that
        // never move into one bottom level gains.
        let merges: &[bool] = match scene.name {
            "cornell-nodes" | "field" => &[true, false],
            _ => &[true],
        };
        for &merge_static in merges {
            let p = prepare(
                platoon::load_scene(scene.file.as_deref())?,
                &PrepareOptions {
                    env: scene.env.clone(),
                    merge_static,
                    ..Default::default()
                },
            )?;
            let mut tracer = Tracer::new(&options, &p.gpu)?;
            if scene.name == "cornell" {
                println!("device: {}", tracer.device_info().name);
            }
            // Camera rays only (max depth 1: the emitters seen directly) against full paths;
            // the instanced variant at depth 8 alone.
            let depths: &[(&str, Option<u32>)] = if merge_static {
                &[
                    ("camera rays", Some(1)),
                    ("depth 8", Some(8)),
                    ("unbounded", None),
                ]
            } else {
                &[("depth 8, instanced", Some(8))]
            };
            for &(what, depth) in depths {
                let mut params = FrameParams::new(256, 256, spp, p.camera);
                if let Some(d) = depth {
                    params.path_loop.max_depth = d;
                }
                let m = measure(&mut tracer, &params, kernels, repeat)?;
                print_row(&format!("{}, {what}", scene.name), &m);
            }
            drop(tracer);
            if scene.name == "field" && merge_static {
                print_build_times(&p.gpu, "sphere field, merged");
            }
        }
    }

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

    // The 16 distinct meshes of the field: build times, BVH layouts on the CPU, refits.
    let path = dir.path().join("field-unique.glb");
    std::fs::write(
        &path,
        platoon_scenegen::to_glb(&platoon_scenegen::sphere_field(4, true)),
    )?;
    let p = prepare(
        platoon::load_scene(Some(&path))?,
        &PrepareOptions::default(),
    )?;
    print_build_times(&p.gpu, "sphere field, unique meshes");
    compare_layouts(&p);
    refit_row(&p);
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
            std::hint::black_box(platoon::core::flatten::mesh_bvh::build_mesh_bvh(m));
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

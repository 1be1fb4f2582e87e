//! Shared helpers of the integration tests: lavapipe forced, validation on, small images.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::sync::Once;

use glam::Vec3;
use platoon::core::frame::FrameParams;
use platoon::core::method::path::PathKernel;
use platoon::core::output::Film;
use platoon::tracer::{MemoryPath, Sampling, Tracer, TracerOptions};
use platoon::{PrepareOptions, Prepared};

static INIT: Once = Once::new();

pub const LAVAPIPE_ICD: &str = "/usr/share/vulkan/icd.d/lvp_icd.x86_64.json";

/// Forces Mesa lavapipe so results do not depend on other installed drivers, and keeps the
/// kernel caches in the target folder shared by all test runs.
pub fn init() {
    INIT.call_once(|| {
        assert!(
            Path::new(LAVAPIPE_ICD).exists(),
            "lavapipe is not installed: run tools/install-deps.sh"
        );
        // Under the tracer's creation lock: a test that creates its tracers without calling
        // this first may be creating them on another thread (the loader reads the environment).
        let icd = std::ffi::OsStr::new(LAVAPIPE_ICD);
        let cache = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("platoon-cache");
        let mut vars = vec![("VK_DRIVER_FILES", icd), ("VK_ICD_FILENAMES", icd)];
        if std::env::var_os("PLATOON_CACHE_DIR").is_none() {
            vars.push(("PLATOON_CACHE_DIR", cache.as_os_str()));
        }
        platoon::tracer::set_environment(&vars);
    });
}

/// The ICD file of a lavapipe with ray queries: bookworm-backports' Mesa 25, which
/// `tools/mesa25.sh` unpacks beside Debian 12's 22.3 on first use (issue 61's tests).
pub fn mesa25_icd() -> String {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let script = std::process::Command::new(root.join("tools/mesa25.sh"))
        .output()
        .expect("run tools/mesa25.sh");
    let why = String::from_utf8_lossy(&script.stderr);
    assert!(script.status.success(), "tools/mesa25.sh: {why}");
    String::from_utf8_lossy(&script.stdout).trim().to_string()
}

pub fn shared(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared")
        .join(rel)
}

pub fn tracer(prepared: &Prepared, sampling: Sampling) -> Tracer {
    init();
    Tracer::new(
        &TracerOptions {
            device: 0,
            validation: true,
            sampling,
            ..Default::default()
        },
        &prepared.gpu,
    )
    .expect("tracer")
}

/// A tracer on lavapipe with validation on, reading the scene arrays by `memory`.
pub fn tracer_reading(scene: &platoon::core::flatten::GpuScene, memory: MemoryPath) -> Tracer {
    init();
    let options = TracerOptions {
        validation: true,
        memory,
        ..Default::default()
    };
    Tracer::new(&options, scene).expect("tracer")
}

/// Renders the whole frame with validation on and asserts the layer said nothing. A path-traced
/// radiance render in the default kernel is rendered again by the streaming path tracer, which
/// must give the same bits: so every closed-form, estimator and feature test holds both kernels.
pub fn render_with(tracer: &mut Tracer, params: &FrameParams) -> Film {
    let film = render_once(tracer, params);
    let path_traced = params.method.is_path_tracing()
        && params.output == platoon::core::frame::Output::Radiance
        && params.options.time_limit.is_none();
    if path_traced && params.method.path().kernel == PathKernel::Auto {
        let mut streamed = params.clone();
        streamed.method = streaming(&params.method);
        assert!(
            render_once(tracer, &streamed) == film,
            "the streaming path tracer's image differs from the megakernel's"
        );
    }
    film
}

/// Path tracing with resampled light over `candidates` lights by contribution, combined with
/// BSDF sampling by MIS (what `--resampled-light` chooses).
pub fn resampled(candidates: u32) -> platoon::core::Method {
    platoon::core::Method::new(platoon::core::method::path::PathTracing {
        resampled_light: Some(platoon::core::method::path::ResampledLight::new(candidates)),
        ..Default::default()
    })
}

/// `method` (the path tracer's) with its paths in the streaming kernels.
pub fn streaming(method: &platoon::core::Method) -> platoon::core::Method {
    let mut method = method.clone();
    method.path_mut().expect("the path tracer").kernel = PathKernel::Streaming;
    method
}

/// `method` (the path tracer's) in `kernel`.
pub fn in_kernel(method: &platoon::core::Method, kernel: PathKernel) -> platoon::core::Method {
    let mut method = method.clone();
    method.path_mut().expect("the path tracer").kernel = kernel;
    method
}

/// Renders the whole frame once in `params`' kernel (see `render_with`).
pub fn render_once(tracer: &mut Tracer, params: &FrameParams) -> Film {
    let r = platoon::render_bands(tracer, params, &[platoon::whole_frame(params)], &mut |_| {})
        .expect("render");
    assert_eq!(r.rejected_samples(), 0, "NaN/Inf samples were produced");
    assert_no_validation_messages(tracer);
    r.film
}

pub fn assert_no_validation_messages(tracer: &Tracer) {
    let msgs = tracer.validation_messages();
    assert!(msgs.is_empty(), "validation messages:\n{}", msgs.join("\n"));
}

pub fn render(prepared: &Prepared, params: &FrameParams, sampling: Sampling) -> Film {
    let mut t = tracer(prepared, sampling);
    render_with(&mut t, params)
}

pub fn prepare(scene: platoon::core::Scene, env: platoon::EnvChoice) -> Prepared {
    platoon::prepare(
        scene,
        &PrepareOptions {
            env,
            ..Default::default()
        },
    )
    .expect("prepare")
}

/// A generated scene written as a .glb and loaded back through the glTF loader, as a user's
/// `platoon-scenegen OUT.glb` file would be.
pub fn load_generated(data: &platoon_scenegen::SceneData) -> platoon::core::Scene {
    let dir = tempfile::tempdir().expect("temporary folder");
    let path = dir.path().join("generated.glb");
    std::fs::write(&path, platoon_scenegen::to_glb(data)).expect("write the glb");
    platoon::load_scene(Some(&path)).expect("load the generated glb")
}

pub fn constant_env(c: f32) -> platoon::EnvChoice {
    platoon::EnvChoice::Color(Vec3::splat(c))
}

/// Mean and standard error of the per-pixel values of one channel-averaged film region.
pub fn mean_and_stderr(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let v: Vec<f64> = values.collect();
    let n = v.len() as f64;
    let mean = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt())
}

use std::sync::Arc;

use platoon::core::scene::{Material, Mesh, Node, Scene};

/// Adds a punctual light of `kind` and `intensity` at `at`, its -Z (where spots and
/// directional lights point) turned straight down.
pub fn add_light(
    scene: &mut Scene,
    kind: platoon::core::scene::LightKind,
    intensity: f32,
    at: Vec3,
) {
    scene.lights.push(platoon::core::scene::PunctualLight {
        name: "light".into(),
        kind,
        color: Vec3::ONE,
        intensity,
        range: 0.0,
    });
    let mut node = Node::new("light");
    node.light = Some(scene.lights.len() - 1);
    node.translation = at.as_dvec3();
    node.rotation = glam::Quat::from_rotation_x(-std::f32::consts::FRAC_PI_2);
    scene.nodes.push(node);
}

pub fn mesh_from(data: &platoon_scenegen::MeshData, material: u32) -> Mesh {
    Mesh::from_arrays(
        "generated",
        &data.positions,
        &data.normals,
        &data.indices,
        material,
    )
}

/// A scene of meshes (one node each, at the given translation and uniform scale) and a camera
/// looking from `eye` at `target`.
pub fn scene_of(
    meshes: Vec<(Mesh, Vec3, f32)>,
    materials: Vec<Material>,
    eye: Vec3,
    target: Vec3,
    yfov: f32,
) -> Scene {
    let mut scene = Scene {
        materials,
        ..Default::default()
    };
    for (i, (mesh, t, s)) in meshes.into_iter().enumerate() {
        scene.meshes.push(Arc::new(mesh));
        let mut node = Node::new(format!("mesh{i}"));
        node.mesh = Some(i);
        node.translation = t.as_dvec3();
        node.scale = Vec3::splat(s);
        scene.nodes.push(node);
    }
    let cam = platoon::core::scene::camera::Camera::look_at(eye, target, yfov);
    let (_, r, t) = cam.camera_to_world.to_scale_rotation_translation();
    let mut node = Node::new("camera");
    node.rotation = r;
    node.translation = t.as_dvec3();
    node.camera = Some(0);
    scene.nodes.push(node);
    scene.cameras.push(platoon::core::scene::CameraModel {
        name: "camera".into(),
        yfov,
        aspect_ratio: None,
        orthographic: None,
    });
    scene
}

/// A unit sphere of `material`, filling most of the view.
pub fn sphere_scene(material: Material) -> Scene {
    let sphere = mesh_from(&platoon_scenegen::uv_sphere(32, 48), 0);
    scene_of(
        vec![(sphere, Vec3::ZERO, 1.0)],
        vec![material],
        Vec3::new(0.0, 0.0, 3.2),
        Vec3::ZERO,
        0.8,
    )
}

/// Pixels whose centre ray hits a sphere of `radius` at the origin seen by `sphere_scene`.
pub fn sphere_pixels(w: u32, h: u32, shrink: f32) -> Vec<usize> {
    let tan = (0.8f32 * 0.5).tan();
    let eye = Vec3::new(0.0, 0.0, 3.2);
    let mut out = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let d = Vec3::new(
                (2.0 * (x as f32 + 0.5) / w as f32 - 1.0) * tan,
                (1.0 - 2.0 * (y as f32 + 0.5) / h as f32) * tan,
                -1.0,
            )
            .normalize();
            // Distance of the ray from the centre.
            let closest = (eye - d * eye.dot(d)).length();
            if closest < shrink {
                out.push((y * w + x) as usize);
            }
        }
    }
    out
}

pub fn luminance(p: [f32; 3]) -> f64 {
    (p[0] as f64 + p[1] as f64 + p[2] as f64) / 3.0
}

/// Root-mean-square difference of two films over every pixel and channel.
pub fn rmse(a: &Film, b: &Film) -> f64 {
    let n = a.pixels.len() as f64 * 3.0;
    let sum: f64 = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .flat_map(|(p, q)| (0..3).map(move |c| (p[c] as f64 - q[c] as f64).powi(2)))
        .sum();
    (sum / n).sqrt()
}

/// Mean of a film over every pixel and channel.
pub fn mean(film: &Film) -> f64 {
    film.pixels
        .iter()
        .map(|p| (p[0] + p[1] + p[2]) as f64)
        .sum::<f64>()
        / (3 * film.pixels.len()) as f64
}

/// `a - b`, pixel by pixel (e.g. a render minus its direct light).
pub fn minus(a: &Film, b: &Film) -> Film {
    let mut d = a.clone();
    for (p, q) in d.pixels.iter_mut().zip(&b.pixels) {
        for c in 0..3 {
            p[c] -= q[c];
        }
    }
    d
}

/// `meshes` of `materials` (with `textures`) seen from `eye` toward the origin by an
/// orthographic camera 0.05 wide, under a sky of 1: the set-up of the tests that hold a surface
/// to an integral of its BSDF (every ray it reflects or refracts finds the sky or a mesh).
pub fn under_unit_sky(
    meshes: Vec<(Mesh, Vec3, f32)>,
    materials: Vec<Material>,
    textures: Vec<platoon::core::scene::Texture>,
    eye: Vec3,
) -> Prepared {
    let mut scene = scene_of(meshes, materials, eye, Vec3::ZERO, 0.5);
    scene.textures = textures;
    scene.cameras[0].orthographic = Some([0.05, 0.05]);
    prepare(scene, constant_env(1.0))
}

/// A texture of one texel, repeating, unfiltered: one value for a texture slot.
pub fn one_texel(name: &str, rgba8: [u8; 4]) -> platoon::core::scene::Texture {
    use platoon::core::scene::{Texture, Wrap};
    Texture {
        name: name.into(),
        width: 1,
        height: 1,
        rgba8: rgba8.to_vec(),
        wrap_s: Wrap::Repeat,
        wrap_t: Wrap::Repeat,
        nearest: true,
        mips: Vec::new(),
    }
}

/// `material` as the plane y = 0 over a black floor at y = -1, seen from cos θ `cos_view` (in
/// the x-y plane) under a sky of 1: of a plane that transmits, the camera sees the reflection
/// alone (what it refracts finds the black floor).
pub fn over_black_floor(material: Material, cos_view: f64) -> Prepared {
    let black = Material {
        name: "black".into(),
        base_color: glam::Vec4::new(0.0, 0.0, 0.0, 1.0),
        metallic: 0.0,
        specular: 0.0,
        ..Material::default()
    };
    let (s, c) = ((1.0 - cos_view * cos_view).sqrt() as f32, cos_view as f32);
    let quad = |m| mesh_from(&platoon_scenegen::quad(1.0, 1.0), m);
    under_unit_sky(
        vec![
            (quad(0), Vec3::ZERO, 1000.0),
            (quad(1), Vec3::new(0.0, -1.0, 0.0), 1000.0),
        ],
        vec![material, black],
        vec![],
        Vec3::new(s, c, 0.0) * 10.0,
    )
}

/// The Cornell box with a glossy plastic floor and a rough metal tall box, open to a dim sky.
pub fn glossy_cornell() -> platoon::Prepared {
    let mut scene = platoon::core::scene::cornell::scene();
    let floor = scene.materials.len() as u32;
    scene.materials.push(Material {
        name: "plastic".into(),
        base_color: Vec3::new(0.7, 0.7, 0.6).extend(1.0),
        metallic: 0.0,
        roughness: 0.25,
        ..Material::default()
    });
    scene.materials.push(Material {
        name: "metal".into(),
        base_color: Vec3::new(0.9, 0.7, 0.4).extend(1.0),
        metallic: 1.0,
        roughness: 0.35,
        ..Material::default()
    });
    let mesh = std::sync::Arc::make_mut(&mut scene.meshes[0]);
    let n = mesh.triangle_materials.len();
    mesh.triangle_materials[0] = floor;
    mesh.triangle_materials[1] = floor;
    // The tall box is the last of the mesh's quads.
    for m in &mut mesh.triangle_materials[n - 10..] {
        *m = floor + 1;
    }
    prepare(scene, constant_env(0.3))
}

/// A smooth clear dielectric of index 1.5 (the white furnace's glass).
pub fn smooth_glass() -> Material {
    Material {
        name: "glass".into(),
        metallic: 0.0,
        roughness: 0.0,
        transmission: 1.0,
        ior: 1.5,
        ..Material::default()
    }
}

/// The mean luminance of each `block` x `block` square of `film`, row by row (the film's sides
/// multiples of `block`).
pub fn block_means(film: &Film, block: u32) -> Vec<f64> {
    let (w, h) = (film.width, film.height);
    let mut out = Vec::new();
    for by in 0..h / block {
        for bx in 0..w / block {
            let mut s = 0.0;
            for y in by * block..(by + 1) * block {
                for x in bx * block..(bx + 1) * block {
                    s += luminance(film.pixels[(y * w + x) as usize]);
                }
            }
            out.push(s / (block * block) as f64);
        }
    }
    out
}

/// MIS's block means (one list per seed, `block_means`) against each other estimator's: every
/// block within 5 standard errors of the difference (at least 1e-4); returns the largest
/// disagreement in standard errors.
pub fn assert_blocks_agree(mis: &[Vec<f64>], others: &[(&str, &[Vec<f64>])]) -> f64 {
    let summary = |v: &[Vec<f64>], b: usize| mean_and_stderr(v.iter().map(|s| s[b]));
    let mut worst = 0.0f64;
    for b in 0..mis[0].len() {
        let m = summary(mis, b);
        for (name, other) in others {
            let o = summary(other, b);
            let sigma = (m.1 * m.1 + o.1 * o.1).sqrt().max(1e-4);
            let z = (m.0 - o.0).abs() / sigma;
            worst = worst.max(z);
            assert!(
                z < 5.0,
                "block {b}: mis {:.4} ± {:.4} vs {name} {:.4} ± {:.4} ({z:.1} sigma)",
                m.0,
                m.1,
                o.0,
                o.1
            );
        }
    }
    worst
}

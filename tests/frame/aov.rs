//! AOVs (issue 24) against what cannot be faked: the albedo of a Lambertian plane is its
//! colour, seen directly or in a mirror (the specular chain is followed); the normal of a sphere
//! is its position's direction; the depth of a plane facing the camera is its distance, not the
//! rays' lengths; ids tell hits from misses; and every layer has the same bits on one tracer and
//! on three.

#[path = "../common/mod.rs"]
mod common;

use common::*;
use glam::{DVec3, Vec3, Vec4};
use platoon::core::frame::aov::{Aov, Layer, MISS_DEPTH};
use platoon::core::frame::light_pass::LightPass;
use platoon::core::frame::{cryptomatte, FrameParams};
use platoon::core::scene::cornell::lambertian;
use platoon::core::scene::{Material, Scene};
use platoon::devices::{tracer_options, DeviceSpec};
use platoon::tracer::Sampling;
use platoon::{Prepared, Tracers};

const COLOUR: Vec3 = Vec3::new(0.2, 0.5, 0.8);

/// The layers of `aovs` on `devices`; motion vectors against the frame before seen from 0.05
/// to the left.
fn layers_on(devices: &str, prepared: &Prepared, params: &FrameParams, aovs: &[Aov]) -> Vec<Layer> {
    let spec: DeviceSpec = devices.parse().unwrap();
    let options = tracer_options(&spec, false, Sampling::Mis).unwrap();
    let mut tracers = Tracers::new(&options, "cost-aware", &prepared.gpu).unwrap();
    let mut camera = params.camera;
    camera.camera_to_world.w_axis.x -= 0.05;
    let previous = platoon::core::frame::motion::PreviousFrame {
        posed: prepared.scene.pose_around(0.0, prepared.posed.origin),
        camera,
    };
    let (gpu, previous) = (&prepared.gpu, Some(&previous));
    platoon::aov::render_layers(&mut tracers, gpu, params, aovs, DVec3::ZERO, previous).unwrap()
}

fn layer<'a>(layers: &'a [Layer], name: &str) -> &'a Layer {
    layers.iter().find(|l| l.name == name).expect("the layer")
}

/// A quad of half-size `h` in the plane z = `z`, facing `facing` (+1: +z), of material `m`.
fn wall(z: f32, h: f32, facing: f32, m: u32) -> platoon::core::scene::Mesh {
    let c = |x: f32, y: f32| [x, y, z];
    let corners = if facing > 0.0 {
        [c(-h, -h), c(h, -h), c(h, h), c(-h, h)]
    } else {
        [c(-h, -h), c(-h, h), c(h, h), c(h, -h)]
    };
    mesh_from(&platoon_scenegen::quad_from(corners), m)
}

/// A Lambertian wall at z = 0 seen from (0, 0, 4); with `mirror`, a mirror wall there instead
/// and the Lambertian one behind the camera at z = 8, seen in it.
fn walls(mirror: bool) -> Scene {
    let diffuse = lambertian("colour", COLOUR);
    let mirror_material = Material {
        base_color: Vec4::ONE,
        metallic: 1.0,
        roughness: 0.0,
        ..Default::default()
    };
    let meshes = if mirror {
        vec![
            (wall(0.0, 50.0, 1.0, 1), Vec3::ZERO, 1.0),
            (wall(8.0, 50.0, -1.0, 0), Vec3::ZERO, 1.0),
        ]
    } else {
        vec![(wall(0.0, 50.0, 1.0, 0), Vec3::ZERO, 1.0)]
    };
    scene_of(
        meshes,
        vec![diffuse, mirror_material],
        Vec3::new(0.0, 0.0, 4.0),
        Vec3::ZERO,
        0.8,
    )
}

#[test]
fn the_albedo_of_a_lambertian_wall_is_its_colour_directly_and_in_a_mirror() {
    for mirror in [false, true] {
        let prepared = prepare(walls(mirror), constant_env(1.0));
        let params = FrameParams::new(16, 12, 8, prepared.camera);
        let layers = layers_on("0", &prepared, &params, &[Aov::Albedo]);
        let albedo = layer(&layers, "albedo");
        for (c, want) in ["R", "G", "B"].iter().zip(COLOUR.to_array()) {
            for v in albedo.channel(c).unwrap() {
                assert!(
                    (v - want).abs() < 1e-6,
                    "mirror {mirror}: {c} = {v}, not {want}"
                );
            }
        }
    }
}

#[test]
fn the_depth_of_a_wall_facing_the_camera_is_its_distance() {
    let prepared = prepare(walls(false), constant_env(1.0));
    let params = FrameParams::new(16, 12, 4, prepared.camera);
    let layers = layers_on(
        "0",
        &prepared,
        &params,
        &[Aov::Depth, Aov::Position, Aov::InstanceId, Aov::MaterialId],
    );
    for d in layer(&layers, "depth").channel("Z").unwrap() {
        assert!(
            (d - 4.0).abs() < 1e-4,
            "depth {d}, not 4 (the rays' lengths?)"
        );
    }
    for z in layer(&layers, "position").channel("Z").unwrap() {
        assert!(z.abs() < 1e-4, "position z {z}");
    }
    for id in layer(&layers, "instance-id").channel("id").unwrap() {
        assert!(*id >= 1.0, "a hit's instance id is at least 1");
    }
    for id in layer(&layers, "material-id").channel("id").unwrap() {
        assert_eq!(*id, 1.0, "material 0");
    }
}

#[test]
fn the_normal_of_a_sphere_is_its_positions_direction_and_misses_are_empty() {
    let prepared = prepare(
        sphere_scene(lambertian("grey", Vec3::splat(0.5))),
        constant_env(1.0),
    );
    let (w, h) = (24, 24);
    let params = FrameParams::new(w, h, 16, prepared.camera);
    let layers = layers_on(
        "0",
        &prepared,
        &params,
        &[Aov::Normal, Aov::Position, Aov::Depth, Aov::InstanceId],
    );
    let normal = layer(&layers, "normal");
    let position = layer(&layers, "position");
    let inside = sphere_pixels(w, h, 0.85);
    assert!(inside.len() > 100);
    for &i in &inside {
        let at = |l: &Layer, c: [&str; 3]| Vec3::from(c.map(|c| l.channel(c).unwrap()[i]));
        let n = at(normal, ["X", "Y", "Z"]);
        let p = at(position, ["X", "Y", "Z"]);
        assert!(
            (p.length() - 1.0).abs() < 0.01,
            "position {p} off the sphere"
        );
        assert!(
            (n - p.normalize()).length() < 0.05,
            "pixel {i}: normal {n}, position {p}"
        );
    }
    // The corners see the sky.
    for i in [0, (w - 1) as usize, (w * h - 1) as usize] {
        assert_eq!(layer(&layers, "instance-id").channel("id").unwrap()[i], 0.0);
        assert_eq!(layer(&layers, "depth").channel("Z").unwrap()[i], MISS_DEPTH);
        assert_eq!(normal.channel("X").unwrap()[i], 0.0);
    }
}

#[test]
fn every_layer_has_the_same_bits_on_one_tracer_and_on_three() {
    let prepared = prepare(
        platoon::core::scene::cornell::scene(),
        platoon::EnvChoice::Scene,
    );
    let params = FrameParams::new(20, 18, 4, prepared.camera);
    let one = layers_on("0", &prepared, &params, &Aov::ALL);
    let three = layers_on("lavapipe:1,1,1", &prepared, &params, &Aov::ALL);
    // The kernel's layers (sample count and variance come from the beauty's batches:
    // tests/frame/adaptive.rs).
    let kernel_layers: usize = (Aov::ALL.iter().filter(|a| !a.passes().is_empty()))
        .map(|a| match a.cryptomatte() {
            Some(_) => cryptomatte::DEPTH / 2,
            None => 1,
        })
        .sum();
    assert_eq!(one.len(), kernel_layers);
    assert!(one == three, "the split changed a layer");
}

/// Three unit spheres side by side at x = -1.8, 0, 1.8, overlapping in view (nodes `mesh0` to
/// `mesh2`, materials `m0` to `m2`), seen from the front.
fn three_spheres() -> (Scene, [Vec3; 3]) {
    let centres = [
        Vec3::new(-1.8, 0.0, 0.0),
        Vec3::ZERO,
        Vec3::new(1.8, 0.0, 0.0),
    ];
    let meshes = (0..3)
        .map(|i| {
            (
                mesh_from(&platoon_scenegen::uv_sphere(24, 32), i as u32),
                centres[i],
                1.0,
            )
        })
        .collect();
    let materials = (0..3)
        .map(|i| lambertian(&format!("m{i}"), Vec3::splat(0.5)))
        .collect();
    let scene = scene_of(meshes, materials, Vec3::new(0.0, 0.0, 7.0), Vec3::ZERO, 0.8);
    (scene, centres)
}

/// A Cryptomatte's ranks per pixel, decoded: (name, coverage), most coverage first.
fn decode(layers: &[Layer], type_name: &str) -> Vec<Vec<(String, f32)>> {
    let first = layer(layers, &format!("{type_name}00"));
    let manifest = first
        .attributes
        .iter()
        .find(|(k, _)| k.starts_with("cryptomatte/") && k.ends_with("/manifest"))
        .map(|(_, v)| serde_json::from_str::<std::collections::HashMap<String, String>>(v))
        .expect("a manifest")
        .unwrap();
    let key = &format!("{:08x}", cryptomatte::murmur3(type_name))[..7];
    let name = (first.attributes.iter())
        .find(|(k, _)| *k == format!("cryptomatte/{key}/name"))
        .map(|(_, v)| v.as_str());
    assert_eq!(
        name,
        Some(type_name),
        "the header names the layer under its key"
    );
    let by_hex: std::collections::HashMap<&str, &str> = manifest
        .iter()
        .map(|(n, h)| (h.as_str(), n.as_str()))
        .collect();
    let pixels = first.channels[0].1.len();
    (0..pixels)
        .map(|i| {
            let mut ranks = Vec::new();
            for l in 0..cryptomatte::DEPTH / 2 {
                let layer = layer(layers, &format!("{type_name}{l:02}"));
                for (id, coverage) in [("R", "G"), ("B", "A")] {
                    let c = layer.channel(coverage).unwrap()[i];
                    if c > 0.0 {
                        let hex = format!("{:08x}", layer.channel(id).unwrap()[i].to_bits());
                        ranks.push((by_hex[hex.as_str()].to_string(), c));
                    }
                }
            }
            ranks
        })
        .collect()
}

#[test]
fn a_cryptomatte_decoded_names_the_object_and_material_under_each_pixel() {
    // The spheres merged into one mesh (a hit's node found by its triangle) and each an
    // instance of its own (by its instance).
    for merge_static in [true, false] {
        let (scene, centres) = three_spheres();
        let options = platoon::PrepareOptions {
            env: constant_env(1.0),
            merge_static,
            ..Default::default()
        };
        let prepared = platoon::prepare(scene, &options).unwrap();
        let merged = prepared.gpu.instances.len() == 1;
        assert_eq!(merged, merge_static);
        cryptomatte_names_each_pixel(&prepared, centres);
    }
}

#[test]
fn a_cryptomatte_asset_is_the_topmost_ancestor_of_the_object() {
    // The first two spheres under a node `pair`: their asset is the pair, the third's itself.
    let (mut scene, centres) = three_spheres();
    for n in &mut scene.nodes {
        n.parent = n.parent.map(|p| p + 1);
    }
    scene
        .nodes
        .insert(0, platoon::core::scene::Node::new("pair"));
    scene.nodes[1].parent = Some(0);
    scene.nodes[2].parent = Some(0);
    let prepared = prepare(scene, constant_env(1.0));
    let params = FrameParams::new(96, 32, 4, prepared.camera);
    let aovs = [Aov::CryptoAsset, Aov::Position];
    let layers = layers_on("0", &prepared, &params, &aovs);
    let assets = decode(&layers, "CryptoAsset");
    let position = layer(&layers, "position");
    let mut seen = [0usize; 3];
    for (i, ranks) in assets.iter().enumerate() {
        let p = Vec3::from(["X", "Y", "Z"].map(|c| position.channel(c).unwrap()[i]));
        let on = (0..3).find(|&s| ((p - centres[s]).length() - 1.0).abs() < 0.02);
        if let (Some(sphere), Some((name, 1.0))) = (on, ranks.first()) {
            let want = if sphere < 2 { "pair" } else { "mesh2" };
            assert_eq!(name, want, "pixel {i}");
            seen[sphere] += 1;
        }
    }
    assert!(seen.iter().all(|&n| n > 20), "{seen:?}");
}

fn cryptomatte_names_each_pixel(prepared: &Prepared, centres: [Vec3; 3]) {
    let (w, h) = (96, 32);
    let params = FrameParams::new(w, h, 4, prepared.camera);
    let aovs = [Aov::CryptoObject, Aov::CryptoMaterial, Aov::Position];
    let layers = layers_on("0", prepared, &params, &aovs);
    let objects = decode(&layers, "CryptoObject");
    let materials = decode(&layers, "CryptoMaterial");
    let position = layer(&layers, "position");
    let mut whole = [0usize; 3];
    let mut shared = 0;
    for i in 0..(w * h) as usize {
        let ranks = &objects[i];
        let total: f32 = ranks.iter().map(|r| r.1).sum();
        assert!(total <= 1.0 + 1e-6, "pixel {i}: coverage {total}");
        assert!(ranks.windows(2).all(|r| r[0].1 >= r[1].1), "{ranks:?}");
        shared += usize::from(ranks.len() > 1);
        // The sphere under the pixel's centre, by its position: the one it lies on.
        let p = Vec3::from(["X", "Y", "Z"].map(|c| position.channel(c).unwrap()[i]));
        let Some(sphere) = (0..3).find(|&s| ((p - centres[s]).length() - 1.0).abs() < 0.02) else {
            continue;
        };
        if ranks.first().map(|r| r.1) == Some(1.0) {
            assert_eq!(ranks[0].0, format!("mesh{sphere}"), "pixel {i}");
            assert_eq!(materials[i][0], (format!("m{sphere}"), 1.0), "pixel {i}");
            whole[sphere] += 1;
        }
    }
    assert!(
        whole.iter().all(|&n| n > 20),
        "pixels wholly on each sphere: {whole:?}"
    );
    assert!(shared > 0, "no pixel on an edge between two objects");
}

/// Spheres of every BSDF part over a Lambertian floor under a sky of 0.5, with a small emitter:
/// glass (delta), rough glass, rough metal, a coated sheen, and a pane of rough glass, each part
/// of the light passes lit.
fn every_part() -> Scene {
    let sphere = || mesh_from(&platoon_scenegen::uv_sphere(16, 24), 0);
    let floor = platoon_scenegen::quad_from([
        [-20.0, -1.0, -20.0],
        [-20.0, -1.0, 20.0],
        [20.0, -1.0, 20.0],
        [20.0, -1.0, -20.0],
    ]);
    let material = |name: &str, m: Material| Material {
        name: name.into(),
        ..m
    };
    let glass = |roughness| Material {
        transmission: 1.0,
        metallic: 0.0,
        roughness,
        ior: 1.5,
        ..Default::default()
    };
    let materials = vec![
        lambertian("floor", Vec3::new(0.6, 0.5, 0.4)),
        material("glass", glass(0.0)),
        material("rough glass", glass(0.3)),
        material(
            "metal",
            Material {
                metallic: 1.0,
                roughness: 0.4,
                base_color: Vec4::new(0.9, 0.6, 0.3, 1.0),
                ..Default::default()
            },
        ),
        material(
            "coated sheen",
            Material {
                clearcoat: 1.0,
                clearcoat_roughness: 0.2,
                sheen_color: Vec3::splat(0.6),
                sheen_roughness: 0.5,
                ..lambertian("", Vec3::new(0.2, 0.4, 0.7))
            },
        ),
        material(
            "lamp",
            Material {
                emissive: Vec3::splat(8.0),
                ..lambertian("", Vec3::ZERO)
            },
        ),
    ];
    let pane = mesh_from(
        &platoon_scenegen::quad_from([
            [-0.6, -1.0, -2.5],
            [-0.6, 0.2, -2.5],
            [0.6, 0.2, -2.5],
            [0.6, -1.0, -2.5],
        ]),
        2,
    );
    let placed = |m: u32, x: f32, z: f32, r: f32| {
        let mut mesh = sphere();
        mesh.triangle_materials.fill(m);
        (mesh, Vec3::new(x, r - 1.0, z), r)
    };
    scene_of(
        vec![
            (mesh_from(&floor, 0), Vec3::ZERO, 1.0),
            placed(1, -2.4, 0.0, 0.8),
            placed(2, -0.8, 0.0, 0.8),
            placed(3, 0.8, 0.0, 0.8),
            placed(4, 2.4, 0.0, 0.8),
            placed(5, 0.0, 2.0, 0.3),
            // A pane of rough glass (a thin sheet): light through it is direct transmission.
            (pane, Vec3::ZERO, 1.0),
        ],
        materials,
        Vec3::new(0.0, 2.5, -7.0),
        Vec3::new(0.0, -0.3, 0.0),
        0.7,
    )
}

/// How far the sum of a still's light passes is off its beauty, the worst pixel's channel
/// relative to its value (at least 1); every pass holds some light, none a negative or a NaN.
fn passes_off_the_beauty(still: &platoon::Still) -> f64 {
    let mut sum = vec![[0.0f64; 3]; still.image.pixels.len()];
    for pass in LightPass::ALL {
        let l = layer(&still.layers, pass.name());
        let total: f64 = (0..3)
            .map(|c| l.channels[c].1.iter().map(|&v| v as f64).sum::<f64>())
            .sum();
        assert!(total > 0.0, "{}: no light at all", pass.name());
        for (c, (_, plane)) in l.channels.iter().enumerate() {
            for (i, v) in plane.iter().enumerate() {
                assert!(*v >= 0.0 && v.is_finite(), "{}: {v}", pass.name());
                sum[i][c] += *v as f64;
            }
        }
    }
    let mut worst = 0.0f64;
    for (i, p) in still.image.pixels.iter().enumerate() {
        for c in 0..3 {
            let (got, want) = (sum[i][c], p[c] as f64);
            worst = worst.max((got - want).abs() / want.max(1.0));
        }
    }
    worst
}

#[test]
fn the_light_passes_sum_to_the_beauty_and_each_holds_its_part() {
    let request = platoon::Request {
        scene: platoon::SceneSource::Scene(Box::new(every_part())),
        env: constant_env(0.5),
        width: 40,
        height: 24,
        spp: 8,
        devices: DeviceSpec::Lavapipe(vec![1]),
        aovs: Aov::parse_list("light").unwrap(),
        ..Default::default()
    };
    let still = request.render(&mut |_| {}).unwrap();
    let worst = passes_off_the_beauty(&still);
    assert!(
        worst < 1e-5,
        "the passes' sum is off the beauty by {worst:e}"
    );
    // The passes are the beauty's own paths, its method's state kept (resampled light here,
    // which picks other lights than the path loop would): they sum to that beauty too.
    let mut resampled = request.method.clone();
    resampled
        .path_mut()
        .expect("the path tracer")
        .resampled_light = Some(platoon::core::method::path::ResampledLight::new(4));
    let resampled = platoon::Request {
        method: resampled,
        ..request.clone()
    }
    .render(&mut |_| {})
    .unwrap();
    let worst = passes_off_the_beauty(&resampled);
    assert!(
        worst < 1e-5,
        "resampled light: the passes' sum is off the beauty by {worst:e}"
    );
    // The streaming kernels carry a path's share between their kernels: the same passes.
    let streamed = platoon::Request {
        method: streaming(&request.method),
        ..request
    }
    .render(&mut |_| {})
    .unwrap();
    assert!(streamed.image.pixels == still.image.pixels);
    assert!(
        streamed.layers == still.layers,
        "the streaming kernels' passes differ"
    );
}

#[test]
fn a_lambertian_plane_under_the_sky_has_direct_diffuse_light_alone() {
    // Nothing the plane reflects comes back to it: no indirect light at all; its direct light
    // is its albedo (a sky of 1); no glossy or transmitted light.
    let albedo = Vec3::new(0.2, 0.5, 0.8);
    let plane = platoon_scenegen::quad_from([
        [-50.0, 0.0, -50.0],
        [-50.0, 0.0, 50.0],
        [50.0, 0.0, 50.0],
        [50.0, 0.0, -50.0],
    ]);
    let prepared = under_unit_sky(
        vec![(mesh_from(&plane, 0), Vec3::ZERO, 1.0)],
        vec![lambertian("plane", albedo)],
        Vec::new(),
        Vec3::new(0.3, 4.0, 0.2),
    );
    let params = FrameParams::new(8, 8, 256, prepared.camera);
    let aovs = Aov::parse_list("light").unwrap();
    let layers = layers_on("0", &prepared, &params, &aovs);
    for pass in LightPass::ALL {
        let plane = &layer(&layers, pass.name()).channels;
        let mean = |c: usize| plane[c].1.iter().map(|&v| v as f64).sum::<f64>() / 64.0;
        for c in 0..3 {
            let want = match pass {
                LightPass::DiffuseDirect => albedo[c] as f64,
                _ => 0.0,
            };
            let tolerance = if want > 0.0 { 0.02 } else { 0.0 };
            assert!(
                (mean(c) - want).abs() <= tolerance,
                "{}: channel {c} is {}, not {want}",
                pass.name(),
                mean(c)
            );
        }
    }
}

#[test]
fn light_seen_in_a_mirror_is_glossy_whatever_it_met_after() {
    // The camera sees a mirror reflecting a Lambertian wall the sky lights: the pass is the
    // first vertex's part (glossy), indirect (the wall's light arrives at the second vertex).
    let prepared = prepare(walls(true), constant_env(1.0));
    let params = FrameParams::new(8, 6, 16, prepared.camera);
    let aovs = Aov::parse_list("light").unwrap();
    let layers = layers_on("0", &prepared, &params, &aovs);
    for pass in LightPass::ALL {
        let total: f64 = (layer(&layers, pass.name()).channels.iter())
            .flat_map(|(_, plane)| plane.iter().map(|&v| v as f64))
            .sum();
        match pass {
            LightPass::GlossyIndirect => assert!(total > 10.0, "glossy-indirect: {total}"),
            _ => assert_eq!(total, 0.0, "{}", pass.name()),
        }
    }
}

/// A wall of half-size 1 at z = 0 facing a camera 4 away (fov 0.8 rad), node 0, under a sky; with
/// `channel` animating it (it is then an instance of its own, not merged).
fn wall_seen_from_4(channel: Option<platoon::core::scene::animation::Channel>) -> Scene {
    use platoon::core::scene::animation::Animation;
    let mut scene = scene_of(
        vec![(wall(0.0, 1.0, 1.0, 0), Vec3::ZERO, 1.0)],
        vec![lambertian("wall", Vec3::splat(0.5))],
        Vec3::new(0.0, 0.0, 4.0),
        Vec3::ZERO,
        0.8,
    );
    if let Some(c) = channel {
        scene.animations.push(Animation {
            name: "move".into(),
            channels: vec![c],
        });
    }
    scene
}

/// Skins the wall of `scene` (node 0, every vertex wholly) to a new bone node at the origin;
/// returns the bone's node.
fn scene_bone(scene: &mut Scene) -> usize {
    use platoon::core::scene::{Node, Skin};
    let mut mesh = (*scene.meshes[0]).clone();
    let n = mesh.positions.len();
    mesh.joints = vec![[0; 4]; n];
    mesh.weights = vec![glam::Vec4::X; n];
    scene.meshes[0] = std::sync::Arc::new(mesh);
    scene.nodes.push(Node::new("bone"));
    let bone = scene.nodes.len() - 1;
    scene.skins.push(Skin {
        name: "skin".into(),
        joints: vec![bone],
        inverse_bind_matrices: vec![glam::Mat4::IDENTITY],
    });
    scene.nodes[0].skin = Some(0);
    bone
}

/// The motion layer's (x, y) at each pixel that sees the wall, with the pixel's position.
fn motion_on_wall(layers: &[Layer]) -> Vec<(Vec3, [f32; 2])> {
    let (motion, position) = (layer(layers, "motion"), layer(layers, "position"));
    let hit = &layer(layers, "instance-id").channels[0].1;
    (0..hit.len())
        .filter(|&i| hit[i] > 0.0)
        .map(|i| {
            let p = Vec3::from(["X", "Y", "Z"].map(|c| position.channel(c).unwrap()[i]));
            let m = ["X", "Y"].map(|c| motion.channel(c).unwrap()[i]);
            (p, m)
        })
        .collect()
}

/// Pixels across a unit of the wall's plane, 4 away, on a `width`-wide image of fov 0.8 rad.
fn pixels_per_unit(width: u32, height: u32) -> f32 {
    let tan_half_x = (0.4f32).tan() * width as f32 / height as f32;
    width as f32 / (2.0 * 4.0 * tan_half_x)
}

#[test]
fn motion_vectors_of_a_camera_moving_sideways_are_its_shift_everywhere() {
    // A still wall (merged static geometry), the camera 0.05 to the right of where it was
    // (`layers_on`'s frame before): every point moved 0.05 units' worth of pixels to the left.
    let prepared = prepare(wall_seen_from_4(None), constant_env(1.0));
    let (w, h) = (32, 24);
    let params = FrameParams::new(w, h, 1, prepared.camera);
    let aovs = [Aov::Motion, Aov::Position, Aov::InstanceId];
    let layers = layers_on("0", &prepared, &params, &aovs);
    let want = -0.05 * pixels_per_unit(w, h);
    let seen = motion_on_wall(&layers);
    assert!(seen.len() > 100);
    for (p, [x, y]) in seen {
        assert!(
            (x - want).abs() < 1e-3 && y.abs() < 1e-3,
            "at {p}: ({x}, {y}), not {want}"
        );
    }
}

#[test]
fn motion_vectors_of_a_moving_and_a_turning_object_follow_their_animation() {
    use platoon::core::scene::animation::{Channel, Interpolation, Property};
    let (w, h) = (32, 24);
    let request = |channel: Channel| platoon::Request {
        scene: platoon::SceneSource::Scene(Box::new(wall_seen_from_4(Some(channel)))),
        env: constant_env(1.0),
        width: w,
        height: h,
        spp: 1,
        time: 0.5,
        frame_interval: 0.1,
        devices: DeviceSpec::Lavapipe(vec![1]),
        aovs: vec![Aov::Motion, Aov::Position, Aov::InstanceId],
        ..Default::default()
    };
    let render = |channel: Channel| request(channel).render(&mut |_| {}).unwrap();
    // Moving right one unit a second: 0.1 units since the frame before.
    let moving_channel = || Channel {
        node: 0,
        property: Property::Translation,
        interpolation: Interpolation::Linear,
        times: vec![0.0, 1.0],
        values: vec![0.0, 0.0, 0.0, 1.0, 0.0, 0.0],
    };
    let moving = render(moving_channel());
    let want = 0.1 * pixels_per_unit(w, h);
    // Every pixel of the wall moved `want` pixels right.
    let assert_moved_right = |layers: &[Layer], what: &str| {
        let seen = motion_on_wall(layers);
        assert!(seen.len() > 100);
        for (p, [x, y]) in seen {
            assert!(
                (x - want).abs() < 1e-3 && y.abs() < 1e-3,
                "{what}at {p}: ({x}, {y}), not {want}"
            );
        }
    };
    assert_moved_right(&moving.layers, "");
    // The same move by a bone skinning the wall (its node still): the vertices' previous pose.
    let mut skinned = wall_seen_from_4(None);
    let bone = scene_bone(&mut skinned);
    skinned
        .animations
        .push(platoon::core::scene::animation::Animation {
            name: "bone".into(),
            channels: vec![Channel {
                node: bone,
                ..moving_channel()
            }],
        });
    let skinned = platoon::Request {
        scene: platoon::SceneSource::Scene(Box::new(skinned)),
        ..request(moving_channel())
    }
    .render(&mut |_| {})
    .unwrap();
    assert_moved_right(&skinned.layers, "skinned, ");
    // Turning about the view axis, a quarter turn a second: 9 degrees since the frame before;
    // each point came from where the turn back puts it, as the camera sees both.
    let quarter = glam::Quat::from_rotation_z(std::f32::consts::FRAC_PI_2);
    let turning = render(Channel {
        node: 0,
        property: Property::Rotation,
        interpolation: Interpolation::Linear,
        times: vec![0.0, 1.0],
        values: [glam::Quat::IDENTITY, quarter]
            .iter()
            .flat_map(|q| q.to_array())
            .collect(),
    });
    let camera = platoon::core::scene::camera::Camera::look_at(Vec3::Z * 4.0, Vec3::ZERO, 0.8);
    let back = glam::Quat::from_rotation_z(-9f32.to_radians());
    let seen = motion_on_wall(&turning.layers);
    assert!(seen.len() > 100);
    let mut largest = 0.0f32;
    for (p, [x, y]) in seen {
        let now = camera.project(p, w, h).unwrap();
        let then = camera.project(back * p, w, h).unwrap();
        let want = now - then;
        assert!(
            (x - want.x).abs() < 2e-3 && (y - want.y).abs() < 2e-3,
            "at {p}: ({x}, {y}), not {want}"
        );
        largest = largest.max(want.length());
    }
    assert!(largest > 1.0, "the turn moved nothing far: {largest}");
}

/// The ao layer (its one channel) of 8 x 8 pixels 0.05 wide, seen straight down from
/// `height` over the point (`x`, 0, 0) of a floor at y = 0 with `other` beside it, within
/// `distance`.
fn ao_over_floor(
    other: platoon_scenegen::MeshData,
    x: f32,
    height: f32,
    distance: f32,
) -> Vec<f32> {
    let floor = platoon_scenegen::quad_from([
        [-50.0, 0.0, -50.0],
        [-50.0, 0.0, 50.0],
        [50.0, 0.0, 50.0],
        [50.0, 0.0, -50.0],
    ]);
    let mut scene = scene_of(
        vec![
            (mesh_from(&floor, 0), Vec3::ZERO, 1.0),
            (mesh_from(&other, 0), Vec3::ZERO, 1.0),
        ],
        vec![lambertian("grey", Vec3::splat(0.5))],
        Vec3::new(x, height, 0.0),
        Vec3::new(x, 0.0, 0.0),
        0.5,
    );
    scene.cameras[0].orthographic = Some([0.05, 0.05]);
    let prepared = prepare(scene, constant_env(1.0));
    let mut params = FrameParams::new(8, 8, 64, prepared.camera);
    params.options.ao_distance = distance;
    let layers = layers_on("0", &prepared, &params, &[Aov::Ao]);
    layer(&layers, "ao").channels[0].1.clone()
}

fn mean_of(plane: &[f32]) -> f64 {
    plane.iter().map(|&v| v as f64).sum::<f64>() / plane.len() as f64
}

#[test]
fn ambient_occlusion_holds_its_closed_forms_beside_a_wall_and_under_a_ceiling() {
    // A floor point 0.3 from a wall 100 high: every direction toward the wall meets it, half of
    // the cosine-weighted hemisphere; within a distance of 0.1 nothing is met at all.
    let wall = || {
        platoon_scenegen::quad_from([
            [0.0, 0.0, -50.0],
            [0.0, 100.0, -50.0],
            [0.0, 100.0, 50.0],
            [0.0, 0.0, 50.0],
        ])
    };
    let mean = mean_of(&ao_over_floor(wall(), -0.3, 4.0, 1000.0));
    assert!(
        (mean - 0.5).abs() < 0.03,
        "AO beside the wall {mean}, not 0.5"
    );
    let out_of_reach = ao_over_floor(wall(), -0.3, 4.0, 0.1);
    assert!(
        out_of_reach.iter().all(|&v| v == 1.0),
        "occluded out of reach"
    );
    // Under a ceiling 0.5 up, AO within 1 counts the rays whose path to the ceiling is longer
    // than 1: cos(theta) < 0.5, of cosine-weighted probability 0.5^2 = 0.25 (uniform: 0.5).
    let ceiling = platoon_scenegen::quad_from([
        [-50.0, 0.5, -50.0],
        [50.0, 0.5, -50.0],
        [50.0, 0.5, 50.0],
        [-50.0, 0.5, 50.0],
    ]);
    let mean = mean_of(&ao_over_floor(ceiling, -20.0, 0.4, 1.0));
    assert!(
        (mean - 0.25).abs() < 0.03,
        "AO under the ceiling {mean}, not 0.25"
    );
}

#[test]
fn the_colour_aovs_are_a_lambertian_walls_colour_and_a_white_mirrors_one() {
    // A Lambertian wall's every sampled weight is its colour: diffuse-color is it exactly; a
    // white metal mirror reflects all (Schlick's F with f0 = 1): glossy-color 1.
    use platoon::core::frame::light_pass::BsdfPart;
    let colors: Vec<Aov> = BsdfPart::ALL.map(Aov::Color).to_vec();
    for mirror in [false, true] {
        let prepared = prepare(walls(mirror), constant_env(1.0));
        let params = FrameParams::new(8, 6, 16, prepared.camera);
        let layers = layers_on("0", &prepared, &params, &colors);
        for part in BsdfPart::ALL {
            let l = layer(&layers, part.color_name());
            let want = match (part, mirror) {
                (BsdfPart::Diffuse, false) => COLOUR.to_array(),
                (BsdfPart::Glossy, true) => [1.0; 3],
                _ => [0.0; 3],
            };
            for (c, w) in ["R", "G", "B"].iter().zip(want) {
                for v in l.channel(c).unwrap() {
                    let what = part.color_name();
                    assert!(
                        (v - w).abs() < 1e-5,
                        "mirror {mirror}: {what}.{c} = {v}, not {w}"
                    );
                }
            }
        }
    }
}

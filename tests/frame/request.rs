//! The facade's front door (`platoon::Request`): a request renders what the layers below render
//! from the same settings, bit for bit and whatever the split; a camera given in world space sees
//! what the scene's camera sees; and every rule refuses by naming its option.

#[path = "../common/mod.rs"]
mod common;

use std::time::Duration;

use common::*;
use platoon::core::frame::adaptive::Adaptive;
use platoon::core::frame::aov::Aov;
use platoon::core::method::registry;
use platoon::core::method::settings::{Settings, Value};
use platoon::core::scene::camera::Camera;
use platoon::core::Method;
use platoon::devices::DeviceSpec;
use platoon::tracer::Sampling;
use platoon::{CameraChoice, Request, RequestError, SceneSource};

/// The frame options with a time limit of `limit`.
fn limited(limit: Option<Duration>) -> platoon::core::frame::FrameOptions {
    platoon::core::frame::FrameOptions {
        time_limit: limit,
        ..Default::default()
    }
}

/// `method` (the path tracer) learning over a game's frames as `cache` and `reuse` say.
fn learning(
    mut method: Method,
    cache: Option<platoon::core::method::path::world_cache::WorldCacheOptions>,
    reuse: Option<platoon::core::method::path::light_reuse::LightReuse>,
) -> Method {
    let path = method.path_mut().expect("the path tracer");
    path.learning.world_cache = cache;
    path.learning.light_reuse = reuse;
    method
}

fn small() -> Request {
    init();
    Request {
        width: 24,
        height: 16,
        spp: 4,
        devices: DeviceSpec::Lavapipe(vec![1]),
        ..Default::default()
    }
}

#[test]
fn a_request_renders_what_the_layers_below_render() {
    let request = Request {
        aovs: vec![Aov::Albedo, Aov::Depth],
        ..small()
    };
    let still = request.render(&mut |_| {}).unwrap();
    // The same frame through the layers below, by hand.
    let prepared = prepare(
        platoon::core::scene::cornell::scene(),
        platoon::EnvChoice::Scene,
    );
    let mut params = platoon::core::frame::FrameParams::new(24, 16, 4, prepared.camera);
    params.options.seed = 0;
    let film = render(&prepared, &params, Sampling::Mis);
    assert_eq!(still.image.pixels, film.pixels);
    assert_eq!(still.rendered.film.pixels, film.pixels);
    let names: Vec<&str> = still.layers.iter().map(|l| l.name.as_str()).collect();
    assert_eq!(names, ["albedo", "depth"]);
    let meta = |k: &str| {
        still
            .metadata
            .iter()
            .find(|(key, _)| key == k)
            .map(|(_, v)| v)
    };
    assert_eq!(meta("aovs").map(String::as_str), Some("albedo,depth"));
    assert_eq!(meta("spp").map(String::as_str), Some("4"));
    // Three tracers under a balancer: the same bits.
    let three = Request {
        devices: DeviceSpec::Lavapipe(vec![1, 1, 1]),
        ..request
    }
    .render(&mut |_| {})
    .unwrap();
    assert_eq!(three.image.pixels, film.pixels);
    assert_eq!(three.layers[1].channels, still.layers[1].channels);
}

#[test]
fn a_camera_given_in_world_space_sees_what_the_scenes_camera_sees() {
    // The box far from the world's origin, where render space is centred on the camera.
    let mut scene = platoon::core::scene::cornell::scene();
    for node in scene.nodes.iter_mut().filter(|n| n.parent.is_none()) {
        node.translation += glam::DVec3::new(65536.0, 0.0, 0.0);
    }
    let world = Camera::from_scene(&scene, &scene.pose(0.0), None).unwrap();
    let far = Request {
        scene: SceneSource::Scene(Box::new(scene)),
        ..small()
    };
    let of_scene = far.render(&mut |_| {}).unwrap();
    assert!(mean(&of_scene.image) > 0.01);
    let given = Request {
        camera: CameraChoice::Given(world),
        ..far.clone()
    }
    .render(&mut |_| {})
    .unwrap();
    // The same view up to the rounding of the two ways to the camera's matrix (a few paths
    // take other turns).
    let close = |a: &platoon::core::output::Film, b: &platoon::core::output::Film| {
        (mean(a) - mean(b)).abs() / mean(b) < 0.01
    };
    assert!(close(&given.image, &of_scene.image));
    let moved = Request {
        camera: CameraChoice::Given(Camera::look_at(
            world.position() + glam::Vec3::new(0.3, 0.0, 0.0),
            glam::Vec3::new(0.0, 1.0, 0.0),
            world.yfov,
        )),
        ..far
    }
    .render(&mut |_| {})
    .unwrap();
    assert!(!close(&moved.image, &of_scene.image));
}

/// The window (x, y, w, h) of a `width`-wide image's pixels.
fn window<T: Copy>(pixels: &[T], width: u32, (x, y, w, h): (u32, u32, u32, u32)) -> Vec<T> {
    (y..y + h)
        .flat_map(|r| (x..x + w).map(move |c| (r * width + c) as usize))
        .map(|i| pixels[i])
        .collect()
}

#[test]
fn a_crop_is_the_whole_renders_pixels_there_on_any_split() {
    use platoon::core::frame::Region;
    use platoon::core::method::path::PathKernel;
    // A thin lens, a wide filter and the AOVs: everything that reads the pixel's place.
    let whole = Request {
        aperture: 0.05,
        frame: platoon::core::frame::FrameOptions {
            filter: platoon::core::frame::PixelFilter::Gaussian,
            ..Default::default()
        },
        aovs: vec![Aov::Albedo, Aov::Depth, Aov::InstanceId],
        ..small()
    };
    let full = whole.render(&mut |_| {}).unwrap();
    let region = (5, 3, 13, 9);
    let crop = Some(Region {
        x: region.0,
        y: region.1,
        width: region.2,
        height: region.3,
    });
    for (devices, kernel) in [
        (vec![1], PathKernel::Mega),
        (vec![1, 1, 1], PathKernel::Mega),
        (vec![1, 1, 1], PathKernel::Streaming),
    ] {
        let cropped = Request {
            crop,
            method: in_kernel(&whole.method, kernel),
            devices: DeviceSpec::Lavapipe(devices.clone()),
            ..whole.clone()
        }
        .render(&mut |_| {})
        .unwrap();
        let what = format!("{} tracers, {kernel:?}", devices.len());
        assert_eq!(
            (cropped.image.width, cropped.image.height),
            (13, 9),
            "{what}"
        );
        assert!(
            cropped.image.pixels == window(&full.image.pixels, 24, region),
            "{what}: the crop differs from the whole render's window"
        );
        for (a, b) in cropped.layers.iter().zip(&full.layers) {
            for ((_, got), (_, want)) in a.channels.iter().zip(&b.channels) {
                assert!(
                    *got == window(want, 24, region),
                    "{what}: the {} layer differs",
                    a.name
                );
            }
        }
        let meta = cropped.metadata.iter().find(|(k, _)| k == "crop").unwrap();
        assert_eq!(meta.1, "5,3,13,9 of 24 x 16");
    }
}

#[test]
fn every_rule_refuses_by_naming_its_option() {
    assert_eq!(small().validate(), Ok(()));
    let igi = registry::kind("igi")
        .unwrap()
        .build(&Settings(vec![("vpls", Value::Count(30))]))
        .unwrap();
    let adaptive = Some(Adaptive {
        threshold: 0.1,
        min_spp: None,
    });
    let cases: Vec<(Request, &str, &str)> = vec![
        (
            Request {
                width: 0,
                ..small()
            },
            "width",
            "positive",
        ),
        (Request { spp: 0, ..small() }, "spp", "positive"),
        (
            Request {
                aovs: Aov::parse_list("light").unwrap(),
                method: igi.clone(),
                ..small()
            },
            "aovs",
            "method igi's is not theirs (render with method path)",
        ),
        (
            Request {
                aovs: Aov::parse_list("emission").unwrap(),
                adaptive,
                ..small()
            },
            "aovs",
            "adaptive",
        ),
        (
            Request {
                crop: Some(platoon::core::frame::Region::parse("20,0,5,4").unwrap()),
                ..small()
            },
            "crop",
            "past the 24 x 16 image",
        ),
        (
            Request {
                width: 100_000,
                height: 100_000,
                ..small()
            },
            "width",
            "pixels",
        ),
        (
            Request {
                path_loop: platoon::core::frame::PathLoop {
                    max_depth: 0,
                    ..Default::default()
                },
                ..small()
            },
            "max_depth",
            "one segment",
        ),
        (
            Request {
                frame: limited(Some(Duration::ZERO)),
                ..small()
            },
            "time_limit",
            "positive",
        ),
        (
            Request {
                time: f32::NAN,
                ..small()
            },
            "time",
            "finite",
        ),
        (
            Request {
                aperture: -1.0,
                ..small()
            },
            "aperture",
            ">= 0",
        ),
        (
            Request {
                focus_distance: Some(0.0),
                ..small()
            },
            "focus_distance",
            "positive",
        ),
        (
            Request {
                balancer: "fastest".into(),
                ..small()
            },
            "balancer",
            "cost-aware",
        ),
        (
            Request {
                adaptive: Some(Adaptive {
                    threshold: 0.0,
                    min_spp: None,
                }),
                ..small()
            },
            "adaptive",
            "positive",
        ),
        (
            Request {
                adaptive,
                method: igi.clone(),
                ..small()
            },
            "adaptive",
            "method igi's kernels render every pixel's samples",
        ),
        (
            Request {
                adaptive,
                frame: limited(Some(Duration::from_secs(1))),
                ..small()
            },
            "time_limit",
            "adaptive",
        ),
        (
            Request {
                aovs: vec![Aov::Variance],
                spp: 1,
                ..small()
            },
            "aovs",
            "2 samples",
        ),
        (
            Request {
                method: resampled(0),
                ..small()
            },
            "resampled_light",
            "at least one candidate",
        ),
        (
            Request {
                method: learning(
                    Method::path_tracing(),
                    Some(
                        platoon::core::method::path::world_cache::WorldCacheOptions {
                            train_stride: 0,
                            ..Default::default()
                        },
                    ),
                    None,
                ),
                ..small()
            },
            "world_cache",
            "training stride",
        ),
        (
            Request {
                method: learning(Method::path_tracing(), None, Some(Default::default())),
                ..small()
            },
            "light_reuse",
            "set resampled_light",
        ),
        (
            Request {
                method: learning(
                    resampled(8),
                    None,
                    Some(platoon::core::method::path::light_reuse::LightReuse {
                        history: 0,
                        ..Default::default()
                    }),
                ),
                ..small()
            },
            "light_reuse",
            "history",
        ),
    ];
    for (request, option, says) in cases {
        let e = request.validate().unwrap_err();
        assert_eq!(e.option, option, "{e}");
        assert!(e.problem.contains(says), "{e}");
    }
    // The world cache learns over a game's frames: a still and a progressive render refuse it.
    let cached = Request {
        method: learning(Method::path_tracing(), Some(Default::default()), None),
        ..small()
    };
    cached.validate().unwrap();
    for e in [
        cached.render(&mut |_| {}).err().unwrap(),
        platoon::Progressive::new(cached.clone()).err().unwrap(),
    ] {
        let e = e.to_string();
        assert!(e.contains("world_cache") && e.contains("game loop"), "{e}");
    }
    // ... nor has a still a previous frame's reservoirs to reuse.
    let reusing = Request {
        method: learning(resampled(8), None, Some(Default::default())),
        ..small()
    };
    reusing.validate().unwrap();
    let e = reusing.render(&mut |_| {}).err().unwrap().to_string();
    assert!(e.contains("light_reuse") && e.contains("game loop"), "{e}");
    // A rule that needs the devices: a time limit cuts one device's frame only.
    let e = Request {
        frame: limited(Some(Duration::from_secs(1))),
        devices: DeviceSpec::Lavapipe(vec![1, 1]),
        ..small()
    }
    .tracer_options()
    .unwrap_err();
    let e = e.downcast::<RequestError>().unwrap();
    assert_eq!(e.option, "time_limit");
    assert!(e.problem.contains("one device"), "{e}");
}

/// The metadata says how the method picks lights where it picks them its own way (the path
/// tracer's resampled light), in place of the path loop's own line.
#[test]
fn the_metadata_says_the_methods_light_selection() {
    let still = Request {
        method: resampled(8),
        ..small()
    }
    .render(&mut |_| {})
    .unwrap();
    let lights = still.metadata.iter().find(|(k, _)| k == "light_selection");
    let lights = lights.map(|(_, v)| v.as_str()).unwrap_or_default();
    assert!(lights.starts_with("MIS+RIS over 8 candidates"), "{lights}");
    let plain = small().render(&mut |_| {}).unwrap();
    let lights = plain.metadata.iter().find(|(k, _)| k == "light_selection");
    assert_eq!(lights.unwrap().1, "power");
}

/// A still of the path tracer or IGI lets the host's copy of the scene's large arrays go once
/// its devices hold them (a big scene is not held twice); a method that reads the scene on the
/// host (vertex links' preparation) keeps it. Without the copy IGI's still is the bits of one
/// rendered with it.
#[test]
fn only_a_method_reading_the_scene_on_its_devices_only_gives_up_the_hosts_copy() {
    use platoon::core::flatten::arrays::SceneArray;
    let request = small();
    let options = request.tracer_options().unwrap();
    for (name, kept) in [("path", false), ("igi", false), ("links", true)] {
        let mut prepared = prepare(
            platoon::core::scene::cornell::scene(),
            platoon::EnvChoice::Scene,
        );
        assert!(!prepared.gpu.bytes_of(SceneArray::Triangles).is_empty());
        let method = registry::kind(name)
            .unwrap()
            .build(&Settings::default())
            .unwrap();
        let _tracers = platoon::Tracers::for_still(
            &options,
            &request.balancer,
            &mut prepared.gpu,
            &method,
            &[],
        )
        .unwrap();
        let triangles = prepared.gpu.bytes_of(SceneArray::Triangles);
        assert_eq!(!triangles.is_empty(), kept, "{name}");
    }
    let igi = Request {
        method: registry::kind("igi")
            .unwrap()
            .build(&Settings(vec![("vpls", Value::Count(30))]))
            .unwrap(),
        aovs: vec![Aov::Albedo],
        ..small()
    };
    let released = igi.render(&mut |_| {}).unwrap();
    let prepared = igi.prepare(igi.load_scene().unwrap()).unwrap();
    let mut kept = igi.tracers(&prepared.gpu, None).unwrap();
    let params = igi.frame_params(igi.camera_in(&prepared));
    let rendered = igi
        .render_frame(&mut kept, &prepared.gpu, &params, &mut |_| {})
        .unwrap();
    let shown = prepared.shown(igi.frame_interval);
    let still = igi
        .outputs(&mut kept, &shown, &params, rendered, Vec::new())
        .unwrap();
    assert!(!prepared.gpu.bytes_of(SceneArray::Triangles).is_empty());
    assert_eq!(released.image.pixels, still.image.pixels);
    assert_eq!(released.layers[0].channels, still.layers[0].channels);
}

/// A still on one device says how far it is as its passes end (what the CLI's progress bar
/// and Python's callback show), though it renders through the renderer on a worker thread:
/// increasing sample counts up to all of them, and the image of a render that heard nothing.
#[test]
fn a_still_on_one_device_reports_its_samples_as_they_are_done() {
    let request = Request {
        width: 16,
        height: 8,
        spp: 8,
        devices: DeviceSpec::Lavapipe(vec![1]),
        ..Default::default()
    };
    let mut heard = Vec::new();
    let still = request.render(&mut |n| heard.push(n)).unwrap();
    assert_eq!(heard.last(), Some(&8), "{heard:?}");
    assert!(heard.windows(2).all(|w| w[0] < w[1]), "{heard:?}");
    let quiet = request.render(&mut |_| {}).unwrap();
    assert_eq!(still.image.pixels, quiet.image.pixels);
}

#[test]
fn a_progressive_render_is_one_render_of_all_its_samples() {
    let whole = Request {
        spp: 7,
        aovs: vec![Aov::Albedo],
        ..small()
    }
    .render(&mut |_| {})
    .unwrap();
    for devices in [vec![1], vec![1, 1, 1]] {
        let mut p = platoon::Progressive::new(Request {
            aovs: vec![Aov::Albedo],
            devices: DeviceSpec::Lavapipe(devices),
            ..small()
        })
        .unwrap();
        p.add(3, &mut |_| {}).unwrap();
        let still = p.add(4, &mut |_| {}).unwrap();
        assert_eq!(p.spp(), 7);
        assert_eq!(still.image.pixels, whole.image.pixels);
        assert_eq!(still.layers[0].channels, whole.layers[0].channels);
        let spp = still.metadata.iter().find(|(k, _)| k == "spp").unwrap();
        assert_eq!(spp.1, "7");
    }
    let e = platoon::Progressive::new(Request {
        frame: limited(Some(Duration::from_secs(1))),
        ..small()
    })
    .err()
    .unwrap();
    assert_eq!(e.downcast::<RequestError>().unwrap().option, "time_limit");
}

/// A game loop holds a frame time by its samples a frame: a time limit, which would cut its
/// frames, is refused rather than left aside.
#[test]
fn a_game_loop_refuses_a_time_limit() {
    let e = Request {
        frame: limited(Some(Duration::from_secs(1))),
        ..small()
    }
    .start_game(None)
    .err()
    .unwrap();
    let e = e.downcast::<RequestError>().unwrap();
    assert_eq!(e.option, "time_limit");
    assert!(e.problem.contains("frame time"), "{e}");
}

#[test]
fn a_game_loop_of_a_still_view_is_one_render_of_its_samples() {
    let scene = platoon::core::scene::cornell::scene();
    let camera = Camera::from_scene(&scene, &scene.pose(0.0), None).unwrap();
    let request = Request {
        spp: 3,
        devices: DeviceSpec::Lavapipe(vec![1, 1]),
        ..small()
    };
    let mut driver = request.start_game(None).unwrap();
    for _ in 0..4 {
        driver.frame(camera).unwrap();
    }
    let last = driver.finish().unwrap().unwrap();
    assert_eq!(last.stats.film_samples, Some(12));
    let whole = Request {
        spp: 12,
        camera: CameraChoice::Given(camera),
        ..small()
    }
    .render(&mut |_| {})
    .unwrap();
    assert_eq!(last.film.pixels, whole.image.pixels);
}

#[test]
fn tracers_driven_directly_refuse_a_time_limit_on_several_devices() {
    init();
    let prepared = prepare(
        platoon::core::scene::cornell::scene(),
        platoon::EnvChoice::Scene,
    );
    let options =
        platoon::devices::tracer_options(&DeviceSpec::Lavapipe(vec![1, 1]), false, Sampling::Mis)
            .unwrap();
    let mut tracers = platoon::Tracers::new(&options, "cost-aware", &prepared.gpu).unwrap();
    let mut params = platoon::core::frame::FrameParams::new(8, 8, 1, prepared.camera);
    params.options.time_limit = Some(Duration::from_secs(1));
    let e = tracers
        .render(&prepared.gpu, &params, &mut |_| {})
        .err()
        .unwrap();
    assert!(e.to_string().contains("one device"), "{e}");
    params.options.time_limit = None;
    assert!(tracers.render(&prepared.gpu, &params, &mut |_| {}).is_ok());
}

#[test]
fn a_camera_is_chosen_by_name() {
    let mut scene = platoon::core::scene::cornell::scene();
    let mut side = scene.cameras[0].clone();
    side.name = "side".into();
    scene.cameras.push(side);
    let mut node = platoon::core::scene::Node::new("side camera");
    node.camera = Some(1);
    node.translation = glam::DVec3::new(0.4, 1.0, 3.0);
    scene.nodes.push(node);
    let with = |camera| {
        Request {
            scene: SceneSource::Scene(Box::new(scene.clone())),
            camera,
            ..small()
        }
        .render(&mut |_| {})
    };
    let first = with(CameraChoice::Scene(None)).unwrap();
    let by_name = with(CameraChoice::Named("cornell".into())).unwrap();
    assert_eq!(by_name.image.pixels, first.image.pixels);
    let side = with(CameraChoice::Named("side".into())).unwrap();
    assert_ne!(side.image.pixels, first.image.pixels);
    assert_eq!(
        side.image.pixels,
        with(CameraChoice::Scene(Some(1))).unwrap().image.pixels
    );
    let e = with(CameraChoice::Named("top".into())).err().unwrap();
    let e = e.downcast::<RequestError>().unwrap();
    assert_eq!(e.option, "camera");
    assert!(e.problem.contains("cornell, side"), "{e}");
}

#[test]
fn a_transparent_film_leaves_the_sky_seen_directly_out_and_says_where() {
    let sky = 0.7f32;
    let request = |transparent_film, tracers: Vec<u32>| {
        Request {
            scene: SceneSource::Scene(Box::new(sphere_scene(
                platoon::core::scene::cornell::lambertian("grey", glam::Vec3::splat(0.5)),
            ))),
            env: constant_env(sky),
            frame: platoon::core::frame::FrameOptions {
                transparent_film,
                ..Default::default()
            },
            devices: DeviceSpec::Lavapipe(tracers),
            ..small()
        }
        .render(&mut |_| {})
        .unwrap()
    };
    let (opaque, clear) = (request(false, vec![1]), request(true, vec![1]));
    assert!(opaque.alpha.is_none());
    let alpha = clear.alpha.as_ref().expect("a transparent film's alpha");
    let (mut covered, mut empty, mut edges) = (0, 0, 0);
    for (i, &a) in alpha.iter().enumerate() {
        let (o, c) = (opaque.image.pixels[i], clear.image.pixels[i]);
        match a {
            // Every camera ray found the sphere: the same paths, the same bits.
            1.0 => {
                assert_eq!(o, c, "pixel {i}");
                covered += 1;
            }
            // Only sky: nothing left.
            0.0 => {
                assert_eq!(c, [0.0; 3], "pixel {i}");
                empty += 1;
            }
            // The opaque film's pixel is the transparent one's plus the sky its misses saw.
            _ => {
                for k in 0..3 {
                    let missing = o[k] - c[k];
                    assert!(
                        (missing - (1.0 - a) * sky).abs() < 1e-5,
                        "pixel {i}: {missing}"
                    );
                }
                edges += 1;
            }
        }
    }
    assert!(
        covered > 20 && empty > 20 && edges > 5,
        "{covered} {empty} {edges}"
    );
    let meta = clear.metadata.iter().find(|(k, _)| k == "film").unwrap();
    assert!(meta.1.starts_with("transparent"), "{meta:?}");
    let three = request(true, vec![1, 1, 1]);
    assert!(three.alpha == clear.alpha && three.image == clear.image);
}

/// The Python stub's `render` keywords of the request's table, each with the type its kind
/// takes in Python and the default request's value (`| None = None` where the request leaves
/// it unset), in the table's order: made here, between the stub's `<made from the request's
/// table>` lines, so a new option of the table is not written into the stub by hand. With
/// `PLATOON_BLESS=1` the test writes them (`PLATOON_BLESS=1 cargo test -p platoon --test
/// request python_stub`); without, it fails where they differ.
#[test]
fn the_python_stubs_table_keywords_are_made_from_the_table() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../platoon-py/python/platoon/__init__.pyi");
    let stub = std::fs::read_to_string(&path).unwrap();
    let begin = "    # <made from the request's table: PLATOON_BLESS=1 cargo test -p platoon --test request python_stub>\n";
    let end = "    # </made from the request's table>\n";
    let (Some(from), Some(to)) = (stub.find(begin), stub.find(end)) else {
        panic!(
            "{}: no lines {begin:?} and {end:?} in render",
            path.display()
        );
    };
    let from = from + begin.len();
    let made: String = platoon::request::options::OPTIONS
        .iter()
        .map(|o| format!("    {}: {},\n", o.key, python_keyword(o)))
        .collect();
    if stub[from..to] == made {
        return;
    }
    if std::env::var_os("PLATOON_BLESS").is_some() {
        let written = format!("{}{made}{}", &stub[..from], &stub[to..]);
        let tmp = path.with_extension("pyi.tmp");
        std::fs::write(&tmp, written).unwrap();
        std::fs::rename(&tmp, &path).unwrap();
        return;
    }
    panic!(
        "{}: render's keywords of the table are\n{}\nwhere the table makes\n{made}\
         (PLATOON_BLESS=1 cargo test -p platoon --test request python_stub writes them)",
        path.display(),
        &stub[from..to]
    );
}

/// `TYPE = DEFAULT` of a table option as a keyword of the Python stub's `render`.
fn python_keyword(o: &platoon::request::options::RequestOption) -> String {
    use platoon::core::method::settings::ValueKind;
    // (A crop is given as a tuple; the table's kind is how the command line writes it.)
    let python = match (o.key, o.kind) {
        ("crop", _) => "tuple[int, int, int, int]",
        (_, ValueKind::Count) => "int",
        (_, ValueKind::Number) => "float",
        (_, ValueKind::Switch) => "bool",
        (_, ValueKind::Tile) => "tuple[int, int]",
        (_, ValueKind::Word(_) | ValueKind::Mode(_)) => "str",
    };
    match (o.get)(&Request::default()) {
        None => format!("{python} | None = None"),
        Some(v) => {
            let default = match v {
                Value::Count(n) => n.to_string(),
                Value::Number(x) => format!("{x:?}"),
                Value::Switch(on) => if on { "True" } else { "False" }.to_string(),
                Value::Tile([m, n]) => format!("({m}, {n})"),
                Value::Word(w) => format!("{w:?}"),
            };
            format!("{python} = {default}")
        }
    }
}

/// A game starts from the scene lit as a still's (not flattened) and the request's camera in
/// world space: the scene's camera where a still's preparation keeps its render space at the
/// world's origin (the built-in box), a given camera as given, and a scene far from the origin
/// seen from where its camera is in the world, which a still's render space moves.
#[test]
fn a_game_starts_from_the_lit_scene_and_the_requests_camera_in_world_space() {
    use platoon::core::scene::environment::Environment;
    let lit = Request {
        env: platoon::EnvChoice::Color(glam::Vec3::splat(0.5)),
        ..small()
    };
    let sky = lit.game_scene().unwrap().environment;
    assert!(matches!(sky, Some(Environment::Constant(c)) if c == glam::Vec3::splat(0.5)));
    let request = small();
    let scene = request.game_scene().unwrap();
    let prepared = request.prepare(request.load_scene().unwrap()).unwrap();
    assert_eq!(prepared.posed.origin, glam::DVec3::ZERO);
    let camera = request.game_camera(&scene, &scene.pose(0.0)).unwrap();
    assert_eq!(camera.camera_to_world, prepared.camera.camera_to_world);
    let given = Camera::look_at(
        glam::Vec3::new(0.1, 0.2, 3.0),
        glam::Vec3::ZERO,
        40f32.to_radians(),
    );
    let looking = Request {
        camera: CameraChoice::Given(given),
        ..small()
    };
    let camera = looking.game_camera(&scene, &scene.pose(0.0)).unwrap();
    assert_eq!(camera.camera_to_world, given.camera_to_world);
    // The box moved 1e5 along x: the game sees it there, a still from around its camera.
    let mut far = platoon::core::scene::cornell::scene();
    for node in &mut far.nodes {
        if node.parent.is_none() {
            node.translation.x += 1e5;
        }
    }
    let camera = request.game_camera(&far, &far.pose(0.0)).unwrap();
    assert!(
        (camera.position().x - 1e5).abs() < 10.0,
        "{:?}",
        camera.position()
    );
    let still = request.prepare(far).unwrap();
    assert!(
        still.camera.position().x.abs() < 10.0,
        "{:?}",
        still.camera.position()
    );
}

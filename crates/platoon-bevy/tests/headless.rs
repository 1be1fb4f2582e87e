//! A headless Bevy app (no window, no GPU backend) rendering through PlatoonPlugin on lavapipe:
//! a glTF scene loaded by Bevy's asset server converges to platoon's own render of the file,
//! the plugin's film is the bits platoon renders from the same scene data, 1 and 3 tracers
//! give the same bits, and moving, adding and despawning entities shows in the image.

use std::path::PathBuf;
use std::time::{Duration, Instant};

use bevy::prelude::*;
use bevy::render::settings::WgpuSettings;
use bevy::render::RenderPlugin;
use bevy::window::ExitCondition;
use platoon::core::output::Film;
use platoon::core::scene::camera::Camera as PCamera;
use platoon::devices::DeviceSpec;
use platoon::drive::DriverOptions;
use platoon::game::GameOptions;
use platoon_bevy::{PlatoonOutput, PlatoonPlugin, PlatoonScene, PlatoonSettings, PlatoonStats};

const W: u32 = 48;
const H: u32 = 36;

fn scenes() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/scenes")
}

fn settings(tracers: &str, spp: u32, converge_at: u32) -> PlatoonSettings {
    std::env::set_var(
        "VK_DRIVER_FILES",
        "/usr/share/vulkan/icd.d/lvp_icd.x86_64.json",
    );
    let mut driver = DriverOptions::new(W, H);
    driver.spp = spp;
    let mut game = GameOptions::new(driver);
    game.devices = tracers.parse::<DeviceSpec>().unwrap();
    PlatoonSettings {
        game,
        converge_at: Some(converge_at),
        ..PlatoonSettings::new(W, H)
    }
}

fn app(settings: PlatoonSettings) -> App {
    let mut app = App::new();
    app.add_plugins(
        DefaultPlugins
            .build()
            .disable::<bevy::winit::WinitPlugin>()
            .set(WindowPlugin {
                primary_window: None,
                exit_condition: ExitCondition::DontExit,
                close_when_requested: false,
                ..default()
            })
            .set(RenderPlugin {
                render_creation: WgpuSettings {
                    backends: None,
                    ..default()
                }
                .into(),
                ..default()
            })
            .set(AssetPlugin {
                file_path: scenes().to_string_lossy().into(),
                ..default()
            }),
    )
    .insert_resource(settings)
    .add_plugins(PlatoonPlugin);
    // What App::run does before its first update: plugins finish (the glTF loader is
    // registered there).
    while app.plugins_state() == bevy::app::PluginsState::Adding {
        bevy::tasks::tick_global_task_pools_on_main_thread();
    }
    app.finish();
    app.cleanup();
    app
}

/// Updates the app until `done` holds of its stats (a minute at most).
fn run_until(app: &mut App, what: &str, done: impl Fn(&mut App) -> bool) {
    let start = Instant::now();
    loop {
        app.update();
        if done(app) {
            return;
        }
        let stats = app.world().resource::<PlatoonStats>();
        assert!(stats.errors.is_empty(), "{:?}", stats.errors);
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "waited two minutes for {what}: {stats:?}"
        );
        std::thread::sleep(Duration::from_millis(2));
    }
}

/// Runs until the mirror has built no new scene for ten updates running.
fn settle(app: &mut App) {
    let last = std::cell::Cell::new((u64::MAX, 0));
    run_until(app, "the mirror to settle", |app| {
        let rebuilds = app.world().resource::<PlatoonStats>().rebuilds;
        let (seen, steady) = last.get();
        last.set(match rebuilds == seen {
            true => (seen, steady + 1),
            false => (rebuilds, 0),
        });
        last.get().1 >= 10
    });
}

/// Runs until the newest build's film holds `spp` samples a pixel; returns the film.
fn converged(app: &mut App, spp: u32) -> Film {
    run_until(app, "a converged film", |app| {
        let s = app.world().resource::<PlatoonStats>();
        s.converged && s.film_samples == Some(spp)
    });
    let out = app.world().resource::<PlatoonOutput>();
    (**out.film.as_ref().unwrap()).clone()
}

fn camera_at(eye: Vec3, target: Vec3) -> impl Bundle {
    (
        Camera3d::default(),
        Projection::Perspective(PerspectiveProjection {
            fov: 0.7,
            ..default()
        }),
        Transform::from_translation(eye).looking_at(target, Vec3::Y),
    )
}

/// A still of a file from ../shared/scenes: loaded by Bevy's asset server and mirrored, seen
/// in three-quarter view (the camera's world transform returned).
fn file_app(file: &'static str, tracers: &str, spp: u32) -> (App, GlobalTransform) {
    let mut app = app(settings(tracers, 4, spp));
    let scene = platoon::load_scene(Some(&scenes().join(file))).unwrap();
    let meshes = scene.nodes.iter().filter(|n| n.mesh.is_some()).count();
    let animated = !scene.animations.is_empty();
    let (lo, hi) = scene.pose(0.0).bounds();
    let (c, size) = ((lo + hi) * 0.5, (hi - lo).length());
    let target = Vec3::new(c.x, c.y, c.z);
    let eye = target + Vec3::new(0.5, 0.4, 1.0) * size * 0.9;
    // The file by its root, once: a labelled path (`file.glb#Scene0`) asks the server for the
    // root anew each time and, the root's handle being dropped, two of them loaded the file
    // twice, the later load arriving as *modified* meshes (a rebuild no game edit caused) when
    // it came after the world had settled (an unoptimised Bevy, one run in two).
    let gltf = app.world().resource::<AssetServer>().load::<Gltf>(file);
    run_until(&mut app, "the file", |app| {
        let server = app.world().resource::<AssetServer>();
        server.is_loaded_with_dependencies(gltf.id())
    });
    let (scene, clips) = {
        let file = app.world().resource::<Assets<Gltf>>().get(&gltf).unwrap();
        (file.scenes[0].clone(), file.animations.len())
    };
    assert_eq!(animated, clips > 0, "{file}: Bevy's animations");
    app.world_mut()
        .spawn(bevy::world_serialization::WorldAssetRoot(scene));
    app.world_mut().spawn(camera_at(eye, target));
    app.insert_resource(FileRoot(gltf));
    // Until the file's meshes are in the world (a glTF mesh node is one entity a primitive)
    // and the mirror has taken them in: a test counting rebuilds counts from there.
    run_until(&mut app, "the file's meshes", |app| {
        let world = app.world_mut();
        let mut q = world.query::<&Mesh3d>();
        let handles: Vec<_> = q.iter(world).map(|m| m.0.id()).collect();
        let loaded = world.resource::<Assets<Mesh>>();
        handles.len() >= meshes && handles.iter().all(|h| loaded.contains(*h))
    });
    settle(&mut app);
    let mut q = app
        .world_mut()
        .query_filtered::<&GlobalTransform, With<Camera3d>>();
    let t = *q.single(app.world()).unwrap();
    (app, t)
}

/// The file a test's app loaded (`file_app`), held so that nothing of it is loaded again.
#[derive(Resource)]
struct FileRoot(Handle<Gltf>);

/// The first animation of the file a test's app loaded.
fn first_animation(app: &App) -> Handle<AnimationClip> {
    let root = &app.world().resource::<FileRoot>().0;
    let file = app.world().resource::<Assets<Gltf>>().get(root).unwrap();
    file.animations[0].clone()
}

/// The camera a Bevy camera's transform (fov 0.7) converts to.
fn camera_of(t: &GlobalTransform) -> PCamera {
    PCamera {
        camera_to_world: glam::Mat4::from_cols_array(&t.to_matrix().to_cols_array()),
        yfov: 0.7,
        ..PCamera::look_at(glam::Vec3::ZERO, -glam::Vec3::Z, 0.7)
    }
}

/// platoon's own render of `scene` (its default sky) from `camera`, 256 samples a pixel.
fn own_render(scene: platoon::core::Scene, camera: PCamera) -> Film {
    let prepared = platoon::prepare(scene, &platoon::PrepareOptions::default()).unwrap();
    let options = platoon::devices::tracer_options(
        &"lavapipe:1".parse().unwrap(),
        false,
        platoon::tracer::Sampling::Mis,
    )
    .unwrap();
    let mut params = platoon::core::frame::FrameParams::new(W, H, 256, camera);
    params.options.seed = 99;
    platoon::render(&prepared, &options[0], &params, &mut |_| {})
        .unwrap()
        .film
}

/// Means within 1%, blocks of 12 x 12 pixels within 3% (the plugin's film has 16 samples a
/// pixel, platoon's 256 of other random numbers).
fn assert_close(film: &Film, own: &Film) {
    let (a, b) = (film.mean(), own.mean());
    for k in 0..3 {
        assert!(
            (a[k] - b[k]).abs() < 0.01 * b[k],
            "means {a:?} against {b:?}"
        );
    }
    let (ba, bb) = (block_means(film, 12), block_means(own, 12));
    for (i, (x, y)) in ba.iter().zip(&bb).enumerate() {
        assert!(
            (x - y).abs() < 0.03 * y.max(0.05),
            "block {i}: {x} against {y}"
        );
    }
}

fn block_means(film: &Film, block: u32) -> Vec<f64> {
    let mut out = Vec::new();
    for by in (0..film.height).step_by(block as usize) {
        for bx in (0..film.width).step_by(block as usize) {
            let mut sum = 0.0;
            let mut n = 0.0;
            for y in by..(by + block).min(film.height) {
                for x in bx..(bx + block).min(film.width) {
                    let p = film.pixels[(y * film.width + x) as usize];
                    sum += (p[0] + p[1] + p[2]) as f64 / 3.0;
                    n += 1.0;
                }
            }
            out.push(sum / n);
        }
    }
    out
}

#[test]
fn a_gltf_scene_through_bevy_renders_what_platoon_renders_of_the_file() {
    // RetroUFO: 77 meshes under a node hierarchy, seven materials.
    let (mut app, t) = file_app("RetroUFO.glb", "lavapipe:1", 16);
    let film = converged(&mut app, 16);
    let stats = app.world().resource::<PlatoonStats>().clone();
    assert!(stats.warnings.is_empty(), "{:?}", stats.warnings);
    let scene = platoon::load_scene(Some(&scenes().join("RetroUFO.glb"))).unwrap();
    assert_close(&film, &own_render(scene, camera_of(&t)));
}

#[test]
fn a_skinned_textured_character_through_bevy_renders_what_platoon_renders_at_rest() {
    // CesiumMan: a skin of 19 joints, a base colour texture, a rotated root. Bevy spawns it
    // in its nodes' rest transforms (no animation player): platoon's file without its walk.
    let (mut app, t) = file_app("CesiumMan.glb", "lavapipe:1", 16);
    let film = converged(&mut app, 16);
    let mut scene = platoon::load_scene(Some(&scenes().join("CesiumMan.glb"))).unwrap();
    scene.animations.clear();
    let built = app.world().resource::<PlatoonScene>().0.clone().unwrap();
    assert_eq!((built.skins.len(), built.textures.len()), (1, 1));
    assert_close(&film, &own_render(scene, camera_of(&t)));
}

#[test]
fn the_plugins_film_is_platoons_render_of_the_same_scene_data_on_one_tracer_and_three() {
    let (mut one, t) = file_app("RetroUFO.glb", "lavapipe:1", 16);
    let film = converged(&mut one, 16);
    let (mut three, _) = file_app("RetroUFO.glb", "lavapipe:1,1,1", 16);
    assert!(film == converged(&mut three, 16), "1 and 3 tracers differ");

    // The scene the mirror built, rendered by platoon's own frame driver: the same bits.
    let scene = one.world().resource::<PlatoonScene>().0.clone().unwrap();
    let s = settings("lavapipe:1", 4, 16);
    let mut scene = (*scene).clone();
    platoon::prepare::light(&mut scene, &s.environment, &Default::default()).unwrap();
    let mut driver = platoon::game::start(scene, &s.game).unwrap();
    for _ in 0..4 {
        driver.frame(camera_of(&t)).unwrap();
    }
    let own = driver.finish().unwrap().unwrap();
    assert_eq!(own.stats.film_samples, Some(16));
    assert!(film == own.film, "the plugin's film is not platoon's");
}

#[derive(Resource)]
struct Cube(Entity, Handle<Mesh>, Handle<StandardMaterial>);

/// A red cube on a grey floor under the default sky, seen from the front.
fn cube_app() -> App {
    let mut app = app(settings("lavapipe:1", 4, 8));
    app.add_systems(
        Startup,
        |mut commands: Commands,
         mut meshes: ResMut<Assets<Mesh>>,
         mut materials: ResMut<Assets<StandardMaterial>>| {
            let floor = meshes.add(Plane3d::default().mesh().size(8.0, 8.0));
            let grey = materials.add(StandardMaterial::from(Color::srgb(0.5, 0.5, 0.5)));
            commands.spawn((Mesh3d(floor), MeshMaterial3d(grey)));
            let cube = meshes.add(Cuboid::new(0.6, 0.6, 0.6));
            let red = materials.add(StandardMaterial {
                base_color: Color::srgb(0.9, 0.05, 0.05),
                perceptual_roughness: 0.8,
                ..default()
            });
            let e = commands
                .spawn((
                    Mesh3d(cube.clone()),
                    MeshMaterial3d(red.clone()),
                    Transform::from_xyz(-0.8, 0.3, 0.0),
                ))
                .id();
            commands.insert_resource(Cube(e, cube, red));
            commands.spawn(camera_at(
                Vec3::new(0.0, 1.5, 4.0),
                Vec3::new(0.0, 0.3, 0.0),
            ));
        },
    );
    app
}

/// The red pixels of a film: how many, and their mean column.
fn red(film: &Film) -> (usize, f64) {
    let mut n = 0;
    let mut x_sum = 0.0;
    for (i, p) in film.pixels.iter().enumerate() {
        if p[0] > 0.15 && p[0] > 3.0 * p[1] {
            n += 1;
            x_sum += (i as u32 % film.width) as f64;
        }
    }
    (n, x_sum / n.max(1) as f64)
}

#[test]
fn moving_adding_and_despawning_entities_shows_in_the_image() {
    let mut app = cube_app();
    let first = converged(&mut app, 8);
    let (n0, x0) = red(&first);
    assert!(n0 > 20, "the cube is seen: {n0} red pixels");
    let builds = app.world().resource::<PlatoonStats>().rebuilds;

    // Moved right: its pixels move right, by an edit (no rebuild).
    let cube = app.world().resource::<Cube>().0;
    app.world_mut()
        .get_mut::<Transform>(cube)
        .unwrap()
        .translation
        .x = 0.8;
    app.update();
    let moved = converged(&mut app, 8);
    let (n1, x1) = red(&moved);
    assert!(
        x1 > x0 + 8.0,
        "the cube moved right: column {x0:.1} -> {x1:.1}"
    );
    assert!(
        (n1 as f64 - n0 as f64).abs() < 0.3 * n0 as f64,
        "{n0} -> {n1}"
    );

    // A second cube of the same mesh and material: an added instance.
    let (mesh, material) = {
        let c = app.world().resource::<Cube>();
        (c.1.clone(), c.2.clone())
    };
    let second = app
        .world_mut()
        .spawn((
            Mesh3d(mesh),
            MeshMaterial3d(material),
            Transform::from_xyz(-0.8, 0.3, 0.0),
        ))
        .id();
    app.update();
    let two = converged(&mut app, 8);
    let (n2, _) = red(&two);
    assert!(
        n2 as f64 > 1.6 * n0 as f64,
        "two cubes: {n0} -> {n2} red pixels"
    );

    // Despawned: one cube again, where it was moved to.
    app.world_mut().despawn(second);
    app.update();
    let one = converged(&mut app, 8);
    let (n3, x3) = red(&one);
    assert!((n3 as f64 - n1 as f64).abs() <= 2.0, "{n1} -> {n3}");
    assert!((x3 - x1).abs() < 1.0, "{x1} -> {x3}");

    // Its material turned blue: no red left, and the film written where the app asks.
    let material = app.world().resource::<Cube>().2.clone();
    app.world_mut()
        .resource_mut::<Assets<StandardMaterial>>()
        .get_mut(&material)
        .unwrap()
        .base_color = Color::srgb(0.05, 0.05, 0.9);
    app.update();
    let blue = converged(&mut app, 8);
    assert_eq!(red(&blue).0, 0, "the material changed");
    // Then given a texture (pure green) platoon has not seen: built anew, the cube green.
    let green = Image::new_fill(
        bevy::render::render_resource::Extent3d {
            width: 2,
            height: 2,
            depth_or_array_layers: 1,
        },
        bevy::render::render_resource::TextureDimension::D2,
        &[0, 255, 0, 255],
        bevy::render::render_resource::TextureFormat::Rgba8UnormSrgb,
        bevy::asset::RenderAssetUsages::default(),
    );
    let green = app.world_mut().resource_mut::<Assets<Image>>().add(green);
    {
        let mut materials = app.world_mut().resource_mut::<Assets<StandardMaterial>>();
        let mut m = materials.get_mut(&material).unwrap();
        m.base_color = Color::WHITE;
        m.base_color_texture = Some(green.clone());
    }
    app.update();
    let textured = converged(&mut app, 8);
    let greens = textured
        .pixels
        .iter()
        .filter(|p| p[1] > 0.15 && p[1] > 3.0 * p[0])
        .count();
    assert!(
        greens as f64 > 0.8 * n1 as f64,
        "the cube green: {greens} pixels ({n1} were red)"
    );
    let rebuilt = app.world().resource::<PlatoonStats>().rebuilds;
    assert_eq!(rebuilt, builds + 1, "a new texture: built anew");
    {
        let mut materials = app.world_mut().resource_mut::<Assets<StandardMaterial>>();
        let mut m = materials.get_mut(&material).unwrap();
        m.base_color = Color::srgb(0.05, 0.05, 0.9);
        m.base_color_texture = None;
    }
    app.update();
    let blue = converged(&mut app, 8);
    assert_eq!(
        app.world().resource::<PlatoonStats>().rebuilds,
        builds + 1,
        "moved, added, despawned and recoloured by edits (but the texture)"
    );
    // A mesh platoon cannot trace (lines): said once, built once, left out.
    let lines = Mesh::new(
        bevy::mesh::PrimitiveTopology::LineList,
        bevy::asset::RenderAssetUsages::default(),
    )
    .with_inserted_attribute(
        Mesh::ATTRIBUTE_POSITION,
        vec![[0.0f32, 0.0, 0.0], [1.0, 1.0, 0.0]],
    );
    let lines = app.world_mut().resource_mut::<Assets<Mesh>>().add(lines);
    app.world_mut().spawn((
        Mesh3d(lines),
        MeshMaterial3d(material),
        Transform::default(),
    ));
    for _ in 0..5 {
        app.update();
    }
    // Built anew (the instances in another order): the same image within noise.
    let (a, b) = (converged(&mut app, 8).mean(), blue.mean());
    assert!(
        (0..3).all(|k| (a[k] - b[k]).abs() < 0.01 * b[k]),
        "the lines add nothing: {a:?} against {b:?}"
    );
    let stats = app.world().resource::<PlatoonStats>();
    assert_eq!(stats.rebuilds, builds + 2, "built once with the lines");
    assert_eq!(
        stats
            .warnings
            .iter()
            .filter(|w| w.contains("LineList"))
            .count(),
        1
    );
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("frame.exr");
    app.world()
        .resource::<PlatoonOutput>()
        .write(&path)
        .unwrap();
    let (read, _) = platoon::core::output::read_exr(&path).unwrap();
    let shown = app
        .world()
        .resource::<PlatoonOutput>()
        .film
        .clone()
        .unwrap();
    assert!(
        read == *shown,
        "the film written differs from the film shown"
    );
}

/// Runs until the film has converged, and returns the mean radiance of its central 4 x 4
/// pixels.
fn centre(app: &mut App, spp: u32) -> f64 {
    let film = converged(app, spp);
    let mut sum = 0.0;
    for y in H / 2 - 2..H / 2 + 2 {
        for x in W / 2 - 2..W / 2 + 2 {
            let p = film.pixels[(y * W + x) as usize];
            sum += (p[0] + p[1] + p[2]) as f64 / 3.0;
        }
    }
    sum / 16.0
}

/// A Lambertian floor of albedo 0.5 (no specular: reflectance 0) seen from straight above,
/// lit by `light` alone (no sky).
fn lit_floor(light: impl Bundle) -> App {
    let mut s = settings("lavapipe:1", 4, 8);
    s.environment = platoon::prepare::EnvChoice::Color(glam::Vec3::ZERO);
    let mut app = app(s);
    let light = std::sync::Mutex::new(Some(light));
    app.add_systems(
        Startup,
        move |mut commands: Commands,
              mut meshes: ResMut<Assets<Mesh>>,
              mut materials: ResMut<Assets<StandardMaterial>>| {
            let floor = meshes.add(Plane3d::default().mesh().size(20.0, 20.0));
            let albedo = materials.add(StandardMaterial {
                base_color: Color::linear_rgb(0.5, 0.5, 0.5),
                reflectance: 0.0,
                ..default()
            });
            commands.spawn((Mesh3d(floor), MeshMaterial3d(albedo)));
            commands.spawn(light.lock().unwrap().take().unwrap());
            commands.spawn((
                Camera3d::default(),
                Projection::Perspective(PerspectiveProjection {
                    fov: 0.2,
                    ..default()
                }),
                Transform::from_xyz(0.0, 3.0, 0.0).looking_at(Vec3::ZERO, Vec3::Z),
            ));
        },
    );
    app
}

#[test]
fn bevys_light_units_reach_platoon_as_the_same_light() {
    // Lambertian radiance albedo / pi * E under irradiance E = 10 (0.5 / pi * 10 = 1.5915).
    let want = 0.5 / std::f64::consts::PI * 10.0;
    // A point light 2 above: 40 cd, which Bevy gives as luminous power (4 pi 40 lm): E = I / h^2.
    let point = PointLight {
        intensity: 4.0 * std::f32::consts::PI * 40.0,
        range: 100.0,
        ..default()
    };
    let mut app = lit_floor((point, Transform::from_xyz(0.0, 2.0, 0.0)));
    let got = centre(&mut app, 8);
    assert!(
        (got - want).abs() < 0.02 * want,
        "point light: {got} against {want}"
    );
    // Raised to 4 by an edit: a quarter of the irradiance.
    let mut q = app
        .world_mut()
        .query_filtered::<&mut Transform, With<PointLight>>();
    q.single_mut(app.world_mut()).unwrap().translation.y = 4.0;
    app.update();
    let got = centre(&mut app, 8);
    let quarter = want / 4.0;
    assert!(
        (got - quarter).abs() < 0.02 * quarter,
        "raised: {got} against {quarter}"
    );
    assert_eq!(app.world().resource::<PlatoonStats>().rebuilds, 1);
    // The sun straight down at 10 lux.
    let sun = DirectionalLight {
        illuminance: 10.0,
        ..default()
    };
    let down = Transform::from_xyz(0.0, 5.0, 0.0).looking_at(Vec3::ZERO, Vec3::Z);
    let got = centre(&mut lit_floor((sun, down)), 8);
    assert!(
        (got - want).abs() < 0.02 * want,
        "directional light: {got} against {want}"
    );
}

#[test]
fn a_character_bevy_animates_renders_as_platoon_poses_its_file() {
    // CesiumMan's walk played by Bevy's animation player, held at 0.5 s: its joints reach
    // platoon as edits, and the skin renders as platoon's own animation of the file at 0.5 s.
    let (mut app, t) = file_app("CesiumMan.glb", "lavapipe:1", 16);
    let builds = app.world().resource::<PlatoonStats>().rebuilds;
    let clip = first_animation(&app);
    app.add_systems(
        Update,
        move |mut commands: Commands,
              mut players: Query<(Entity, &mut AnimationPlayer), Added<AnimationPlayer>>,
              mut graphs: ResMut<Assets<AnimationGraph>>| {
            for (entity, mut player) in &mut players {
                let (graph, index) = AnimationGraph::from_clip(clip.clone());
                player.play(index).seek_to(0.5).pause();
                commands
                    .entity(entity)
                    .insert(AnimationGraphHandle(graphs.add(graph)));
            }
        },
    );
    // Until the pose has been applied (the clip loads with the file; a few frames).
    run_until(&mut app, "the walk's pose", |app| {
        let world = app.world_mut();
        let mut q = world.query::<&AnimationPlayer>();
        q.iter(world)
            .any(|p| p.playing_animations().any(|(_, a)| a.seek_time() == 0.5))
    });
    for _ in 0..10 {
        app.update();
    }
    let film = converged(&mut app, 16);
    let scene = platoon::load_scene(Some(&scenes().join("CesiumMan.glb"))).unwrap();
    let prepared_at = |time| {
        let options = platoon::PrepareOptions {
            time,
            ..Default::default()
        };
        platoon::prepare(scene.clone(), &options).unwrap()
    };
    let own = |time| {
        let options = platoon::devices::tracer_options(
            &"lavapipe:1".parse().unwrap(),
            false,
            platoon::tracer::Sampling::Mis,
        )
        .unwrap();
        let mut params = platoon::core::frame::FrameParams::new(W, H, 256, camera_of(&t));
        params.options.seed = 99;
        platoon::render(&prepared_at(time), &options[0], &params, &mut |_| {})
            .unwrap()
            .film
    };
    let stats = app.world().resource::<PlatoonStats>();
    assert_eq!(
        stats.rebuilds, builds,
        "the joints moved by edits: {stats:?}"
    );
    assert_close(&film, &own(0.5));
}

#[test]
fn the_cameras_environment_map_light_is_the_sky_platoon_sees() {
    // A cubemap of six colours (+X red, -X green, +Y blue, -Y yellow, +Z magenta, -Z cyan) at
    // intensity 2: looking along a world axis shows the face Bevy's shader samples there
    // (environment_map.wgsl mirrors z: looking along -Z samples +Z).
    let faces: [[f32; 4]; 6] = [
        [1.0, 0.0, 0.0, 1.0],
        [0.0, 1.0, 0.0, 1.0],
        [0.0, 0.0, 1.0, 1.0],
        [1.0, 1.0, 0.0, 1.0],
        [1.0, 0.0, 1.0, 1.0],
        [0.0, 1.0, 1.0, 1.0],
    ];
    let looks: [(Vec3, usize); 6] = [
        (-Vec3::Z, 4),
        (Vec3::Z, 5),
        (Vec3::X, 0),
        (-Vec3::X, 1),
        (Vec3::Y, 2),
        (-Vec3::Y, 3),
    ];
    for (look, face) in looks {
        let mut app = app(settings("lavapipe:1", 4, 4));
        app.add_systems(
            Startup,
            move |mut commands: Commands, mut images: ResMut<Assets<Image>>| {
                let mut cube = Image::new(
                    bevy::render::render_resource::Extent3d {
                        width: 1,
                        height: 1,
                        depth_or_array_layers: 6,
                    },
                    bevy::render::render_resource::TextureDimension::D2,
                    faces
                        .iter()
                        .flatten()
                        .flat_map(|c| c.to_le_bytes())
                        .collect(),
                    bevy::render::render_resource::TextureFormat::Rgba32Float,
                    bevy::asset::RenderAssetUsages::default(),
                );
                cube.texture_view_descriptor =
                    Some(bevy::render::render_resource::TextureViewDescriptor {
                        dimension: Some(bevy::render::render_resource::TextureViewDimension::Cube),
                        ..default()
                    });
                let cube = images.add(cube);
                commands.spawn((
                    Camera3d::default(),
                    Projection::Perspective(PerspectiveProjection {
                        fov: 0.2,
                        ..default()
                    }),
                    Transform::default()
                        .looking_to(look, if look.y.abs() > 0.5 { Vec3::Z } else { Vec3::Y }),
                    bevy::light::EnvironmentMapLight {
                        diffuse_map: cube.clone(),
                        specular_map: cube,
                        intensity: 2.0,
                        ..default()
                    },
                ));
            },
        );
        let film = converged(&mut app, 4);
        let p = film.pixels[(H / 2 * W + W / 2) as usize];
        let want = faces[face];
        for k in 0..3 {
            assert!(
                (p[k] - 2.0 * want[k]).abs() < 1e-3,
                "looking along {look}: {p:?}, not face {face} {want:?} x 2"
            );
        }
    }
}

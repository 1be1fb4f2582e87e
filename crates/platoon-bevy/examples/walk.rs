//! A small Bevy game path traced by platoon on every Vulkan device: CesiumMan walks in a
//! circle on a floor beside two blocks, and the player flies around carrying a lamp. Bevy runs
//! the game (input, animation, transforms); PlatoonPlugin mirrors the world into platoon and
//! the window shows platoon's frames (Bevy's own 3D camera stays inactive).
//!
//! ```sh
//! cargo run --release --manifest-path crates/platoon-bevy/Cargo.toml --example walk -- \
//!     [--devices lavapipe:1,1] [--size 320x180] [--target-ms 60] [--frames N]
//! ```
//! W/S: forward and back, A/D: turn, Q/E: down and up. `--frames N` quits after N frames of
//! platoon (what the window test uses). The window's title says platoon's frames, samples a
//! pixel, frame time and idle share, and the game's own frame time.

use std::time::Duration;

use anyhow::{bail, Context, Result};
use bevy::prelude::*;
use bevy::window::WindowResolution;
use bevy::world_serialization::WorldAssetRoot;
use platoon_bevy::platoon::prepare::EnvChoice;
use platoon_bevy::{PlatoonCamera, PlatoonOutput, PlatoonPlugin, PlatoonSettings, PlatoonStats};

/// What the command line chose.
#[derive(Resource, Clone)]
struct Args {
    frames: Option<u64>,
    size: (u32, u32),
}

#[derive(Component)]
struct Walker;

#[derive(Component)]
struct Player;

fn main() -> Result<()> {
    let (settings, args) = parse()?;
    let scenes = concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/scenes");
    let (w, h) = args.size;
    App::new()
        .add_plugins(
            DefaultPlugins
                .set(WindowPlugin {
                    primary_window: Some(Window {
                        title: "platoon walk".into(),
                        resolution: WindowResolution::new(w * 2, h * 2),
                        ..default()
                    }),
                    ..default()
                })
                .set(AssetPlugin {
                    file_path: scenes.into(),
                    ..default()
                }),
        )
        .insert_resource(settings)
        .insert_resource(args)
        .add_plugins(PlatoonPlugin)
        .add_systems(Startup, setup)
        .add_systems(Update, (start_walk, walk_in_a_circle, fly, title_and_exit))
        .run();
    Ok(())
}

fn parse() -> Result<(PlatoonSettings, Args)> {
    let mut settings = PlatoonSettings::new(320, 180);
    settings.game.driver.target = Some(Duration::from_millis(60));
    // An evening sky around the lights (with lights in the world platoon adds none itself).
    settings.environment = EnvChoice::Color(glam::Vec3::new(0.15, 0.2, 0.3));
    let mut args = Args {
        frames: None,
        size: (320, 180),
    };
    let mut it = std::env::args().skip(1);
    while let Some(a) = it.next() {
        let mut value = || it.next().with_context(|| format!("{a} needs a value"));
        match a.as_str() {
            "--devices" => settings.game.devices = value()?.parse().map_err(anyhow::Error::msg)?,
            "--frames" => args.frames = Some(value()?.parse()?),
            "--target-ms" => {
                let ms: u64 = value()?.parse()?;
                settings.game.driver.target = Some(Duration::from_millis(ms));
            }
            "--size" => {
                let v = value()?;
                let (w, h) = v.split_once('x').context("--size is WIDTHxHEIGHT")?;
                args.size = (w.parse()?, h.parse()?);
            }
            other => bail!("unknown argument {other} (see the example's documentation)"),
        }
    }
    settings.game.driver.width = args.size.0;
    settings.game.driver.height = args.size.1;
    Ok((settings, args))
}

fn setup(
    mut commands: Commands,
    assets: Res<AssetServer>,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
    output: Res<PlatoonOutput>,
    args: Res<Args>,
) {
    let floor = meshes.add(Plane3d::default().mesh().size(12.0, 12.0));
    let grey = materials.add(StandardMaterial::from(Color::srgb(0.6, 0.6, 0.6)));
    commands.spawn((Mesh3d(floor), MeshMaterial3d(grey)));
    let block = meshes.add(Cuboid::new(0.8, 1.6, 0.8));
    let red = materials.add(StandardMaterial {
        base_color: Color::srgb(0.8, 0.1, 0.1),
        perceptual_roughness: 0.4,
        ..default()
    });
    let gold = materials.add(StandardMaterial {
        base_color: Color::srgb(1.0, 0.8, 0.4),
        metallic: 1.0,
        perceptual_roughness: 0.3,
        ..default()
    });
    commands.spawn((
        Mesh3d(block.clone()),
        MeshMaterial3d(red),
        Transform::from_xyz(-2.0, 0.8, -1.0),
    ));
    commands.spawn((
        Mesh3d(block),
        MeshMaterial3d(gold),
        Transform::from_xyz(2.0, 0.8, -1.5),
    ));
    // CesiumMan (Z up in its file: its root turns it upright) walks about the centre.
    commands.spawn((
        Walker,
        Transform::default(),
        Visibility::default(),
        children![WorldAssetRoot(
            assets.load(GltfAssetLabel::Scene(0).from_asset("CesiumMan.glb"))
        )],
    ));
    commands.spawn((
        DirectionalLight {
            illuminance: 2.0,
            ..default()
        },
        Transform::from_xyz(1.0, 3.0, 2.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    // The player: platoon's camera, a lamp in hand.
    commands.spawn((
        Player,
        PlatoonCamera,
        Camera3d::default(),
        Camera {
            is_active: false,
            ..default()
        },
        Transform::from_xyz(0.0, 1.6, 5.0).looking_at(Vec3::new(0.0, 0.8, 0.0), Vec3::Y),
        children![(
            PointLight {
                intensity: 4.0 * std::f32::consts::PI * 3.0,
                range: 30.0,
                ..default()
            },
            Transform::from_xyz(0.3, -0.2, 0.0),
        )],
    ));
    // What the window shows: platoon's image, twice its size.
    commands.spawn((
        Camera2d,
        Camera {
            clear_color: ClearColorConfig::Custom(Color::BLACK),
            ..default()
        },
    ));
    let (w, h) = args.size;
    commands.spawn(Sprite {
        custom_size: Some(Vec2::new(2.0 * w as f32, 2.0 * h as f32)),
        ..Sprite::from_image(output.image.clone())
    });
}

/// Plays the walk on CesiumMan once its scene has spawned.
fn start_walk(
    mut commands: Commands,
    mut players: Query<(Entity, &mut AnimationPlayer), Added<AnimationPlayer>>,
    assets: Res<AssetServer>,
    mut graphs: ResMut<Assets<AnimationGraph>>,
) {
    for (entity, mut player) in &mut players {
        let clip = assets.load(GltfAssetLabel::Animation(0).from_asset("CesiumMan.glb"));
        let (graph, index) = AnimationGraph::from_clip(clip);
        player.play(index).repeat();
        commands
            .entity(entity)
            .insert(AnimationGraphHandle(graphs.add(graph)));
    }
}

fn walk_in_a_circle(time: Res<Time>, mut walker: Query<&mut Transform, With<Walker>>) {
    let a = time.elapsed_secs() * 0.4;
    for mut t in &mut walker {
        t.translation = Vec3::new(1.5 * a.cos(), 0.0, 1.5 * a.sin());
        // Facing along the circle (CesiumMan walks along its +X once upright).
        t.rotation = Quat::from_rotation_y(-a - std::f32::consts::FRAC_PI_2);
    }
}

fn fly(
    keys: Res<ButtonInput<KeyCode>>,
    time: Res<Time>,
    mut player: Query<&mut Transform, With<Player>>,
) {
    let dt = time.delta_secs();
    for mut t in &mut player {
        let forward = t.forward().as_vec3();
        if keys.pressed(KeyCode::KeyW) {
            t.translation += forward * 2.0 * dt;
        }
        if keys.pressed(KeyCode::KeyS) {
            t.translation -= forward * 2.0 * dt;
        }
        if keys.pressed(KeyCode::KeyA) {
            t.rotate_y(1.2 * dt);
        }
        if keys.pressed(KeyCode::KeyD) {
            t.rotate_y(-1.2 * dt);
        }
        if keys.pressed(KeyCode::KeyQ) {
            t.translation.y -= 1.5 * dt;
        }
        if keys.pressed(KeyCode::KeyE) {
            t.translation.y += 1.5 * dt;
        }
    }
}

fn title_and_exit(
    stats: Res<PlatoonStats>,
    args: Res<Args>,
    time: Res<Time>,
    mut game_ms: Local<f64>,
    mut windows: Query<&mut Window>,
    mut exit: MessageWriter<AppExit>,
) {
    // The game's own frame time, smoothed: what the player's input and animation run at,
    // whatever the path tracer's frames cost.
    *game_ms = 0.9 * *game_ms + 0.1 * time.delta_secs_f64() * 1e3;
    if !stats.is_changed() {
        return;
    }
    for mut w in &mut windows {
        w.title = format!(
            "platoon walk: {} frames, {} spp, {:.0} ms, idle {:.1}%; game {:.1} ms",
            stats.frames,
            stats.spp,
            stats.frame_ms,
            100.0 * stats.idle,
            *game_ms
        );
    }
    for e in &stats.errors {
        eprintln!("platoon: {e}");
    }
    if !stats.errors.is_empty() {
        exit.write(AppExit::error());
    } else if args.frames.is_some_and(|n| stats.frames >= n) {
        exit.write(AppExit::Success);
    }
}

//! `platoon view [SCENE]`: a window showing the converging image live, through the frame
//! driver. Drag with the left mouse button to look, WASD to fly (Q/E down/up), space to play
//! the animation, B to switch balancer, +/- to change the frame-time target; the title shows
//! fps, spp, the film's samples and idle%. `--denoise` shows each frame denoised with its
//! history reprojected (`platoon::core::denoise::temporal`). On a machine without a display it
//! says so and exits non-zero.

use std::num::NonZeroU32;
use std::path::PathBuf;
use std::rc::Rc;
use std::time::{Duration, Instant};

use anyhow::{anyhow, Context, Result};
use glam::{Vec2, Vec3};
use platoon::core::balance;
use platoon::core::colour::View;
use platoon::core::denoise::Denoiser;
use platoon::core::output::{write_image_as, Film};
use platoon::core::scene::camera::Camera;
use platoon::drive::Edit;
use platoon::drive::{FrameDriver, GiUpdate};
use platoon::game::start;
use winit::application::ApplicationHandler;
use winit::dpi::{LogicalSize, PhysicalPosition};
use winit::event::{ElementState, MouseButton, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{KeyCode, PhysicalKey};
use winit::window::{Window, WindowId};

use crate::scene_args::SceneArgs;

#[derive(Clone, Copy, clap::ValueEnum)]
enum GiUpdateArg {
    Sync,
    Async,
}

#[derive(clap::Args)]
pub struct ViewArgs {
    #[command(flatten)]
    scene: SceneArgs,
    #[command(flatten)]
    method: crate::method_args::MethodArgs,
    #[command(flatten)]
    options: crate::request_args::RequestArgs<crate::request_args::Live>,
    /// Render size, WIDTHxHEIGHT; the window shows it scaled to its size.
    #[arg(long, default_value = "320x240", value_parser = crate::size_arg::parse_size)]
    size: (u32, u32),
    /// Frame time to hold, in milliseconds.
    #[arg(long, default_value_t = 50.0)]
    target_ms: f64,
    /// Vertex links: update the lighting on tracers of their own while frames render (async,
    /// the paper's way), or before each frame of a changed scene (sync).
    #[arg(long, value_enum, default_value = "async")]
    gi_update: GiUpdateArg,
    /// Below one sample a frame, scale Russian-roulette survival down (unbiased, noisier).
    #[arg(long)]
    roulette_scaling: bool,
    /// Below one sample a frame, render fewer pixels and upscale them (biased; the title says
    /// so).
    #[arg(long)]
    resolution_scaling: bool,
    /// Show each frame denoised: none, atrous (the edge-avoiding a-trous filter), atrous-device
    /// (the same on the first device) or oidn (Intel Open Image Denoise, in a build with
    /// `--features oidn`). The frame's samples join the
    /// earlier frames' reprojected into the view before the filter; biased, the title says so.
    #[arg(long, default_value = "none")]
    denoise: Denoiser,
    /// A game's real-time settings: resampled direct light over 8 candidates and the a-trous
    /// denoiser over the history (moving objects keep theirs), unless --resampled-light or
    /// --denoise say otherwise. Biased by the denoiser; the title says so.
    #[arg(long)]
    realtime: bool,
    // What the method learns over the frames (the path tracer's --world-cache, --light-reuse).
    #[command(flatten)]
    learning: crate::learning_args::LearningArgs,
    /// Close after this many frames (for scripts and tests).
    #[arg(long)]
    frames: Option<u32>,
    /// On closing, write the last frame shown to this PNG or EXR.
    #[arg(long)]
    screenshot: Option<PathBuf>,
    #[command(flatten)]
    display: crate::display_args::DisplayArgs,
}

pub fn run(mut args: ViewArgs) -> Result<()> {
    let mut method = args.method.method()?;
    if args.realtime {
        // The game loop's rule, on the flags before the request validates them.
        args.denoise = platoon::drive::realtime(&mut method, args.denoise);
    }
    // After the real-time settings, whose resampled light light reuse needs.
    let method = args.learning.apply(method)?;
    args.denoise
        .available()
        .map_err(|e| anyhow!("--denoise: {e}"))?;
    // Before any loading: on a machine without a display, say so at once.
    let event_loop = EventLoop::new().map_err(|e| {
        anyhow!(
            "no display to open a window on ({e}); platoon view needs DISPLAY (X11) set; \
             to render without a window use `platoon render`"
        )
    })?;
    let (w, h) = args.size;
    let view = args.display.view()?;
    // The screenshot's format and bits, refused before the window opens.
    let screenshot = match &args.screenshot {
        Some(path) => Some((path, args.display.image(path)?)),
        None => None,
    };
    // The request holds the rules (the method's, the denoiser's...); the view adds the game
    // loop's own options.
    let request = platoon::Request {
        scene: match &args.scene.scene {
            Some(path) => platoon::SceneSource::File(path.clone()),
            None => platoon::SceneSource::BuiltIn,
        },
        load: args.scene.load_options(),
        env: args.scene.env_choice(),
        env_light: args.scene.env_light(),
        time: args.scene.time,
        width: w,
        height: h,
        method,
        denoiser: args.denoise,
        ..args.options.request()?
    };
    request.validate().map_err(crate::request_flags::as_flags)?;
    let target = Duration::from_secs_f64(args.target_ms.max(1.0) * 1e-3);
    let mut options = request.game_options(Some(target));
    // The scene as the game starts from it, and its camera and size, without the flattening
    // and BVHs a still's preparation makes (the game's updater makes its own).
    let scene = request.game_scene()?;
    let posed = scene.pose(request.time);
    let camera = request.game_camera(&scene, &posed)?;
    let (lo, hi) = posed.bounds();
    // Not held for the session: the game poses the scene itself.
    drop(posed);
    options.driver.gi_update = match args.gi_update {
        GiUpdateArg::Sync => GiUpdate::Synchronous,
        GiUpdateArg::Async => GiUpdate::Asynchronous,
    };
    options.driver.below_one = platoon::drive::scaling::BelowOneSample {
        roulette: args.roulette_scaling,
        resolution: args.resolution_scaling,
    };
    let animation = scene.animations.first().map_or(0.0, |a| a.duration());
    let driver = start(scene, &options)?;
    let mut app = Viewer {
        driver,
        camera: Fly::from(camera, (hi - lo).length().max(1e-3)),
        window: None,
        surface: None,
        keys: Vec::new(),
        dragging: None,
        last: None,
        frames: 0,
        max_frames: args.frames,
        playing: false,
        time: args.scene.time,
        animation,
        fps: Fps::default(),
        error: None,
        size: (w, h),
        redrawn: None,
        view,
    };
    let p = app.camera.position;
    println!("camera starts at {:.4} {:.4} {:.4}", p.x, p.y, p.z);
    event_loop.set_control_flow(ControlFlow::Poll);
    event_loop.run_app(&mut app)?;
    if let Some(e) = app.error {
        return Err(e);
    }
    let p = app.camera.position;
    println!(
        "camera at {:.4} {:.4} {:.4} after {} frames",
        p.x, p.y, p.z, app.frames
    );
    if let (Some((path, shown)), Some(film)) = (screenshot, &app.last) {
        write_image_as(path, film, &[], &[], &shown)?;
        println!("last frame written to {}", path.display());
    }
    Ok(())
}

/// A fly camera: a position and a yaw/pitch.
struct Fly {
    position: Vec3,
    yaw: f32,
    pitch: f32,
    yfov: f32,
    /// Distance flown per second.
    speed: f32,
}

impl Fly {
    fn from(camera: Camera, scene_size: f32) -> Fly {
        let m = camera.camera_to_world;
        // glTF cameras look down their -Z.
        let forward = -m.z_axis.truncate().normalize_or(Vec3::NEG_Z);
        Fly {
            position: m.w_axis.truncate(),
            yaw: forward.x.atan2(-forward.z),
            pitch: forward.y.clamp(-1.0, 1.0).asin(),
            yfov: camera.yfov,
            speed: 0.25 * scene_size,
        }
    }

    fn forward(&self) -> Vec3 {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        Vec3::new(sy * cp, sp, -cy * cp)
    }

    fn camera(&self) -> Camera {
        Camera::look_at(self.position, self.position + self.forward(), self.yfov)
    }

    fn fly(&mut self, keys: &[KeyCode], dt: f32) {
        let forward = self.forward();
        let right = forward.cross(Vec3::Y).normalize_or(Vec3::X);
        let mut d = Vec3::ZERO;
        for k in keys {
            d += match k {
                KeyCode::KeyW => forward,
                KeyCode::KeyS => -forward,
                KeyCode::KeyD => right,
                KeyCode::KeyA => -right,
                KeyCode::KeyE => Vec3::Y,
                KeyCode::KeyQ => -Vec3::Y,
                _ => Vec3::ZERO,
            };
        }
        self.position += d * self.speed * dt;
    }
}

/// Frames per second over the last second.
#[derive(Default)]
struct Fps {
    since: Option<Instant>,
    count: u32,
    value: f64,
}

impl Fps {
    fn tick(&mut self) {
        let now = Instant::now();
        let since = *self.since.get_or_insert(now);
        self.count += 1;
        let dt = (now - since).as_secs_f64();
        if dt >= 1.0 {
            self.value = self.count as f64 / dt;
            self.count = 0;
            self.since = Some(now);
        }
    }
}

struct Viewer {
    driver: FrameDriver,
    camera: Fly,
    window: Option<Rc<Window>>,
    surface: Option<softbuffer::Surface<Rc<Window>, Rc<Window>>>,
    keys: Vec<KeyCode>,
    dragging: Option<PhysicalPosition<f64>>,
    last: Option<Film>,
    frames: u32,
    max_frames: Option<u32>,
    playing: bool,
    time: f32,
    animation: f32,
    fps: Fps,
    error: Option<anyhow::Error>,
    size: (u32, u32),
    redrawn: Option<Instant>,
    /// How the window (and a PNG screenshot) shows the film.
    view: View,
}

impl Viewer {
    fn open(&mut self, event_loop: &ActiveEventLoop) -> Result<()> {
        let attributes = Window::default_attributes()
            .with_title("platoon")
            .with_inner_size(LogicalSize::new(self.size.0 * 2, self.size.1 * 2));
        let window = Rc::new(event_loop.create_window(attributes)?);
        let context = softbuffer::Context::new(window.clone()).map_err(|e| anyhow!("{e}"))?;
        let surface =
            softbuffer::Surface::new(&context, window.clone()).map_err(|e| anyhow!("{e}"))?;
        self.window = Some(window);
        self.surface = Some(surface);
        Ok(())
    }

    /// One game frame: input, the driver's call, the previous frame on screen.
    fn frame(&mut self, dt: f32) -> Result<()> {
        self.camera.fly(&self.keys, dt);
        if self.playing && self.animation > 0.0 {
            self.time = (self.time + dt) % self.animation;
            self.driver.scene().push(Edit::Time(self.time))?;
        }
        let out = self.driver.frame(self.camera.camera())?;
        let Some(done) = out.finished else {
            return Ok(());
        };
        self.fps.tick();
        self.frames += 1;
        if let Some(window) = &self.window {
            let s = &done.stats;
            let film = s
                .film_samples
                .map_or("blended".into(), |n| format!("{n} spp in film"));
            let mut below = String::new();
            if s.plan.rr_survival < 1.0 {
                below += &format!(", roulette x{:.2}", s.plan.rr_survival);
            }
            if s.plan.resolution < 1.0 {
                below += &format!(", {:.0}% resolution (upscaled)", 100.0 * s.plan.resolution);
            }
            if let Some(brief) = self.driver.options().method.unit().brief() {
                below += &format!(", {brief}");
            }
            if let Some(gi) = &s.gi {
                below += &format!(", lighting {} generations old", gi.age);
            }
            if let Some(learned) = &s.learned {
                for line in self.driver.options().method.unit().report(learned).lines {
                    below += &format!(", {line}");
                }
            }
            if let Some(d) = &s.denoise {
                below += &format!(
                    ", denoised ({}, history {:.0} spp)",
                    d.denoiser.name(),
                    d.history_samples
                );
            }
            window.set_title(&format!(
                "platoon: {:.1} fps, {} spp a frame{below}, {film}, idle {:.1}%, {}, target {:.0} ms{}",
                self.fps.value,
                s.plan.spp,
                100.0 * s.idle_fraction,
                self.driver.balancer_name(),
                self.driver
                    .options()
                    .target
                    .map_or(0.0, |t| t.as_secs_f64() * 1e3),
                if self.playing { ", playing" } else { "" },
            ));
        }
        let shown = done.denoised.unwrap_or(done.film);
        self.show(&shown)?;
        self.last = Some(shown);
        Ok(())
    }

    /// Scales the film to the window (nearest pixel) and presents it.
    fn show(&mut self, film: &Film) -> Result<()> {
        let (Some(window), Some(surface)) = (&self.window, self.surface.as_mut()) else {
            return Ok(());
        };
        let size = window.inner_size();
        let (Some(ww), Some(wh)) = (NonZeroU32::new(size.width), NonZeroU32::new(size.height))
        else {
            return Ok(());
        };
        surface.resize(ww, wh).map_err(|e| anyhow!("{e}"))?;
        let mut buffer = surface.buffer_mut().map_err(|e| anyhow!("{e}"))?;
        let srgb = film.srgb8_viewed(&self.view);
        let (fw, fh) = (film.width as usize, film.height as usize);
        let (ww, wh) = (size.width as usize, size.height as usize);
        for y in 0..wh {
            let sy = y * fh / wh;
            for x in 0..ww {
                let i = 3 * (sy * fw + x * fw / ww);
                let [r, g, b] = [srgb[i], srgb[i + 1], srgb[i + 2]].map(u32::from);
                buffer[y * ww + x] = (r << 16) | (g << 8) | b;
            }
        }
        buffer.present().map_err(|e| anyhow!("{e}"))?;
        Ok(())
    }

    fn key(&mut self, code: KeyCode, pressed: bool, event_loop: &ActiveEventLoop) -> Result<()> {
        if !pressed {
            self.keys.retain(|k| *k != code);
            return Ok(());
        }
        if !self.keys.contains(&code) {
            self.keys.push(code);
        }
        match code {
            KeyCode::Escape => event_loop.exit(),
            KeyCode::Space => self.playing = !self.playing,
            KeyCode::KeyB => {
                let names = balance::NAMES;
                let now = names.iter().position(|n| *n == self.driver.balancer_name());
                let next = names[now.map_or(0, |i| (i + 1) % names.len())];
                let b = balance::by_name(next).context("a known balancer")?;
                self.driver.set_balancer(b)?;
            }
            KeyCode::Equal | KeyCode::NumpadAdd | KeyCode::Minus | KeyCode::NumpadSubtract => {
                let up = matches!(code, KeyCode::Equal | KeyCode::NumpadAdd);
                let now = self
                    .driver
                    .options()
                    .target
                    .unwrap_or(Duration::from_millis(50));
                let next = now.mul_f64(if up { 1.25 } else { 0.8 });
                self.driver
                    .set_target(Some(next.max(Duration::from_millis(1))));
            }
            _ => {}
        }
        Ok(())
    }

    fn fail(&mut self, e: anyhow::Error, event_loop: &ActiveEventLoop) {
        self.error = Some(e);
        event_loop.exit();
    }
}

impl ApplicationHandler for Viewer {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.window.is_none() {
            if let Err(e) = self.open(event_loop) {
                self.fail(e.context("opening the window"), event_loop);
            }
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        let result = match event {
            WindowEvent::CloseRequested => {
                event_loop.exit();
                Ok(())
            }
            WindowEvent::KeyboardInput { event, .. } => match event.physical_key {
                PhysicalKey::Code(code) => {
                    self.key(code, event.state == ElementState::Pressed, event_loop)
                }
                PhysicalKey::Unidentified(_) => Ok(()),
            },
            WindowEvent::MouseInput {
                state,
                button: MouseButton::Left,
                ..
            } => {
                self.dragging =
                    (state == ElementState::Pressed).then_some(PhysicalPosition::new(-1.0, -1.0));
                Ok(())
            }
            WindowEvent::CursorMoved { position, .. } => {
                if let Some(from) = self.dragging {
                    if from.x >= 0.0 {
                        let d =
                            Vec2::new((position.x - from.x) as f32, (position.y - from.y) as f32);
                        self.camera.yaw += d.x * 0.005;
                        self.camera.pitch = (self.camera.pitch - d.y * 0.005).clamp(-1.5, 1.5);
                    }
                    self.dragging = Some(position);
                }
                Ok(())
            }
            WindowEvent::RedrawRequested => {
                let now = Instant::now();
                let dt = self
                    .redrawn
                    .map_or(0.0, |t| (now - t).as_secs_f32().min(0.25));
                let r = self.frame(dt);
                self.redrawn = Some(now);
                r
            }
            _ => Ok(()),
        };
        if let Err(e) = result {
            self.fail(e, event_loop);
        }
        if self.max_frames.is_some_and(|n| self.frames >= n) {
            event_loop.exit();
        }
    }

    fn about_to_wait(&mut self, _: &ActiveEventLoop) {
        if let Some(window) = &self.window {
            window.request_redraw();
        }
    }
}

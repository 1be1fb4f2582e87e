//! One game frame: throw the next body when it is time, step the physics, walk the characters,
//! move the camera along its script, ask the CPU what the screen centre sees and highlight
//! that character, then hand it all to the frame driver.

use std::path::PathBuf;
use std::time::{Duration, Instant};

use anyhow::Result;
use glam::{DVec3, Quat, Vec3};
use platoon::core::scene::camera::Camera;
use platoon::core::scene::{Material, Placement};
use platoon::devices::DeviceSpec;
use platoon::drive::Edit;
use platoon::drive::{DriverOptions, FinishedFrame, FrameDriver, UpdaterThreads};

use crate::physics::{Physics, Shape, FRAME_SECONDS};
use crate::world::{self, Character, GROUND};

#[derive(Clone, Debug)]
pub struct GameOptions {
    /// The skinned, animated glTF the characters are made of.
    pub character: PathBuf,
    pub characters: usize,
    /// Bodies thrown in all, one every `toss_every` frames.
    pub tosses: u32,
    pub toss_every: u32,
    pub driver: DriverOptions,
    pub devices: DeviceSpec,
    pub balancer: String,
    pub updater: UpdaterThreads,
    pub validation: bool,
    /// Rank 0 of an MPI job: the frames split between the ranks (platoon::distributed::game).
    pub ranks: Option<platoon::distributed::Ranks>,
}

impl GameOptions {
    pub fn new(character: PathBuf) -> GameOptions {
        let mut driver = DriverOptions::new(160, 120);
        driver.queries = true;
        GameOptions {
            character,
            characters: 4,
            tosses: 24,
            toss_every: 10,
            driver,
            devices: DeviceSpec::All,
            balancer: "cost-aware".into(),
            updater: UpdaterThreads::default(),
            validation: false,
            ranks: None,
        }
    }
}

/// What one call of [`Game::frame`] did and got back.
pub struct Step {
    /// The previous frame, finished.
    pub finished: Option<FinishedFrame>,
    pub waited_render: Duration,
    pub waited_update: Duration,
    /// The game's own work this frame: physics, edits, the ray query.
    pub game: Duration,
    /// The character the screen centre sees (highlighted).
    pub highlighted: Option<usize>,
}

pub struct Game {
    driver: FrameDriver,
    physics: Physics,
    body_nodes: Vec<usize>,
    box_meshes: Vec<usize>,
    sphere_meshes: Vec<usize>,
    characters: Vec<Character>,
    /// The scene's materials as loaded, to restore a character's when it is no longer seen.
    materials: Vec<Material>,
    highlighted: Option<usize>,
    unit: f32,
    walk_cycle: f32,
    tosses: u32,
    toss_every: u32,
    frame: u32,
}

impl Game {
    pub fn start(o: &GameOptions) -> Result<Game> {
        let w = world::build(&o.character, o.characters)?;
        let materials = w.scene.materials.clone();
        let mut options = platoon::game::GameOptions::new(o.driver.clone());
        options.devices = o.devices.clone();
        options.balancer = o.balancer.clone();
        options.updater = o.updater.clone();
        options.validation = o.validation;
        let driver = match &o.ranks {
            Some(ranks) => platoon::distributed::game::start(w.scene, &options, ranks)?,
            None => platoon::game::start(w.scene, &options)?,
        };
        let physics = Physics::new(w.unit, GROUND * w.unit);
        let mut game = Game {
            body_nodes: Vec::new(),
            box_meshes: w.box_meshes,
            sphere_meshes: w.sphere_meshes,
            characters: w.characters,
            materials,
            highlighted: None,
            unit: w.unit,
            walk_cycle: w.walk_cycle,
            tosses: o.tosses,
            toss_every: o.toss_every.max(1),
            frame: 0,
            physics,
            driver,
        };
        for i in 0..game.physics.bodies.len() {
            game.add_body_instance(i)?;
        }
        Ok(game)
    }

    pub fn driver(&mut self) -> &mut FrameDriver {
        &mut self.driver
    }

    pub fn frame(&mut self) -> Result<Step> {
        let start = Instant::now();
        let f = self.frame;
        let t = f as f32 * FRAME_SECONDS;
        if f.is_multiple_of(self.toss_every) && f / self.toss_every < self.tosses {
            let body = self.physics.toss();
            self.add_body_instance(body)?;
        }
        self.physics.step();
        for (i, &node) in self.body_nodes.iter().enumerate() {
            if !self.physics.sleeping(i) {
                self.driver.scene().push(Edit::Placement {
                    node,
                    placement: self.physics.placement(i),
                })?;
            }
        }
        for (c, character) in self.characters.iter().enumerate() {
            let p = walking(c, t, self.unit);
            self.driver.scene().push(Edit::Placement {
                node: character.node,
                placement: p,
            })?;
        }
        self.driver.scene().push(Edit::Time(t % self.walk_cycle))?;
        let camera = self.camera(t);
        self.highlight(camera)?;
        let game = start.elapsed();

        let out = self.driver.frame(camera)?;
        self.frame += 1;
        Ok(Step {
            finished: out.finished,
            waited_render: out.waited_render,
            waited_update: out.waited_update,
            game,
            highlighted: self.highlighted,
        })
    }

    /// The last frame in flight, at the end of the game.
    pub fn finish(&mut self) -> Result<Option<FinishedFrame>> {
        Ok(self.driver.finish()?)
    }

    fn add_body_instance(&mut self, i: usize) -> Result<()> {
        let b = &self.physics.bodies[i];
        let meshes = match b.shape {
            Shape::Box => &self.box_meshes,
            Shape::Sphere => &self.sphere_meshes,
        };
        let mesh = meshes[b.colour % meshes.len()];
        let node = self
            .driver
            .scene()
            .push(Edit::AddInstance {
                mesh,
                placement: self.physics.placement(i),
            })?
            .expect("an added instance has a node");
        self.body_nodes.push(node);
        Ok(())
    }

    /// The camera's script, in periods of 6 s: for 3 s it circles the scene following a
    /// character, then it rests for 3 s where it stopped (the film converges; moving objects
    /// keep the blend floor).
    fn camera(&self, t: f32) -> Camera {
        let period = 6.0;
        let cycle = (t / period).floor();
        let moving = (t - cycle * period).min(3.0);
        let a = 0.25 * (cycle * 3.0 + moving);
        let u = self.unit;
        let eye = Vec3::new(4.2 * a.sin(), 1.6, 4.2 * a.cos()) * u;
        let followed = (cycle as usize) % self.characters.len().max(1);
        let target = if self.characters.is_empty() {
            Vec3::ZERO
        } else {
            let p = walking(followed, cycle * period + moving, u).translation;
            p.as_vec3() + Vec3::Y * 0.55 * u
        };
        Camera::look_at(eye, target, 0.75)
    }

    /// Highlights the character under the screen centre (asked on the CPU, on the scene the
    /// tracers are rendering) and restores the one highlighted before.
    fn highlight(&mut self, camera: Camera) -> Result<()> {
        let Some(q) = self.driver.queries() else {
            return Ok(());
        };
        let o = self.driver.options();
        let basis = camera.basis(o.width, o.height);
        let dir = basis.pixel_centre_direction(o.width / 2, o.height / 2, o.width, o.height);
        let seen = q
            .closest_hit(basis.origin, dir, f32::INFINITY)
            .and_then(|hit| {
                let m = q.material(&hit) as usize;
                self.characters
                    .iter()
                    .position(|c| c.materials.contains(&m))
            });
        if seen == self.highlighted {
            return Ok(());
        }
        if let Some(old) = self.highlighted {
            for &m in &self.characters[old].materials {
                self.driver
                    .scene()
                    .push(Edit::Material(m, Box::new(self.materials[m].clone())))?;
            }
        }
        if let Some(new) = seen {
            for &m in &self.characters[new].materials {
                let lit = world::highlighted(&self.materials[m]);
                self.driver.scene().push(Edit::Material(m, Box::new(lit)))?;
            }
        }
        self.highlighted = seen;
        Ok(())
    }
}

/// Character `c` at time `t`: walking a circle around the scene's centre, every other one the
/// other way, facing where it goes.
fn walking(c: usize, t: f32, unit: f32) -> Placement {
    let radius = (0.7 + 0.45 * c as f32) * unit;
    let speed = 0.55 * unit;
    let dir = if c.is_multiple_of(2) { 1.0 } else { -1.0 };
    let a = dir * speed * t / radius + c as f32 * 1.3;
    let at = Vec3::new(radius * a.cos(), 0.0, radius * a.sin());
    // The tangent of the circle in the walking direction.
    let heading = Vec3::new(-a.sin(), 0.0, a.cos()) * dir;
    Placement {
        translation: DVec3::new(at.x as f64, 0.0, at.z as f64),
        rotation: Quat::from_rotation_arc(FORWARD, heading),
        scale: Vec3::ONE,
    }
}

/// The direction the character faces in its own frame (CesiumMan's walk goes along +Z).
const FORWARD: Vec3 = Vec3::Z;

//! Rigid bodies simulated by rapier3d: a stack of boxes on the ground, and boxes and spheres
//! tossed at it one after another. Deterministic: a fixed time step and a fixed sequence of
//! throws, so two runs of the game are the same game.

use glam::{DVec3, Quat, Vec3};
use platoon::core::scene::Placement;
use rapier3d::prelude::*;

/// The simulation's step; a game frame is one step.
pub const FRAME_SECONDS: f32 = 1.0 / 30.0;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shape {
    Box,
    Sphere,
}

/// A body the scene shows: rapier's handle, its shape, colour and half size.
pub struct Body {
    pub handle: RigidBodyHandle,
    pub shape: Shape,
    pub colour: usize,
    pub half: f32,
}

pub struct Physics {
    world: PhysicsWorld,
    pub bodies: Vec<Body>,
    unit: f32,
    throws: u32,
}

impl Physics {
    /// The ground (a thick slab under y = 0) and a stack of boxes, sized by `unit`.
    pub fn new(unit: f32, ground_half: f32) -> Physics {
        let mut world = PhysicsWorld::new();
        world.integration_parameters.dt = FRAME_SECONDS / 2.0;
        let slab = ColliderBuilder::cuboid(ground_half, unit, ground_half)
            .translation(Vector::new(0.0, -unit, 0.0))
            .friction(0.8)
            .build();
        world.colliders.insert(slab);
        let mut p = Physics {
            world,
            bodies: Vec::new(),
            unit,
            throws: 0,
        };
        // A pyramid of boxes, 4-3-2-1, beside the characters' paths.
        let half = 0.12 * unit;
        for (row, count) in [4, 3, 2, 1].into_iter().enumerate() {
            for k in 0..count {
                let x = 2.4 * unit + (k as f32 - (count - 1) as f32 / 2.0) * 2.05 * half;
                let y = half + row as f32 * 2.0 * half;
                p.add(
                    Shape::Box,
                    k + row,
                    half,
                    Vec3::new(x, y, -1.2 * unit),
                    Vec3::ZERO,
                );
            }
        }
        p
    }

    /// Throws the next body at the stack, from the left, a little differently each time.
    pub fn toss(&mut self) -> usize {
        let n = self.throws;
        self.throws += 1;
        // A fixed pseudo-random sequence (golden-ratio steps) for the throws' spread.
        let r = |k: u32| ((n * 7 + k) as f32 * 0.618_034).fract() - 0.5;
        let u = self.unit;
        let shape = if n.is_multiple_of(2) {
            Shape::Sphere
        } else {
            Shape::Box
        };
        let half = (0.09 + 0.05 * (r(1) + 0.5)) * u;
        let from = Vec3::new(-0.5 * u, 1.6 * u, -1.2 * u + r(2) * 0.8 * u);
        let velocity = Vec3::new(5.0 + 1.5 * r(3), 1.5 + r(4), r(5)) * u;
        self.add(shape, n as usize, half, from, velocity)
    }

    fn add(&mut self, shape: Shape, colour: usize, half: f32, at: Vec3, velocity: Vec3) -> usize {
        let body = RigidBodyBuilder::dynamic()
            .translation(Vector::new(at.x, at.y, at.z))
            .linvel(Vector::new(velocity.x, velocity.y, velocity.z))
            .build();
        let handle = self.world.bodies.insert(body);
        let collider = match shape {
            Shape::Box => ColliderBuilder::cuboid(half, half, half),
            Shape::Sphere => ColliderBuilder::ball(half),
        }
        .restitution(0.35)
        .friction(0.7)
        .density(1.0)
        .build();
        self.world
            .colliders
            .insert_with_parent(collider, handle, &mut self.world.bodies);
        self.bodies.push(Body {
            handle,
            shape,
            colour,
            half,
        });
        self.bodies.len() - 1
    }

    /// Advances one game frame.
    pub fn step(&mut self) {
        for _ in 0..2 {
            self.world.step();
        }
    }

    /// Where body `i` is, as the scene places its mesh (unit mesh scaled by the half size).
    pub fn placement(&self, i: usize) -> Placement {
        let b = &self.bodies[i];
        let body = &self.world.bodies[b.handle];
        let t = body.translation();
        let q = body.rotation();
        Placement {
            translation: DVec3::new(t.x as f64, t.y as f64, t.z as f64),
            rotation: Quat::from_xyzw(q.x, q.y, q.z, q.w).normalize(),
            scale: Vec3::splat(b.half),
        }
    }

    /// Whether body `i` rests (rapier put it to sleep): its placement need not be sent again.
    pub fn sleeping(&self, i: usize) -> bool {
        self.world.bodies[self.bodies[i].handle].is_sleeping()
    }
}

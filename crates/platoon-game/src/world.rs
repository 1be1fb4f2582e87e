//! The game's scene: a ground under a sky and a low sun, the meshes of the rigid bodies (a
//! flat-shaded box and a sphere), and the walking characters, each appended with its own
//! materials so that one can be highlighted alone. Sizes follow the character's height, so any
//! skinned glTF fits.

use std::path::Path;
use std::sync::Arc;

use anyhow::{bail, Context, Result};
use glam::{DVec3, Quat, Vec3, Vec4};
use platoon::core::scene::environment::Environment;
use platoon::core::scene::{LightKind, Material, Mesh, Node, Placement, PunctualLight, Scene};

/// A character of the scene: its placing node and its materials.
#[derive(Clone, Debug)]
pub struct Character {
    pub node: usize,
    pub materials: Vec<usize>,
}

pub struct World {
    pub scene: Scene,
    /// The character's height: the unit of every size in the game.
    pub unit: f32,
    /// A box and a sphere mesh per body colour (a mesh's triangles carry their material).
    pub box_meshes: Vec<usize>,
    pub sphere_meshes: Vec<usize>,
    pub characters: Vec<Character>,
    /// Length of the characters' walk cycle, seconds.
    pub walk_cycle: f32,
}

/// The ground's half width, in character heights.
pub const GROUND: f32 = 8.0;

pub fn build(character_path: &Path, characters: usize) -> Result<World> {
    let character = platoon::load_scene(Some(character_path))?;
    if character.skins.is_empty() || character.animations.is_empty() {
        bail!(
            "{}: not a skinned, animated glTF (the game's characters walk)",
            character_path.display()
        );
    }
    let walk_cycle = character.animations[0].duration();
    if walk_cycle.is_nan() || walk_cycle <= 0.0 {
        bail!(
            "{}: its animation has no duration",
            character_path.display()
        );
    }
    let (lo, hi) = character.pose(0.0).bounds();
    let unit = (hi.y - lo.y).max(1e-3);

    let mut scene = Scene::default();
    let material = |scene: &mut Scene, name: &str, color: Vec3, metallic: f32, roughness: f32| {
        scene.materials.push(Material {
            name: name.into(),
            base_color: color.extend(1.0),
            metallic,
            roughness,
            ..Default::default()
        });
        scene.materials.len() as u32 - 1
    };
    let ground_material = material(&mut scene, "ground", Vec3::splat(0.45), 0.0, 0.9);
    let body_materials: Vec<usize> = [
        ("red", Vec3::new(0.75, 0.12, 0.1), 0.0, 0.5),
        ("teal", Vec3::new(0.1, 0.55, 0.55), 0.0, 0.4),
        ("gold", Vec3::new(0.9, 0.7, 0.3), 1.0, 0.3),
        ("white", Vec3::splat(0.8), 0.0, 0.6),
    ]
    .iter()
    .map(|&(n, c, m, r)| material(&mut scene, n, c, m, r) as usize)
    .collect();

    let g = GROUND * unit;
    let ground =
        platoon_scenegen::quad_from([[-g, 0.0, g], [g, 0.0, g], [g, 0.0, -g], [-g, 0.0, -g]]);
    scene
        .meshes
        .push(Arc::new(generated_mesh(&ground, ground_material, true)));
    let mut node = Node::new("ground");
    node.mesh = Some(0);
    scene.nodes.push(node);
    // The box's corners are [-1, 1]^3; flat shading (no normals) keeps its faces flat.
    let (cube, ball) = (
        platoon_scenegen::smooth_box(),
        platoon_scenegen::icosphere(2),
    );
    let mut meshes_of = |data: &platoon_scenegen::MeshData, smooth: bool| -> Vec<usize> {
        body_materials
            .iter()
            .map(|&m| {
                scene
                    .meshes
                    .push(Arc::new(generated_mesh(data, m as u32, smooth)));
                scene.meshes.len() - 1
            })
            .collect()
    };
    let box_meshes = meshes_of(&cube, false);
    let sphere_meshes = meshes_of(&ball, true);

    // A low sun from the side, so the bodies and characters cast long shadows.
    scene.lights.push(PunctualLight {
        name: "sun".into(),
        kind: LightKind::Directional,
        color: Vec3::new(1.0, 0.92, 0.8),
        intensity: 2.5,
        range: 0.0,
    });
    let mut sun = Node::new("sun");
    sun.light = Some(0);
    sun.rotation = Quat::from_rotation_y(0.7) * Quat::from_rotation_x(-0.75);
    scene.nodes.push(sun);
    scene.environment = Some(Environment::Constant(Vec3::new(0.35, 0.45, 0.6)));

    let characters = (0..characters)
        .map(|c| {
            let first_material = scene.materials.len();
            let node = scene.append(
                &character,
                Placement::at(DVec3::new(c as f64 * unit as f64, 0.0, 0.0)),
            )?;
            Ok(Character {
                node,
                materials: (first_material..scene.materials.len()).collect(),
            })
        })
        .collect::<Result<Vec<_>>>()
        .with_context(|| format!("placing {}", character_path.display()))?;
    Ok(World {
        scene,
        unit,
        box_meshes,
        sphere_meshes,
        characters,
        walk_cycle,
    })
}

/// A highlighted copy of a character's material: tinted orange, so what the screen centre
/// sees stands out in the frames.
pub fn highlighted(m: &Material) -> Material {
    Material {
        base_color: Vec4::new(1.0, 0.5, 0.12, m.base_color.w),
        ..m.clone()
    }
}

/// `data` as a scene mesh, every triangle of `material`; with `smooth` false its normals are
/// left out and it is shaded flat (a box's faces stay flat).
fn generated_mesh(data: &platoon_scenegen::MeshData, material: u32, smooth: bool) -> Mesh {
    let normals: &[[f32; 3]] = if smooth { &data.normals } else { &[] };
    Mesh::from_arrays(
        "generated",
        &data.positions,
        normals,
        &data.indices,
        material,
    )
}

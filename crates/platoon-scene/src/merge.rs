//! Appending one scene to another (a level streaming in a character, a benchmark placing a crowd):
//! every index of the appended scene (nodes, meshes, materials, textures, lights, cameras,
//! skins, animation targets) is moved past the ones already there, and its root nodes hang under
//! one new node that places the whole of it.

use std::sync::Arc;

use crate::error::Result;
use crate::{Material, Node, Placement, Scene, TextureRef};

impl Scene {
    /// Appends `other` under a new node at `placement`; returns that node. Its animation
    /// channels join this scene's first animation (the one posing plays), so an appended
    /// character walks with the scene's clock.
    pub fn append(&mut self, other: &Scene, placement: Placement) -> Result<usize> {
        let p = placement.checked()?;
        let node_base = self.nodes.len() + 1;
        let (mesh_base, material_base) = (self.meshes.len(), self.materials.len() as u32);
        let texture_base = self.textures.len() as u32;
        let (light_base, camera_base, skin_base) =
            (self.lights.len(), self.cameras.len(), self.skins.len());

        let mut root = Node::new(match &other.source {
            Some(path) => format!("placed {}", path.display()),
            None => "placed scene".into(),
        });
        p.place(&mut root);
        let root_index = self.nodes.len();
        self.nodes.push(root);
        for n in &other.nodes {
            let mut n = n.clone();
            n.parent = Some(n.parent.map_or(root_index, |q| q + node_base));
            n.mesh = n.mesh.map(|m| m + mesh_base);
            n.skin = n.skin.map(|s| s + skin_base);
            n.camera = n.camera.map(|c| c + camera_base);
            n.light = n.light.map(|l| l + light_base);
            self.nodes.push(n);
        }
        self.meshes.extend(other.meshes.iter().map(|m| {
            let mut m = (**m).clone();
            for t in &mut m.triangle_materials {
                *t += material_base;
            }
            Arc::new(m)
        }));
        self.materials.extend(
            other
                .materials
                .iter()
                .map(|m| with_textures_moved(m, texture_base)),
        );
        self.textures.extend(other.textures.iter().cloned());
        self.lights.extend(other.lights.iter().cloned());
        self.cameras.extend(other.cameras.iter().cloned());
        self.skins.extend(other.skins.iter().map(|s| {
            let mut s = s.clone();
            for j in &mut s.joints {
                *j += node_base;
            }
            s
        }));
        if let Some(anim) = other.animations.first() {
            let mut channels = anim.channels.clone();
            for c in &mut channels {
                c.node += node_base;
            }
            match self.animations.first_mut() {
                Some(mine) => mine.channels.extend(channels),
                None => self.animations.push(crate::animation::Animation {
                    name: anim.name.clone(),
                    channels,
                }),
            }
        }
        self.warnings.extend(other.warnings.iter().cloned());
        Ok(root_index)
    }
}

fn with_textures_moved(m: &Material, base: u32) -> Material {
    let moved = |t: Option<TextureRef>| {
        t.map(|t| TextureRef {
            texture: t.texture + base,
            ..t
        })
    };
    Material {
        base_color_texture: moved(m.base_color_texture),
        metallic_roughness_texture: moved(m.metallic_roughness_texture),
        normal_texture: moved(m.normal_texture),
        emissive_texture: moved(m.emissive_texture),
        specular_texture: moved(m.specular_texture),
        specular_color_texture: moved(m.specular_color_texture),
        transmission_texture: moved(m.transmission_texture),
        ..m.clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn an_appended_scene_is_placed_and_keeps_its_references() {
        let mut scene = crate::cornell::scene();
        let box_only = scene.clone();
        let before = scene.pose(0.0);
        let root = scene
            .append(&box_only, Placement::at(DVec3::new(10.0, 0.0, 0.0)))
            .unwrap();
        assert_eq!(scene.nodes[root].parent, None);
        let after = scene.pose(0.0);
        assert_eq!(after.instances.len(), 2 * before.instances.len());
        let (lo, hi) = after.bounds();
        let (lo0, hi0) = before.bounds();
        assert_eq!(lo, lo0);
        assert!((hi.x - (hi0.x + 10.0)).abs() < 1e-4);
        let moved = &scene.meshes[after.instances.last().unwrap().mesh];
        let n = box_only.materials.len() as u32;
        assert!(moved.triangle_materials.iter().all(|&m| m >= n));
        assert!(scene
            .append(&box_only, Placement::at(DVec3::splat(f64::NAN)))
            .is_err());
    }
}

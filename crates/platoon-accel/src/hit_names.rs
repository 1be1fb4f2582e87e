//! What names the object and the material a ray hit, from the ids the kernel reports (the
//! instance in top-level leaf order, the triangle in the global leaf order, the material):
//! the scene node and posed mesh of each instance, the node of each triangle of a merged mesh
//! (whose one instance stands for many nodes), the nodes' roots and the nodes' and materials'
//! names. CPU side only: what Cryptomatte's manifests are written from and motion vectors
//! follow a hit back by. Set when a scene is flattened; a living scene's nodes added later
//! are not named (the game loop writes no AOVs).

use super::static_merge::MERGED_NODE;
use platoon_scene::{Mesh, Scene};

#[derive(Clone, Debug, Default)]
pub struct HitNames {
    /// The node of each instance, in top-level leaf order ([`MERGED_NODE`] for a merged mesh's).
    pub instance_nodes: Vec<usize>,
    /// The posed mesh (and so the region) of each instance, in the same order: what motion
    /// vectors find a hit triangle's vertices by.
    pub instance_meshes: Vec<usize>,
    /// The node of each triangle (global leaf order) of a merged mesh, `u32::MAX` for the
    /// others; empty when no mesh is merged.
    pub triangle_nodes: Vec<u32>,
    /// Each node's name as Cryptomatte lists it (`node N` for an unnamed one).
    pub node_names: Vec<String>,
    /// Each node's topmost ancestor (itself for a root): its asset.
    pub node_roots: Vec<usize>,
    /// Each material's name (`material N` for an unnamed one).
    pub material_names: Vec<String>,
}

fn named(name: &str, kind: &str, index: usize) -> String {
    match name.is_empty() {
        true => format!("{kind} {index}"),
        false => name.to_string(),
    }
}

impl HitNames {
    /// The names of `scene`'s nodes and materials (the ids' tables are filled as the
    /// geometry is flattened).
    pub fn set_names(&mut self, scene: &Scene) {
        self.node_names = (scene.nodes.iter().enumerate())
            .map(|(i, n)| named(&n.name, "node", i))
            .collect();
        // A parent comes before its children (the scene's order), so its root is known.
        self.node_roots.clear();
        for (i, n) in scene.nodes.iter().enumerate() {
            let root = n.parent.and_then(|p| self.node_roots.get(p).copied());
            self.node_roots.push(root.unwrap_or(i));
        }
        self.material_names = (scene.materials.iter().enumerate())
            .map(|(i, m)| named(&m.name, "material", i))
            .collect();
    }

    /// Records the nodes of `mesh`'s triangles, written at `base` in leaf order (`order`: the
    /// mesh's triangle of each leaf slot), when it is a merged mesh; `triangles` is the
    /// global triangle count.
    pub fn set_mesh(&mut self, mesh: &Mesh, base: usize, order: &[u32], triangles: usize) {
        if mesh.parts.is_empty() {
            if !self.triangle_nodes.is_empty() {
                self.triangle_nodes.resize(triangles, u32::MAX);
                self.triangle_nodes[base..base + order.len()].fill(u32::MAX);
            }
            return;
        }
        self.triangle_nodes.resize(triangles, u32::MAX);
        for (k, &orig) in order.iter().enumerate() {
            self.triangle_nodes[base + k] = mesh.part_node(orig).map_or(u32::MAX, |n| n as u32);
        }
    }

    /// The node a ray hit, from the kernel's instance and triangle.
    pub fn node(&self, instance: u32, triangle: u32) -> Option<usize> {
        match *self.instance_nodes.get(instance as usize)? {
            MERGED_NODE => match *self.triangle_nodes.get(triangle as usize)? {
                u32::MAX => None,
                n => Some(n as usize),
            },
            node => Some(node),
        }
    }

    /// The name of the object (node) a ray hit.
    pub fn object(&self, instance: u32, triangle: u32) -> Option<&str> {
        let node = self.node(instance, triangle)?;
        self.node_names.get(node).map(String::as_str)
    }

    /// The name of the asset (the object's topmost ancestor) a ray hit.
    pub fn asset(&self, instance: u32, triangle: u32) -> Option<&str> {
        let node = self.node(instance, triangle)?;
        let root = *self.node_roots.get(node)?;
        self.node_names.get(root).map(String::as_str)
    }

    /// The name of material `material`.
    pub fn material(&self, material: u32) -> Option<&str> {
        self.material_names
            .get(material as usize)
            .map(String::as_str)
    }
}

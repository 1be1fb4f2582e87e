//! The elements of a flattened scene: each instance's mesh welded (once per mesh, shared by its
//! instances) and placed in render space by the instance's transform. Elements are numbered
//! instance after instance in the scene arrays' order (the order a hit's instance index counts),
//! so a hit's corners map to elements without search.

use glam::{Mat3, Vec3};

use super::elements::{weld, Welded};
use super::gather::Rings;
use crate::error::{Error, Result};
use crate::flatten::GpuScene;

pub struct SceneElements {
    /// First element of each instance, then the element count.
    pub instance_base: Vec<u32>,
    /// Render-space positions and normals.
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    /// One-rings, within each instance.
    pub rings: Rings,
    /// Each instance's mesh region (`GpuScene::regions`) and each region's welded mesh.
    region_of_instance: Vec<usize>,
    welded: Vec<Welded>,
    vertex_base: Vec<u32>,
}

impl SceneElements {
    /// Welds every instance's mesh with the feature angle `cos_feature` (as `weld` does).
    pub fn of(g: &GpuScene, cos_feature: f32) -> Result<SceneElements> {
        let welded: Vec<Welded> = g
            .regions
            .iter()
            .map(|r| {
                let vertices = &g.vertices[r.vertex_base as usize..][..r.vertex_count as usize];
                let positions: Vec<Vec3> = vertices
                    .iter()
                    .map(|v| Vec3::from_slice(&v.position_u[..3]))
                    .collect();
                let normals: Vec<Vec3> = vertices
                    .iter()
                    .map(|v| Vec3::from_slice(&v.normal_v[..3]))
                    .collect();
                let triangles: Vec<[u32; 3]> = g.triangles[r.triangle_base as usize..]
                    [..r.triangle_count as usize]
                    .iter()
                    .map(|t| t.v.map(|v| v - r.vertex_base))
                    .collect();
                weld(&positions, &normals, &triangles, cos_feature)
            })
            .collect();
        let mut e = SceneElements {
            instance_base: vec![0],
            positions: Vec::new(),
            normals: Vec::new(),
            rings: Rings {
                offsets: vec![0],
                neighbours: Vec::new(),
            },
            region_of_instance: Vec::new(),
            vertex_base: g.regions.iter().map(|r| r.vertex_base).collect(),
            welded: Vec::new(),
        };
        for (i, instance) in g.instances.iter().enumerate() {
            let region = g
                .region_of_instance(i)
                .ok_or_else(|| Error::Invalid(format!("links: instance {i} has no mesh region")))?;
            let w = &welded[region];
            let rows = instance.object_to_world;
            let linear = Mat3::from_cols_array(&[
                rows[0][0], rows[1][0], rows[2][0], rows[0][1], rows[1][1], rows[2][1], rows[0][2],
                rows[1][2], rows[2][2],
            ]);
            let offset = Vec3::new(rows[0][3], rows[1][3], rows[2][3]);
            // Normals by the inverse transpose (mirrors and non-uniform scales included).
            let normal_matrix = linear.inverse().transpose();
            let base = e.positions.len() as u32;
            e.positions
                .extend(w.positions.iter().map(|&p| linear * p + offset));
            e.normals.extend(
                w.normals
                    .iter()
                    .map(|&n| (normal_matrix * n).normalize_or_zero()),
            );
            for x in 0..w.positions.len() {
                let range = w.rings.offsets[x] as usize..w.rings.offsets[x + 1] as usize;
                e.rings
                    .neighbours
                    .extend(w.rings.neighbours[range].iter().map(|&n| n + base));
                e.rings.offsets.push(e.rings.neighbours.len() as u32);
            }
            e.instance_base.push(e.positions.len() as u32);
            e.region_of_instance.push(region);
        }
        e.welded = welded;
        Ok(e)
    }

    pub fn len(&self) -> usize {
        self.positions.len()
    }

    pub fn is_empty(&self) -> bool {
        self.positions.is_empty()
    }

    /// The mesh region (`GpuScene::regions`) instance `instance` places.
    pub fn region_of(&self, instance: usize) -> usize {
        self.region_of_instance[instance]
    }

    /// The element of a hit triangle's corner: `vertex` (a global vertex index, `GpuTriangle::v`)
    /// on instance `instance`.
    pub fn element(&self, instance: u32, vertex: u32) -> u32 {
        let region = self.region_of_instance[instance as usize];
        let local = vertex - self.vertex_base[region];
        self.instance_base[instance as usize]
            + self.welded[region].element_of_vertex[local as usize]
    }
}

impl SceneElements {
    /// One triangle corner of each element (instance, scene triangle, corner 0-2, 0): the first
    /// in the scene arrays' order, where the element's material is read.
    pub fn corners(&self, g: &GpuScene) -> Vec<[u32; 4]> {
        let mut corners = vec![[u32::MAX; 4]; self.len()];
        for (i, &region) in self.region_of_instance.iter().enumerate() {
            let r = &g.regions[region];
            for t in r.triangle_base..r.triangle_base + r.triangle_count {
                for (k, &v) in g.triangles[t as usize].v.iter().enumerate() {
                    let c = &mut corners[self.element(i as u32, v) as usize];
                    if c[0] == u32::MAX {
                        *c = [i as u32, t, k as u32, 0];
                    }
                }
            }
        }
        corners
    }

    /// The triangles around each element (its fan: every triangle with a corner that is the
    /// element), for direct light averaged over the fan: per element its entries
    /// `fan[offsets[x]..offsets[x + 1]]`, each (scene triangle, the element's corner 0-2, the
    /// fan's cumulative render-space area up to and with it over the whole fan's), in the scene
    /// arrays' order. The instance is the element's.
    pub fn fans(&self, g: &GpuScene) -> (Vec<u32>, Vec<[u32; 4]>) {
        let mut per: Vec<Vec<(u32, u32, f32)>> = vec![Vec::new(); self.len()];
        for (i, &region) in self.region_of_instance.iter().enumerate() {
            let r = &g.regions[region];
            for t in r.triangle_base..r.triangle_base + r.triangle_count {
                let v = g.triangles[t as usize].v;
                let [a, b, c] = v.map(|v| g.world_vertex(i as u32, v));
                let area = 0.5 * (b - a).cross(c - a).length();
                for (k, &corner) in v.iter().enumerate() {
                    per[self.element(i as u32, corner) as usize].push((t, k as u32, area));
                }
            }
        }
        let mut offsets = vec![0u32];
        let mut fan = Vec::new();
        for tris in per {
            let total: f64 = tris.iter().map(|t| t.2 as f64).sum();
            let mut sum = 0.0f64;
            for (k, &(t, corner, area)) in tris.iter().enumerate() {
                sum += area as f64;
                // The last entry closes at exactly one whatever the rounding.
                let cdf = if k + 1 == tris.len() || total <= 0.0 {
                    1.0
                } else {
                    (sum / total) as f32
                };
                fan.push([t, corner, cdf.to_bits(), 0]);
            }
            offsets.push(fan.len() as u32);
        }
        (offsets, fan)
    }

    /// The table a kernel maps a hit's corners to elements with: the first element of each
    /// instance, then each scene vertex's element within its welded mesh (`u32::MAX` for a
    /// vertex of no region); the instance count is where the vertices start.
    pub fn table(&self, g: &GpuScene) -> Vec<u32> {
        let instances = self.region_of_instance.len();
        let mut table = self.instance_base[..instances].to_vec();
        let start = table.len();
        table.resize(start + g.vertices.len(), u32::MAX);
        for (region, w) in self.welded.iter().enumerate() {
            let base = start + self.vertex_base[region] as usize;
            table[base..base + w.element_of_vertex.len()].copy_from_slice(&w.element_of_vertex);
        }
        table
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use super::super::elements::tests::seamed_quad;
    use super::*;
    use crate::scene::{Material, Mesh, Node, Scene};

    /// A quad written with a seam (its shared edge's vertices twice), in two instances: one
    /// moved up by 2, one mirrored in x.
    fn scene() -> Scene {
        let (positions, normals, indices) = seamed_quad();
        let quad = Mesh {
            positions,
            normals,
            indices,
            triangle_materials: vec![0, 0],
            ..Default::default()
        };
        let mut nodes: Vec<Node> = (0..2).map(|i| Node::new(format!("n{i}"))).collect();
        for n in &mut nodes {
            n.mesh = Some(0);
        }
        nodes[0].translation = glam::DVec3::new(0.0, 0.0, 2.0);
        nodes[1].scale = Vec3::new(-1.0, 1.0, 1.0);
        Scene {
            nodes,
            meshes: vec![Arc::new(quad)],
            materials: vec![Material::default()],
            ..Default::default()
        }
    }

    #[test]
    fn each_instance_gets_its_welded_mesh_in_render_space() {
        let scene = scene();
        let g = GpuScene::build(&scene, &scene.pose(0.0), None).unwrap();
        let e = SceneElements::of(&g, 0.9).unwrap();
        assert_eq!(e.instance_base, [0, 4, 8]);
        assert_eq!(e.rings.offsets.len(), 9);
        // Every corner of every triangle maps to an element of its instance at the corner's
        // render-space position (the seam's two copies to one element).
        for (i, inst) in g.instances.iter().enumerate() {
            let region = g.regions.iter().find(|r| r.root == inst.blas_root).unwrap();
            let tris = &g.triangles[region.triangle_base as usize..][..2];
            let mut seen = std::collections::BTreeSet::new();
            for t in tris {
                for &v in &t.v {
                    let x = e.element(i as u32, v);
                    assert!(x >= e.instance_base[i] && x < e.instance_base[i + 1]);
                    seen.insert(x);
                    let rows = inst.object_to_world;
                    let p = Vec3::from_slice(&g.vertices[v as usize].position_u[..3]);
                    let world = Vec3::new(
                        rows[0][0] * p.x + rows[0][1] * p.y + rows[0][2] * p.z + rows[0][3],
                        rows[1][0] * p.x + rows[1][1] * p.y + rows[1][2] * p.z + rows[1][3],
                        rows[2][0] * p.x + rows[2][1] * p.y + rows[2][2] * p.z + rows[2][3],
                    );
                    assert!((e.positions[x as usize] - world).length() < 1e-6);
                }
            }
            assert_eq!(seen.len(), 4);
        }
        // The normals: +z for both (a mirror in x keeps a z normal), unit.
        for n in &e.normals {
            assert!((*n - Vec3::Z).length() < 1e-6, "{n}");
        }
    }
}

//! CPU ray queries (Bikker section 7.3.6): closest hit and occlusion against the same flattened
//! scene the tracers render, full detail, animated meshes included, for picking, line of sight
//! and physics. A [`QueryScene`] follows the generations exactly as a tracer does, by applying
//! their commits, so the game thread can query the frame being rendered while the updater builds
//! the next one. The traversal mirrors shaders/intersect.glsl (two levels, nodes holding both
//! children's boxes, the watertight triangle test), so its hits are the kernel's.

use glam::{Vec3, Vec4};

use crate::arrays::SceneArray;
use crate::bvh::{unpack_item, BvhNode};
use crate::commit::{Commit, SceneHeader, ARRAY_COUNT};
use crate::{GpuInstance, GpuScene};

/// A copy of the scene arrays the queries read, kept current by commits.
pub struct QueryScene {
    /// Each scene array's bytes, in u32 words (every GPU struct is made of 4-byte fields).
    arrays: Vec<Vec<u32>>,
    header: SceneHeader,
}

/// The closest hit of a query ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QueryHit {
    pub t: f32,
    /// Barycentrics of the triangle's second and third corners.
    pub b1: f32,
    pub b2: f32,
    /// Instance (top-level leaf order) and triangle (global, bottom-level leaf order), as the
    /// kernel numbers them.
    pub instance: u32,
    pub triangle: u32,
}

const TRI_POS: usize = SceneArray::TrianglePositions.index();
const TRIANGLES: usize = SceneArray::Triangles.index();
const BLAS: usize = SceneArray::Blas.index();
const TLAS: usize = SceneArray::Tlas.index();
const INSTANCES: usize = SceneArray::Instances.index();

impl QueryScene {
    pub fn new(scene: &GpuScene) -> QueryScene {
        let arrays = scene
            .array_bytes()
            .iter()
            .map(|b| bytemuck::pod_collect_to_vec::<u8, u32>(b))
            .collect();
        QueryScene {
            arrays,
            header: scene.header(),
        }
    }

    /// Follows the next generation (the same commit the tracers apply).
    pub fn apply_commit(&mut self, commit: &Commit) {
        for a in &commit.arrays {
            let words = &mut self.arrays[a.array];
            words.resize((a.len / 4) as usize, 0);
            a.write_into(bytemuck::cast_slice_mut(words));
        }
        self.header = commit.header;
        debug_assert_eq!(self.arrays.len(), ARRAY_COUNT);
    }

    /// The flattened scene it holds, rebuilt from its arrays: what a tracer joining mid-run
    /// uploads, at the generation the others render.
    pub fn scene(&self) -> GpuScene {
        fn typed<T: bytemuck::Pod>(words: &[u32]) -> Vec<T> {
            bytemuck::pod_collect_to_vec(bytemuck::cast_slice::<u32, u8>(words))
        }
        use SceneArray::*;
        let a = |array: SceneArray| &self.arrays[array.index()];
        let h = &self.header;
        let triangles: Vec<crate::GpuTriangle> = typed(a(Triangles));
        GpuScene {
            vertices: typed(a(Vertices)),
            vertex_extras: typed(a(VertexExtras)),
            triangle_positions: typed(a(TrianglePositions)),
            triangle_count: triangles.len(),
            triangles,
            triangle_lights: typed(a(TriangleLights)),
            blas_nodes: typed(a(Blas)),
            tlas_nodes: typed(a(Tlas)),
            tlas_root: h.tlas_root,
            instances: typed(a(Instances)),
            materials: typed(a(Materials)),
            textures: typed(a(Textures)),
            texels: typed(a(Texels)),
            lights: typed(a(Lights)),
            light_cdf: typed(a(LightCdf)),
            env: crate::GpuEnvironment {
                kind: h.env_kind,
                color: h.env_color,
                width: h.env_size[0],
                height: h.env_size[1],
                texels: typed(a(EnvTexels)),
                marginal_cdf: typed(a(EnvMarginal)),
                conditional_cdf: typed(a(EnvConditional)),
                integral: h.env_integral,
                mean_radiance: [0.0; 3],
            },
            features: h.features,
            scene_radius: h.scene_sphere[3] as f64,
            scene_center: [h.scene_sphere[0], h.scene_sphere[1], h.scene_sphere[2]],
            ..Default::default()
        }
    }

    fn nodes(&self, array: usize) -> &[BvhNode] {
        bytemuck::cast_slice(&self.arrays[array])
    }

    fn tri_pos(&self) -> &[[f32; 4]] {
        bytemuck::cast_slice(&self.arrays[TRI_POS])
    }

    fn instances(&self) -> &[GpuInstance] {
        bytemuck::cast_slice(&self.arrays[INSTANCES])
    }

    /// The material of the triangle `hit` found.
    pub fn material(&self, hit: &QueryHit) -> u32 {
        let triangles: &[crate::GpuTriangle] = bytemuck::cast_slice(&self.arrays[TRIANGLES]);
        triangles[hit.triangle as usize].material
    }

    /// The closest surface along `origin + t dir`, 0 < t < tmax.
    pub fn closest_hit(&self, origin: Vec3, dir: Vec3, tmax: f32) -> Option<QueryHit> {
        self.trace(origin, dir, tmax, false)
    }

    /// Whether any surface lies along `origin + t dir`, 0 < t < tmax.
    pub fn occluded(&self, origin: Vec3, dir: Vec3, tmax: f32) -> bool {
        self.trace(origin, dir, tmax, true).is_some()
    }

    fn trace(&self, origin: Vec3, dir: Vec3, tmax: f32, any_hit: bool) -> Option<QueryHit> {
        if self.header.instances == 0 {
            return None;
        }
        let world = RayTri::new(origin, dir);
        let mut hit: Option<QueryHit> = None;
        let mut t_max = tmax;
        let mut stack: Vec<u32> = Vec::with_capacity(32);
        let mut item = self.header.tlas_root;
        let (tlas, instances) = (self.nodes(TLAS), self.instances());
        loop {
            let (index, count) = unpack_item(item);
            if count > 0 {
                for i in index..index + count {
                    let inst = &instances[i as usize];
                    let row = |k: usize| Vec4::from_array(inst.world_to_object[k]);
                    let o4 = origin.extend(1.0);
                    let o = Vec3::new(row(0).dot(o4), row(1).dot(o4), row(2).dot(o4));
                    let d = Vec3::new(
                        row(0).truncate().dot(dir),
                        row(1).truncate().dot(dir),
                        row(2).truncate().dot(dir),
                    );
                    let local = RayTri::new(o, d);
                    if self.traverse_blas(&local, inst.blas_root, i, any_hit, &mut t_max, &mut hit)
                        && any_hit
                    {
                        return hit;
                    }
                }
            } else if let Some((near, far)) = order_children(&world, &tlas[index as usize], t_max) {
                if let Some(far) = far {
                    stack.push(far);
                }
                item = near;
                continue;
            }
            match stack.pop() {
                Some(next) => item = next,
                None => return hit,
            }
        }
    }

    fn traverse_blas(
        &self,
        r: &RayTri,
        root: u32,
        instance: u32,
        any_hit: bool,
        t_max: &mut f32,
        hit: &mut Option<QueryHit>,
    ) -> bool {
        let (blas, pos) = (self.nodes(BLAS), self.tri_pos());
        let mut stack: Vec<u32> = Vec::with_capacity(64);
        let mut item = root;
        let mut found = false;
        loop {
            let (index, count) = unpack_item(item);
            if count > 0 {
                let i = index as usize;
                let corner = |k: usize| Vec3::from_slice(&pos[3 * i + k][..3]);
                if let Some((t, b1, b2)) =
                    r.intersect_triangle(corner(0), corner(1), corner(2), *t_max)
                {
                    *hit = Some(QueryHit {
                        t,
                        b1,
                        b2,
                        instance,
                        triangle: index,
                    });
                    *t_max = t;
                    found = true;
                    if any_hit {
                        return true;
                    }
                }
                if count > 1 {
                    item = crate::bvh::item(index + 1, count - 1);
                    continue;
                }
            } else if let Some((near, far)) = order_children(r, &blas[index as usize], *t_max) {
                if let Some(far) = far {
                    stack.push(far);
                }
                item = near;
                continue;
            }
            match stack.pop() {
                Some(next) => item = next,
                None => return found,
            }
        }
    }
}

/// Both children of `n` hit before `tmax`, nearer first (ties: the first child).
fn order_children(r: &RayTri, n: &BvhNode, tmax: f32) -> Option<(u32, Option<u32>)> {
    let ta = r.intersect_aabb(n.min0, n.max0, tmax);
    let tb = r.intersect_aabb(n.min1, n.max1, tmax);
    let (ta, tb, near, far) = if tb < ta {
        (tb, ta, n.item1, n.item0)
    } else {
        (ta, tb, n.item0, n.item1)
    };
    if ta == f32::INFINITY {
        None
    } else if tb == f32::INFINITY {
        Some((near, None))
    } else {
        Some((near, Some(far)))
    }
}

/// Per-ray constants of the watertight test (Woop, Benthin, Wald 2013), as the kernel's RayTri
/// (public for the tests that check the traversal against every triangle).
pub struct RayTri {
    org: Vec3,
    inv_dir: Vec3,
    kz: usize,
    swap_xy: bool,
    shear: Vec3,
}

impl RayTri {
    fn permute(&self, v: Vec3) -> Vec3 {
        let p = match self.kz {
            0 => Vec3::new(v.y, v.z, v.x),
            1 => Vec3::new(v.z, v.x, v.y),
            _ => v,
        };
        if self.swap_xy {
            Vec3::new(p.y, p.x, p.z)
        } else {
            p
        }
    }

    pub fn new(org: Vec3, dir: Vec3) -> RayTri {
        let ad = dir.abs();
        let kz = if ad.x > ad.y {
            if ad.x > ad.z {
                0
            } else {
                2
            }
        } else if ad.y > ad.z {
            1
        } else {
            2
        };
        let mut r = RayTri {
            org,
            inv_dir: Vec3::ZERO,
            kz,
            swap_xy: false,
            shear: Vec3::ZERO,
        };
        let mut d = r.permute(dir);
        r.swap_xy = d.z < 0.0;
        if r.swap_xy {
            d = Vec3::new(d.y, d.x, d.z);
        }
        r.shear = Vec3::new(d.x / d.z, d.y / d.z, 1.0 / d.z);
        // Zero components would give 0 * inf = NaN in the slab test.
        let safe = Vec3::select(
            ad.cmplt(Vec3::splat(1e-30)),
            Vec3::select(
                dir.cmplt(Vec3::ZERO),
                Vec3::splat(-1e-30),
                Vec3::splat(1e-30),
            ),
            dir,
        );
        r.inv_dir = 1.0 / safe;
        r
    }

    pub fn intersect_triangle(
        &self,
        v0: Vec3,
        v1: Vec3,
        v2: Vec3,
        tmax: f32,
    ) -> Option<(f32, f32, f32)> {
        let a = self.permute(v0 - self.org);
        let b = self.permute(v1 - self.org);
        let c = self.permute(v2 - self.org);
        let s = self.shear;
        let (ax, ay) = (a.x - s.x * a.z, a.y - s.y * a.z);
        let (bx, by) = (b.x - s.x * b.z, b.y - s.y * b.z);
        let (cx, cy) = (c.x - s.x * c.z, c.y - s.y * c.z);
        let u = cx * by - cy * bx;
        let v = ax * cy - ay * cx;
        let w = bx * ay - by * ax;
        if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
            return None;
        }
        let det = u + v + w;
        if det == 0.0 {
            return None;
        }
        let t_scaled = s.z * (u * a.z + v * b.z + w * c.z);
        let inv = 1.0 / det;
        let t = t_scaled * inv;
        if !(t > 0.0 && t < tmax) {
            return None;
        }
        Some((t, v * inv, w * inv))
    }

    /// Slab test, conservative by 2 gamma(3) (Ize 2013).
    fn intersect_aabb(&self, bmin: [f32; 3], bmax: [f32; 3], tmax: f32) -> f32 {
        let t0 = (Vec3::from_array(bmin) - self.org) * self.inv_dir;
        let t1 = (Vec3::from_array(bmax) - self.org) * self.inv_dir;
        let tn = t0.min(t1).max_element().max(0.0);
        let tf = t0.max(t1).min_element() * 1.000_000_4;
        if tn <= tf && tn < tmax {
            tn
        } else {
            f32::INFINITY
        }
    }
}

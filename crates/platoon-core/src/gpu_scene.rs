//! Flattens a posed scene into the plain arrays the kernel reads (std430 layouts mirrored in
//! shaders/scene.glsl). This is the only data the tracer crate receives from the core.

use std::f64::consts::PI;
use std::time::Duration;

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3};

use crate::bvh::{self, BvhNode, FlatBvh};
use crate::environment::{luminance, Environment};
use crate::error::{Error, Result};
use crate::features::FeatureSet;
use crate::scene::{AlphaMode, LightKind, Posed, Scene, Wrap};

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuVertex {
    /// xyz position, w = u
    pub position_u: [f32; 4],
    /// xyz normal (zero when the mesh has none), w = v
    pub normal_v: [f32; 4],
    /// xyz tangent, w = bitangent sign
    pub tangent: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuTriangle {
    /// Global vertex indices and material index.
    pub v: [u32; 3],
    pub material: u32,
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuInstance {
    /// Rows of the 3x4 world-to-object matrix.
    pub world_to_object: [[f32; 4]; 3],
    /// Rows of the 3x4 object-to-world matrix.
    pub object_to_world: [[f32; 4]; 3],
    pub blas_root: u32,
    /// First light entry of this instance's emissive triangles (u32::MAX if none).
    pub light_base: u32,
    pub _pad: [u32; 2],
}

pub const NO_TEXTURE: i32 = -1;
pub const MATERIAL_DOUBLE_SIDED: i32 = 1;
pub const MATERIAL_ALPHA_MASK: i32 = 2;

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuMaterial {
    pub base_color: [f32; 4],
    /// rgb emission, w = normal scale
    pub emissive: [f32; 4],
    /// metallic, roughness, transmission, ior
    pub params: [f32; 4],
    /// specular colour rgb, w = specular factor
    pub specular: [f32; 4],
    /// base colour, metallic-roughness, normal, emissive textures
    pub textures0: [i32; 4],
    /// specular, specular colour, transmission textures, flags
    pub textures1: [i32; 4],
    /// alpha cutoff
    pub misc: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuTexture {
    pub offset: u32,
    pub width: u32,
    pub height: u32,
    /// wrap_s | wrap_t << 2 (0 repeat, 1 mirrored repeat, 2 clamp)
    pub wrap: u32,
}

pub const LIGHT_TRIANGLE: u32 = 0;
pub const LIGHT_POINT: u32 = 1;
pub const LIGHT_SPOT: u32 = 2;
pub const LIGHT_DIRECTIONAL: u32 = 3;
pub const LIGHT_ENVIRONMENT: u32 = 4;

/// One entry of the light-selection distribution.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuLight {
    /// Triangle: world v0, w = +1, or -1 when the instance mirrors (a negative determinant
    /// flips the world winding; glTF keeps the object's front face, and so does the hit shader).
    /// Punctual: position.
    pub a: [f32; 4],
    /// Triangle: world v1; spot/directional: direction. w = range
    pub b: [f32; 4],
    /// Triangle: world v2; spot: cos(outer), 1/(cos(inner) - cos(outer)).
    pub c: [f32; 4],
    /// Radiance (triangle) or intensity (punctual) rgb; w = selection probability.
    pub emission: [f32; 4],
    /// type, instance, triangle (BLAS order, global), material
    pub ids: [u32; 4],
}

/// Everything the kernel needs, as flat arrays.
#[derive(Clone, Debug, Default)]
pub struct GpuScene {
    pub vertices: Vec<GpuVertex>,
    /// Object-space triangle corners in BLAS leaf order, xyz + pad.
    pub triangle_positions: Vec<[f32; 4]>,
    pub triangles: Vec<GpuTriangle>,
    /// Per triangle: index of its emissive light relative to the instance's `light_base`.
    pub triangle_lights: Vec<u32>,
    pub blas_nodes: Vec<BvhNode>,
    pub tlas_nodes: Vec<BvhNode>,
    /// The item the top level starts at (inner node 0, or the one instance's leaf).
    pub tlas_root: u32,
    pub instances: Vec<GpuInstance>,
    pub materials: Vec<GpuMaterial>,
    pub textures: Vec<GpuTexture>,
    pub texels: Vec<u32>,
    pub lights: Vec<GpuLight>,
    /// Light selection CDF, `lights.len() + 1` entries.
    pub light_cdf: Vec<f32>,
    pub env: GpuEnvironment,
    pub features: FeatureSet,
    pub triangle_count: usize,
    pub build_times: bvh::BuildTimes,
    /// Radius of the scene's bounding sphere (for directional and environment light power), in
    /// f64: a vertex at 1e30 makes its square overflow f32.
    pub scene_radius: f64,
}

#[derive(Clone, Debug, Default)]
pub struct GpuEnvironment {
    /// 0 = none (black), 1 = constant colour, 2 = map
    pub kind: u32,
    pub color: [f32; 3],
    pub width: u32,
    pub height: u32,
    pub texels: Vec<[f32; 4]>,
    pub marginal_cdf: Vec<f32>,
    pub conditional_cdf: Vec<f32>,
    pub integral: f32,
}

fn rows(m: &Mat4) -> [[f32; 4]; 3] {
    let t = m.transpose();
    [
        t.x_axis.to_array(),
        t.y_axis.to_array(),
        t.z_axis.to_array(),
    ]
}

fn tex(t: Option<crate::scene::TextureRef>) -> i32 {
    t.map(|t| t.texture as i32).unwrap_or(NO_TEXTURE)
}

fn wrap_code(w: Wrap) -> u32 {
    match w {
        Wrap::Repeat => 0,
        Wrap::MirroredRepeat => 1,
        Wrap::ClampToEdge => 2,
    }
}

impl GpuScene {
    /// Flattens `posed` (a pose of `scene`). `environment` is the distant light in effect.
    /// Fails when the light-selection distribution is not finite (an emitter of infinite power).
    pub fn build(
        scene: &Scene,
        posed: &Posed,
        environment: Option<&Environment>,
    ) -> Result<GpuScene> {
        let mut g = GpuScene::default();
        // Only meshes some instance uses (a skinned mesh's bind pose is replaced by its pose).
        let mut used = vec![false; posed.meshes.len()];
        for i in &posed.instances {
            used[i.mesh] = true;
        }
        let live_meshes: Vec<std::sync::Arc<crate::scene::Mesh>> = posed
            .meshes
            .iter()
            .zip(&used)
            .map(|(m, &u)| if u { m.clone() } else { Default::default() })
            .collect();
        let (mesh_bvhs, mesh_time) = bvh::timed(|| bvh::build_mesh_bvhs(&live_meshes));

        // Bottom level: vertices, triangles in leaf order, node indices made global.
        let mut blas_root = Vec::with_capacity(posed.meshes.len());
        let mut tri_base = Vec::with_capacity(posed.meshes.len());
        for (mesh, flat) in live_meshes.iter().zip(&mesh_bvhs) {
            let vbase = g.vertices.len() as u32;
            let tbase = g.triangles.len() as u32;
            let nbase = g.blas_nodes.len() as u32;
            tri_base.push(tbase);
            for (i, p) in mesh.positions.iter().enumerate() {
                let uv = mesh.uvs.get(i).copied().unwrap_or_default();
                let n = mesh.normals.get(i).copied().unwrap_or_default();
                let t = mesh.tangents.get(i).copied().unwrap_or_default();
                g.vertices.push(GpuVertex {
                    position_u: [p.x, p.y, p.z, uv.x],
                    normal_v: [n.x, n.y, n.z, uv.y],
                    tangent: t.to_array(),
                });
            }
            let mut local_light = 0u32;
            for &orig in &flat.order {
                let tri = mesh.indices[orig as usize];
                let material = mesh.triangle_materials[orig as usize];
                for &v in &tri {
                    let p = mesh.positions[v as usize];
                    g.triangle_positions.push([p.x, p.y, p.z, 0.0]);
                }
                g.triangles.push(GpuTriangle {
                    v: tri.map(|v| v + vbase),
                    material,
                });
                if scene.materials[material as usize].is_emissive() {
                    g.triangle_lights.push(local_light);
                    local_light += 1;
                } else {
                    g.triangle_lights.push(u32::MAX);
                }
            }
            let too_large = || {
                Error::Invalid(format!(
                    "more than {} triangles or BVH nodes: too large for the kernel's node items",
                    bvh::MAX_ITEM_INDEX
                ))
            };
            for n in &flat.nodes {
                g.blas_nodes
                    .push(n.rebased(nbase, tbase).ok_or_else(too_large)?);
            }
            blas_root.push(bvh::rebase_item(flat.root, nbase, tbase).ok_or_else(too_large)?);
        }
        g.triangle_count = g.triangles.len();

        // Top level over the instances of non-empty meshes whose world box is placeable.
        let (live, boxes): (Vec<&crate::scene::Instance>, Vec<obvhs::aabb::Aabb>) = posed
            .instances
            .iter()
            .filter(|i| !mesh_bvhs[i.mesh].is_empty())
            .map(|i| {
                let b = bvh::transform_bounds(&i.object_to_world, mesh_bvhs[i.mesh].bounds());
                (i, b)
            })
            .filter(|(_, b)| bvh::placeable(b.min.into()) && bvh::placeable(b.max.into()))
            .unzip();
        let (tlas, instance_time): (FlatBvh, Duration) =
            bvh::timed(|| bvh::build_instance_bvh(&boxes));
        g.build_times = bvh::BuildTimes {
            meshes: mesh_time,
            instances: instance_time,
        };
        g.tlas_nodes = tlas.nodes.clone();
        g.tlas_root = tlas.root;
        let (lo, hi) = tlas.bounds();
        g.scene_radius = ((hi.as_dvec3() - lo.as_dvec3()).length() * 0.5).max(1e-3);

        // Materials and textures.
        g.materials = scene.materials.iter().map(gpu_material).collect();
        for t in &scene.textures {
            g.textures.push(GpuTexture {
                offset: g.texels.len() as u32,
                width: t.width,
                height: t.height,
                wrap: wrap_code(t.wrap_s) | wrap_code(t.wrap_t) << 2,
            });
            g.texels.extend(
                t.rgba8
                    .chunks_exact(4)
                    .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]])),
            );
        }

        // Instances (in top-level leaf order) and their emissive triangles as lights.
        let mut power: Vec<f64> = Vec::new();
        for (new_index, &orig) in tlas.order.iter().enumerate() {
            let inst = live[orig as usize];
            let tb = tri_base[inst.mesh] as usize;
            let tri_count = mesh_bvhs[inst.mesh].order.len();
            let first_light = g.lights.len() as u32;
            let facing = if inst.object_to_world.determinant() < 0.0 {
                -1.0
            } else {
                1.0
            };
            for t in tb..tb + tri_count {
                if g.triangle_lights[t] == u32::MAX {
                    continue;
                }
                let material = g.triangles[t].material;
                let mat = &scene.materials[material as usize];
                let w: Vec<Vec3> = (0..3)
                    .map(|k| {
                        inst.object_to_world.transform_point3(Vec3::from_slice(
                            &g.triangle_positions[3 * t + k][..3],
                        ))
                    })
                    .collect();
                let area = 0.5 * (w[1] - w[0]).cross(w[2] - w[0]).length();
                let sides = if mat.double_sided { 2.0 } else { 1.0 };
                power.push(luminance(mat.emissive) as f64 * area as f64 * PI * sides);
                g.lights.push(GpuLight {
                    a: w[0].extend(facing).to_array(),
                    b: w[1].extend(0.0).to_array(),
                    c: w[2].extend(0.0).to_array(),
                    emission: mat.emissive.extend(0.0).to_array(),
                    ids: [LIGHT_TRIANGLE, new_index as u32, t as u32, material],
                });
            }
            g.instances.push(GpuInstance {
                world_to_object: rows(&inst.object_to_world.inverse()),
                object_to_world: rows(&inst.object_to_world),
                blas_root: blas_root[inst.mesh],
                light_base: if g.lights.len() as u32 > first_light {
                    first_light
                } else {
                    u32::MAX
                },
                _pad: [0; 2],
            });
        }

        for placed in &posed.lights {
            let l = &scene.lights[placed.light];
            let intensity = l.color * l.intensity;
            let lum = luminance(intensity) as f64;
            let (kind, c, p) = match l.kind {
                LightKind::Point => (LIGHT_POINT, [0.0; 4], 4.0 * PI * lum),
                LightKind::Spot {
                    inner_cone,
                    outer_cone,
                } => {
                    let (ci, co) = (inner_cone.cos(), outer_cone.cos());
                    let solid_angle = 2.0 * PI * (1.0 - 0.5 * (ci + co) as f64);
                    (
                        LIGHT_SPOT,
                        [co, 1.0 / (ci - co).max(1e-4), 0.0, 0.0],
                        solid_angle * lum,
                    )
                }
                LightKind::Directional => (
                    LIGHT_DIRECTIONAL,
                    [0.0; 4],
                    PI * g.scene_radius * g.scene_radius * lum,
                ),
            };
            power.push(p);
            g.lights.push(GpuLight {
                a: placed.position.extend(0.0).to_array(),
                b: placed.direction.extend(l.range).to_array(),
                c,
                emission: intensity.extend(0.0).to_array(),
                ids: [kind, 0, 0, 0],
            });
        }

        if let Some(env) = environment {
            g.env = gpu_environment(env);
            // Flux of the environment through the scene's bounding sphere.
            let r = g.scene_radius;
            power.push(PI * PI * r * r * luminance(env.mean_radiance()) as f64);
            g.lights.push(GpuLight {
                ids: [LIGHT_ENVIRONMENT, 0, 0, 0],
                ..Default::default()
            });
        }

        let (cdf, pmf) = selection_distribution(&power)?;
        g.light_cdf = cdf;
        for (light, p) in g.lights.iter_mut().zip(pmf) {
            light.emission[3] = p;
        }

        g.features = FeatureSet::of_scene(scene);
        g.features.emissive_triangles = g.lights.iter().any(|l| l.ids[0] == LIGHT_TRIANGLE);
        g.features.environment_map = g.env.kind == 2;
        Ok(g)
    }
}

/// The light-selection CDF (f32, as the kernel searches it) and each light's probability, taken
/// from that same f32 CDF so that the pdf the kernel evaluates is exactly the one it samples
/// with. Powers are summed in f64; if everything is black, lights are picked uniformly (still
/// unbiased). A non-finite power is an error here rather than a silently black frame.
pub fn selection_distribution(power: &[f64]) -> Result<(Vec<f32>, Vec<f32>)> {
    if let Some(i) = power.iter().position(|p| !p.is_finite()) {
        return Err(Error::Invalid(format!(
            "light {i} has a non-finite power ({}): check emission strengths and light intensities",
            power[i]
        )));
    }
    let total: f64 = power.iter().map(|&p| p.max(0.0)).sum();
    let n = power.len();
    let mut cdf = Vec::with_capacity(n + 1);
    cdf.push(0.0f32);
    let mut acc = 0.0f64;
    for (i, p) in power.iter().enumerate() {
        acc += if total > 0.0 {
            p.max(0.0) / total
        } else {
            1.0 / n as f64
        };
        cdf.push(if i + 1 == n { 1.0 } else { acc.min(1.0) as f32 });
    }
    let pmf = cdf.windows(2).map(|w| w[1] - w[0]).collect();
    Ok((cdf, pmf))
}

fn gpu_material(m: &crate::scene::Material) -> GpuMaterial {
    let mut flags = 0;
    if m.double_sided {
        flags |= MATERIAL_DOUBLE_SIDED;
    }
    let cutoff = match m.alpha_mode {
        AlphaMode::Mask(c) => {
            flags |= MATERIAL_ALPHA_MASK;
            c
        }
        _ => 0.0,
    };
    GpuMaterial {
        base_color: m.base_color.to_array(),
        emissive: m.emissive.extend(m.normal_scale).to_array(),
        params: [
            m.metallic.clamp(0.0, 1.0),
            m.roughness.clamp(0.0, 1.0),
            m.transmission.clamp(0.0, 1.0),
            m.ior.max(1.0),
        ],
        specular: m.specular_color.extend(m.specular.max(0.0)).to_array(),
        textures0: [
            tex(m.base_color_texture),
            tex(m.metallic_roughness_texture),
            tex(m.normal_texture),
            tex(m.emissive_texture),
        ],
        textures1: [
            tex(m.specular_texture),
            tex(m.specular_color_texture),
            tex(m.transmission_texture),
            flags,
        ],
        misc: [cutoff, 0.0, 0.0, 0.0],
    }
}

fn gpu_environment(env: &Environment) -> GpuEnvironment {
    match env {
        Environment::Constant(c) => GpuEnvironment {
            kind: 1,
            color: c.to_array(),
            ..Default::default()
        },
        Environment::Map(map) => {
            let d = map.distribution();
            GpuEnvironment {
                kind: 2,
                color: [1.0; 3],
                width: map.width,
                height: map.height,
                texels: map.texels.iter().map(|t| [t[0], t[1], t[2], 0.0]).collect(),
                marginal_cdf: d.marginal_cdf,
                conditional_cdf: d.conditional_cdf,
                integral: d.integral,
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::selection_distribution;

    #[test]
    fn probabilities_are_the_widths_of_the_searched_cdf() {
        // An emitter beside a sun whose power comes from a radius of 1e30: the emitter's share
        // vanishes in f32, and its probability must then be 0, not 1e-61.
        for power in [vec![8.0, 1e61], vec![1.0, 2.0, 3.0], vec![0.0, 0.0]] {
            let (cdf, pmf) = selection_distribution(&power).unwrap();
            assert_eq!((cdf.len(), pmf.len()), (power.len() + 1, power.len()));
            assert_eq!((cdf[0], *cdf.last().unwrap()), (0.0, 1.0));
            for i in 0..pmf.len() {
                assert_eq!(pmf[i], cdf[i + 1] - cdf[i]);
                assert!(pmf[i].is_finite() && pmf[i] >= 0.0);
            }
        }
        let (_, pmf) = selection_distribution(&[8.0, 1e61]).unwrap();
        assert_eq!(pmf, vec![0.0, 1.0]);
        let (_, pmf) = selection_distribution(&[0.0, 0.0]).unwrap();
        assert_eq!(pmf, vec![0.5, 0.5]);
    }

    #[test]
    fn a_non_finite_power_is_an_error() {
        assert!(selection_distribution(&[1.0, f64::INFINITY]).is_err());
        assert!(selection_distribution(&[f64::NAN]).is_err());
    }
}

//! The update of vertex links over the devices (the facade runs it before a frame that needs
//! it): elements welded on the CPU, rays shot by the devices in shooting frames of a batch of
//! elements each, the hits reduced to link groups, the direct light at the elements from a
//! lighting frame, then the gather and the smoothing on the CPU. Every device frame goes
//! through `run` (one tracer's bands, or the renderer's split between tracers): each pixel of
//! those frames is a pure function of its element and direction, so the solution is the same
//! bits whichever devices rendered which part.

use std::sync::Arc;
use std::time::Instant;

use glam::Vec3;

use super::directions::directions;
use super::gather::{gather, smooth, Rgb};
use rayon::prelude::*;

use super::job::{
    ElementAlbedo, ElementRay, ElementRays, Job, Links, Shot, ShotHit, Solution, UpdateStats,
    LIGHT_WIDTH, RAY_WIDTH,
};
use super::options::LinksOptions;
use super::reduce::{LinkGroups, RayHit};
use super::revalidate;
use super::scene_elements::SceneElements;
use super::shoot_cpu::{link_of_hit, ray_direction, ray_frame};
use crate::error::{Error, Result};
use crate::flatten::GpuScene;
use crate::frame::FrameParams;
use crate::method::render_method::{DeviceFrame, DeviceRun};
use crate::method::Method;

/// A device frame's records that do not read back as the update's (`PixelData::records`).
fn invalid(e: String) -> Error {
    Error::Invalid(format!("links update: {e}"))
}

/// Rays a shooting frame carries at most: its hits are read back whole (16 bytes each).
pub const MAX_RAYS_PER_FRAME: u64 = 1 << 22;

/// A digest of what shapes the links of `g` with `options`: vertices, triangles, instances,
/// the directions and the feature angle (not lights, materials or the other options).
pub fn geometry_digest(g: &GpuScene, options: &LinksOptions) -> u64 {
    use std::hash::Hasher;
    let mut h = revalidate::hasher();
    h.write(bytemuck::cast_slice(&g.vertices));
    h.write(bytemuck::cast_slice(&g.triangle_positions));
    h.write(bytemuck::cast_slice(&g.triangles));
    h.write(bytemuck::cast_slice(&g.instances));
    h.write_u32(options.directions);
    h.write_u32(options.feature_angle.to_bits());
    h.write_u64(revalidate::surface_digest(g));
    h.finish()
}

/// Solves the links of `g` (the scene the devices hold) for frames like `params`, taking the
/// links of `previous` when it was solved on the same geometry (relighting).
pub fn solve(
    g: &GpuScene,
    options: &LinksOptions,
    params: &FrameParams,
    previous: Option<&Solution>,
    run: &mut DeviceRun,
) -> Result<Solution> {
    options.validate().map_err(Error::Invalid)?;
    let mut stats = UpdateStats::default();
    let clock = Instant::now();
    let elements = SceneElements::of(g, options.cos_feature())?;
    let rays = element_rays(g, &elements, options)?;
    stats.elements = elements.len() as u32;
    stats.weld_s = clock.elapsed().as_secs_f64();
    let n = elements.len();
    let mut device = |job: Job, width: u32, height: u32, spp: u32| {
        let mut p = params.clone();
        p.method = Method::new(Links {
            options: *options,
            job: Some(job),
            previous: None,
        });
        (p.width, p.height, p.spp) = (width, height, spp);
        p.film.accumulated = None;
        p.options.time_limit = None;
        p.first_sample = 0;
        run(&p).map_err(|e| Error::Invalid(format!("links update: {e}")))
    };

    let geometry = geometry_digest(g, options);
    let table = elements.table(g);
    let rays = Arc::new(rays);
    let (links, shot) = match previous {
        Some(p) if p.geometry == geometry => {
            stats.relit = true;
            (p.links.clone(), p.shot.clone())
        }
        _ => {
            // What a later revalidation compares with, when the options keep the hits.
            let digests = options.revalidate.then(|| {
                (
                    revalidate::layout(g, &rays.directions),
                    revalidate::shapes(g, &elements),
                )
            });
            let earlier = previous
                .filter(|p| p.table == table)
                .and_then(|p| Some((p, p.shot.as_ref()?, digests.as_ref()?)));
            let clock = Instant::now();
            let stale = earlier.and_then(|(_, shot, (layout, shapes))| {
                revalidate::stale_rays(g, &elements, &rays, shapes, *layout, shot)
            });
            stats.revalidate_s = clock.elapsed().as_secs_f64();
            let (links, hits) = match (earlier, stale) {
                (Some((p, shot, _)), Some(stale)) => {
                    stats.revalidated = true;
                    stats.moved_instances = stale.moved_instances;
                    stats.moved_elements = stale.moved_elements;
                    stats.rays = stale.rays.len() as u64;
                    let clock = Instant::now();
                    let mut hits = shot.hits.clone();
                    stats.revalidate_s += clock.elapsed().as_secs_f64();
                    reshoot(&rays, &stale.rays, &mut hits, &mut device, &mut stats)?;
                    let clock = Instant::now();
                    let (links, regrouped) =
                        regroup(g, &elements, &rays, &p.links, &stale.rays, &hits)?;
                    stats.regrouped = regrouped as u32;
                    stats.reduce_s += clock.elapsed().as_secs_f64();
                    (links, hits)
                }
                _ => {
                    stats.rays = n as u64 * rays.directions.len() as u64;
                    shoot(
                        g,
                        &elements,
                        &rays,
                        options.revalidate,
                        &mut device,
                        &mut stats,
                    )?
                }
            };
            let shot = digests.map(|(layout, shapes)| {
                Arc::new(Shot {
                    rays: rays.clone(),
                    hits,
                    shapes,
                    layout,
                })
            });
            (Arc::new(links), shot)
        }
    };
    stats.raw_links = links.raw_links;
    stats.links = links.peers.len() as u64;
    stats.link_bytes = links.bytes() as u64;

    // Direct light and albedo at every element.
    let clock = Instant::now();
    let height = (n as u32).div_ceil(LIGHT_WIDTH).max(1);
    let frame = device(Job::Light(rays), LIGHT_WIDTH, height, options.light_samples)?;
    stats.light_s = clock.elapsed().as_secs_f64();
    stats.light_device_s = frame.gpu_time.as_secs_f64();
    let albedo = frame
        .per_pixel
        .records::<ElementAlbedo>()
        .map_err(invalid)?;
    if frame.film.len() < n || albedo.len() < n {
        return Err(Error::Invalid(format!(
            "links update: the lighting frame returned {} of {n} elements",
            albedo.len().min(frame.film.len())
        )));
    }
    let direct: Vec<Rgb> = frame.film[..n].to_vec();
    let albedo: Vec<Rgb> = albedo[..n].iter().map(|a| a.albedo).collect();

    let clock = Instant::now();
    let mut indirect = gather(&links, &albedo, &direct, options.bounces);
    stats.gather_s = clock.elapsed().as_secs_f64();
    if options.smooth {
        let clock = Instant::now();
        indirect = smooth(
            &indirect,
            &elements.normals,
            &elements.rings,
            options.cos_feature(),
        );
        stats.smooth_s = clock.elapsed().as_secs_f64();
    }
    Ok(Solution {
        irradiance: indirect.iter().map(|e| [e[0], e[1], e[2], 0.0]).collect(),
        table,
        instances: g.instances.len() as u32,
        links,
        geometry,
        shot,
        stats,
    })
}

/// A shooting or lighting frame on the devices: (job, width, height, samples).
type Device<'a> = dyn FnMut(Job, u32, u32, u32) -> Result<DeviceFrame> + 'a;

/// Shooting frames of a batch of elements each, reduced batch by batch into link groups; with
/// every ray's hit when `keep` (for a later revalidation), else none.
fn shoot(
    g: &GpuScene,
    elements: &SceneElements,
    rays: &ElementRays,
    keep: bool,
    device: &mut Device,
    stats: &mut UpdateStats,
) -> Result<(LinkGroups, Vec<ShotHit>)> {
    let n = elements.len();
    let n_c = rays.directions.len() as u32;
    let batch = (MAX_RAYS_PER_FRAME / n_c as u64).max(1) as usize;
    let mut links = LinkGroups {
        offsets: vec![0],
        ..Default::default()
    };
    let mut kept = Vec::new();
    let mut first = 0;
    while first < n {
        let end = (first + batch).min(n);
        let part = Arc::new(ElementRays {
            elements: rays.elements[first..end].to_vec(),
            directions: rays.directions.clone(),
            fans: Vec::new(),
            single_rays: false,
        });
        let clock = Instant::now();
        let frame = device(Job::Shoot(part), n_c, (end - first) as u32, 1)?;
        stats.shoot_s += clock.elapsed().as_secs_f64();
        stats.shoot_device_s += frame.gpu_time.as_secs_f64();
        let clock = Instant::now();
        let shot = frame.per_pixel.records::<ShotHit>().map_err(invalid)?;
        let hits = hits_of(g, elements, rays, first, shot)?;
        links.append(LinkGroups::from_hits(n_c, &hits));
        if keep {
            kept.extend_from_slice(shot);
        }
        stats.reduce_s += clock.elapsed().as_secs_f64();
        first = end;
    }
    Ok((links, kept))
}

/// Shoots the `stale` rays (element * n_C + direction, ascending) again in frames of single
/// rays, writing their hits into `hits`.
fn reshoot(
    rays: &ElementRays,
    stale: &[u32],
    hits: &mut [ShotHit],
    device: &mut Device,
    stats: &mut UpdateStats,
) -> Result<()> {
    let n_c = rays.directions.len() as u32;
    for part in stale.chunks(MAX_RAYS_PER_FRAME as usize) {
        let single = Arc::new(ElementRays {
            elements: part
                .iter()
                .map(|&r| {
                    let mut e = rays.elements[(r / n_c) as usize];
                    e.fan[2] = r % n_c;
                    e
                })
                .collect(),
            directions: rays.directions.clone(),
            fans: Vec::new(),
            single_rays: true,
        });
        let height = (part.len() as u32).div_ceil(RAY_WIDTH);
        let clock = Instant::now();
        let frame = device(Job::Shoot(single), RAY_WIDTH, height, 1)?;
        stats.shoot_s += clock.elapsed().as_secs_f64();
        stats.shoot_device_s += frame.gpu_time.as_secs_f64();
        let shot = frame.per_pixel.records::<ShotHit>().map_err(invalid)?;
        if shot.len() < part.len() {
            return Err(Error::Invalid(format!(
                "links update: a shooting frame returned {} of {} rays",
                shot.len(),
                part.len()
            )));
        }
        for (&r, &h) in part.iter().zip(shot) {
            hits[r as usize] = h;
        }
    }
    Ok(())
}

/// `earlier` with the groups of the elements that shot a `stale` ray reduced again from
/// `hits`; and how many those were.
fn regroup(
    g: &GpuScene,
    elements: &SceneElements,
    rays: &ElementRays,
    earlier: &LinkGroups,
    stale: &[u32],
    hits: &[ShotHit],
) -> Result<(LinkGroups, usize)> {
    let n_c = rays.directions.len();
    let mut changed: Vec<usize> = stale.iter().map(|&r| r as usize / n_c).collect();
    changed.dedup();
    let groups: Vec<(usize, LinkGroups)> = changed
        .par_iter()
        .map(|&x| {
            let of = hits_of(g, elements, rays, x, &hits[x * n_c..(x + 1) * n_c])?;
            Ok((x, LinkGroups::from_hits(n_c as u32, &of)))
        })
        .collect::<Result<_>>()?;
    Ok((earlier.spliced(&groups), changed.len()))
}

/// The elements as the kernels read them, with the directions.
fn element_rays(
    g: &GpuScene,
    elements: &SceneElements,
    options: &LinksOptions,
) -> Result<ElementRays> {
    let corners = elements.corners(g);
    let (fan_offsets, fans) = elements.fans(g);
    Ok(ElementRays {
        elements: (0..elements.len())
            .map(|x| {
                let f = ray_frame(elements, x);
                ElementRay {
                    origin: f[0].extend(0.0).to_array(),
                    tangent: f[1].extend(0.0).to_array(),
                    bitangent: f[2].extend(0.0).to_array(),
                    normal: f[3].extend(0.0).to_array(),
                    corner: corners[x],
                    fan: [fan_offsets[x], fan_offsets[x + 1] - fan_offsets[x], 0, 0],
                }
            })
            .collect(),
        directions: directions(options.directions)?
            .iter()
            .map(|d| d.extend(0.0).to_array())
            .collect(),
        fans,
        single_rays: false,
    })
}

/// The links of elements [first, first + batch) from a shooting frame's hits.
fn hits_of(
    g: &GpuScene,
    elements: &SceneElements,
    rays: &ElementRays,
    first: usize,
    per_pixel: &[ShotHit],
) -> Result<Vec<Option<RayHit>>> {
    let n_c = rays.directions.len();
    if !per_pixel.len().is_multiple_of(n_c) {
        return Err(Error::Invalid(format!(
            "links update: a shooting frame returned {} hits for {n_c} directions",
            per_pixel.len()
        )));
    }
    let dirs: Vec<Vec3> = rays
        .directions
        .iter()
        .map(|d| Vec3::from_slice(&d[..3]))
        .collect();
    let mut hits = Vec::with_capacity(per_pixel.len());
    for (k, rays_of) in per_pixel.chunks(n_c).enumerate() {
        // The frame the element's rays were shot in (`element_rays`' copy of `ray_frame`).
        let e = &rays.elements[first + k];
        let frame = [e.origin, e.tangent, e.bitangent, e.normal].map(|v| Vec3::from_slice(&v[..3]));
        for (&d, h) in dirs.iter().zip(rays_of) {
            let (instance, triangle) = (h.instance, h.triangle);
            if h.missed() {
                hits.push(None);
                continue;
            }
            if instance as usize >= g.instances.len() || triangle as usize >= g.triangles.len() {
                return Err(Error::Invalid(format!(
                    "links update: a device returned a hit on instance {instance}, triangle \
                     {triangle}, not in the scene"
                )));
            }
            let dir = ray_direction(&frame, d);
            hits.push(link_of_hit(g, elements, dir, instance, triangle, h.b));
        }
    }
    Ok(hits)
}

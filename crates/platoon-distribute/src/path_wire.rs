//! The path tracer's state on the wire (`method::path::PathTracing`): its kernel, the last
//! paths cut, resampled light, and what its frames carry from one to the next (the world
//! cache's table and light reuse's reservoirs, which every rank reads whole). Every field is
//! written out by name: a new one breaks the build here until it travels.

use std::sync::Arc;

use super::wire::{get_camera, put_camera, Reader, WireError, Writer};
use platoon_core::frame::light_reuse::{LightReuse, ReservoirHistory};
use platoon_core::frame::world_cache::CacheTable;
use platoon_core::method::path::{PathKernel, PathTracing, ResampledLight};

pub fn put_path_tracing(w: &mut Writer, p: &PathTracing) {
    let PathTracing {
        kernel,
        cut_last_paths,
        resampled_light,
        world_cache,
        light_reuse,
    } = p;
    w.u8(match kernel {
        PathKernel::Auto => 0,
        PathKernel::Mega => 1,
        PathKernel::Streaming => 2,
    });
    w.flag(*cut_last_paths);
    w.flag(resampled_light.is_some());
    if let Some(ResampledLight {
        candidates,
        mis,
        contribution,
    }) = resampled_light
    {
        w.u32(*candidates);
        w.flag(*mis);
        w.flag(*contribution);
    }
    w.flag(world_cache.is_some());
    if let Some(c) = world_cache {
        w.f32(c.cell_size);
        w.u32(c.train_stride);
        w.pod(bytemuck::cast_slice::<[f32; 4], f32>(&c.slots));
    }
    w.flag(light_reuse.is_some());
    if let Some(h) = light_reuse {
        put_light_reuse(w, h);
    }
}

pub fn get_path_tracing(r: &mut Reader) -> Result<PathTracing, WireError> {
    let kernel = match r.u8()? {
        0 => PathKernel::Auto,
        1 => PathKernel::Mega,
        2 => PathKernel::Streaming,
        k => return Err(WireError(format!("unknown path kernel {k}"))),
    };
    let cut_last_paths = r.flag()?;
    let resampled_light = match r.flag()? {
        true => Some(ResampledLight {
            candidates: r.u32()?,
            mis: r.flag()?,
            contribution: r.flag()?,
        }),
        false => None,
    };
    let world_cache = match r.flag()? {
        true => Some(Arc::new(get_cache_table(r)?)),
        false => None,
    };
    let light_reuse = match r.flag()? {
        true => Some(Arc::new(get_light_reuse(r)?)),
        false => None,
    };
    Ok(PathTracing {
        kernel,
        cut_last_paths,
        resampled_light,
        world_cache,
        light_reuse,
    })
}

fn get_cache_table(r: &mut Reader) -> Result<CacheTable, WireError> {
    let cell_size = r.f32()?;
    let train_stride = r.u32()?;
    let flat: Vec<f32> = r.pod()?;
    let slots: Vec<[f32; 4]> = flat
        .chunks_exact(4)
        .map(|c| [c[0], c[1], c[2], c[3]])
        .collect();
    if !slots.len().is_power_of_two() {
        return Err(WireError("the world cache's table".into()));
    }
    Ok(CacheTable {
        cell_size,
        train_stride,
        slots,
    })
}

/// The reuse's settings and the previous frame's reservoirs (every rank reads the whole
/// image's: the reuse finds them by reprojection, anywhere).
pub(crate) fn put_light_reuse(w: &mut Writer, h: &ReservoirHistory) {
    let ReservoirHistory {
        options,
        camera,
        width,
        height,
        records,
    } = h;
    let LightReuse {
        unbiased,
        neighbours,
        radius,
        history,
    } = options;
    w.u8(*unbiased as u8);
    w.u32(*neighbours);
    w.f32(*radius);
    w.u32(*history);
    put_camera(w, camera);
    w.u32(*width);
    w.u32(*height);
    w.pod(records);
}

pub(crate) fn get_light_reuse(r: &mut Reader) -> Result<ReservoirHistory, WireError> {
    let options = LightReuse {
        unbiased: r.flag()?,
        neighbours: r.u32()?,
        radius: r.f32()?,
        history: r.u32()?,
    };
    let camera = get_camera(r)?;
    let (width, height) = (r.u32()?, r.u32()?);
    Ok(ReservoirHistory {
        options,
        camera,
        width,
        height,
        records: r.pod()?,
    })
}

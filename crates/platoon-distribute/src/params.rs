//! A frame's parameters on the wire, for ranks that cannot make them themselves (the game
//! loop's workers: the frame driver on rank 0 decides each frame's camera, samples and film).
//! Every field is written out by name: a new field of `FrameParams` breaks the build here until
//! it travels. The accumulated sums and the converged mask travel only for the span the rank
//! renders (`wire::put_film_span`); the method by its settings (`method_wire`).

use std::time::Duration;

use super::method_wire::{get_method, put_method};
use super::wire::{get_film_span, put_film_span, Reader, WireError, Writer};
use platoon_core::frame::aov::AovPass;
use platoon_core::frame::light_pass::{BsdfPart, LightPass};
use platoon_core::frame::light_reuse::{LightReuse, ReservoirHistory};
use platoon_core::frame::world_cache::CacheTable;
use platoon_core::frame::{Crop, FrameParams, Output, PathLoop, PixelFilter, Span};
use platoon_core::method::path_kernel::PathKernel;
use platoon_core::scene::camera::Camera;

fn opt_f32(w: &mut Writer, v: Option<f32>) {
    w.u8(v.is_some() as u8);
    w.f32(v.unwrap_or(0.0));
}

fn get_opt_f32(r: &mut Reader) -> Result<Option<f32>, WireError> {
    let some = r.u8()? == 1;
    let v = r.f32()?;
    Ok(some.then_some(v))
}

fn flag(r: &mut Reader) -> Result<bool, WireError> {
    Ok(r.u8()? != 0)
}

fn put_camera(w: &mut Writer, camera: &Camera) {
    let Camera {
        camera_to_world,
        yfov,
        aperture_radius,
        focus_distance,
        orthographic,
    } = camera;
    w.pod(&camera_to_world.to_cols_array());
    w.f32(*yfov);
    w.f32(*aperture_radius);
    w.f32(*focus_distance);
    w.u8(orthographic.is_some() as u8);
    w.pod(&orthographic.unwrap_or_default());
}

fn get_camera(r: &mut Reader) -> Result<Camera, WireError> {
    let cols: Vec<f32> = r.pod()?;
    let cols: [f32; 16] = cols
        .try_into()
        .map_err(|_| WireError("the camera's matrix".into()))?;
    Ok(Camera {
        camera_to_world: glam::Mat4::from_cols_array(&cols),
        yfov: r.f32()?,
        aperture_radius: r.f32()?,
        focus_distance: r.f32()?,
        orthographic: {
            let some = flag(r)?;
            let xy: Vec<f32> = r.pod()?;
            let xy: [f32; 2] = xy
                .try_into()
                .map_err(|_| WireError("the orthographic size".into()))?;
            some.then_some(xy)
        },
    })
}

/// The reuse's settings and the previous frame's reservoirs (every rank reads the whole
/// image's: the reuse finds them by reprojection, anywhere).
fn put_light_reuse(w: &mut Writer, h: &ReservoirHistory) {
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
    w.pod(bytemuck::cast_slice::<[f32; 4], f32>(records));
}

fn get_light_reuse(r: &mut Reader) -> Result<ReservoirHistory, WireError> {
    let options = LightReuse {
        unbiased: flag(r)?,
        neighbours: r.u32()?,
        radius: r.f32()?,
        history: r.u32()?,
    };
    let camera = get_camera(r)?;
    let (width, height) = (r.u32()?, r.u32()?);
    let flat: Vec<f32> = r.pod()?;
    if !flat.len().is_multiple_of(4) {
        return Err(WireError("the light reuse's reservoirs".into()));
    }
    Ok(ReservoirHistory {
        options,
        camera,
        width,
        height,
        records: flat
            .chunks_exact(4)
            .map(|c| [c[0], c[1], c[2], c[3]])
            .collect(),
    })
}

fn put_path_loop(w: &mut Writer, l: &PathLoop) {
    let PathLoop {
        max_depth,
        rr_depth,
        rr_survival,
        rr_fixed,
        clamp_indirect,
        uniform_light_selection,
        generic_kernel,
        deterministic_termination,
        single_diffuse_bounce,
    } = l;
    w.u32(*max_depth);
    w.u32(*rr_depth);
    w.f32(*rr_survival);
    opt_f32(w, *rr_fixed);
    opt_f32(w, *clamp_indirect);
    for b in [
        uniform_light_selection,
        generic_kernel,
        deterministic_termination,
        single_diffuse_bounce,
    ] {
        w.u8(*b as u8);
    }
}

fn get_path_loop(r: &mut Reader) -> Result<PathLoop, WireError> {
    Ok(PathLoop {
        max_depth: r.u32()?,
        rr_depth: r.u32()?,
        rr_survival: r.f32()?,
        rr_fixed: get_opt_f32(r)?,
        clamp_indirect: get_opt_f32(r)?,
        uniform_light_selection: flag(r)?,
        generic_kernel: flag(r)?,
        deterministic_termination: flag(r)?,
        single_diffuse_bounce: flag(r)?,
    })
}

/// `p` for a rank rendering `span`: everything, with the sums and mask of the span only.
pub fn put_params(w: &mut Writer, p: &FrameParams, span: Span) -> Result<(), String> {
    let FrameParams {
        width,
        height,
        spp,
        path_loop,
        cut_last_paths,
        ris_candidates,
        ris_mis,
        ris_contribution,
        world_cache,
        light_reuse,
        method,
        kernel,
        seed,
        frame,
        first_sample,
        film,
        samples_per_pass,
        time_limit,
        camera,
        filter,
        crop,
        transparent_film,
        ao_distance,
        output,
    } = p;
    for v in [width, height, spp] {
        w.u32(*v);
    }
    put_path_loop(w, path_loop);
    for b in [cut_last_paths, ris_mis, ris_contribution] {
        w.u8(*b as u8);
    }
    w.u8(ris_candidates.is_some() as u8);
    w.u32(ris_candidates.unwrap_or(0));
    w.u8(world_cache.is_some() as u8);
    if let Some(c) = world_cache {
        w.f32(c.cell_size);
        w.u32(c.train_stride);
        w.pod(bytemuck::cast_slice::<[f32; 4], f32>(&c.slots));
    }
    w.u8(light_reuse.is_some() as u8);
    if let Some(h) = light_reuse {
        put_light_reuse(w, h);
    }
    put_method(w, method)?;
    w.u8(match kernel {
        PathKernel::Auto => 0,
        PathKernel::Mega => 1,
        PathKernel::Streaming => 2,
    });
    for v in [seed, frame, first_sample, samples_per_pass] {
        w.u32(*v);
    }
    // The film's sums and mask: the span's only.
    let _ = film;
    put_film_span(w, p, span);
    w.u8(time_limit.is_some() as u8);
    w.duration(time_limit.unwrap_or_default());
    put_camera(w, camera);
    w.u8(match filter {
        PixelFilter::Box => 0,
        PixelFilter::Gaussian => 1,
        PixelFilter::BlackmanHarris => 2,
    });
    w.u8(crop.is_some() as u8);
    let Crop {
        x,
        y,
        image_width,
        image_height,
    } = p.image_crop();
    for v in [x, y, image_width, image_height] {
        w.u32(v);
    }
    w.u8(match output {
        Output::Radiance => 0,
        Output::PrimaryHit => 1,
        Output::BsdfSample => 2,
        Output::BsdfValue => 3,
        Output::Aov(AovPass::Albedo) => 4,
        Output::Aov(AovPass::Normal) => 5,
        Output::Aov(AovPass::Position) => 6,
        Output::Aov(AovPass::Ids) => 7,
        Output::Aov(AovPass::SampleIds(_)) => 8,
        Output::Aov(AovPass::Light(_)) => 9,
        Output::Aov(AovPass::Alpha) => 10,
        Output::Aov(AovPass::Ao) => 11,
        Output::Aov(AovPass::Color(_)) => 12,
    });
    match output {
        Output::Aov(AovPass::SampleIds(sample)) => w.u32(*sample),
        Output::Aov(AovPass::Light(pass)) => w.u8(*pass as u8),
        Output::Aov(AovPass::Color(part)) => w.u8(*part as u8),
        _ => {}
    }
    w.u8(*transparent_film as u8);
    w.f32(*ao_distance);
    Ok(())
}

/// The parameters `put_params` wrote for `span`: the sums and mask outside it are zero.
pub fn get_params(r: &mut Reader, span: Span) -> Result<FrameParams, WireError> {
    let camera0 = Camera::look_at(glam::Vec3::Z, glam::Vec3::ZERO, 1.0);
    let mut p = FrameParams::new(r.u32()?, r.u32()?, r.u32()?, camera0);
    p.path_loop = get_path_loop(r)?;
    p.cut_last_paths = flag(r)?;
    p.ris_mis = flag(r)?;
    p.ris_contribution = flag(r)?;
    let some = flag(r)?;
    let m = r.u32()?;
    p.ris_candidates = some.then_some(m);
    if flag(r)? {
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
        p.world_cache = Some(std::sync::Arc::new(CacheTable {
            cell_size,
            train_stride,
            slots,
        }));
    }
    if flag(r)? {
        p.light_reuse = Some(std::sync::Arc::new(get_light_reuse(r)?));
    }
    p.method = get_method(r)?;
    p.kernel = match r.u8()? {
        0 => PathKernel::Auto,
        1 => PathKernel::Mega,
        2 => PathKernel::Streaming,
        k => return Err(WireError(format!("unknown path kernel {k}"))),
    };
    p.seed = r.u32()?;
    p.frame = r.u32()?;
    p.first_sample = r.u32()?;
    p.samples_per_pass = r.u32()?;
    get_film_span(r, &mut p, span)?;
    let some = flag(r)?;
    let limit: Duration = r.duration()?;
    p.time_limit = some.then_some(limit);
    p.camera = get_camera(r)?;
    p.filter = match r.u8()? {
        0 => PixelFilter::Box,
        1 => PixelFilter::Gaussian,
        2 => PixelFilter::BlackmanHarris,
        k => return Err(WireError(format!("unknown pixel filter {k}"))),
    };
    let cropped = flag(r)?;
    let crop = Crop {
        x: r.u32()?,
        y: r.u32()?,
        image_width: r.u32()?,
        image_height: r.u32()?,
    };
    p.crop = cropped.then_some(crop);
    p.output = match r.u8()? {
        0 => Output::Radiance,
        1 => Output::PrimaryHit,
        2 => Output::BsdfSample,
        3 => Output::BsdfValue,
        4 => Output::Aov(AovPass::Albedo),
        5 => Output::Aov(AovPass::Normal),
        6 => Output::Aov(AovPass::Position),
        7 => Output::Aov(AovPass::Ids),
        8 => Output::Aov(AovPass::SampleIds(r.u32()?)),
        9 => {
            let k = r.u8()? as usize;
            let pass = *(LightPass::ALL.get(k))
                .ok_or_else(|| WireError(format!("unknown light pass {k}")))?;
            Output::Aov(AovPass::Light(pass))
        }
        10 => Output::Aov(AovPass::Alpha),
        11 => Output::Aov(AovPass::Ao),
        12 => {
            let k = r.u8()? as usize;
            let part = *(BsdfPart::ALL.get(k))
                .ok_or_else(|| WireError(format!("unknown BSDF part {k}")))?;
            Output::Aov(AovPass::Color(part))
        }
        k => return Err(WireError(format!("unknown output {k}"))),
    };
    p.transparent_film = flag(r)?;
    p.ao_distance = r.f32()?;
    Ok(p)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::wire::fingerprint;
    use platoon_core::method::igi::IgiOptions;
    use platoon_core::method::Method;

    fn round_trip(p: &FrameParams, span: Span) -> FrameParams {
        let mut w = Writer::default();
        put_params(&mut w, p, span).unwrap();
        let mut r = Reader::new(&w.0);
        let back = get_params(&mut r, span).unwrap();
        r.finish().unwrap();
        back
    }

    #[test]
    fn every_setting_travels_and_the_span_takes_its_sums() {
        let mut camera = Camera::look_at(glam::Vec3::new(1.0, 2.0, 3.0), glam::Vec3::ZERO, 0.7);
        camera.orthographic = Some([2.0, 1.5]);
        camera.aperture_radius = 0.1;
        let mut p = FrameParams::new(5, 4, 3, camera);
        p.path_loop.rr_fixed = Some(0.5);
        p.path_loop.clamp_indirect = Some(9.0);
        p.ris_candidates = Some(4);
        p.ris_mis = true;
        p.ris_contribution = true;
        p.cut_last_paths = true;
        p.transparent_film = true;
        p.ao_distance = 2.5;
        // Every IGI option away from its default: each must travel.
        p.method = Method::new(IgiOptions {
            paths: 7,
            bounces: 2,
            min_distance: 0.25,
            imperfect_visibility: true,
            downsample: 2,
            interleave: [2, 3],
        });
        p.kernel = PathKernel::Streaming;
        p.world_cache = Some(std::sync::Arc::new(CacheTable {
            cell_size: 0.5,
            train_stride: 3,
            slots: (0..4)
                .map(|i| [f32::from_bits(i * 257 + 1), 0.5, 1.5, 2.5])
                .collect(),
        }));
        let mut camera = p.camera;
        camera.yfov = 0.75;
        p.light_reuse = Some(std::sync::Arc::new(ReservoirHistory {
            options: LightReuse {
                unbiased: false,
                neighbours: 5,
                radius: 7.5,
                history: 9,
            },
            camera,
            width: 2,
            height: 1,
            records: (0..6).map(|i| [i as f32, 0.5, -1.5, 2.5]).collect(),
        }));
        p.seed = 11;
        p.frame = 12;
        p.first_sample = 13;
        p.output = Output::Aov(AovPass::Normal);
        p.filter = PixelFilter::BlackmanHarris;
        p.crop = Some(Crop {
            x: 2,
            y: 3,
            image_width: 9,
            image_height: 8,
        });
        p.film.accumulated = Some(
            (0..20)
                .map(|i| [i as f32, 0.5, -1.0])
                .collect::<Vec<_>>()
                .into(),
        );
        p.film.converged = Some((0..20).map(|i| i % 3 == 0).collect::<Vec<_>>().into());
        let span = Span::new(6, 13);
        let back = round_trip(&p, span);
        assert_eq!(fingerprint(&back), fingerprint(&p));
        let (a, b) = (p.film.accumulated.unwrap(), back.film.accumulated.unwrap());
        for i in 0..20 {
            let inside = (6..13).contains(&i);
            assert_eq!(b[i], if inside { a[i] } else { [0.0; 3] }, "{i}");
            assert_eq!(
                back.film.converged.as_ref().unwrap()[i],
                inside && p.film.converged.as_ref().unwrap()[i]
            );
        }
        let plain = FrameParams::new(
            3,
            3,
            1,
            Camera::look_at(glam::Vec3::Z, glam::Vec3::ZERO, 1.0),
        );
        assert_eq!(round_trip(&plain, Span::new(0, 9)), plain);
        // An output with a value of its own: the sample whose ids a pass holds.
        let ids = FrameParams {
            output: Output::Aov(AovPass::SampleIds(9)),
            ..plain
        };
        assert_eq!(round_trip(&ids, Span::new(0, 9)), ids);
        let light = FrameParams {
            output: Output::Aov(AovPass::Light(LightPass::GlossyIndirect)),
            ..ids
        };
        assert_eq!(round_trip(&light, Span::new(0, 9)), light);
        let color = FrameParams {
            output: Output::Aov(AovPass::Color(BsdfPart::Transmission)),
            ..light
        };
        assert_eq!(round_trip(&color, Span::new(0, 9)), color);
    }

    #[test]
    fn methods_whose_preparation_does_not_travel_are_refused() {
        let mut p = FrameParams::new(
            3,
            3,
            1,
            Camera::look_at(glam::Vec3::Z, glam::Vec3::ZERO, 1.0),
        );
        p.method = Method::new(platoon_core::method::lhb::Lhb::new(Default::default()));
        let e = put_params(&mut Writer::default(), &p, Span::new(0, 9)).unwrap_err();
        assert!(e.contains("--method path or igi"), "{e}");
    }
}

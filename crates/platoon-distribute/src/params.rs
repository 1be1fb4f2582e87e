//! A frame's parameters on the wire, for ranks that cannot make them themselves (the game
//! loop's workers: the frame driver on rank 0 decides each frame's camera, samples and film).
//! Every field is written out by name: a new field of `FrameParams` breaks the build here until
//! it travels. The accumulated sums and the converged mask travel only for the span the rank
//! renders (`wire::put_film_span`); the method by its settings (`method_wire`).

use std::time::Duration;

use super::method_wire::{get_method, put_method};
use super::path_wire::{get_path_tracing, put_path_tracing};
use super::wire::{
    get_camera, get_film_span, put_camera, put_film_span, Reader, WireError, Writer,
};
use platoon_core::frame::aov::AovPass;
use platoon_core::frame::light_pass::{BsdfPart, LightPass};
use platoon_core::frame::{Crop, FrameParams, Output, PathLoop, PixelFilter, Span};
use platoon_core::method::path::PathTracing;
use platoon_core::scene::camera::Camera;

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
    w.opt_f32(*rr_fixed);
    w.opt_f32(*clamp_indirect);
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
        rr_fixed: r.opt_f32()?,
        clamp_indirect: r.opt_f32()?,
        uniform_light_selection: r.flag()?,
        generic_kernel: r.flag()?,
        deterministic_termination: r.flag()?,
        single_diffuse_bounce: r.flag()?,
    })
}

/// `p` for a rank rendering `span`: everything, with the sums and mask of the span only.
pub fn put_params(w: &mut Writer, p: &FrameParams, span: Span) -> Result<(), String> {
    let FrameParams {
        width,
        height,
        spp,
        path_loop,
        method,
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
    put_method(w, method)?;
    // The path tracer's state beyond its settings: what its frames carry.
    if let Some(path) = method.state::<PathTracing>() {
        put_path_tracing(w, path);
    }
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
    p.method = get_method(r)?;
    if let Some(path) = p.method.path_mut() {
        *path = get_path_tracing(r)?;
    }
    p.seed = r.u32()?;
    p.frame = r.u32()?;
    p.first_sample = r.u32()?;
    p.samples_per_pass = r.u32()?;
    get_film_span(r, &mut p, span)?;
    let some = r.flag()?;
    let limit: Duration = r.duration()?;
    p.time_limit = some.then_some(limit);
    p.camera = get_camera(r)?;
    p.filter = match r.u8()? {
        0 => PixelFilter::Box,
        1 => PixelFilter::Gaussian,
        2 => PixelFilter::BlackmanHarris,
        k => return Err(WireError(format!("unknown pixel filter {k}"))),
    };
    let cropped = r.flag()?;
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
    p.transparent_film = r.flag()?;
    p.ao_distance = r.f32()?;
    Ok(p)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::wire::fingerprint;
    use platoon_core::frame::light_reuse::{LightReuse, ReservoirHistory};
    use platoon_core::frame::world_cache::CacheTable;
    use platoon_core::method::igi::IgiOptions;
    use platoon_core::method::path::{PathKernel, ResampledLight};
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
        let (a, b) = (
            p.film.accumulated.clone().unwrap(),
            back.film.accumulated.unwrap(),
        );
        for i in 0..20 {
            let inside = (6..13).contains(&i);
            assert_eq!(b[i], if inside { a[i] } else { [0.0; 3] }, "{i}");
            assert_eq!(
                back.film.converged.as_ref().unwrap()[i],
                inside && p.film.converged.as_ref().unwrap()[i]
            );
        }
        let mut camera = p.camera;
        camera.yfov = 0.75;
        // Every path tracer's option away from its default, with what its frames carry.
        let path = PathTracing {
            kernel: PathKernel::Streaming,
            cut_last_paths: true,
            resampled_light: Some(ResampledLight {
                candidates: 4,
                mis: false,
                contribution: true,
            }),
            world_cache: Some(std::sync::Arc::new(CacheTable {
                cell_size: 0.5,
                train_stride: 3,
                slots: (0..4)
                    .map(|i| [f32::from_bits(i * 257 + 1), 0.5, 1.5, 2.5])
                    .collect(),
            })),
            light_reuse: Some(std::sync::Arc::new(ReservoirHistory {
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
            })),
        };
        let path_traced = FrameParams {
            method: Method::new(path),
            ..p.clone()
        };
        let back = round_trip(&path_traced, span);
        assert_eq!(back.method, path_traced.method);
        assert_eq!(fingerprint(&back), fingerprint(&path_traced));
        assert_ne!(fingerprint(&back), fingerprint(&p));
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

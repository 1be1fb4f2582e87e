//! A frame's parameters on the wire, for ranks that cannot make them themselves (the game
//! loop's workers: the frame driver on rank 0 decides each frame's camera, samples and film).
//! The settings travel as `FrameParams` derives them (serde, in CBOR: every f32 bit, infinities
//! included), so a new field travels without a line here; the method by its settings and its
//! state (`method_wire`), and the accumulated sums and the converged mask only for the span the
//! rank renders (`wire::put_film_span`).

use super::method_wire::{get_method, put_method};
use super::wire::{get_film_span, put_film_span, Reader, WireError, Writer};
use platoon_core::frame::{FrameParams, Span};

/// `p` for a rank rendering `span`: everything, with the sums and mask of the span only.
pub fn put_params(w: &mut Writer, p: &FrameParams, span: Span) -> Result<(), String> {
    let mut settings = Vec::new();
    ciborium::into_writer(p, &mut settings)
        .map_err(|e| format!("encoding the frame's parameters: {e}"))?;
    w.bytes(&settings);
    put_method(w, &p.method)?;
    put_film_span(w, p, span);
    Ok(())
}

/// The parameters `put_params` wrote for `span`: the sums and mask outside it are zero.
pub fn get_params(r: &mut Reader, span: Span) -> Result<FrameParams, WireError> {
    let mut p: FrameParams = ciborium::from_reader(r.bytes()?)
        .map_err(|e| WireError(format!("the frame's parameters: {e}")))?;
    p.method = get_method(r)?;
    get_film_span(r, &mut p, span)?;
    Ok(p)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::wire::fingerprint;
    use platoon_core::frame::aov::AovPass;
    use platoon_core::frame::light_pass::{BsdfPart, LightPass};
    use platoon_core::frame::{Crop, Output, PixelFilter};
    use platoon_core::method::igi::IgiOptions;
    use platoon_core::method::path::light_reuse::{LightReuse, ReservoirHistory, ReservoirRecord};
    use platoon_core::method::path::world_cache::{CacheTable, WorldCacheOptions};
    use platoon_core::method::path::{LearningOptions, PathKernel, PathTracing, ResampledLight};
    use platoon_core::method::Method;
    use platoon_core::scene::camera::Camera;

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
        p.options.transparent_film = true;
        p.options.ao_distance = 2.5;
        // Every IGI option away from its default: each must travel.
        p.method = Method::new(IgiOptions {
            paths: 7,
            bounces: 2,
            min_distance: 0.25,
            imperfect_visibility: true,
            downsample: 2,
            interleave: [2, 3],
        });
        p.options.seed = 11;
        p.frame = 12;
        p.first_sample = 13;
        p.output = Output::Aov(AovPass::Normal);
        p.options.filter = PixelFilter::BlackmanHarris;
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
                records: (0..2)
                    .map(|i| ReservoirRecord {
                        position: [i as f32, 0.5, -1.5],
                        light: 2.5,
                        ..Default::default()
                    })
                    .collect(),
            })),
            learning: LearningOptions {
                world_cache: Some(WorldCacheOptions {
                    stale_frames: 3,
                    ..Default::default()
                }),
                light_reuse: Some(LightReuse {
                    history: 4,
                    ..Default::default()
                }),
            },
        };
        let path_traced = FrameParams {
            method: Method::new(path),
            ..p.clone()
        };
        let back = round_trip(&path_traced, span);
        assert_eq!(back.method, path_traced.method);
        assert_eq!(fingerprint(&back), fingerprint(&path_traced));
        assert_ne!(fingerprint(&back), fingerprint(&p));
        // One bit of what the path tracer's frames carry is another frame.
        let mut other = back.clone();
        let mut path = other.method.path().clone();
        let mut table = (**path.world_cache.as_ref().unwrap()).clone();
        table.slots[3][2] = f32::from_bits(table.slots[3][2].to_bits() ^ 1);
        path.world_cache = Some(std::sync::Arc::new(table));
        other.method = Method::new(path);
        assert_ne!(fingerprint(&other), fingerprint(&back));
        let plain = FrameParams::new(
            3,
            3,
            1,
            Camera::look_at(glam::Vec3::Z, glam::Vec3::ZERO, 1.0),
        );
        assert_eq!(round_trip(&plain, Span::new(0, 9)), plain);
        // Every bit of a float, an infinity too (the encoding is CBOR, not JSON).
        let mut far = plain.clone();
        far.options.ao_distance = f32::INFINITY;
        far.path_loop.rr_survival = f32::from_bits(0x3f00_0001);
        assert_eq!(round_trip(&far, Span::new(0, 9)), far);
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

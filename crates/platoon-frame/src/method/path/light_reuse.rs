//! Reuse of resampled direct light between pixels and frames (issue 43; ReSTIR DI, Bitterli et
//! al. 2020): each pixel's first vertex keeps a reservoir (one light sample, its unbiased
//! contribution weight W and the candidates M it stands for), and the next frame combines its
//! fresh candidates with the reservoir where the same surface was the frame before (temporal)
//! and with a few of that frame's reservoirs around it (spatial), then shades the one sample
//! kept with one shadow ray (shaders/path/light_reuse.glsl).
//!
//! Both kinds of reuse read the previous frame's reservoirs of the whole image (RTXDI's fused
//! spatiotemporal resampling), so the reuse never crosses a band border of this frame: every
//! device reads the same history and the image is the same bits for any split. The bands leave
//! their reservoirs per pixel (`Band::per_pixel`), joined in pixel order into the next frame's
//! [`ReservoirHistory`] (in the path tracer's state, `PathTracing::light_reuse`, and over the
//! wire with the frame).
//!
//! A sample is (light, u): the light's index and the two numbers that placed it on the light,
//! the same sample from any shading point; its target at a pixel is the unshadowed luminance of
//! f cos Le in that measure. Unbiased by default: each source's resampling weight carries a
//! balance-heuristic MIS weight over stand-in targets (a Lambertian surface at each source's
//! stored point and normals; generalised RIS, Lin et al. 2022), which sum to one wherever a
//! source could have drawn the sample; the biased setting weighs by the candidates M alone
//! (Bitterli's 1/M: darker where a neighbour cannot see a light the pixel sees; an explicit
//! option, named in the view's title and the benches' output).

use std::sync::Arc;

use crate::frame::PixelRecord;
use crate::scene::camera::Camera;

/// The reuse's settings.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct LightReuse {
    /// The balance heuristic over the sources' stand-in targets (unbiased); false: weights by
    /// the candidates M alone (1/M, biased; no stand-ins evaluated, but in the many-light hall
    /// its fireflies made it no better at equal time: docs/REALTIME.md).
    pub unbiased: bool,
    /// Reservoirs of the previous frame taken from around the pixel's reprojection.
    pub neighbours: u32,
    /// ... within this many pixels.
    pub radius: f32,
    /// A reservoir stands for at most this many times the pixel's fresh candidates (temporal
    /// reuse's cap: a history that long forgets what moved at that pace).
    pub history: u32,
}

impl Default for LightReuse {
    fn default() -> Self {
        LightReuse {
            unbiased: true,
            neighbours: 3,
            // RTXDI's 32 at 1080p; at a game's 160 x 90 on lavapipe 4 and 30 pixels measured
            // the same error (tests/drive/light_reuse.rs).
            radius: 30.0,
            history: 20,
        }
    }
}

impl LightReuse {
    pub fn validate(&self) -> Result<(), String> {
        if self.history == 0 {
            return Err("light reuse needs a history of at least 1".into());
        }
        if self.neighbours > 16 {
            return Err(format!(
                "light reuse takes at most 16 neighbours, not {}",
                self.neighbours
            ));
        }
        if !(self.radius.is_finite() && self.radius >= 1.0 && self.radius <= 256.0) {
            return Err(format!(
                "light reuse's radius is 1 to 256 pixels, not {}",
                self.radius
            ));
        }
        Ok(())
    }

    /// Its mode's name, which `from_str` reads back (`unbiased`, `biased`).
    pub fn mode(&self) -> &'static str {
        if self.unbiased {
            "unbiased"
        } else {
            "biased"
        }
    }

    /// The kernel option's label (the view's title and `bench game` name the biased one).
    pub fn label(&self) -> &'static str {
        if self.unbiased {
            "light-reuse"
        } else {
            "light-reuse-biased"
        }
    }
}

impl std::str::FromStr for LightReuse {
    type Err = String;

    /// A mode's name: `unbiased` (the default settings) or `biased` (1/M over all sources).
    fn from_str(s: &str) -> Result<LightReuse, String> {
        match s {
            "unbiased" => Ok(LightReuse::default()),
            "biased" => Ok(LightReuse {
                unbiased: false,
                ..LightReuse::default()
            }),
            _ => Err(format!("light reuse is unbiased or biased, not {s:?}")),
        }
    }
}

/// Whether light reuse can run: it resamples the path tracer's resampled light (one rule for the
/// frame driver and the tracer).
pub fn check_context(resampled_light: bool, path_tracing: bool) -> Result<(), String> {
    if resampled_light && path_tracing {
        Ok(())
    } else {
        Err(
            "light reuse resamples the path tracer's direct light: it needs resampled light \
             (by contribution) and the path tracer"
                .into(),
        )
    }
}

/// A pixel's reservoir as light_reuse.glsl leaves it (`reuse_write`, three vec4s): the
/// surface point and the light, the sample's numbers with W and M, the surface's normals.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ReservoirRecord {
    pub position: [f32; 3],
    /// (light + 1) x 2 + whether the surface transmits: below 2, no sample kept.
    pub light: f32,
    /// The two numbers that placed the sample on its light.
    pub u: [f32; 2],
    /// The unbiased contribution weight.
    pub w: f32,
    /// The candidates the sample stands for.
    pub m: f32,
    /// The geometric and shading normals, octahedral.
    pub normals: [f32; 4],
}

impl PixelRecord for ReservoirRecord {
    const KIND: &'static str = "path.reservoir";
}

// Three vec4s (light_reuse.glsl's REUSE_RECORD), as the kernels write and read them.
const _: () = assert!(std::mem::size_of::<ReservoirRecord>() == 48);

/// What a frame's kernels read: the settings and the previous frame's reservoirs.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ReservoirHistory {
    pub options: LightReuse,
    /// The previous frame's camera and size (its reservoirs are found by reprojection); empty
    /// records: no history (the first frame, or after the lights changed).
    pub camera: Camera,
    pub width: u32,
    pub height: u32,
    /// One a pixel, in pixel order.
    #[serde(with = "crate::frame::pod_bytes")]
    pub records: Vec<ReservoirRecord>,
}

impl ReservoirHistory {
    /// No history yet: the frame's reservoirs are its fresh candidates'.
    pub fn empty(options: LightReuse) -> ReservoirHistory {
        ReservoirHistory {
            options,
            // (Unread: nothing to reproject into.)
            camera: Camera {
                camera_to_world: glam::Mat4::IDENTITY,
                yfov: 1.0,
                aperture_radius: 0.0,
                focus_distance: 1.0,
                orthographic: None,
            },
            width: 0,
            height: 0,
            records: Vec::new(),
        }
    }

    /// Whether it holds a frame's reservoirs.
    pub fn has_frame(&self) -> bool {
        self.width > 0 && self.records.len() == self.pixels()
    }

    fn pixels(&self) -> usize {
        self.width as usize * self.height as usize
    }
}

/// The reuse across a stream of frames: the history the next frame reads.
#[derive(Clone, Debug)]
pub struct LightReuseState {
    history: Arc<ReservoirHistory>,
    /// The light count the history's samples index (a scene whose lights changed starts over;
    /// None: not known yet).
    lights: Option<usize>,
}

impl LightReuseState {
    pub fn new(options: LightReuse) -> LightReuseState {
        LightReuseState {
            history: Arc::new(ReservoirHistory::empty(options)),
            lights: None,
        }
    }

    /// The history for a frame whose scene has `lights` lights (None: as the last frame's):
    /// none when their number changed (a sample names its light by index).
    pub fn history(&mut self, lights: Option<usize>) -> Arc<ReservoirHistory> {
        if let Some(n) = lights {
            if self.lights.is_some_and(|m| m != n) && self.history.has_frame() {
                self.history = Arc::new(ReservoirHistory::empty(self.history.options));
            }
            self.lights = Some(n);
        }
        Arc::clone(&self.history)
    }

    /// Keeps the reservoirs a frame of `camera`, `width` x `height`, left (in pixel order) for
    /// the next; records of another length (a frame that rendered no beauty) leave no history.
    pub fn keep(
        &mut self,
        records: Vec<ReservoirRecord>,
        camera: Camera,
        width: u32,
        height: u32,
    ) -> ReuseStats {
        let mut h = ReservoirHistory {
            options: self.history.options,
            camera,
            width,
            height,
            records,
        };
        if !h.has_frame() {
            h = ReservoirHistory::empty(h.options);
        }
        let stats = ReuseStats::of(&h.records);
        self.history = Arc::new(h);
        stats
    }
}

/// What a frame's reservoirs hold.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ReuseStats {
    /// Pixels whose reservoir kept a light sample.
    pub samples: u32,
    /// The mean candidates a kept sample stands for (M, capped by the history).
    pub mean_candidates: f32,
}

impl ReuseStats {
    fn of(records: &[ReservoirRecord]) -> ReuseStats {
        let (mut samples, mut m) = (0u32, 0.0f64);
        for r in records {
            if r.light >= 2.0 {
                samples += 1;
                m += r.m as f64;
            }
        }
        ReuseStats {
            samples,
            mean_candidates: if samples > 0 {
                (m / samples as f64) as f32
            } else {
                0.0
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_history_starts_over_when_the_lights_change_or_a_frame_left_none() {
        let camera = Camera {
            camera_to_world: glam::Mat4::IDENTITY,
            yfov: 1.0,
            aperture_radius: 0.0,
            focus_distance: 1.0,
            orthographic: None,
        };
        let mut s = LightReuseState::new(LightReuse::default());
        assert!(!s.history(Some(3)).has_frame());
        s.keep(vec![ReservoirRecord::default(); 2 * 3], camera, 2, 3);
        assert!(s.history(None).has_frame());
        assert!(s.history(Some(3)).has_frame(), "the same lights");
        assert!(!s.history(Some(4)).has_frame(), "the lights changed");
        s.keep(vec![ReservoirRecord::default(); 5], camera, 2, 3);
        assert!(!s.history(None).has_frame(), "a frame without reservoirs");
    }

    #[test]
    fn bad_settings_are_refused() {
        let ok = LightReuse::default();
        assert!(ok.validate().is_ok());
        for bad in [
            LightReuse { history: 0, ..ok },
            LightReuse {
                neighbours: 17,
                ..ok
            },
            LightReuse { radius: 0.5, ..ok },
            LightReuse {
                radius: f32::NAN,
                ..ok
            },
        ] {
            assert!(bad.validate().is_err(), "{bad:?}");
        }
    }
}

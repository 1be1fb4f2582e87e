//! What the path tracer learns over a game loop's frames and gives each next one: the world
//! cache's table and light reuse's reservoirs, each when its state's learning settings ask
//! (`LearningOptions`; `platoon view --world-cache --light-reuse`). Its learner
//! (`PathLearning`, the `FrameLearning` a frame driver holds) gives the frame its state before
//! it renders and learns from the records its bands left, joined in pixel order, so the cache
//! and the reservoirs are the same whatever the split between devices.

use super::light_reuse::{LightReuseState, ReservoirRecord, ReuseStats};
use super::state::{LearningOptions, PathTracing};
use super::world_cache::{CacheUpdate, TrainingRecord, WorldCache};
use crate::frame::{FrameParams, MethodReport, PixelData, ReportValue};
use crate::method::learning::FrameLearning;
use crate::method::Method;

pub struct PathLearning {
    cache: Option<WorldCache>,
    reuse: Option<LightReuseState>,
}

/// What a frame taught (the path tracer's report of a driver's frame).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Learned {
    pub world_cache: Option<CacheUpdate>,
    pub light_reuse: Option<ReuseStats>,
}

impl ReportValue for Learned {
    const KIND: &'static str = "path.learned";
}

/// What is wrong with what `path` learns over frames: the setting it is about
/// (`world_cache`, `light_reuse`) and the problem. One rule for a request (`Request::validate`),
/// the settings and the frame driver.
pub fn check(path: &PathTracing) -> Result<(), (&'static str, String)> {
    let LearningOptions {
        world_cache,
        light_reuse,
    } = &path.learning;
    if let Some(c) = world_cache {
        c.validate().map_err(|e| ("world_cache", e))?;
    }
    if let Some(o) = light_reuse {
        o.validate().map_err(|e| ("light_reuse", e))?;
        if path.resampled_light.is_none() {
            return Err((
                "light_reuse",
                "reuses resampled light's reservoirs: set resampled_light (8 candidates are a \
                 game's choice)"
                    .into(),
            ));
        }
    }
    Ok(())
}

impl PathLearning {
    /// Learning what `path` asks over frames in a scene whose bounding sphere has radius
    /// `scene_radius`; an error says why not (light reuse without resampled light, bad
    /// settings).
    pub fn new(path: &PathTracing, scene_radius: f32) -> Result<PathLearning, String> {
        check(path).map_err(|(option, problem)| format!("{option}: {problem}"))?;
        let LearningOptions {
            world_cache,
            light_reuse,
        } = path.learning;
        Ok(PathLearning {
            cache: world_cache
                .map(|o| WorldCache::new(o, scene_radius))
                .transpose()?,
            reuse: light_reuse.map(LightReuseState::new),
        })
    }
}

impl FrameLearning for PathLearning {
    fn give(&mut self, method: &mut Method, lights: Option<usize>) {
        let Some(path) = method.path_mut() else {
            return;
        };
        path.world_cache = self.cache.as_ref().map(|c| c.table());
        if let Some(reuse) = &mut self.reuse {
            path.light_reuse = Some(reuse.history(lights));
        }
    }

    fn learn(
        &mut self,
        pixels: &PixelData,
        params: &FrameParams,
        frame: u32,
    ) -> Result<MethodReport, String> {
        let records = pixels.records::<TrainingRecord>()?;
        let reservoirs = pixels.records::<ReservoirRecord>()?;
        Ok(MethodReport::of(&Learned {
            world_cache: self.cache.as_mut().map(|c| c.update(records, frame)),
            light_reuse: self.reuse.as_mut().map(|r| {
                r.keep(
                    reservoirs.to_vec(),
                    params.camera,
                    params.width,
                    params.height,
                )
            }),
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::method::path::light_reuse::LightReuse;
    use crate::method::path::world_cache::WorldCacheOptions;
    use crate::method::path::{PathTracing, ResampledLight};
    use crate::scene::camera::Camera;

    fn resampled(learning: LearningOptions) -> PathTracing {
        PathTracing {
            resampled_light: Some(ResampledLight::new(8)),
            learning,
            ..Default::default()
        }
    }

    #[test]
    fn reuse_without_resampled_light_and_bad_settings_are_refused() {
        let reuse = LearningOptions {
            light_reuse: Some(LightReuse::default()),
            ..Default::default()
        };
        let plain = PathTracing {
            learning: reuse,
            ..Default::default()
        };
        assert_eq!(check(&plain).unwrap_err().0, "light_reuse");
        assert!(Method::new(plain).unit().learning(1.0).is_err());
        let coarse = LearningOptions {
            world_cache: Some(WorldCacheOptions {
                resolution: 0,
                ..Default::default()
            }),
            ..Default::default()
        };
        assert_eq!(check(&resampled(coarse)).unwrap_err().0, "world_cache");
        let both = LearningOptions {
            world_cache: Some(WorldCacheOptions::default()),
            light_reuse: Some(LightReuse::default()),
        };
        assert!(check(&resampled(both)).is_ok());
        // Nothing asked: the method learns nothing. (A frame of another method is given
        // nothing: platoon-core's `method/tests.rs`, where the other methods are.)
        assert!(Method::path_tracing()
            .unit()
            .learning(1.0)
            .unwrap()
            .is_none());
    }

    #[test]
    fn a_frames_records_reach_the_next_frame() {
        let options = WorldCacheOptions {
            slots_log2: 4,
            min_samples: 1,
            ..Default::default()
        };
        let path = resampled(LearningOptions {
            world_cache: Some(options),
            light_reuse: Some(LightReuse::default()),
        });
        let mut learning = PathLearning::new(&path, 1.0).unwrap();
        let mut params = FrameParams::new(
            2,
            1,
            1,
            Camera::look_at(glam::Vec3::Z, glam::Vec3::ZERO, 1.0),
        );
        params.method = Method::new(path);
        learning.give(&mut params.method, Some(3));
        assert!(params
            .method
            .path()
            .world_cache
            .as_ref()
            .unwrap()
            .slots
            .iter()
            .all(|s| s[0] == 0.0));
        assert!(!has_history(&params.method));
        let key = 0x0080_0007; // slot 3
        let trained = TrainingRecord {
            key,
            radiance: [1.0, 2.0, 3.0],
        };
        let pixels = PixelData::of(&[trained, TrainingRecord::default()])
            .with(&[ReservoirRecord::default(); 2]);
        let learned = (learning.learn(&pixels, &params, 0).unwrap())
            .value::<Learned>()
            .unwrap();
        assert_eq!(learned.world_cache.unwrap().records, 1);
        assert_eq!(learned.light_reuse, Some(ReuseStats::default()));
        learning.give(&mut params.method, None);
        let path = params.method.path();
        assert_eq!(
            path.world_cache.as_ref().unwrap().slots[3],
            [f32::from_bits(key), 1.0, 2.0, 3.0]
        );
        assert!(has_history(&params.method));
        // Other lights: the reservoirs name lights by index, so the history starts over.
        learning.give(&mut params.method, Some(4));
        assert!(!has_history(&params.method));
    }

    /// Whether `method` carries a frame's reservoirs.
    fn has_history(method: &Method) -> bool {
        method.path().light_reuse.as_ref().unwrap().has_frame()
    }
}

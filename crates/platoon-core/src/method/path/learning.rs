//! What the path tracer learns over a game loop's frames and gives each next one: the world
//! cache's table and light reuse's reservoirs, each when asked for. A frame driver holds one,
//! gives the frame its state before it renders (`give`) and learns from the records its bands
//! left, joined in pixel order (`learn`), so the cache and the reservoirs are the same whatever
//! the split between devices.

use crate::frame::light_reuse::{LightReuse, LightReuseState, ReservoirRecord, ReuseStats};
use crate::frame::world_cache::{CacheUpdate, TrainingRecord, WorldCache, WorldCacheOptions};
use crate::frame::{FrameParams, PixelData};
use crate::method::Method;

pub struct PathLearning {
    cache: Option<WorldCache>,
    reuse: Option<LightReuseState>,
}

/// What a frame taught.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Learned {
    pub world_cache: Option<CacheUpdate>,
    pub light_reuse: Option<ReuseStats>,
}

/// What is wrong with learning a world cache (`cache`) and reusing light (`reuse`) over the
/// frames of `method`: the option it is about (`world_cache`, `light_reuse`) and the problem.
/// One rule for a request (`Request::validate`) and the frame driver.
pub fn check(
    method: &Method,
    cache: Option<&WorldCacheOptions>,
    reuse: Option<&LightReuse>,
) -> Result<(), (&'static str, String)> {
    if let Some(c) = cache {
        c.validate().map_err(|e| ("world_cache", e))?;
        if !method.is_path_tracing() {
            return Err((
                "world_cache",
                format!(
                    "caches the path tracer's bounces; {} gathers its light its own way",
                    method.unit().name()
                ),
            ));
        }
    }
    if let Some(o) = reuse {
        o.validate().map_err(|e| ("light_reuse", e))?;
        if method.path().resampled_light.is_none() {
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
    /// Learning a world cache (`cache`) and reusing light (`reuse`) over the frames of
    /// `method` in a scene whose bounding sphere has radius `scene_radius`; an error says why
    /// not (another method, light reuse without resampled light, bad settings).
    pub fn new(
        method: &Method,
        cache: Option<WorldCacheOptions>,
        reuse: Option<LightReuse>,
        scene_radius: f32,
    ) -> Result<PathLearning, String> {
        check(method, cache.as_ref(), reuse.as_ref())
            .map_err(|(option, problem)| format!("{option}: {problem}"))?;
        Ok(PathLearning {
            cache: cache
                .map(|o| WorldCache::new(o, scene_radius))
                .transpose()?,
            reuse: reuse.map(LightReuseState::new),
        })
    }

    /// `method` (a frame's) with what the frames so far learned; `lights` is the scene's light
    /// count where a commit changed the scene (reservoirs of other lights are dropped).
    pub fn give(&mut self, method: &mut Method, lights: Option<usize>) {
        let Some(path) = method.path_mut() else {
            return;
        };
        path.world_cache = self.cache.as_ref().map(|c| c.table());
        if let Some(reuse) = &mut self.reuse {
            path.light_reuse = Some(reuse.history(lights));
        }
    }

    /// Learns from the frame `params`' records (`pixels`, its bands' joined in pixel order);
    /// `frame` is its number in the cache's staleness.
    pub fn learn(
        &mut self,
        pixels: &PixelData,
        params: &FrameParams,
        frame: u32,
    ) -> Result<Learned, String> {
        let records = pixels.records::<TrainingRecord>()?;
        let reservoirs = pixels.records::<ReservoirRecord>()?;
        Ok(Learned {
            world_cache: self.cache.as_mut().map(|c| c.update(records, frame)),
            light_reuse: self.reuse.as_mut().map(|r| {
                r.keep(
                    reservoirs.to_vec(),
                    params.camera,
                    params.width,
                    params.height,
                )
            }),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::method::igi::IgiOptions;
    use crate::method::path::{PathTracing, ResampledLight};
    use crate::scene::camera::Camera;

    fn resampled() -> Method {
        Method::new(PathTracing {
            resampled_light: Some(ResampledLight::new(8)),
            ..Default::default()
        })
    }

    #[test]
    fn another_method_or_reuse_without_resampled_light_is_refused() {
        let cache = Some(WorldCacheOptions::default());
        let igi = Method::new(IgiOptions::default());
        assert!(PathLearning::new(&igi, cache, None, 1.0).is_err());
        let reuse = Some(LightReuse::default());
        assert!(PathLearning::new(&Method::path_tracing(), None, reuse, 1.0).is_err());
        assert!(PathLearning::new(&resampled(), cache, reuse, 1.0).is_ok());
        // Nothing asked: nothing given, for any method.
        let mut none = PathLearning::new(&igi, None, None, 1.0).unwrap();
        let mut m = igi.clone();
        none.give(&mut m, None);
        assert_eq!(m, igi);
    }

    #[test]
    fn a_frames_records_reach_the_next_frame() {
        let options = WorldCacheOptions {
            slots_log2: 4,
            min_samples: 1,
            ..Default::default()
        };
        let reuse = Some(LightReuse::default());
        let mut learning = PathLearning::new(&resampled(), Some(options), reuse, 1.0).unwrap();
        let mut params = FrameParams::new(
            2,
            1,
            1,
            Camera::look_at(glam::Vec3::Z, glam::Vec3::ZERO, 1.0),
        );
        params.method = resampled();
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
        let learned = learning.learn(&pixels, &params, 0).unwrap();
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

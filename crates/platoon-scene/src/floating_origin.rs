//! The floating origin of render space. f32 world coordinates cannot hold a small room far from
//! the world origin (at 1e7 their spacing is a whole unit), so the scene is flattened relative
//! to a point near the camera ([`crate::Scene::pose_around`] composes in f64 and rounds
//! after subtracting it). As in games, the origin moves only when the camera drifts far from
//! it, so a moving camera does not force the whole scene to be re-flattened every frame.

use glam::DVec3;

/// Drift after which the origin follows the camera: within it, f32 coordinates near the camera
/// keep a spacing below 1.3e-4 units.
pub const DEFAULT_RECENTER_DISTANCE: f64 = 1024.0;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FloatingOrigin {
    /// The world point at render space's origin.
    pub origin: DVec3,
    /// How far the camera may be from `origin` before the origin moves onto it.
    pub recenter_distance: f64,
}

impl Default for FloatingOrigin {
    fn default() -> Self {
        FloatingOrigin {
            origin: DVec3::ZERO,
            recenter_distance: DEFAULT_RECENTER_DISTANCE,
        }
    }
}

impl FloatingOrigin {
    /// Moves the origin onto `camera` (world space) when the camera is farther than
    /// `recenter_distance` from it. True when it moved: everything flattened relative to the
    /// old origin must then be flattened again.
    pub fn follow(&mut self, camera: DVec3) -> bool {
        if !camera.is_finite() || camera.distance(self.origin) <= self.recenter_distance {
            return false;
        }
        self.origin = camera;
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn moves_only_when_the_camera_drifts_far() {
        let mut o = FloatingOrigin::default();
        assert!(!o.follow(DVec3::new(1000.0, 0.0, 0.0)));
        assert_eq!(o.origin, DVec3::ZERO);
        assert!(o.follow(DVec3::new(1e7, 2.0, 0.0)));
        assert_eq!(o.origin, DVec3::new(1e7, 2.0, 0.0));
        assert!(!o.follow(DVec3::new(1e7 + 500.0, 2.0, 0.0)));
        assert!(!o.follow(DVec3::NAN));
    }
}

//! Where a game puts a node: translation (f64, like node translations), rotation and scale,
//! checked so that an invalid one is refused at the call, with the reason, and never reaches a
//! frame.

use glam::{DVec3, Quat, Vec3};

use crate::error::{Error, Result};
use crate::Node;

/// A node's placement relative to its parent, as a game sets it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    pub translation: DVec3,
    pub rotation: Quat,
    pub scale: Vec3,
}

impl Placement {
    pub fn at(translation: DVec3) -> Placement {
        Placement {
            translation,
            rotation: Quat::IDENTITY,
            scale: Vec3::ONE,
        }
    }

    /// Puts `node` here (relative to its parent).
    pub fn place(&self, node: &mut Node) {
        node.translation = self.translation;
        node.rotation = self.rotation;
        node.scale = self.scale;
    }

    /// The placement with its rotation normalised; an error for a non-finite value, a rotation
    /// that is not one (length far from 1) or a scale that flattens the node (singular).
    pub fn checked(self) -> Result<Placement> {
        if !self.translation.is_finite() {
            return Err(invalid(format!(
                "non-finite translation {}",
                self.translation
            )));
        }
        let len = self.rotation.length();
        if !self.rotation.is_finite() || (len - 1.0).abs() > 1e-3 {
            return Err(invalid(format!(
                "rotation {} is not a unit quaternion",
                self.rotation
            )));
        }
        if !self.scale.is_finite() || self.scale.abs().min_element() < 1e-12 {
            return Err(invalid(format!(
                "scale {} is not finite or makes the transform singular",
                self.scale
            )));
        }
        Ok(Placement {
            rotation: self.rotation / len,
            ..self
        })
    }
}

/// The error of a refused scene edit.
pub fn invalid(message: String) -> Error {
    Error::Invalid(format!("scene edit refused: {message}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_placements_are_refused_with_the_reason() {
        assert!(Placement::at(DVec3::new(1.0, 2.0, 3.0)).checked().is_ok());
        let nan = Placement::at(DVec3::new(f64::NAN, 0.0, 0.0)).checked();
        assert!(nan
            .unwrap_err()
            .to_string()
            .contains("non-finite translation"));
        let flat = Placement {
            scale: Vec3::new(1.0, 0.0, 1.0),
            ..Placement::at(DVec3::ZERO)
        };
        assert!(flat.checked().unwrap_err().to_string().contains("singular"));
        let bent = Placement {
            rotation: Quat::from_xyzw(0.0, 0.0, 0.0, 2.0),
            ..Placement::at(DVec3::ZERO)
        };
        assert!(bent.checked().is_err());
    }
}

//! The scene a technique renders when it is not the sweep's own: without one of its effects
//! (`effects`), or with every mesh subdivided (vertex links' tessellation: the same surfaces,
//! so the same reference). Seen by the same camera.

use anyhow::{Context as _, Result};
use platoon::Prepared;

use super::effects::Effect;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Variant {
    Without(Effect),
    /// Every mesh that can be subdivided 1:4 this many times (`Scene::subdivide`).
    Subdivided(u32),
}

impl Variant {
    fn name(self) -> String {
        match self {
            Variant::Without(e) => format!("without {}", e.name()),
            Variant::Subdivided(k) => format!("subdivided {k} times"),
        }
    }
}

/// `prepared` as `variant` has it; None when the variant changes nothing (the scene has no
/// such effect, or no mesh to subdivide).
pub fn prepare(prepared: &Prepared, variant: Variant) -> Result<Option<Prepared>> {
    let mut scene = prepared.scene.clone();
    let changed = match variant {
        Variant::Without(effect) => effect.remove(&mut scene),
        Variant::Subdivided(levels) => scene.subdivide(levels) > 0,
    };
    if !changed {
        return Ok(None);
    }
    let mut p = platoon::prepare(
        scene,
        &platoon::PrepareOptions {
            time: prepared.time,
            ..Default::default()
        },
    )
    .with_context(|| format!("preparing the scene {}", variant.name()))?;
    p.camera = prepared.camera;
    Ok(Some(p))
}

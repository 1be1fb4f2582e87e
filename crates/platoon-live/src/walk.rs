//! A character walking in a room: the living scene that vertex links' and layered hit buffers'
//! tests and benches drive, one generation a step.

use glam::{DVec3, Vec3};

use crate::Edit;
use platoon_core::scene::{cornell, Placement, Scene};
use platoon_core::Result;

/// The Cornell box with every face `cells` x `cells` quads and `character` (CesiumMan: its
/// skin walks) appended at [`walk_step`] 0; returns the scene and the node that places the character.
pub fn walk_in_a_room(character: &Scene, cells: u32) -> Result<(Scene, usize)> {
    let mut scene = cornell::tessellated(cells);
    let node = scene.append(character, walk_step(0.0))?;
    Ok((scene, node))
}

/// The edits that take the walk's character `node` to whole step `step`: its animation at
/// 0.3 s a step and its placement ([`walk_step`]); one generation a step.
pub fn walk_edits(node: usize, step: usize) -> [Edit; 2] {
    [
        Edit::Time(0.3 * step as f32),
        Edit::Placement {
            node,
            placement: walk_step(step as f64),
        },
    ]
}

/// Where step `k` of the walk (a fraction between steps too) puts the character: 0.4 m further
/// along the floor each step, between the Cornell box's blocks, one and a half times its size.
pub fn walk_step(k: f64) -> Placement {
    Placement {
        scale: Vec3::splat(1.5),
        ..Placement::at(DVec3::new(1.6 + 0.4 * k, 0.0, 2.8))
    }
}

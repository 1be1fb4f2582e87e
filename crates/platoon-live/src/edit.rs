//! An edit of a living scene: one value the game makes, checked once against the values' own
//! rules and against the scene's structure (`Structure`), applied by [`super::Updater::apply`] or
//! queued by [`super::Pipeline::push`] for the updater's thread.

use std::collections::HashSet;

use glam::DVec3;

use platoon_core::error::Result;
use platoon_core::scene::environment::Environment;
use platoon_core::scene::placement::invalid;
use platoon_core::scene::{LightKind, Material, Placement, PunctualLight, Scene};

/// One change to the scene, taking effect at the next generation.
#[derive(Clone, Debug)]
pub enum Edit {
    /// Animation time (glTF animations and the skins they drive): finite.
    Time(f32),
    /// Moves, rotates and scales `node` relative to its parent. An animated node follows its
    /// animation again at the next update.
    Placement { node: usize, placement: Placement },
    /// A new instance of scene mesh `mesh` at `placement` (world space): applying it returns
    /// its node.
    AddInstance { mesh: usize, placement: Placement },
    /// Removes the instance a node places (the node stays, without its mesh: node indices used
    /// by parents, skins and animations keep their meaning).
    RemoveInstance(usize),
    /// Replaces material `index`; its factors must be finite.
    Material(usize, Box<Material>),
    /// Replaces punctual light `index` (its node places it): finite, non-negative colour and
    /// intensity, a non-negative range, cones within (0, pi/2] with the inner one inside.
    Light(usize, Box<PunctualLight>),
    /// Replaces the distant light (None: black). A map is re-sampled into its CDFs.
    Environment(Box<Option<Environment>>),
    /// Where the camera is (world space): once it has drifted more than the floating origin's
    /// `recenter_distance` (1024 units) from the render origin, the origin moves onto it and
    /// the next generation is posed around it, so a world far larger than f32 can place stays
    /// precise where the camera looks.
    FollowCamera(DVec3),
}

impl Edit {
    /// The edit if its values are ones a scene may take (a placement made exact), else why not.
    pub(crate) fn checked(self) -> Result<Edit> {
        Ok(match self {
            Edit::Time(t) => {
                check_time(t)?;
                self
            }
            Edit::Placement { node, placement } => Edit::Placement {
                node,
                placement: placement.checked()?,
            },
            Edit::AddInstance { mesh, placement } => Edit::AddInstance {
                mesh,
                placement: placement.checked()?,
            },
            Edit::RemoveInstance(_) => self,
            Edit::Material(i, ref m) => {
                check_material(i, m)?;
                self
            }
            Edit::Light(i, ref l) => {
                check_light(i, l)?;
                self
            }
            Edit::Environment(ref e) => {
                check_environment(e.as_ref().as_ref())?;
                self
            }
            Edit::FollowCamera(c) => {
                check_camera(c)?;
                self
            }
        })
    }
}

/// The scene's structure as edits change it: what an edit is checked against, by the updater
/// and by the game thread's pipeline alike (which has no scene of its own).
#[derive(Clone, Debug)]
pub(crate) struct Structure {
    nodes: usize,
    meshes: usize,
    materials: usize,
    lights: usize,
    removed: HashSet<usize>,
    instanced: HashSet<usize>,
}

impl Structure {
    pub fn of(scene: &Scene) -> Structure {
        Structure {
            nodes: scene.nodes.len(),
            meshes: scene.meshes.len(),
            materials: scene.materials.len(),
            lights: scene.lights.len(),
            removed: HashSet::new(),
            instanced: (0..scene.nodes.len())
                .filter(|&i| scene.nodes[i].mesh.is_some())
                .collect(),
        }
    }

    /// Checks that `edit` names what exists and records what it changes; returns the node an
    /// added instance gets.
    pub fn admit(&mut self, edit: &Edit) -> Result<Option<usize>> {
        let within = |what: &str, index: usize, count: usize| {
            if index < count {
                Ok(())
            } else {
                Err(invalid(format!(
                    "no {what} {index} (the scene has {count})"
                )))
            }
        };
        match *edit {
            Edit::Placement { node, .. } => self.live(node)?,
            Edit::AddInstance { mesh, .. } => {
                within("mesh", mesh, self.meshes)?;
                let node = self.nodes;
                self.nodes += 1;
                self.instanced.insert(node);
                return Ok(Some(node));
            }
            Edit::RemoveInstance(node) => {
                self.live(node)?;
                if !self.instanced.remove(&node) {
                    return Err(invalid(format!("node {node} places no instance")));
                }
                self.removed.insert(node);
            }
            Edit::Material(i, _) => within("material", i, self.materials)?,
            Edit::Light(i, _) => within("light", i, self.lights)?,
            Edit::Time(_) | Edit::Environment(_) | Edit::FollowCamera(_) => {}
        }
        Ok(None)
    }

    fn live(&self, node: usize) -> Result<()> {
        if self.removed.contains(&node) {
            return Err(invalid(format!(
                "node {node}'s instance was already removed"
            )));
        }
        if node >= self.nodes {
            return Err(invalid(format!(
                "no node {node} (the scene has {})",
                self.nodes
            )));
        }
        Ok(())
    }
}

/// An animation time a game may set: finite.
fn check_time(time: f32) -> Result<()> {
    if !time.is_finite() {
        return Err(invalid(format!("animation time {time} is not finite")));
    }
    Ok(())
}

/// A camera position the render origin may follow: finite.
fn check_camera(camera: DVec3) -> Result<()> {
    if !camera.is_finite() {
        return Err(invalid(format!("camera position {camera} is not finite")));
    }
    Ok(())
}

/// An environment a game may set: a constant one finite and non-negative (a map was checked
/// when it was read).
fn check_environment(environment: Option<&Environment>) -> Result<()> {
    if let Some(Environment::Constant(c)) = environment {
        if !c.is_finite() || c.min_element() < 0.0 {
            return Err(invalid(format!(
                "environment colour {c} is not finite and non-negative"
            )));
        }
    }
    Ok(())
}

/// A light a game may set.
fn check_light(index: usize, l: &PunctualLight) -> Result<()> {
    let cones_ok = match l.kind {
        LightKind::Spot {
            inner_cone,
            outer_cone,
        } => {
            inner_cone >= 0.0
                && inner_cone <= outer_cone
                && outer_cone > 0.0
                && outer_cone <= std::f32::consts::FRAC_PI_2
        }
        _ => true,
    };
    let ok = l.color.is_finite()
        && l.color.min_element() >= 0.0
        && l.intensity.is_finite()
        && l.intensity >= 0.0
        && l.range.is_finite()
        && l.range >= 0.0
        && cones_ok;
    if !ok {
        return Err(invalid(format!(
            "light {index}: colour, intensity and range must be finite and non-negative, spot cones within (0, 90] degrees"
        )));
    }
    Ok(())
}

/// A material a game may set: every factor finite.
fn check_material(index: usize, m: &Material) -> Result<()> {
    let finite = [
        m.base_color.is_finite(),
        m.emissive.is_finite(),
        m.metallic.is_finite(),
        m.roughness.is_finite(),
        m.transmission.is_finite(),
        m.ior.is_finite(),
        m.specular.is_finite(),
        m.specular_color.is_finite(),
        m.normal_scale.is_finite(),
    ];
    if finite.contains(&false) {
        return Err(invalid(format!("material {index} has a non-finite factor")));
    }
    Ok(())
}

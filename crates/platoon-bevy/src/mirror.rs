//! The Bevy world as a platoon scene: built whole when its structure changes (a mesh, material,
//! skin or light platoon has not seen), and otherwise followed by edits of what changed
//! (placements, instances added and removed, materials and lights changed), the only thing
//! sent to the render thread on a frame where the game moved something.

use std::collections::{HashMap, HashSet};
use std::sync::Arc;

use bevy::asset::{Asset, AssetEvent, AssetId, Assets};
use bevy::camera::visibility::InheritedVisibility;
use bevy::ecs::system::SystemParam;
use bevy::image::Image;
use bevy::light::{DirectionalLight, PointLight, SpotLight};
use bevy::mesh::skinning::{SkinnedMesh, SkinnedMeshInverseBindposes};
use bevy::mesh::{Mesh, Mesh3d};
use bevy::pbr::{MeshMaterial3d, StandardMaterial};
use bevy::prelude::{Entity, GlobalTransform, MessageReader, Name, Query, Res};
use glam::Mat4;
use platoon::core::scene::environment::Environment;
use platoon::core::scene::{Node, Placement, PunctualLight, Scene, Skin};
use platoon::drive::Edit;

use crate::convert;
use crate::warnings::Warnings;

/// A mesh entity's components the mirror reads.
type ObjectItem = (
    Entity,
    &'static Mesh3d,
    &'static MeshMaterial3d<StandardMaterial>,
    &'static GlobalTransform,
    Option<&'static InheritedVisibility>,
    Option<&'static SkinnedMesh>,
    Option<&'static Name>,
);

/// What the mirror reads of the world.
#[derive(SystemParam)]
pub struct WorldView<'w, 's> {
    objects: Query<'w, 's, ObjectItem>,
    points: Query<
        'w,
        's,
        (
            Entity,
            &'static PointLight,
            &'static GlobalTransform,
            Option<&'static Name>,
        ),
    >,
    spots: Query<
        'w,
        's,
        (
            Entity,
            &'static SpotLight,
            &'static GlobalTransform,
            Option<&'static Name>,
        ),
    >,
    suns: Query<
        'w,
        's,
        (
            Entity,
            &'static DirectionalLight,
            &'static GlobalTransform,
            Option<&'static Name>,
        ),
    >,
    transforms: Query<'w, 's, &'static GlobalTransform>,
    meshes: Res<'w, Assets<Mesh>>,
    materials: Res<'w, Assets<StandardMaterial>>,
    images: Res<'w, Assets<Image>>,
    bindposes: Res<'w, Assets<SkinnedMeshInverseBindposes>>,
}

/// The assets changed since the last frame: materials (edited in) and meshes (a rebuild).
#[derive(SystemParam)]
pub struct AssetChanges<'w, 's> {
    materials: MessageReader<'w, 's, AssetEvent<StandardMaterial>>,
    meshes: MessageReader<'w, 's, AssetEvent<Mesh>>,
}

impl AssetChanges<'_, '_> {
    /// The materials and meshes modified.
    pub fn take(&mut self) -> (HashSet<AssetId<StandardMaterial>>, HashSet<AssetId<Mesh>>) {
        (modified(&mut self.materials), modified(&mut self.meshes))
    }
}

/// The assets of the events not yet read that were modified.
fn modified<A: Asset>(events: &mut MessageReader<AssetEvent<A>>) -> HashSet<AssetId<A>> {
    events
        .read()
        .filter_map(|e| match e {
            AssetEvent::Modified { id } => Some(*id),
            _ => None,
        })
        .collect()
}

/// A mesh entity as the mirror sees it this frame (only those whose assets are loaded).
struct Object {
    entity: Entity,
    mesh: AssetId<Mesh>,
    material: AssetId<StandardMaterial>,
    placement: Placement,
    skin: Option<SkinKey>,
    name: String,
}

/// A skin: its inverse bind matrices and joint entities, shared by the meshes it deforms.
#[derive(Clone, PartialEq, Eq, Hash)]
struct SkinKey {
    bindposes: AssetId<SkinnedMeshInverseBindposes>,
    joints: Vec<Entity>,
}

/// A platoon mesh: a Bevy mesh drawn with one material (platoon's meshes carry a material per
/// triangle), skinned or not.
type MeshKey = (AssetId<Mesh>, AssetId<StandardMaterial>, bool);

struct Instance {
    node: usize,
    key: MeshKey,
    placement: Placement,
    skin: Option<SkinKey>,
}

struct Light {
    index: usize,
    node: usize,
    light: PunctualLight,
    placement: Placement,
}

/// The environment map light of the camera rendered: its specular cubemap, intensity and
/// rotation (None: platoon's own distant light).
pub type EnvironmentKey = Option<(AssetId<Image>, f32, bevy::math::Quat)>;

/// What changed since the last frame.
pub enum Change {
    /// A scene built anew: the structure changed (or it is the first).
    Rebuilt(Box<Scene>),
    /// Edits of the scene last built (empty: nothing changed).
    Edits(Vec<Edit>),
}

/// The platoon scene the render thread holds, by Bevy's ids.
#[derive(Default)]
pub struct Mirror {
    built: bool,
    meshes: HashMap<MeshKey, usize>,
    /// Meshes platoon cannot render (said in a warning): their entities are left out.
    unrenderable: HashSet<MeshKey>,
    materials: HashMap<AssetId<StandardMaterial>, usize>,
    textures: HashMap<AssetId<Image>, u32>,
    instances: HashMap<Entity, Instance>,
    lights: HashMap<Entity, Light>,
    joints: HashMap<Entity, (usize, Placement)>,
    /// Nodes so far (the next added instance's node: the updater numbers them the same way).
    nodes: usize,
    environment: EnvironmentKey,
    pub warnings: Warnings,
}

impl Mirror {
    /// Follows the world: a new scene when its structure changed (or a mesh it holds), else
    /// the edits since the last call. `modified` are the materials and meshes whose assets
    /// changed ([`AssetChanges::take`]).
    pub fn follow(
        &mut self,
        view: &WorldView,
        modified: &HashSet<AssetId<StandardMaterial>>,
        meshes_modified: &HashSet<AssetId<Mesh>>,
        environment: EnvironmentKey,
    ) -> Change {
        let mut objects = self.objects(view);
        objects.retain(|o| {
            let key = (o.mesh, o.material, o.skin.is_some());
            !self.unrenderable.contains(&key)
        });
        let lights = self.light_entities(view);
        let mesh_changed = self.meshes.keys().any(|k| meshes_modified.contains(&k.0));
        // A modified material showing an image platoon has no texture of needs a new scene
        // (textures are not edited in).
        let new_texture = self
            .materials
            .keys()
            .filter(|id| modified.contains(id))
            .any(|&id| {
                view.materials.get(id).is_some_and(|m| {
                    convert::texture_handles(m).any(|h| {
                        view.images.contains(h.id()) && !self.textures.contains_key(&h.id())
                    })
                })
            });
        // A new distant light changes the kernel's features (a map or not): built anew.
        if !self.built
            || mesh_changed
            || new_texture
            || environment != self.environment
            || self.structure_changed(&objects, &lights, view)
        {
            let mut scene = self.build(view, &objects, &lights);
            self.environment = environment;
            if let Some((image, intensity, rotation)) = environment {
                let map = view
                    .images
                    .get(image)
                    .ok_or_else(|| "not loaded".to_string())
                    .and_then(|cube| crate::environment::equirect(cube, intensity, rotation));
                match map {
                    Ok(map) => scene.environment = Some(Environment::Map(map)),
                    Err(why) => self.warnings.once(format!(
                        "the camera's environment map light is not mirrored: {why}"
                    )),
                }
            }
            return Change::Rebuilt(Box::new(scene));
        }
        let mut edits = Vec::new();
        // Materials first: an instance added below may show one.
        for (&id, &index) in &self.materials {
            if !modified.contains(&id) {
                continue;
            }
            if let Some(m) = view.materials.get(id) {
                let textures = &self.textures;
                let mut texture = |image: AssetId<Image>| textures.get(&image).copied();
                let name = format!("material {index}");
                let m = convert::material(m, &name, &mut texture, &mut self.warnings);
                edits.push(Edit::Material(index, Box::new(m)));
            }
        }
        let seen: HashSet<Entity> = objects.iter().map(|o| o.entity).collect();
        let mut gone: Vec<(Entity, usize)> = self
            .instances
            .iter()
            .filter(|(e, _)| !seen.contains(e))
            .map(|(&e, i)| (e, i.node))
            .collect();
        gone.sort();
        for (entity, node) in gone {
            self.instances.remove(&entity);
            edits.push(Edit::RemoveInstance(node));
        }
        for o in &objects {
            let key = (o.mesh, o.material, o.skin.is_some());
            match self.instances.get_mut(&o.entity) {
                Some(i) if i.skin.is_some() => {}
                Some(i) if i.placement != o.placement => {
                    i.placement = o.placement;
                    edits.push(Edit::Placement {
                        node: i.node,
                        placement: o.placement,
                    });
                }
                Some(_) => {}
                None => {
                    let node = self.nodes;
                    self.nodes += 1;
                    edits.push(Edit::AddInstance {
                        mesh: self.meshes[&key],
                        placement: o.placement,
                    });
                    self.instances.insert(
                        o.entity,
                        Instance {
                            node,
                            key,
                            placement: o.placement,
                            skin: None,
                        },
                    );
                }
            }
        }
        for (entity, light, placement) in lights {
            let l = self.lights.get_mut(&entity).expect("the same lights");
            if placement != l.placement {
                l.placement = placement;
                edits.push(Edit::Placement {
                    node: l.node,
                    placement,
                });
            }
            if !same_light(&light, &l.light) {
                edits.push(Edit::Light(l.index, Box::new(light.clone())));
                l.light = light;
            }
        }
        let mut joints: Vec<_> = self.joints.iter_mut().collect();
        joints.sort_by_key(|(_, (node, _))| *node);
        for (entity, (node, placement)) in joints {
            if let Ok(t) = view.transforms.get(*entity) {
                let now = convert::placement(t);
                if now != *placement {
                    *placement = now;
                    edits.push(Edit::Placement {
                        node: *node,
                        placement: now,
                    });
                }
            }
        }
        Change::Edits(edits)
    }

    /// The mesh entities that render: visible, with their mesh and material loaded, in a
    /// fixed order.
    fn objects(&mut self, view: &WorldView) -> Vec<Object> {
        let mut out = Vec::new();
        for (entity, mesh, material, t, visibility, skinned, name) in &view.objects {
            if visibility.is_some_and(|v| !v.get()) {
                continue;
            }
            if !view.meshes.contains(mesh.0.id()) || !view.materials.contains(material.0.id()) {
                continue;
            }
            let placement = convert::placement(t);
            if placement.checked().is_err() {
                // Scaled to nothing (or not finite): nothing to hit, as a hidden one.
                continue;
            }
            let skin = skinned.and_then(|s| {
                view.bindposes
                    .contains(s.inverse_bindposes.id())
                    .then(|| SkinKey {
                        bindposes: s.inverse_bindposes.id(),
                        joints: s.joints.clone(),
                    })
            });
            out.push(Object {
                entity,
                mesh: mesh.0.id(),
                material: material.0.id(),
                placement,
                skin,
                name: name.map_or_else(|| format!("entity {entity}"), |n| n.as_str().into()),
            });
        }
        out.sort_by_key(|o| o.entity);
        out
    }

    /// Every light entity with its platoon light and placement, in a fixed order.
    fn light_entities(&mut self, view: &WorldView) -> Vec<(Entity, PunctualLight, Placement)> {
        let name =
            |e: Entity, n: Option<&Name>| n.map_or(format!("entity {e}"), |n| n.as_str().into());
        let mut out = Vec::new();
        for (e, l, t, n) in &view.points {
            let light = convert::point_light(l, &name(e, n), &mut self.warnings);
            out.push((e, light, convert::placement(t)));
        }
        for (e, l, t, n) in &view.spots {
            let light = convert::spot_light(l, &name(e, n), &mut self.warnings);
            out.push((e, light, convert::placement(t)));
        }
        for (e, l, t, n) in &view.suns {
            out.push((
                e,
                convert::directional_light(l, &name(e, n)),
                convert::placement(t),
            ));
        }
        out.sort_by_key(|(e, ..)| *e);
        out
    }

    /// Whether the world holds what an edit cannot bring: a mesh or material platoon has not
    /// seen, a skinned mesh or joint it has not placed, a light come or gone.
    fn structure_changed(
        &self,
        objects: &[Object],
        lights: &[(Entity, PunctualLight, Placement)],
        view: &WorldView,
    ) -> bool {
        let new_object = objects.iter().any(|o| {
            let key = (o.mesh, o.material, o.skin.is_some());
            match self.instances.get(&o.entity) {
                Some(i) => i.key != key || i.skin != o.skin,
                None => !self.meshes.contains_key(&key) || o.skin.is_some(),
            }
        });
        let lights_differ = lights.len() != self.lights.len()
            || lights.iter().any(|(e, ..)| !self.lights.contains_key(e));
        let joint_gone = self.joints.keys().any(|&e| view.transforms.get(e).is_err());
        new_object || lights_differ || joint_gone
    }

    /// The whole scene from the world, and the mirror's maps of it.
    fn build(
        &mut self,
        view: &WorldView,
        objects: &[Object],
        lights: &[(Entity, PunctualLight, Placement)],
    ) -> Scene {
        // What was said and what cannot render stay known: neither is worth a rebuild.
        let warnings = std::mem::take(&mut self.warnings);
        let unrenderable = std::mem::take(&mut self.unrenderable);
        *self = Mirror {
            built: true,
            warnings,
            unrenderable,
            ..Mirror::default()
        };
        let mut scene = Scene::default();
        let mut skins: HashMap<SkinKey, usize> = HashMap::new();
        for o in objects {
            let material = self.material_index(&mut scene, view, o.material);
            let key = (o.mesh, o.material, o.skin.is_some());
            let mesh = match self.meshes.get(&key) {
                Some(&m) => Some(m),
                None => {
                    let needs_tangents = {
                        let m = &scene.materials[material];
                        m.normal_texture.is_some()
                            || m.clearcoat_normal_texture.is_some()
                            || m.has_anisotropy()
                    };
                    let bevy_mesh = view
                        .meshes
                        .get(o.mesh)
                        .expect("loaded, as objects() checked");
                    let converted = convert::mesh(
                        bevy_mesh,
                        &o.name,
                        material as u32,
                        needs_tangents,
                        &mut self.warnings,
                    );
                    match converted {
                        Some(m) => {
                            scene.meshes.push(Arc::new(m));
                            self.meshes.insert(key, scene.meshes.len() - 1);
                            Some(scene.meshes.len() - 1)
                        }
                        None => {
                            self.unrenderable.insert(key);
                            None
                        }
                    }
                }
            };
            let Some(mesh) = mesh else { continue };
            let skin = o.skin.as_ref().map(|k| match skins.get(k) {
                Some(&s) => s,
                None => {
                    let s = self.skin(&mut scene, view, k);
                    skins.insert(k.clone(), s);
                    s
                }
            });
            let mut node = Node::new(o.name.clone());
            o.placement.place(&mut node);
            node.mesh = Some(mesh);
            node.skin = skin;
            scene.nodes.push(node);
            self.instances.insert(
                o.entity,
                Instance {
                    node: scene.nodes.len() - 1,
                    key,
                    placement: o.placement,
                    skin: o.skin.clone(),
                },
            );
        }
        for (entity, light, placement) in lights {
            let mut node = Node::new(light.name.clone());
            placement.place(&mut node);
            node.light = Some(scene.lights.len());
            scene.nodes.push(node);
            self.lights.insert(
                *entity,
                Light {
                    index: scene.lights.len(),
                    node: scene.nodes.len() - 1,
                    light: light.clone(),
                    placement: *placement,
                },
            );
            scene.lights.push(light.clone());
        }
        self.nodes = scene.nodes.len();
        scene
    }

    /// The platoon material of a StandardMaterial asset (converted once a build).
    fn material_index(
        &mut self,
        scene: &mut Scene,
        view: &WorldView,
        id: AssetId<StandardMaterial>,
    ) -> usize {
        if let Some(&i) = self.materials.get(&id) {
            return i;
        }
        let m = view
            .materials
            .get(id)
            .expect("loaded, as objects() checked");
        let index = scene.materials.len();
        let name = format!("material {index}");
        let textures = &mut self.textures;
        let mut said = Warnings::default();
        let mut pending = Vec::new();
        let first = scene.textures.len();
        let mut texture = |image: AssetId<Image>| {
            if let Some(&t) = textures.get(&image) {
                return Some(t);
            }
            let converted = view
                .images
                .get(image)
                .and_then(|img| convert::texture(img, &format!("{image}"), &mut said));
            converted.map(|t| {
                let i = (first + pending.len()) as u32;
                pending.push(t);
                textures.insert(image, i);
                i
            })
        };
        let material = convert::material(m, &name, &mut texture, &mut self.warnings);
        for message in said.take_fresh() {
            self.warnings.once(message);
        }
        scene.textures.extend(pending);
        scene.materials.push(material);
        self.materials.insert(id, index);
        index
    }

    /// A skin's joints as nodes (placed where their entities are) and its matrices.
    fn skin(&mut self, scene: &mut Scene, view: &WorldView, key: &SkinKey) -> usize {
        let bindposes = view
            .bindposes
            .get(key.bindposes)
            .expect("loaded, as objects() checked");
        let mut joints = Vec::with_capacity(key.joints.len());
        for &entity in &key.joints {
            let node = match self.joints.get(&entity) {
                Some(&(node, _)) => node,
                None => {
                    let placement = view
                        .transforms
                        .get(entity)
                        .map(convert::placement)
                        .unwrap_or(Placement::at(glam::DVec3::ZERO));
                    let mut node = Node::new(format!("joint {entity}"));
                    placement.place(&mut node);
                    scene.nodes.push(node);
                    self.joints
                        .insert(entity, (scene.nodes.len() - 1, placement));
                    scene.nodes.len() - 1
                }
            };
            joints.push(node);
        }
        scene.skins.push(Skin {
            name: format!("skin {}", scene.skins.len()),
            joints,
            inverse_bind_matrices: bindposes
                .iter()
                .map(|m| Mat4::from_cols_array(&m.to_cols_array()))
                .collect(),
        });
        scene.skins.len() - 1
    }
}

/// Lights compare by what platoon renders of them.
fn same_light(a: &PunctualLight, b: &PunctualLight) -> bool {
    a.kind == b.kind && a.color == b.color && a.intensity == b.intensity && a.range == b.range
}

//! The node hierarchy, with cameras and punctual lights, and the skins and animations that move it.

use std::collections::HashMap;

use glam::{Mat4, Quat, Vec3};
use gltf::accessor::Dimensions;

use super::validate::{self, Check, Expect};
use crate::animation::{Animation, Channel, Interpolation, Property};
use crate::*;

pub fn load_nodes(doc: &gltf::Document, buffers: &[Vec<u8>], scene: &mut Scene) -> Check {
    let gscene = doc.default_scene().or_else(|| doc.scenes().next());
    let mut map: HashMap<usize, usize> = HashMap::new();
    // Breadth-first from the roots, so a parent always precedes its children.
    let mut queue: std::collections::VecDeque<(gltf::Node, Option<usize>)> = gscene
        .iter()
        .flat_map(|s| s.nodes())
        .map(|n| (n, None))
        .collect();
    let mut pending = Vec::new();
    while let Some((gn, parent)) = queue.pop_front() {
        if map.contains_key(&gn.index()) {
            return Err(format!(
                "node {} appears twice in the hierarchy",
                gn.index()
            ));
        }
        let idx = scene.nodes.len();
        map.insert(gn.index(), idx);
        let mut node = Node::new(gn.name().unwrap_or(""));
        node.parent = parent;
        let (t, r, s) = gn.transform().decomposed();
        if t.iter().chain(&r).chain(&s).all(|v| v.is_finite()) {
            node.translation = Vec3::from_array(t).as_dvec3();
            node.rotation = Quat::from_array(r);
            node.scale = Vec3::from_array(s);
        } else {
            // A singular matrix decomposes into NaN; a scale of zero hides the node, as
            // posing leaves out singular transforms.
            scene.warnings.push(format!(
                "node {} ('{}') has a singular or non-finite transform: it and its children are not drawn",
                gn.index(),
                gn.name().unwrap_or("")
            ));
            node.scale = Vec3::ZERO;
        }
        node.mesh = gn.mesh().map(|m| m.index());
        node.weights = gn.weights().map(<[f32]>::to_vec);
        node.skin = gn.skin().map(|s| s.index());
        if let Some(c) = gn.camera() {
            let name = c.name().unwrap_or("");
            let model = match c.projection() {
                gltf::camera::Projection::Perspective(p) => CameraModel {
                    name: name.into(),
                    yfov: p.yfov(),
                    aspect_ratio: p.aspect_ratio(),
                    orthographic: None,
                },
                gltf::camera::Projection::Orthographic(o) => {
                    let (x, y) = (o.xmag(), o.ymag());
                    // glTF forbids zero magnifications; a negative one would mirror the view.
                    if !(x.is_finite() && y.is_finite() && x > 0.0 && y > 0.0) {
                        return Err(format!(
                            "camera '{name}': orthographic xmag {x} and ymag {y} must be positive"
                        ));
                    }
                    CameraModel {
                        name: name.into(),
                        yfov: 0.0,
                        aspect_ratio: None,
                        orthographic: Some([x, y]),
                    }
                }
            };
            node.camera = Some(scene.cameras.len());
            scene.cameras.push(model);
        }
        if let Some(l) = gn.light() {
            node.light = Some(scene.lights.len());
            scene.lights.push(light(&l)?);
        }
        let instances = gpu_instances(doc, &gn, buffers)?;
        if !instances.is_empty() {
            // EXT_mesh_gpu_instancing: the node's mesh drawn once per instance, each placed by
            // its TRS under the node (children of it, so the node's own transform applies).
            for (k, (t, r, s)) in instances.into_iter().enumerate() {
                let mut instance = Node::new(format!("{} instance {k}", node.name));
                instance.parent = Some(idx);
                instance.mesh = node.mesh;
                instance.weights = node.weights.clone();
                instance.translation = t.as_dvec3();
                instance.rotation = r;
                instance.scale = s;
                pending.push(instance);
            }
            node.mesh = None;
        }
        scene.nodes.push(node);
        scene.nodes.append(&mut pending);
        for child in gn.children() {
            queue.push_back((child, Some(idx)));
        }
    }
    for skin in doc.skins() {
        if let Some(a) = skin.inverse_bind_matrices() {
            validate::accessor(
                &a,
                &Expect {
                    what: "inverseBindMatrices",
                    types: validate::FLOAT,
                    dims: Dimensions::Mat4,
                },
            )?;
        }
        let reader = skin.reader(|b| buffers.get(b.index()).map(Vec::as_slice));

        let ibm: Vec<Mat4> = reader
            .read_inverse_bind_matrices()
            .map(|it| it.map(|m| Mat4::from_cols_array_2d(&m)).collect())
            .unwrap_or_default();
        let joints = skin
            .joints()
            .filter_map(|j| map.get(&j.index()).copied())
            .collect::<Vec<_>>();
        scene.skins.push(Skin {
            name: skin.name().unwrap_or("").into(),
            joints,
            inverse_bind_matrices: ibm,
        });
    }
    for anim in doc.animations() {
        let mut channels = Vec::new();
        for ch in anim.channels() {
            let Some(&node) = map.get(&ch.target().node().index()) else {
                continue;
            };
            let anim_name = anim.name().unwrap_or("");
            animation_accessors(&ch).map_err(|e| format!("animation '{anim_name}': {e}"))?;
            let reader = ch.reader(|b| buffers.get(b.index()).map(Vec::as_slice));
            let times: Vec<f32> = reader
                .read_inputs()
                .map(|it| it.collect())
                .unwrap_or_default();
            if times.iter().any(|t| !t.is_finite()) || times.windows(2).any(|w| w[1] < w[0]) {
                return Err(format!(
                    "animation '{anim_name}' has key times that are not finite and increasing"
                ));
            }
            use gltf::animation::util::ReadOutputs;
            let (property, values): (Property, Vec<f32>) = match reader.read_outputs() {
                Some(ReadOutputs::Translations(it)) => {
                    (Property::Translation, it.flatten().collect())
                }
                Some(ReadOutputs::Scales(it)) => (Property::Scale, it.flatten().collect()),
                Some(ReadOutputs::Rotations(it)) => {
                    (Property::Rotation, it.into_f32().flatten().collect())
                }
                Some(ReadOutputs::MorphTargetWeights(it)) => {
                    (Property::Weights, it.into_f32().collect())
                }
                None => continue,
            };
            let interpolation = match ch.sampler().interpolation() {
                gltf::animation::Interpolation::Step => Interpolation::Step,
                gltf::animation::Interpolation::Linear => Interpolation::Linear,
                gltf::animation::Interpolation::CubicSpline => Interpolation::CubicSpline,
            };
            let per_key = match property {
                Property::Translation | Property::Scale => 3,
                Property::Rotation => 4,
                Property::Weights => 1,
            } * if interpolation == Interpolation::CubicSpline {
                3
            } else {
                1
            };
            if property != Property::Weights && values.len() < times.len() * per_key {
                return Err(format!("animation '{anim_name}' has too few output values"));
            }
            channels.push(Channel {
                node,
                property,
                interpolation,
                times,
                values,
            });
        }
        scene.animations.push(Animation {
            name: anim.name().unwrap_or("").into(),
            channels,
        });
    }
    Ok(())
}

fn light(l: &gltf::khr_lights_punctual::Light) -> Check<PunctualLight> {
    use gltf::khr_lights_punctual::Kind;
    let name = l.name().unwrap_or("");
    let kind = match l.kind() {
        Kind::Point => LightKind::Point,
        Kind::Directional => LightKind::Directional,
        Kind::Spot {
            inner_cone_angle,
            outer_cone_angle,
        } => LightKind::Spot {
            inner_cone: inner_cone_angle,
            outer_cone: outer_cone_angle,
        },
    };
    let cones = match kind {
        LightKind::Spot {
            inner_cone,
            outer_cone,
        } => [inner_cone, outer_cone],
        _ => [0.0; 2],
    };
    let range = l.range().unwrap_or(0.0);
    let numbers = [l.color().as_slice(), &[l.intensity(), range], &cones].concat();
    if numbers.iter().any(|v| !v.is_finite()) {
        return Err(format!("light '{name}' has a value that is not finite"));
    }
    Ok(PunctualLight {
        name: name.into(),
        kind,
        color: Vec3::from_array(l.color()),
        intensity: l.intensity(),
        range,
    })
}

/// Key times are scalar floats; values are float vectors (rotations may be normalised integers).
fn animation_accessors(ch: &gltf::animation::Channel) -> Check {
    use gltf::animation::Property as P;
    let sampler = ch.sampler();
    validate::accessor(
        &sampler.input(),
        &Expect {
            what: "keyframe time",
            types: validate::FLOAT,
            dims: Dimensions::Scalar,
        },
    )?;
    let (types, dims) = match ch.target().property() {
        P::Translation | P::Scale => (validate::FLOAT, Dimensions::Vec3),
        P::Rotation => (validate::NORM_OR_FLOAT, Dimensions::Vec4),
        P::MorphTargetWeights => (validate::NORM_OR_FLOAT, Dimensions::Scalar),
    };
    validate::accessor(
        &sampler.output(),
        &Expect {
            what: "keyframe value",
            types,
            dims,
        },
    )
}

/// The instances of EXT_mesh_gpu_instancing on node `gn` (none without it): translation,
/// rotation and scale accessors of one count, each defaulting to the identity.
fn gpu_instances(
    doc: &gltf::Document,
    gn: &gltf::Node,
    buffers: &[Vec<u8>],
) -> Check<Vec<(Vec3, Quat, Vec3)>> {
    let Some(ext) = gn.extension_value("EXT_mesh_gpu_instancing") else {
        return Ok(Vec::new());
    };
    let name = format!("node {} EXT_mesh_gpu_instancing", gn.index());
    // The checked accessor an attribute names, if it names one.
    let accessor = |key: &'static str, types, dims| -> Check<Option<gltf::Accessor>> {
        let Some(index) = ext.get("attributes").and_then(|a| a.get(key)) else {
            return Ok(None);
        };
        let accessor = index
            .as_u64()
            .and_then(|i| doc.accessors().nth(i as usize))
            .ok_or_else(|| format!("{name}: {key} names no accessor"))?;
        validate::accessor(
            &accessor,
            &Expect {
                what: key,
                types,
                dims,
            },
        )?;
        Ok(Some(accessor))
    };
    use super::attributes::read_as;
    let vec3 = Dimensions::Vec3;
    let t = read_as(
        accessor("TRANSLATION", validate::FLOAT, vec3)?,
        buffers,
        Vec3::from_array,
    )?;
    // As a node's rotation is read: glTF asks for unit quaternions.
    let r = read_as(
        accessor("ROTATION", validate::SNORM_OR_FLOAT, Dimensions::Vec4)?,
        buffers,
        Quat::from_array,
    )?;
    let s = read_as(
        accessor("SCALE", validate::FLOAT, vec3)?,
        buffers,
        Vec3::from_array,
    )?;
    let counts: Vec<usize> = [
        t.as_ref().map(Vec::len),
        r.as_ref().map(Vec::len),
        s.as_ref().map(Vec::len),
    ]
    .into_iter()
    .flatten()
    .collect();
    let Some(&count) = counts.first() else {
        return Ok(Vec::new());
    };
    if counts.iter().any(|&c| c != count) {
        return Err(format!("{name}: its attributes have different counts"));
    }
    (0..count)
        .map(|i| {
            let t = t.as_ref().map_or(Vec3::ZERO, |v| v[i]);
            let r = r.as_ref().map_or(Quat::IDENTITY, |v| v[i]);
            let s = s.as_ref().map_or(Vec3::ONE, |v| v[i]);
            if !(t.is_finite() && r.is_finite() && s.is_finite()) {
                return Err(format!("{name}: instance {i} is not finite"));
            }
            Ok((t, r, s))
        })
        .collect()
}

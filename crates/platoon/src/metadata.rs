//! What an output file says about how it was made.

use platoon_core::frame::FrameParams;

use crate::{Prepared, Rendered};

/// What the metadata says of the scene a frame was rendered from.
pub struct SceneFacts<'a> {
    pub source: Option<&'a std::path::Path>,
    /// The material variant loaded (KHR_materials_variants), if one was chosen.
    pub variant: Option<&'a str>,
    /// What the scene as loaded approximates (`Scene::approximations`: its textures).
    pub approximations: &'a [String],
    pub features: platoon_core::SceneFeatures,
    pub env_label: &'a str,
    /// Where render space is centred (the floating origin).
    pub origin: glam::DVec3,
}

impl Prepared {
    pub fn facts(&self) -> SceneFacts<'_> {
        SceneFacts {
            source: self.scene.source.as_deref(),
            variant: self.scene.variant.as_deref(),
            approximations: &self.scene.approximations,
            features: self.gpu.features,
            env_label: &self.env_label,
            origin: self.posed.origin,
        }
    }
}

/// The metadata written into EXR outputs.
pub fn metadata(
    prepared: &Prepared,
    params: &FrameParams,
    rendered: &Rendered,
    sampling: &str,
) -> Vec<(String, String)> {
    metadata_of(&prepared.facts(), params, rendered, sampling)
}

/// The same for a frame of a scene described by `facts` (an animation's frames).
pub fn metadata_of(
    facts: &SceneFacts,
    params: &FrameParams,
    rendered: &Rendered,
    sampling: &str,
) -> Vec<(String, String)> {
    let features = platoon_core::KernelVariant::new(facts.features, params);
    let source = facts
        .source
        .map(|p| p.display().to_string())
        .unwrap_or_else(|| "built-in Cornell box".into());
    let mut m = vec![
        ("scene".into(), source),
        (
            "material_variant".into(),
            facts.variant.unwrap_or("(default)").to_string(),
        ),
        ("spp".into(), rendered.spp.to_string()),
    ];
    // The frame options' part, as the request's table declares it.
    m.extend(crate::request::options::frame_metadata(params));
    m.extend([
        ("frame".into(), params.frame.to_string()),
        // 1 means no path regeneration within a kernel pass (a trade-off knob).
        (
            "samples_per_pass".into(),
            params.samples_per_pass.to_string(),
        ),
    ]);
    let method_lights = params.method.unit().light_selection();
    m.extend(params.path_loop.metadata(method_lights));
    m.extend([
        (
            "render_time_s".into(),
            format!("{:.3}", rendered.wall_time.as_secs_f64()),
        ),
        (
            "gpu_time_s".into(),
            format!("{:.3}", rendered.gpu_time().as_secs_f64()),
        ),
        ("device".into(), rendered.device.clone()),
        (
            "balancer".into(),
            rendered.balancer.unwrap_or("single device").into(),
        ),
        ("features".into(), features.to_string()),
        ("kernel_defines".into(), rendered.kernel_defines.join(",")),
        // Per device, in the order of `device`: what `--traversal` resolved to on each.
        ("traversal".into(), rendered.traversals.join(", ")),
        (
            "kernel_fallbacks".into(),
            rendered.kernel_fallbacks.to_string(),
        ),
        ("sampling".into(), sampling.into()),
        ("method".into(), method(params)),
        ("environment".into(), facts.env_label.to_string()),
        (
            "render_origin".into(),
            format!("{},{},{}", facts.origin.x, facts.origin.y, facts.origin.z),
        ),
        (
            "rejected_samples".into(),
            rendered.rejected_samples().to_string(),
        ),
        (
            "approximations".into(),
            [approximations(params)]
                .into_iter()
                .chain(facts.approximations.iter().cloned())
                .collect::<Vec<_>>()
                .join("; "),
        ),
        ("texture_lod".into(), texture_lod(facts.features).into()),
    ]);
    if let Some(r) = &rendered.ranks {
        m.extend([
            ("mpi_ranks".into(), r.ranks.to_string()),
            ("mpi_balancer".into(), r.balancer.to_string()),
        ]);
    }
    if let Some(a) = rendered.batched.as_ref().and_then(|b| b.adaptive) {
        m.extend([
            ("adaptive_threshold".into(), a.threshold.to_string()),
            ("adaptive_min_spp".into(), a.min_spp(params.spp).to_string()),
            ("mean_spp".into(), format!("{:.2}", rendered.mean_spp())),
        ]);
        for (k, v) in &mut m {
            if k == "approximations" {
                v.push_str(&format!(
                    "; adaptive sampling (threshold {}): a pixel stops on its own samples' error \
                     estimate",
                    a.threshold
                ));
            }
        }
    }
    m.extend(rendered.method_metadata.iter().cloned());
    m
}

/// The rendering method and its options.
fn method(params: &FrameParams) -> String {
    params.method.unit().describe()
}

/// Every approximation in effect, so a reader of the image knows what it is not.
pub fn approximations(params: &FrameParams) -> String {
    let mut a = vec!["roughness<0.01 rendered as perfectly specular".to_string()];
    a.extend(params.path_loop.approximations());
    a.extend(params.method.unit().approximations());
    a.join("; ")
}

/// How textures were read: mip levels by ray cone where the scene was loaded with them.
fn texture_lod(features: platoon_core::SceneFeatures) -> &'static str {
    use platoon_core::scene::texture_levels::TextureLod;
    match features.texture_lod {
        true => TextureLod::RayCone.name(),
        false => TextureLod::Off.name(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use platoon_core::scene::camera::Camera;

    #[test]
    fn every_biased_knob_is_listed_as_an_approximation() {
        let mut p = FrameParams::new(
            4,
            4,
            1,
            Camera::look_at(glam::Vec3::Z, glam::Vec3::ZERO, 1.0),
        );
        let plain = approximations(&p);
        p.path_loop.max_depth = 2;
        p.path_loop.clamp_indirect = Some(1.5);
        p.path_loop.deterministic_termination = true;
        p.path_loop.single_diffuse_bounce = true;
        p.method = platoon_core::Method::new(platoon_core::method::igi::IgiOptions {
            min_distance: 0.1,
            imperfect_visibility: true,
            downsample: 4,
            interleave: [3, 3],
            ..Default::default()
        });
        let a = approximations(&p);
        for says in [
            "capped at 2",
            "clamped at 1.5",
            "deterministic path termination",
            "single diffuse bounce",
            "instant global illumination",
            "minimum distance",
            "leaf boxes",
            "1/4 x 1/4",
            "3x3 VPL subsets",
        ] {
            assert!(a.contains(says) && !plain.contains(says), "{says}: {a}");
        }
        // Unbiased knobs are not approximations.
        let mut q = FrameParams::new(
            4,
            4,
            1,
            Camera::look_at(glam::Vec3::Z, glam::Vec3::ZERO, 1.0),
        );
        q.path_loop.rr_fixed = Some(0.5);
        q.path_loop.uniform_light_selection = true;
        q.method = platoon_core::Method::new(platoon_core::method::path::PathTracing {
            resampled_light: Some(platoon_core::method::path::ResampledLight::new(4)),
            ..Default::default()
        });
        assert_eq!(approximations(&q), plain);
    }
}

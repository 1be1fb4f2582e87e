//! Punctual lights, the environment as a light, and the light-selection distribution over all
//! lights (by power, summed in f64).

use std::f64::consts::PI;

use glam::Vec3;

use super::layout::{
    GpuEnvironment, GpuLight, LIGHT_DIRECTIONAL, LIGHT_ENVIRONMENT, LIGHT_POINT, LIGHT_SPOT,
};
use super::GpuScene;
use platoon_scene::environment::{luminance, Environment};
use platoon_scene::error::{Error, Result};
use platoon_scene::{LightKind, Posed, Scene};

/// Appends the posed punctual lights to `g` and their powers to `power`.
pub(super) fn add_punctual(scene: &Scene, posed: &Posed, g: &mut GpuScene, power: &mut Vec<f64>) {
    for placed in &posed.lights {
        let l = &scene.lights[placed.light];
        let intensity = l.color * l.intensity;
        let lum = luminance(intensity) as f64;
        let (kind, c, p) = match l.kind {
            LightKind::Point => (LIGHT_POINT, [0.0; 4], 4.0 * PI * lum),
            LightKind::Spot {
                inner_cone,
                outer_cone,
            } => {
                let (ci, co) = (inner_cone.cos(), outer_cone.cos());
                let solid_angle = 2.0 * PI * (1.0 - 0.5 * (ci + co) as f64);
                (
                    LIGHT_SPOT,
                    [co, 1.0 / (ci - co).max(1e-4), 0.0, 0.0],
                    solid_angle * lum,
                )
            }
            LightKind::Directional => (
                LIGHT_DIRECTIONAL,
                [0.0; 4],
                PI * g.scene_radius * g.scene_radius * lum,
            ),
        };
        power.push(p);
        g.lights.push(GpuLight {
            a: placed.position.extend(0.0).to_array(),
            b: placed.direction.extend(l.range).to_array(),
            c,
            emission: intensity.extend(0.0).to_array(),
            ids: [kind, 0, 0, 0],
        });
    }
}

/// The environment as the kernel reads it (its map, CDFs and mean radiance, computed once).
pub(super) fn set_environment(environment: Option<&Environment>, g: &mut GpuScene) {
    g.env = environment.map(gpu_environment).unwrap_or_default();
}

/// Appends the environment set by [`set_environment`] to the lights.
pub(super) fn add_environment_light(g: &mut GpuScene, power: &mut Vec<f64>) {
    // Flux of the environment through the scene's bounding sphere.
    let r = g.scene_radius;
    power.push(PI * PI * r * r * luminance(Vec3::from_array(g.env.mean_radiance)) as f64);
    g.lights.push(GpuLight {
        ids: [LIGHT_ENVIRONMENT, 0, 0, 0],
        ..Default::default()
    });
}

/// Stores the selection CDF of `power` and each light's probability (in `emission.w`).
pub(super) fn set_selection(g: &mut GpuScene, power: &[f64]) -> Result<()> {
    let (cdf, pmf) = selection_distribution(power)?;
    g.light_cdf = cdf;
    for (light, p) in g.lights.iter_mut().zip(pmf) {
        light.emission[3] = p;
    }
    Ok(())
}

/// The light-selection CDF (f32, as the kernel searches it) and each light's probability, taken
/// from that same f32 CDF so that the pdf the kernel evaluates is exactly the one it samples
/// with. Powers are summed in f64; if everything is black, lights are picked uniformly (still
/// unbiased). A non-finite power is an error here rather than a silently black frame.
pub fn selection_distribution(power: &[f64]) -> Result<(Vec<f32>, Vec<f32>)> {
    if let Some(i) = power.iter().position(|p| !p.is_finite()) {
        return Err(Error::Invalid(format!(
            "light {i} has a non-finite power ({}): check emission strengths and light intensities",
            power[i]
        )));
    }
    let total: f64 = power.iter().map(|&p| p.max(0.0)).sum();
    let n = power.len();
    let mut cdf = Vec::with_capacity(n + 1);
    cdf.push(0.0f32);
    let mut acc = 0.0f64;
    for (i, p) in power.iter().enumerate() {
        acc += if total > 0.0 {
            p.max(0.0) / total
        } else {
            1.0 / n as f64
        };
        cdf.push(if i + 1 == n { 1.0 } else { acc.min(1.0) as f32 });
    }
    let pmf = cdf.windows(2).map(|w| w[1] - w[0]).collect();
    Ok((cdf, pmf))
}

fn gpu_environment(env: &Environment) -> GpuEnvironment {
    match env {
        Environment::Constant(c) => GpuEnvironment {
            kind: super::layout::ENV_CONSTANT,
            color: c.to_array(),
            mean_radiance: c.to_array(),
            ..Default::default()
        },
        Environment::Map(map) => {
            let d = map.distribution();
            GpuEnvironment {
                kind: super::layout::ENV_MAP,
                color: [1.0; 3],
                width: map.width,
                height: map.height,
                texels: map.texels.iter().map(|t| [t[0], t[1], t[2], 0.0]).collect(),
                marginal_cdf: d.marginal_cdf,
                conditional_cdf: d.conditional_cdf,
                integral: d.integral,
                mean_radiance: map.mean_radiance().to_array(),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::selection_distribution;

    #[test]
    fn probabilities_are_the_widths_of_the_searched_cdf() {
        // An emitter beside a sun whose power comes from a radius of 1e30: the emitter's share
        // vanishes in f32, and its probability must then be 0, not 1e-61.
        for power in [vec![8.0, 1e61], vec![1.0, 2.0, 3.0], vec![0.0, 0.0]] {
            let (cdf, pmf) = selection_distribution(&power).unwrap();
            assert_eq!((cdf.len(), pmf.len()), (power.len() + 1, power.len()));
            assert_eq!((cdf[0], *cdf.last().unwrap()), (0.0, 1.0));
            for i in 0..pmf.len() {
                assert_eq!(pmf[i], cdf[i + 1] - cdf[i]);
                assert!(pmf[i].is_finite() && pmf[i] >= 0.0);
            }
        }
        let (_, pmf) = selection_distribution(&[8.0, 1e61]).unwrap();
        assert_eq!(pmf, vec![0.0, 1.0]);
        let (_, pmf) = selection_distribution(&[0.0, 0.0]).unwrap();
        assert_eq!(pmf, vec![0.5, 0.5]);
    }

    #[test]
    fn a_non_finite_power_is_an_error() {
        assert!(selection_distribution(&[1.0, f64::INFINITY]).is_err());
        assert!(selection_distribution(&[f64::NAN]).is_err());
    }
}

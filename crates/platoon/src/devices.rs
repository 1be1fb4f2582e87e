//! Which tracers a render uses: `all`, a list of device indices, or `lavapipe:T1,T2,...` (one
//! software tracer per entry, entry i with Ti llvmpipe threads in its own VkInstance).

use std::fmt;
use std::str::FromStr;

use anyhow::{bail, Context as _, Result};
use platoon_core::balance::Balancer;
use platoon_core::flatten::GpuScene;
use platoon_core::frame::renderer::Renderer;
use platoon_tracer::{list_devices, Sampling, Tracer, TracerOptions};

#[derive(Clone, Debug, PartialEq)]
pub enum DeviceSpec {
    All,
    Indices(Vec<usize>),
    Lavapipe(Vec<u32>),
}

impl FromStr for DeviceSpec {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        let list = |text: &str| -> Result<Vec<u32>, String> {
            let v: Result<Vec<u32>, _> = text.split(',').map(|p| p.trim().parse::<u32>()).collect();
            v.map_err(|_| format!("{s}: expected comma-separated numbers"))
        };
        if s == "all" {
            Ok(DeviceSpec::All)
        } else if let Some(rest) = s.strip_prefix("lavapipe:") {
            let threads = list(rest)?;
            if threads.is_empty() || threads.contains(&0) {
                return Err(format!(
                    "{s}: every lavapipe tracer needs at least one thread"
                ));
            }
            Ok(DeviceSpec::Lavapipe(threads))
        } else {
            Ok(DeviceSpec::Indices(
                list(s)?.into_iter().map(|i| i as usize).collect(),
            ))
        }
    }
}

impl fmt::Display for DeviceSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let join = |v: Vec<String>| v.join(",");
        match self {
            DeviceSpec::All => write!(f, "all"),
            DeviceSpec::Indices(i) => {
                write!(f, "{}", join(i.iter().map(|x| x.to_string()).collect()))
            }
            DeviceSpec::Lavapipe(t) => write!(
                f,
                "lavapipe:{}",
                join(t.iter().map(|x| x.to_string()).collect())
            ),
        }
    }
}

/// Options of every tracer the spec asks for.
pub fn tracer_options(
    spec: &DeviceSpec,
    validation: bool,
    sampling: Sampling,
) -> Result<Vec<TracerOptions>> {
    let devices = list_devices()?;
    if devices.is_empty() {
        bail!("no Vulkan devices found (install mesa-vulkan-drivers for lavapipe)");
    }
    let base = TracerOptions {
        device: 0,
        validation,
        sampling,
        ..Default::default()
    };
    Ok(match spec {
        DeviceSpec::All => devices
            .iter()
            .map(|d| TracerOptions {
                device: d.index,
                ..base.clone()
            })
            .collect(),
        DeviceSpec::Indices(list) => {
            for &i in list {
                if i >= devices.len() {
                    bail!(
                        "no Vulkan device {i}: {} device(s) found (see `platoon devices`)",
                        devices.len()
                    );
                }
            }
            list.iter()
                .map(|&i| TracerOptions {
                    device: i,
                    ..base.clone()
                })
                .collect()
        }
        DeviceSpec::Lavapipe(threads) => {
            let Some(lvp) = devices.iter().find(|d| d.name.contains("llvmpipe")) else {
                bail!("lavapipe (llvmpipe) is not among the Vulkan devices: install mesa-vulkan-drivers");
            };
            threads
                .iter()
                .map(|&t| TracerOptions {
                    device: lvp.index,
                    lavapipe_threads: Some(t),
                    ..base.clone()
                })
                .collect()
        }
    })
}

/// One tracer per entry of the spec, each with its own copy of the scene.
pub fn create_tracers(
    spec: &DeviceSpec,
    scene: &GpuScene,
    validation: bool,
    sampling: Sampling,
) -> Result<Vec<Tracer>> {
    tracers_from_options(&tracer_options(spec, validation, sampling)?, scene)
}

/// One tracer per set of options already resolved by [`tracer_options`].
pub fn tracers_from_options(options: &[TracerOptions], scene: &GpuScene) -> Result<Vec<Tracer>> {
    options
        .iter()
        .enumerate()
        .map(|(i, o)| {
            Tracer::new(o, scene)
                .with_context(|| format!("creating tracer {i} (device {})", o.device))
        })
        .collect()
}

/// The balancer named `name` (one of `platoon_core::balance::NAMES`), or an error listing them.
pub fn balancer(name: &str) -> Result<Box<dyn Balancer>> {
    platoon_core::balance::by_name(name).with_context(|| {
        format!(
            "unknown balancer {name:?} (known: {})",
            platoon_core::balance::NAMES.join(", ")
        )
    })
}

/// A renderer over the devices of `spec`, balanced by `balancer`.
pub fn renderer(
    spec: &DeviceSpec,
    scene: &GpuScene,
    balancer: Box<dyn Balancer>,
    validation: bool,
    sampling: Sampling,
) -> Result<Renderer<Tracer>> {
    Ok(Renderer::new(
        create_tracers(spec, scene, validation, sampling)?,
        balancer,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_every_form() {
        assert_eq!("all".parse::<DeviceSpec>().unwrap(), DeviceSpec::All);
        assert_eq!(
            "0,2".parse::<DeviceSpec>().unwrap(),
            DeviceSpec::Indices(vec![0, 2])
        );
        assert_eq!(
            "lavapipe:2,1".parse::<DeviceSpec>().unwrap(),
            DeviceSpec::Lavapipe(vec![2, 1])
        );
        assert!("lavapipe:0".parse::<DeviceSpec>().is_err());
        assert!("gpu".parse::<DeviceSpec>().is_err());
        assert_eq!(
            "lavapipe:1,1,1".parse::<DeviceSpec>().unwrap().to_string(),
            "lavapipe:1,1,1"
        );
    }
}

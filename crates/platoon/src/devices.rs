//! Which tracers a render uses: `auto` (every GPU, or lavapipe where there is none), `all`, a
//! list of device indices, or `lavapipe:T1,T2,...` (one software tracer per entry, entry i with
//! Ti llvmpipe threads in its own VkInstance).

use std::fmt;
use std::str::FromStr;

use anyhow::{bail, Context as _, Result};
use platoon_core::balance::Balancer;
use platoon_core::flatten::GpuScene;
use platoon_schedule::renderer::Renderer;
use platoon_tracer::{list_devices, DeviceInfo, Sampling, Tracer, TracerOptions};

#[derive(Clone, Debug, PartialEq)]
pub enum DeviceSpec {
    /// Every device that is not a CPU implementation; the first CPU one (lavapipe) where there
    /// is nothing else. A GPU is tens to hundreds of times lavapipe's speed: beside GPUs,
    /// lavapipe's band would be a sliver (`all` takes it too).
    Auto,
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
        if s == "auto" {
            Ok(DeviceSpec::Auto)
        } else if s == "all" {
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
            DeviceSpec::Auto => write!(f, "auto"),
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

/// The indices `auto` takes among `devices`: every one that is not a CPU implementation, or
/// the first (a CPU one) where all are.
pub fn auto_devices(devices: &[DeviceInfo]) -> Vec<usize> {
    let gpus: Vec<usize> = devices.iter().filter(|d| !d.cpu).map(|d| d.index).collect();
    if gpus.is_empty() {
        devices.iter().map(|d| d.index).take(1).collect()
    } else {
        gpus
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
        DeviceSpec::Auto => auto_devices(&devices)
            .into_iter()
            .map(|device| TracerOptions {
                device,
                ..base.clone()
            })
            .collect(),
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

/// The balancer named `name` (`platoon_core::balance::by_name`), or an error listing them.
pub fn balancer(name: &str) -> Result<Box<dyn Balancer>> {
    platoon_core::balance::by_name(name).with_context(|| {
        format!(
            "unknown balancer {name:?} ({})",
            platoon_core::balance::names_help()
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

    fn device(index: usize, cpu: bool) -> DeviceInfo {
        DeviceInfo {
            index,
            name: if cpu {
                "llvmpipe".into()
            } else {
                "a GPU".into()
            },
            device_type: if cpu {
                "CPU".into()
            } else {
                "discrete GPU".into()
            },
            driver: String::new(),
            api_version: "1.3.0".into(),
            max_storage_buffer_range: 1 << 27,
            max_texel_buffer_elements: 1 << 27,
            cpu,
            mesa: None,
            memory: Default::default(),
            ray_queries: false,
        }
    }

    #[test]
    fn auto_takes_every_gpu_and_lavapipe_only_alone() {
        let lavapipe_first = [device(0, true), device(1, false), device(2, false)];
        assert_eq!(auto_devices(&lavapipe_first), vec![1, 2]);
        assert_eq!(auto_devices(&[device(0, false), device(1, true)]), vec![0]);
        assert_eq!(auto_devices(&[device(0, true)]), vec![0]);
        assert_eq!(auto_devices(&[device(0, true), device(1, true)]), vec![0]);
        assert_eq!(auto_devices(&[]), Vec::<usize>::new());
    }

    #[test]
    fn parses_every_form() {
        assert_eq!("auto".parse::<DeviceSpec>().unwrap(), DeviceSpec::Auto);
        assert_eq!("auto".parse::<DeviceSpec>().unwrap().to_string(), "auto");
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

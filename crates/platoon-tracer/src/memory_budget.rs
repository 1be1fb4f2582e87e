//! The device memory a scene's arrays take, checked against the device before anything is
//! allocated: a scene too large for a device is refused naming the device, what the scene needs
//! and what the device has, instead of failing inside the driver (an out-of-memory error from
//! the allocator, or a buffer past `maxBufferSize` that a driver need not even report).

use crate::{DeviceInfo, Error, Result};
pub use platoon_core::byte_size::size;

/// The bytes a device can give a scene: `limit` when one is set below it, else what the device
/// has. A CPU device (lavapipe) allocates from the host's memory whatever heap size it states
/// (Mesa 22.3 states 2 GiB, and the Cornell box cut into 18M triangles renders with 2.15 GiB of
/// it), so the host's memory is its bound there.
pub fn budget(info: &DeviceInfo, limit: Option<u64>, host_memory: Option<u64>) -> u64 {
    let device = match (info.cpu, host_memory) {
        (true, Some(host)) => host.max(info.memory.device_local),
        _ => info.memory.device_local,
    };
    limit.map_or(device, |l| l.min(device))
}

/// The host's physical memory (`MemTotal` of /proc/meminfo), where the system says.
pub fn host_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

/// Refuses `arrays` (name, bytes) on the device of `info` when one of them is larger than one
/// buffer can be, or all together more than `budget` bytes. `limit_set`: the budget is a limit
/// the caller asked for (said in the message).
pub fn check(
    info: &DeviceInfo,
    arrays: &[(&str, u64)],
    budget: u64,
    limit_set: bool,
) -> Result<()> {
    let device = || format!("{} ({})", info.index, info.name);
    let largest = info.memory.largest_array();
    if let Some((name, bytes)) = arrays.iter().find(|(_, b)| *b > largest) {
        return Err(Error::Unsupported {
            device: device(),
            message: format!(
                "the scene's {name} take {}, more than one buffer of this device can hold \
                 ({}){}",
                size(*bytes),
                size(largest),
                texture_hint(name)
            ),
        });
    }
    let total: u64 = arrays.iter().map(|(_, b)| b).sum();
    if total <= budget {
        return Ok(());
    }
    let mut by_size: Vec<&(&str, u64)> = arrays.iter().filter(|(_, b)| *b > 0).collect();
    by_size.sort_by_key(|(_, b)| std::cmp::Reverse(*b));
    let parts: Vec<String> = by_size
        .iter()
        .take(4)
        .map(|(name, b)| format!("{name} {}", size(*b)))
        .collect();
    let bound = if limit_set {
        format!("the device-memory limit of {}", size(budget))
    } else if info.cpu {
        format!("the host's {} of memory", size(budget))
    } else {
        format!("the device's {} of memory", size(budget))
    };
    Err(Error::Unsupported {
        device: device(),
        message: format!(
            "the scene needs {} of device memory ({}), more than {bound}: refused before \
             upload{}",
            size(total),
            parts.join(", "),
            texture_hint(by_size[0].0)
        ),
    })
}

/// What to do when the texels are the array too large: a texture budget.
fn texture_hint(largest: &str) -> &'static str {
    match largest {
        "texels" => {
            "; a texture budget (`--texture-budget`, `TextureOptions::budget`) halves the \
             largest textures until they fit"
        }
        _ => "",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn device(cpu: bool) -> DeviceInfo {
        DeviceInfo::for_tests(cpu)
    }

    #[test]
    fn a_scene_over_the_budget_is_refused_naming_the_device_and_the_sizes() {
        let d = device(false);
        let arrays = [("blas", 600 << 20), ("vertices", 300 << 20), ("lights", 0)];
        assert!(check(&d, &arrays, 1 << 30, true).is_ok());
        let e = check(&d, &arrays, 800 << 20, true).unwrap_err().to_string();
        assert!(e.contains("device 1 (test device)"), "{e}");
        assert!(e.contains("900.00 MiB"), "{e}");
        assert!(e.contains("blas 600.00 MiB, vertices 300.00 MiB"), "{e}");
        assert!(e.contains("limit of 800.00 MiB"), "{e}");
    }

    #[test]
    fn an_array_past_one_buffer_is_refused_whatever_the_budget() {
        let d = device(true);
        let e = check(&d, &[("texels", 3 << 30)], u64::MAX, false)
            .unwrap_err()
            .to_string();
        assert!(e.contains("texels take 3.00 GiB"), "{e}");
        assert!(e.contains("(1.00 GiB); a texture budget"), "{e}");
        // Other arrays get no such advice.
        let e = check(&d, &[("blas", 3 << 30)], u64::MAX, false)
            .unwrap_err()
            .to_string();
        assert!(!e.contains("texture budget"), "{e}");
    }

    #[test]
    fn a_cpu_device_is_bounded_by_the_host_and_a_limit_by_itself() {
        let (cpu, gpu) = (device(true), device(false));
        assert_eq!(budget(&cpu, None, Some(24 << 30)), 24 << 30);
        assert_eq!(budget(&gpu, None, Some(24 << 30)), 2 << 30);
        assert_eq!(budget(&cpu, Some(1 << 20), Some(24 << 30)), 1 << 20);
        assert_eq!(budget(&gpu, Some(8 << 30), None), 2 << 30);
        assert_eq!(size(1536), "1.50 KiB");
        assert_eq!(size(12), "12 B");
    }
}

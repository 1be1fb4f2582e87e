//! `platoon devices`: the Vulkan devices a render can use.

use anyhow::{bail, Result};

pub fn run() -> Result<()> {
    let devices = platoon::tracer::list_devices()?;
    if devices.is_empty() {
        bail!("no Vulkan devices found (install mesa-vulkan-drivers for lavapipe)");
    }
    for d in devices {
        println!(
            "{}: {} ({}), driver {}, Vulkan {}",
            d.index, d.name, d.device_type, d.driver, d.api_version
        );
    }
    Ok(())
}

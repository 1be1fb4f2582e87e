//! `platoon devices`: the Vulkan devices a render can use.

use anyhow::{bail, Result};
use platoon::tracer::Traversal;

pub fn run() -> Result<()> {
    let devices = platoon::tracer::list_devices()?;
    if devices.is_empty() {
        bail!("no Vulkan devices found (install mesa-vulkan-drivers for lavapipe)");
    }
    for d in &devices {
        // Ray queries: the device's own traversal of acceleration structures (issue 61), what
        // a user with a GPU or a newer lavapipe asks first.
        let queries = if d.ray_queries { "yes" } else { "no" };
        let auto = Traversal::Auto.resolved(d, 0).name();
        println!(
            "{}: {} ({}), driver {}, Vulkan {}, ray queries: {queries} (--traversal auto: {auto})",
            d.index, d.name, d.device_type, d.driver, d.api_version
        );
    }
    let auto: Vec<String> = platoon::devices::auto_devices(&devices)
        .iter()
        .map(|i| i.to_string())
        .collect();
    let why = if devices.iter().any(|d| !d.cpu) {
        "every GPU; lavapipe with --devices all or its index"
    } else {
        "no GPU found: lavapipe"
    };
    println!(
        "rendering by default (--devices auto) on {} ({why})",
        auto.join(",")
    );
    Ok(())
}

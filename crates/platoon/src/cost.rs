//! What preparing and rendering a scene cost the machine, stage by stage: the times a user
//! with a big scene waits through (reading it, building its BVHs, uploading it, the first
//! pixel) and the memory it took on the host and on each device (`render`'s report and its
//! `--log-json` line; `platoon bench scale` reads the latter).

use std::time::Duration;

/// The stages of one render, as measured by whoever ran them.
#[derive(Clone, Debug, Default)]
pub struct RenderCost {
    /// Reading and converting the scene file.
    pub load: Duration,
    /// Posing and flattening it (BVHs included).
    pub prepare: Duration,
    /// Of `prepare`: the bottom and top levels' BVH builds.
    pub bvh: Duration,
    /// Creating the devices and uploading the scene to them.
    pub upload: Duration,
    /// From the command's start to the first pass of samples done.
    pub first_pixel: Duration,
    /// The render itself.
    pub render: Duration,
    /// The process's peak resident memory, when the system says.
    pub peak_host_bytes: Option<u64>,
    /// Device memory each device holds.
    pub device_bytes: Vec<u64>,
    /// Triangles the devices hold (an instanced mesh's once: the bottom levels').
    pub triangles: usize,
    /// Instances of the top level (the merged static geometry is one).
    pub instances: usize,
}

impl RenderCost {
    /// Device bytes per triangle of the first device (the scene's own copy there).
    pub fn device_bytes_per_triangle(&self) -> Option<f64> {
        let bytes = *self.device_bytes.first()?;
        (self.triangles > 0).then(|| bytes as f64 / self.triangles as f64)
    }

    /// The report's line: stages, then memory.
    pub fn line(&self) -> String {
        let s = |d: Duration| format!("{:.2} s", d.as_secs_f64());
        let mut line = format!(
            "load {}, prepare {} (BVH {}), upload {}, first pixel at {}",
            s(self.load),
            s(self.prepare),
            s(self.bvh),
            s(self.upload),
            s(self.first_pixel)
        );
        if let Some(peak) = self.peak_host_bytes {
            line += &format!("; host peak {}", gib(peak));
        }
        if !self.device_bytes.is_empty() {
            let each: Vec<String> = self.device_bytes.iter().map(|&b| gib(b)).collect();
            line += &format!("; device {}", each.join(" + "));
        }
        if let Some(per) = self.device_bytes_per_triangle() {
            line += &format!(
                " for {} triangles ({per:.0} bytes a triangle) and {} instances",
                self.triangles, self.instances
            );
        }
        line
    }
}

fn gib(bytes: u64) -> String {
    crate::tracer::memory_budget::size(bytes)
}

/// The peak resident memory of this process so far (`VmHWM` of /proc/self/status), where the
/// system says.
pub fn peak_host_bytes() -> Option<u64> {
    peak_bytes_in(&std::fs::read_to_string("/proc/self/status").ok()?)
}

/// The peak resident memory (`VmHWM`) a /proc status file says, in bytes.
pub fn peak_bytes_in(status: &str) -> Option<u64> {
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_line_says_every_stage_and_the_memory() {
        let c = RenderCost {
            load: Duration::from_millis(1500),
            prepare: Duration::from_millis(2250),
            bvh: Duration::from_secs(2),
            upload: Duration::from_millis(500),
            first_pixel: Duration::from_secs(5),
            render: Duration::from_secs(1),
            peak_host_bytes: Some(3 << 29),
            device_bytes: vec![1 << 30, 1 << 29],
            triangles: 1 << 22,
            instances: 3,
        };
        assert_eq!(
            c.line(),
            "load 1.50 s, prepare 2.25 s (BVH 2.00 s), upload 0.50 s, first pixel at 5.00 s; \
             host peak 1.50 GiB; device 1.00 GiB + 512.00 MiB for 4194304 triangles (256 bytes a \
             triangle) and 3 instances"
        );
        assert!(peak_host_bytes().is_some_and(|b| b > 0));
    }
}

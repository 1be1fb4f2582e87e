//! How the path tracer's work is cut into kernels on a device (a setting of its state).

/// How the path tracer's work is cut into kernels on a device: the same estimator and random
/// numbers either way, so the same image.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize,
)]
pub enum PathKernel {
    /// The one measured faster on the kind of device (docs/PERFORMANCE.md).
    #[default]
    Auto,
    /// One kernel takes each path from the camera to its end, regenerating paths within a pass
    /// (shaders/path/pathtrace.comp).
    Mega,
    /// Streaming path tracing (Bikker 2012, 6.3.3): small kernels (regenerate, extend, shade,
    /// connect) over a stream of path states in memory, compacted by atomic counters
    /// (shaders/path/stream/).
    Streaming,
}

impl PathKernel {
    pub const NAMES: [&'static str; 3] = ["auto", "mega", "spt"];

    pub fn name(self) -> &'static str {
        match self {
            PathKernel::Auto => "auto",
            PathKernel::Mega => "mega",
            PathKernel::Streaming => "spt",
        }
    }

    pub fn by_name(name: &str) -> Option<PathKernel> {
        match name {
            "auto" => Some(PathKernel::Auto),
            "mega" => Some(PathKernel::Mega),
            "spt" | "streaming" => Some(PathKernel::Streaming),
            _ => None,
        }
    }

    /// As an image's metadata says it: `auto` with what it stands for on each kind of device.
    pub fn label(self) -> String {
        match self {
            PathKernel::Auto => format!(
                "auto ({} on CPU devices, {} on GPUs)",
                self.resolved(true).name(),
                self.resolved(false).name()
            ),
            k => k.name().into(),
        }
    }

    /// The kernel `Auto` stands for on a CPU device (`cpu`) or a GPU.
    pub fn resolved(self, cpu: bool) -> PathKernel {
        match self {
            PathKernel::Auto => {
                let _ = cpu;
                PathKernel::Mega
            }
            k => k,
        }
    }
}

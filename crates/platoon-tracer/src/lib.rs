//! platoon-tracer: one Vulkan device. It owns the device's memory (`gpu`), the kernels (GLSL
//! compiled at run time by shaderc, specialised per kernel variant), the device side of each
//! rendering method (`method`) and the dispatch of a band of pixels (`band`). It receives only
//! plain data from platoon-core.

mod band;
mod buffer;
mod commit;
mod context;
mod device_info;
mod dispatch;
mod filter;
mod globals;
mod gpu;
mod kernel;
mod memory;
pub mod memory_budget;
mod method;
mod ray_query;
pub mod stop;
mod structures;
mod submission;
mod tracer;

pub use commit::CommitStats;
pub use context::{list_devices, set_environment};
pub use device_info::{DeviceInfo, DeviceMemory};
pub use kernel::{cache_dir, sources_hash, Sampling};
pub use memory::{
    choose as choose_memory_paths, scene_array_bytes, ArrayPath, MemoryLimits, MemoryPath,
    SCENE_ARRAYS,
};
pub use method::{kernel_label, kernel_spirv, path_kernel};
pub use ray_query::Traversal;
pub use structures::StructureCounts;

/// The device-method API: what a rendering method's device half implements (`MethodPasses`)
/// and records a band with (`Recorder`), the buffers it grows (`ensure`, `GpuBuffer`), the
/// push constants its kernels read (`Push`: the band and `METHOD_WORDS` of its own), and the
/// registration of a method's device half with its GLSL from outside platoon's crates
/// (`register`, `DeviceMethodKind`). The built-in methods are written against it too.
pub mod device {
    pub use crate::buffer::GpuBuffer;
    pub use crate::globals::{method_words, Push, METHOD_WORDS};
    pub use crate::gpu::Gpu;
    pub use crate::method::registry::{refusal, register, DeviceMethodKind};
    pub use crate::method::{ensure, path_passes, MethodPasses, Recorder};
    pub use ash::vk;
    pub use gpu_allocator::MemoryLocation;
}
pub use tracer::{Tracer, TracerOptions};

/// Tracer failures; each says which device or file it concerns.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    #[error("Vulkan is not available: {0} (install libvulkan1 and mesa-vulkan-drivers)")]
    Loader(String),
    #[error("{context}: {result}")]
    Vulkan {
        context: &'static str,
        result: ash::vk::Result,
    },
    #[error("no Vulkan device {index}: {count} device(s) found (see `platoon devices`)")]
    NoDevice { index: usize, count: usize },
    #[error("device {device}: {message}")]
    Unsupported { device: String, message: String },
    #[error("GPU memory: {0}")]
    Memory(#[from] gpu_allocator::AllocationError),
    #[error("shader compilation failed: {0}")]
    Shader(String),
    #[error("{0}")]
    Invalid(String),
}

pub type Result<T> = std::result::Result<T, Error>;

pub(crate) trait VkContext<T> {
    fn ctx(self, context: &'static str) -> Result<T>;
}

impl<T> VkContext<T> for std::result::Result<T, ash::vk::Result> {
    fn ctx(self, context: &'static str) -> Result<T> {
        self.map_err(|result| Error::Vulkan { context, result })
    }
}

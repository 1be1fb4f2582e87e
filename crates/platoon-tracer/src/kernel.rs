//! The path-tracing kernel: GLSL from shaders/ (embedded in the binary), compiled at run time by
//! shaderc with the scene's feature defines, one compute pipeline per variant. SPIR-V and the
//! driver's pipeline cache are kept on disk so repeated runs and tests skip recompilation.

use std::collections::hash_map::DefaultHasher;
use std::hash::{Hash, Hasher};
use std::path::{Path, PathBuf};

use ash::vk;
use platoon_core::FeatureSet;

use crate::{Error, Result, VkContext};

const SOURCES: &[(&str, &str)] = &[
    (
        "pathtrace.comp",
        include_str!("../../../shaders/pathtrace.comp"),
    ),
    ("scene.glsl", include_str!("../../../shaders/scene.glsl")),
    (
        "scene_arrays.glsl",
        include_str!("../../../shaders/scene_arrays.glsl"),
    ),
    ("rng.glsl", include_str!("../../../shaders/rng.glsl")),
    (
        "sampling.glsl",
        include_str!("../../../shaders/sampling.glsl"),
    ),
    (
        "textures.glsl",
        include_str!("../../../shaders/textures.glsl"),
    ),
    (
        "intersect.glsl",
        include_str!("../../../shaders/intersect.glsl"),
    ),
    ("trace.glsl", include_str!("../../../shaders/trace.glsl")),
    (
        "surface.glsl",
        include_str!("../../../shaders/surface.glsl"),
    ),
    (
        "environment.glsl",
        include_str!("../../../shaders/environment.glsl"),
    ),
    ("bsdf.glsl", include_str!("../../../shaders/bsdf.glsl")),
    ("lights.glsl", include_str!("../../../shaders/lights.glsl")),
    ("path.glsl", include_str!("../../../shaders/path.glsl")),
    (
        "bsdf_probe.glsl",
        include_str!("../../../shaders/bsdf_probe.glsl"),
    ),
    (
        "igi/emit.comp",
        include_str!("../../../shaders/igi/emit.comp"),
    ),
    (
        "igi/camera.comp",
        include_str!("../../../shaders/igi/camera.comp"),
    ),
    (
        "igi/gather.comp",
        include_str!("../../../shaders/igi/gather.comp"),
    ),
    (
        "igi/pixel.glsl",
        include_str!("../../../shaders/igi/pixel.glsl"),
    ),
    (
        "igi/visibility.glsl",
        include_str!("../../../shaders/igi/visibility.glsl"),
    ),
];

/// Defines that select IGI's VPL pass and gather passes instead of its camera pass.
pub(crate) const EMIT_VPLS: &str = "IGI_EMIT_VPLS";
pub(crate) const GATHER: &str = "IGI_GATHER";

/// The main source of a kernel variant: IGI's passes when its defines say so, else the path
/// tracer.
fn main_source(defines: &[&str]) -> &'static str {
    if defines.contains(&EMIT_VPLS) {
        "igi/emit.comp"
    } else if defines.contains(&GATHER) {
        "igi/gather.comp"
    } else if defines.contains(&"METHOD_IGI") {
        "igi/camera.comp"
    } else {
        "pathtrace.comp"
    }
}

/// The kernel sources: the embedded ones, or with $PLATOON_SHADER_DIR set, the files of that
/// folder read now (kernel work on lavapipe then needs no rebuild per edit; the SPIR-V cache is
/// keyed by the text, so edits are never served stale).
fn sources() -> Result<Vec<(&'static str, String)>> {
    let Some(dir) = std::env::var_os("PLATOON_SHADER_DIR") else {
        return Ok(SOURCES.iter().map(|(n, s)| (*n, s.to_string())).collect());
    };
    let dir = PathBuf::from(dir);
    SOURCES
        .iter()
        .map(|(n, _)| {
            let path = dir.join(n);
            std::fs::read_to_string(&path)
                .map(|s| (*n, s))
                .map_err(|e| Error::Shader(format!("{} (PLATOON_SHADER_DIR): {e}", path.display())))
        })
        .collect()
}

/// A hash of the kernel's sources (embedded, or $PLATOON_SHADER_DIR's): what renders cached
/// across runs (a converged reference) are keyed by, so a changed kernel is never served stale.
pub fn sources_hash() -> Result<u64> {
    let sources = sources()?;
    let parts: Vec<&[u8]> = sources
        .iter()
        .flat_map(|(n, s)| [n.as_bytes(), s.as_bytes()])
        .collect();
    Ok(hash_of(&parts))
}

/// Which estimator the kernel uses. MIS is the renderer; the other two exist to test it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Sampling {
    #[default]
    Mis,
    /// BSDF sampling only (no next-event estimation).
    Bsdf,
    /// Light sampling only (emission found by BSDF rays is ignored after non-delta bounces).
    Light,
}

impl Sampling {
    fn define(self) -> Option<&'static str> {
        match self {
            Sampling::Mis => None,
            Sampling::Bsdf => Some("SAMPLING_BSDF"),
            Sampling::Light => Some("SAMPLING_LIGHT"),
        }
    }
}

/// Where SPIR-V and pipeline caches live: $PLATOON_CACHE_DIR, else $XDG_CACHE_HOME/platoon,
/// else ~/.cache/platoon.
pub fn cache_dir() -> PathBuf {
    if let Some(d) = std::env::var_os("PLATOON_CACHE_DIR") {
        return PathBuf::from(d);
    }
    let base = std::env::var_os("XDG_CACHE_HOME")
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".cache")))
        .unwrap_or_else(std::env::temp_dir);
    base.join("platoon")
}

/// The defines of one kernel variant, in a stable order.
pub fn defines(features: FeatureSet, sampling: Sampling) -> Vec<&'static str> {
    let mut d = features.defines();
    d.extend(sampling.define());
    d
}

fn hash_of(parts: &[&[u8]]) -> u64 {
    let mut h = DefaultHasher::new();
    for p in parts {
        p.hash(&mut h);
    }
    h.finish()
}

/// Writes `bytes` to `path` via a temporary file, ignoring failures (a cache is optional).
fn store(path: &Path, bytes: &[u8]) {
    let Some(dir) = path.parent() else { return };
    if std::fs::create_dir_all(dir).is_err() {
        return;
    }
    if let Ok(mut tmp) = tempfile::NamedTempFile::new_in(dir) {
        use std::io::Write;
        if tmp.write_all(bytes).is_ok() {
            let _ = tmp.persist(path);
        }
    }
}

/// SPIR-V for the variant, from the disk cache or compiled now.
pub(crate) fn spirv(defines: &[&str]) -> Result<Vec<u32>> {
    let sources = sources()?;
    let mut parts: Vec<&[u8]> = sources
        .iter()
        .flat_map(|(n, s)| [n.as_bytes(), s.as_bytes()])
        .collect();
    parts.extend(defines.iter().map(|d| d.as_bytes()));
    let key = hash_of(&parts);
    let path = cache_dir().join(format!("spirv-{key:016x}.spv"));
    if let Ok(bytes) = std::fs::read(&path) {
        if bytes.len() % 4 == 0 && bytes.len() >= 20 && bytes[..4] == 0x0723_0203u32.to_le_bytes() {
            return Ok(bytes
                .chunks_exact(4)
                .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
                .collect());
        }
    }
    let words = compile(&sources, defines)?;
    store(&path, bytemuck::cast_slice(&words));
    Ok(words)
}

fn compile(sources: &[(&'static str, String)], defines: &[&str]) -> Result<Vec<u32>> {
    let compiler = shaderc::Compiler::new().map_err(|e| Error::Shader(e.to_string()))?;
    let mut options = shaderc::CompileOptions::new().map_err(|e| Error::Shader(e.to_string()))?;
    options.set_target_env(
        shaderc::TargetEnv::Vulkan,
        shaderc::EnvVersion::Vulkan1_2 as u32,
    );
    options.set_optimization_level(shaderc::OptimizationLevel::Performance);
    for d in defines {
        options.add_macro_definition(d, Some("1"));
    }
    let includes = sources.to_vec();
    options.set_include_callback(move |name, _kind, _from, _depth| {
        includes
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(n, s)| shaderc::ResolvedInclude {
                resolved_name: n.to_string(),
                content: s.to_string(),
            })
            .ok_or_else(|| format!("no shader include named {name}"))
    });
    let main = main_source(defines);
    let (name, text) = sources
        .iter()
        .find(|(n, _)| *n == main)
        .expect("every main source is in SOURCES");
    let artifact = compiler
        .compile_into_spirv(
            text,
            shaderc::ShaderKind::Compute,
            name,
            "main",
            Some(&options),
        )
        .map_err(|e| Error::Shader(e.to_string()))?;
    Ok(artifact.as_binary().to_vec())
}

/// The driver's pipeline cache for one device, loaded from and saved to disk.
pub(crate) struct PipelineCache {
    pub cache: vk::PipelineCache,
    path: PathBuf,
}

impl PipelineCache {
    pub fn open(
        device: &ash::Device,
        props: &vk::PhysicalDeviceProperties,
    ) -> Result<PipelineCache> {
        let id = hash_of(&[
            &props.pipeline_cache_uuid,
            &props.vendor_id.to_le_bytes(),
            &props.device_id.to_le_bytes(),
        ]);
        let path = cache_dir().join(format!("pipelines-{id:016x}.bin"));
        let data = std::fs::read(&path).unwrap_or_default();
        let info = vk::PipelineCacheCreateInfo::default().initial_data(&data);
        let cache = match unsafe { device.create_pipeline_cache(&info, None) } {
            Ok(c) => c,
            // A corrupt or foreign cache file: start empty.
            Err(_) => unsafe {
                device.create_pipeline_cache(&vk::PipelineCacheCreateInfo::default(), None)
            }
            .ctx("creating the pipeline cache")?,
        };
        Ok(PipelineCache { cache, path })
    }

    pub fn save(&self, device: &ash::Device) {
        if let Ok(data) = unsafe { device.get_pipeline_cache_data(self.cache) } {
            if !data.is_empty() {
                store(&self.path, &data);
            }
        }
    }
}

/// A compute pipeline of one kernel variant.
pub(crate) struct Kernel {
    pub pipeline: vk::Pipeline,
    pub layout: vk::PipelineLayout,
}

impl Kernel {
    /// The pipeline of `defines`, reading the SSBO scene arrays through `set_layout` (set 0).
    pub fn new(
        device: &ash::Device,
        cache: &PipelineCache,
        defines: &[&str],
        set_layout: vk::DescriptorSetLayout,
    ) -> Result<Kernel> {
        let code = spirv(defines)?;
        let module = unsafe {
            device.create_shader_module(&vk::ShaderModuleCreateInfo::default().code(&code), None)
        }
        .ctx("creating the shader module")?;
        let ranges = [vk::PushConstantRange::default()
            .stage_flags(vk::ShaderStageFlags::COMPUTE)
            .size(std::mem::size_of::<crate::globals::Push>() as u32)];
        let set_layouts = [set_layout];
        let layout = unsafe {
            device.create_pipeline_layout(
                &vk::PipelineLayoutCreateInfo::default()
                    .set_layouts(&set_layouts)
                    .push_constant_ranges(&ranges),
                None,
            )
        }
        .ctx("creating the pipeline layout")?;
        let entry = c"main";
        let stage = vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::COMPUTE)
            .module(module)
            .name(entry);
        let info = vk::ComputePipelineCreateInfo::default()
            .stage(stage)
            .layout(layout);
        let result = unsafe { device.create_compute_pipelines(cache.cache, &[info], None) };
        unsafe { device.destroy_shader_module(module, None) };
        let pipeline = result
            .map_err(|(_, e)| e)
            .ctx("creating the compute pipeline")?[0];
        cache.save(device);
        Ok(Kernel { pipeline, layout })
    }

    pub fn destroy(&self, device: &ash::Device) {
        unsafe {
            device.destroy_pipeline(self.pipeline, None);
            device.destroy_pipeline_layout(self.layout, None);
        }
    }
}

/// Human-readable name of the kernel variant for a feature set (MIS estimator).
pub fn kernel_label(features: FeatureSet) -> String {
    let d = defines(features, Sampling::Mis);
    if d.is_empty() {
        "pathtrace.comp (no feature defines)".into()
    } else {
        format!("pathtrace.comp -D{}", d.join(" -D"))
    }
}

/// The SPIR-V of the kernel variant for a feature set and estimator (cached on disk).
pub fn kernel_spirv(features: FeatureSet, sampling: Sampling) -> Result<Vec<u32>> {
    spirv(&defines(features, sampling))
}

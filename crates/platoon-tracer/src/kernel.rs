//! The kernels: GLSL from shaders/ (embedded in the binary), compiled at run time by shaderc
//! from a method's entry file with the render's kernel-variant defines, one compute pipeline per
//! variant. SPIR-V and the driver's pipeline cache are kept on disk so repeated runs and tests
//! skip recompilation.

use std::collections::hash_map::DefaultHasher;
use std::hash::{Hash, Hasher};
use std::path::{Path, PathBuf};
use std::sync::RwLock;

use ash::vk;

use crate::{Error, Result, VkContext};

/// Every file under shaders/ by its path there (what `#include` names): the kernel registry's
/// sources, listed by build.rs. A kernel is an entry file among them (a method's `kernels`) and
/// its defines.
const SOURCES: &[(&str, &str)] = include!(concat!(env!("OUT_DIR"), "/shaders.rs"));

/// What writes a generated source's text.
type Writer = fn() -> String;

/// The sources made here rather than kept in shaders/ (what a table of the code declares,
/// which a hand-kept GLSL mirror would repeat), by name and what writes them: the accessors
/// of the frame's words.
const GENERATED: &[(&str, Writer)] = &[(
    crate::globals::FRAME_WORDS_INCLUDE,
    crate::globals::frame_words_glsl,
)];

/// Whether shaders/ has a file named `name`, or the tracer makes one (`GENERATED`).
pub(crate) fn built_in_source(name: &str) -> bool {
    SOURCES.iter().any(|(n, _)| *n == name) || GENERATED.iter().any(|(n, _)| *n == name)
}

/// The sources of methods registered from outside platoon's crates (`method::registry`), by
/// the names their entry files and `#include`s use.
static REGISTERED: RwLock<Vec<(&'static str, &'static str)>> = RwLock::new(Vec::new());

/// Whether a kernel source (shaders/'s or a registered one) is named `name`.
pub(crate) fn source_named(name: &str) -> bool {
    built_in_source(name)
        || REGISTERED
            .read()
            .unwrap_or_else(|e| e.into_inner())
            .iter()
            .any(|(n, _)| *n == name)
}

/// Adds registered sources (their names checked free by the caller, `source_named`).
pub(crate) fn add_sources(sources: &[(&'static str, &'static str)]) {
    let mut registered = REGISTERED.write().unwrap_or_else(|e| e.into_inner());
    registered.extend_from_slice(sources);
}

/// The kernel sources: shaders/'s (`built_in_sources`), then the registered ones, which may
/// include shaders/'s.
fn sources() -> Result<Vec<(&'static str, String)>> {
    let mut sources = built_in_sources()?;
    let registered = REGISTERED.read().unwrap_or_else(|e| e.into_inner());
    sources.extend(registered.iter().map(|(n, s)| (*n, s.to_string())));
    Ok(sources)
}

/// shaders/'s files: the embedded ones, or with $PLATOON_SHADER_DIR set, the files of that
/// folder read now (kernel work on lavapipe then needs no rebuild per edit; the SPIR-V cache is
/// keyed by the text, so edits are never served stale); then the generated ones. As many as
/// `built_in_count`, `SOURCES`' in its order first.
fn built_in_sources() -> Result<Vec<(&'static str, String)>> {
    let mut sources: Vec<(&'static str, String)> = match std::env::var_os("PLATOON_SHADER_DIR") {
        None => SOURCES.iter().map(|(n, s)| (*n, s.to_string())).collect(),
        Some(dir) => {
            let dir = PathBuf::from(dir);
            SOURCES
                .iter()
                .map(|(n, _)| {
                    let path = dir.join(n);
                    std::fs::read_to_string(&path)
                        .map(|s| (*n, s))
                        .map_err(|e| {
                            Error::Shader(format!("{} (PLATOON_SHADER_DIR): {e}", path.display()))
                        })
                })
                .collect::<Result<_>>()?
        }
    };
    sources.extend(GENERATED.iter().map(|(n, write)| (*n, write())));
    Ok(sources)
}

/// How many sources `built_in_sources` gives.
fn built_in_count() -> usize {
    SOURCES.len() + GENERATED.len()
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
    /// Every estimator, by the name the metadata and the command line give it.
    pub const NAMES: [(&'static str, Sampling); 3] = [
        ("mis", Sampling::Mis),
        ("bsdf", Sampling::Bsdf),
        ("light", Sampling::Light),
    ];

    pub fn name(self) -> &'static str {
        Self::NAMES
            .iter()
            .find(|(_, s)| *s == self)
            .map(|(n, _)| *n)
            .expect("every estimator is named")
    }

    pub fn by_name(name: &str) -> Option<Sampling> {
        Self::NAMES
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, s)| *s)
    }

    pub(crate) fn define(self) -> Option<&'static str> {
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

/// SPIR-V of the entry file `entry` with `defines`, from the disk cache or compiled now.
pub(crate) fn spirv(entry: &str, defines: &[&str]) -> Result<Vec<u32>> {
    let sources = sources()?;
    // A kernel of shaders/ includes only shaders/'s files: its key leaves out the registered
    // methods' (their registration does not make it compile again).
    let keyed = if built_in_source(entry) {
        &sources[..built_in_count()]
    } else {
        &sources[..]
    };
    let mut parts: Vec<&[u8]> = keyed
        .iter()
        .flat_map(|(n, s)| [n.as_bytes(), s.as_bytes()])
        .collect();
    parts.push(entry.as_bytes());
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
    let words = compile(&sources, entry, defines)?;
    store(&path, bytemuck::cast_slice(&words));
    Ok(words)
}

fn compile(sources: &[(&'static str, String)], entry: &str, defines: &[&str]) -> Result<Vec<u32>> {
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
    let (name, text) = sources.iter().find(|(n, _)| *n == entry).ok_or_else(|| {
        Error::Shader(format!(
            "no kernel entry file {entry} (shaders/ or a registered method's)"
        ))
    })?;
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
    /// The pipeline of `entry` with `defines`, reading the scene arrays through set 0 and a
    /// method's buffers through set 1 (`set_layouts`).
    pub fn new(
        device: &ash::Device,
        cache: &PipelineCache,
        entry: &str,
        defines: &[&str],
        set_layouts: &[vk::DescriptorSetLayout],
    ) -> Result<Kernel> {
        let code = spirv(entry, defines)?;
        let module = unsafe {
            device.create_shader_module(&vk::ShaderModuleCreateInfo::default().code(&code), None)
        }
        .ctx("creating the shader module")?;
        let ranges = [vk::PushConstantRange::default()
            .stage_flags(vk::ShaderStageFlags::COMPUTE)
            .size(std::mem::size_of::<crate::globals::Push>() as u32)];
        let layout = unsafe {
            device.create_pipeline_layout(
                &vk::PipelineLayoutCreateInfo::default()
                    .set_layouts(set_layouts)
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

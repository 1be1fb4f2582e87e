//! How the kernel reads each scene array: through a storage-buffer descriptor (SSBO) where the
//! array fits the device's `maxStorageBufferRange`, else through its buffer device address
//! (BDA). On lavapipe a BDA load is compiled into a loop over the SIMD lanes for every 32-bit
//! component, an SSBO load into one loop per whole vector (../shared/BRIEF.md section 7), so
//! SSBOs are much faster there; the image is the same bits either way (tests/determinism.rs).

use ash::vk;
use platoon_core::gpu_scene::GpuScene;

use crate::{Result, VkContext};

/// The memory path of the scene arrays.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum MemoryPath {
    /// SSBO for every array that fits the device's storage-buffer range, BDA for the rest.
    #[default]
    Auto,
    /// Every array through its device address (the path that has no size limit).
    DeviceAddress,
}

/// The read-only scene arrays in upload and binding order, with the define that makes the
/// kernel read each through its SSBO binding. Must match shaders/scene_arrays.glsl.
pub const SCENE_ARRAYS: [(&str, &str); 15] = [
    ("vertices", "SSBO_VERTICES"),
    ("triangle positions", "SSBO_TRI_POS"),
    ("triangles", "SSBO_TRIANGLES"),
    ("triangle lights", "SSBO_TRI_LIGHTS"),
    ("blas", "SSBO_BLAS"),
    ("tlas", "SSBO_TLAS"),
    ("instances", "SSBO_INSTANCES"),
    ("materials", "SSBO_MATERIALS"),
    ("textures", "SSBO_TEXTURES"),
    ("texels", "SSBO_TEXELS"),
    ("lights", "SSBO_LIGHTS"),
    ("light cdf", "SSBO_LIGHT_CDF"),
    ("environment", "SSBO_ENV_TEXELS"),
    ("environment marginal", "SSBO_ENV_MARGINAL"),
    ("environment conditional", "SSBO_ENV_CONDITIONAL"),
];

/// The bytes of each scene array of `s`, in `SCENE_ARRAYS` order.
pub fn scene_array_bytes(s: &GpuScene) -> [&[u8]; 15] {
    use bytemuck::cast_slice as b;
    [
        b(&s.vertices),
        b(&s.triangle_positions),
        b(&s.triangles),
        b(&s.triangle_lights),
        b(&s.blas_nodes),
        b(&s.tlas_nodes),
        b(&s.instances),
        b(&s.materials),
        b(&s.textures),
        b(&s.texels),
        b(&s.lights),
        b(&s.light_cdf),
        b(&s.env.texels),
        b(&s.env.marginal_cdf),
        b(&s.env.conditional_cdf),
    ]
}

/// Which scene arrays are bound as SSBOs, chosen per array from its size.
pub fn choose(sizes: &[u64], max_range: u64, path: MemoryPath) -> Vec<bool> {
    sizes
        .iter()
        .map(|&s| path == MemoryPath::Auto && s <= max_range)
        .collect()
}

/// The kernel defines of a choice.
pub fn defines(ssbo: &[bool]) -> Vec<&'static str> {
    SCENE_ARRAYS
        .iter()
        .zip(ssbo)
        .filter(|(_, &s)| s)
        .map(|((_, d), _)| *d)
        .collect()
}

/// The descriptor set binding the SSBO arrays (binding i = `SCENE_ARRAYS[i]`).
pub(crate) struct SceneDescriptors {
    pub layout: vk::DescriptorSetLayout,
    pub pool: vk::DescriptorPool,
    pub set: vk::DescriptorSet,
}

impl SceneDescriptors {
    /// Binds `buffers[i]` at binding i wherever `ssbo[i]`.
    pub fn new(device: &ash::Device, buffers: &[vk::Buffer], ssbo: &[bool]) -> Result<Self> {
        let bound: Vec<u32> = (0..ssbo.len() as u32)
            .filter(|&i| ssbo[i as usize])
            .collect();
        let bindings: Vec<vk::DescriptorSetLayoutBinding> = bound
            .iter()
            .map(|&i| {
                vk::DescriptorSetLayoutBinding::default()
                    .binding(i)
                    .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                    .descriptor_count(1)
                    .stage_flags(vk::ShaderStageFlags::COMPUTE)
            })
            .collect();
        let layout = unsafe {
            device.create_descriptor_set_layout(
                &vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings),
                None,
            )
        }
        .ctx("creating the scene descriptor set layout")?;
        let sizes = [vk::DescriptorPoolSize::default()
            .ty(vk::DescriptorType::STORAGE_BUFFER)
            .descriptor_count(bound.len().max(1) as u32)];
        let pool = unsafe {
            device.create_descriptor_pool(
                &vk::DescriptorPoolCreateInfo::default()
                    .max_sets(1)
                    .pool_sizes(&sizes),
                None,
            )
        }
        .ctx("creating the scene descriptor pool")?;
        let layouts = [layout];
        let set = unsafe {
            device.allocate_descriptor_sets(
                &vk::DescriptorSetAllocateInfo::default()
                    .descriptor_pool(pool)
                    .set_layouts(&layouts),
            )
        }
        .ctx("allocating the scene descriptor set")?[0];
        let infos: Vec<[vk::DescriptorBufferInfo; 1]> = bound
            .iter()
            .map(|&i| {
                [vk::DescriptorBufferInfo::default()
                    .buffer(buffers[i as usize])
                    .offset(0)
                    .range(vk::WHOLE_SIZE)]
            })
            .collect();
        let writes: Vec<vk::WriteDescriptorSet> = bound
            .iter()
            .zip(&infos)
            .map(|(&i, info)| {
                vk::WriteDescriptorSet::default()
                    .dst_set(set)
                    .dst_binding(i)
                    .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                    .buffer_info(info)
            })
            .collect();
        unsafe { device.update_descriptor_sets(&writes, &[]) };
        Ok(SceneDescriptors { layout, pool, set })
    }

    pub fn destroy(&self, device: &ash::Device) {
        unsafe {
            device.destroy_descriptor_pool(self.pool, None);
            device.destroy_descriptor_set_layout(self.layout, None);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arrays_past_the_storage_range_go_by_address() {
        let mut sizes = [16u64; 15];
        sizes[9] = 149_000_000; // a texel array past lavapipe's 128 MiB
        let auto = choose(&sizes, 128 << 20, MemoryPath::Auto);
        assert_eq!(auto.iter().filter(|&&s| s).count(), 14);
        assert!(!auto[9]);
        assert!(!defines(&auto).contains(&"SSBO_TEXELS"));
        assert!(choose(&sizes, 128 << 20, MemoryPath::DeviceAddress)
            .iter()
            .all(|&s| !s));
    }
}

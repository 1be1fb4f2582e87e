//! How the kernel reads each scene array: through a uniform texel buffer, a storage-buffer
//! descriptor (SSBO) or its buffer device address (BDA), chosen per array. On lavapipe a BDA load
//! is compiled into a loop over the SIMD lanes for every 32-bit component and an SSBO load into
//! one such loop per vector, while a texel fetch is straight-line vector loads (llvmpipe's
//! texture gather), so texel buffers are the fastest path there; on GPUs storage buffers are the
//! conventional choice. From Mesa 25 on, lavapipe's storage-buffer loads are the faster ones
//! (docs/PERFORMANCE.md, "A newer lavapipe"). The image is the same bits on every path
//! (tests/frame/determinism.rs), and on Mesa 22.3 and 25.0.

use ash::vk;
use platoon_core::flatten::GpuScene;

use crate::{Result, VkContext};

/// The memory-path policy of a tracer.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum MemoryPath {
    /// Texel buffers on CPU devices (lavapipe before Mesa 25), storage buffers on GPUs and newer
    /// lavapipe, each where the array fits the device's limits; device addresses for the rest.
    #[default]
    Auto,
    /// Texel buffers wherever the array fits `maxTexelBufferElements`.
    TexelBuffers,
    /// Storage buffers wherever the array fits `maxStorageBufferRange`.
    StorageBuffers,
    /// Every array through its device address (the path that has no size limit).
    DeviceAddress,
}

/// How the kernel reads one scene array.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ArrayPath {
    Texel,
    Storage,
    Address,
}

impl ArrayPath {
    pub fn describe(self) -> &'static str {
        match self {
            ArrayPath::Texel => "texel buffer",
            ArrayPath::Storage => "storage buffer",
            ArrayPath::Address => "device address",
        }
    }
}

/// The device limits the choice depends on.
#[derive(Clone, Copy, Debug)]
pub struct MemoryLimits {
    pub max_storage_buffer_range: u64,
    pub max_texel_buffer_elements: u64,
    /// Texel fetches are the device's cheapest loads (lavapipe before Mesa 25: `texel_fastest`).
    pub texel_fastest: bool,
}

/// The first Mesa release whose lavapipe reads storage buffers faster than texel buffers
/// (measured on 25.0.7 against 22.3.6; the releases between were not measured).
pub const MESA_STORAGE_FASTEST: u32 = 25;

/// Whether texel fetches are a device's cheapest loads: on CPU devices (lavapipe), unless its
/// Mesa release is one whose storage-buffer loads are faster. Another CPU driver keeps texel
/// buffers, the measured choice for CPUs.
pub fn texel_fastest(cpu: bool, mesa: Option<(u32, u32)>) -> bool {
    cpu && mesa.is_none_or(|(major, _)| major < MESA_STORAGE_FASTEST)
}

/// The read-only scene arrays in upload and binding order: core's table, which
/// shaders/scene_arrays.glsl is checked against.
pub use platoon_core::flatten::arrays::ARRAYS as SCENE_ARRAYS;

/// The bytes of each scene array of `s`, in `SCENE_ARRAYS` order.
pub fn scene_array_bytes(s: &GpuScene) -> [&[u8]; SCENE_ARRAYS.len()] {
    s.array_bytes()
}

/// The path of each scene array of these byte sizes (`SCENE_ARRAYS` order).
pub fn choose(sizes: &[u64], limits: &MemoryLimits, policy: MemoryPath) -> Vec<ArrayPath> {
    let texel = match policy {
        MemoryPath::Auto => limits.texel_fastest,
        MemoryPath::TexelBuffers => true,
        MemoryPath::StorageBuffers | MemoryPath::DeviceAddress => false,
    };
    let storage = policy != MemoryPath::DeviceAddress;
    sizes
        .iter()
        .zip(&SCENE_ARRAYS)
        .map(|(&size, array)| {
            if texel && size / array.texel_bytes <= limits.max_texel_buffer_elements {
                ArrayPath::Texel
            } else if storage && size <= limits.max_storage_buffer_range {
                ArrayPath::Storage
            } else {
                ArrayPath::Address
            }
        })
        .collect()
}

/// The kernel defines of a choice.
pub fn defines(paths: &[ArrayPath]) -> Vec<&'static str> {
    SCENE_ARRAYS
        .iter()
        .zip(paths)
        .filter_map(|(a, p)| match p {
            ArrayPath::Texel => Some(a.texel_define),
            ArrayPath::Storage => Some(a.storage_define),
            ArrayPath::Address => None,
        })
        .collect()
}

/// The binding of the frame block: `Globals` read as a uniform buffer (its per-render constants;
/// shaders/common/scene.glsl), after the scene arrays' bindings.
pub(crate) const FRAME_BINDING: u32 = SCENE_ARRAYS.len() as u32;

/// The binding of the scene's top-level acceleration structure, with ray queries
/// (`TRAVERSAL_RAY_QUERY` in shaders/common/trace.glsl).
pub(crate) const STRUCTURE_BINDING: u32 = FRAME_BINDING + 1;

/// The descriptor set binding the scene arrays read through texel or storage buffers (binding
/// i = `SCENE_ARRAYS[i]`), the buffer views of the texel ones, the frame block and, with ray
/// queries, the scene's top-level acceleration structure.
pub(crate) struct SceneDescriptors {
    pub layout: vk::DescriptorSetLayout,
    pub pool: vk::DescriptorPool,
    pub set: vk::DescriptorSet,
    views: Vec<vk::BufferView>,
}

fn descriptor_type(path: ArrayPath) -> Option<vk::DescriptorType> {
    match path {
        ArrayPath::Texel => Some(vk::DescriptorType::UNIFORM_TEXEL_BUFFER),
        ArrayPath::Storage => Some(vk::DescriptorType::STORAGE_BUFFER),
        ArrayPath::Address => None,
    }
}

impl SceneDescriptors {
    /// Binds `buffers[i]` at binding i wherever `paths[i]` is a descriptor path, `frame` (the
    /// tracer's `Globals`) at `FRAME_BINDING` and `structure` at `STRUCTURE_BINDING`.
    pub fn new(
        device: &ash::Device,
        buffers: &[vk::Buffer],
        paths: &[ArrayPath],
        frame: vk::Buffer,
        structure: Option<vk::AccelerationStructureKHR>,
    ) -> Result<Self> {
        let mut bound: Vec<(u32, vk::DescriptorType)> = paths
            .iter()
            .enumerate()
            .filter_map(|(i, &p)| descriptor_type(p).map(|t| (i as u32, t)))
            .collect();
        bound.push((FRAME_BINDING, vk::DescriptorType::UNIFORM_BUFFER));
        if structure.is_some() {
            bound.push((
                STRUCTURE_BINDING,
                vk::DescriptorType::ACCELERATION_STRUCTURE_KHR,
            ));
        }
        let bindings: Vec<vk::DescriptorSetLayoutBinding> = bound
            .iter()
            .map(|&(i, ty)| {
                vk::DescriptorSetLayoutBinding::default()
                    .binding(i)
                    .descriptor_type(ty)
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
        let count = |ty| bound.iter().filter(|(_, t)| *t == ty).count().max(1) as u32;
        let sizes = [
            vk::DescriptorPoolSize::default()
                .ty(vk::DescriptorType::STORAGE_BUFFER)
                .descriptor_count(count(vk::DescriptorType::STORAGE_BUFFER)),
            vk::DescriptorPoolSize::default()
                .ty(vk::DescriptorType::UNIFORM_TEXEL_BUFFER)
                .descriptor_count(count(vk::DescriptorType::UNIFORM_TEXEL_BUFFER)),
            vk::DescriptorPoolSize::default()
                .ty(vk::DescriptorType::UNIFORM_BUFFER)
                .descriptor_count(1),
            vk::DescriptorPoolSize::default()
                .ty(vk::DescriptorType::ACCELERATION_STRUCTURE_KHR)
                .descriptor_count(1),
        ];
        // The structures' size only where the device has their extension.
        let sizes = &sizes[..if structure.is_some() { 4 } else { 3 }];
        let pool = unsafe {
            device.create_descriptor_pool(
                &vk::DescriptorPoolCreateInfo::default()
                    .max_sets(1)
                    .pool_sizes(sizes),
                None,
            )
        }
        .ctx("creating the scene descriptor pool")?;
        let mut d = SceneDescriptors {
            layout,
            pool,
            set: vk::DescriptorSet::null(),
            views: Vec::new(),
        };
        let layouts = [layout];
        d.set = unsafe {
            device.allocate_descriptor_sets(
                &vk::DescriptorSetAllocateInfo::default()
                    .descriptor_pool(pool)
                    .set_layouts(&layouts),
            )
        }
        .ctx("allocating the scene descriptor set")?[0];
        d.write(device, buffers, paths)?;
        let info = [vk::DescriptorBufferInfo::default()
            .buffer(frame)
            .offset(0)
            .range(vk::WHOLE_SIZE)];
        let write = vk::WriteDescriptorSet::default()
            .dst_set(d.set)
            .dst_binding(FRAME_BINDING)
            .descriptor_type(vk::DescriptorType::UNIFORM_BUFFER)
            .buffer_info(&info);
        unsafe { device.update_descriptor_sets(&[write], &[]) };
        if let Some(structure) = structure {
            d.write_structure(device, structure);
        }
        Ok(d)
    }

    /// Points `STRUCTURE_BINDING` at `structure` (a set made with one, between frames).
    pub fn write_structure(&self, device: &ash::Device, structure: vk::AccelerationStructureKHR) {
        let structures = [structure];
        let mut info = vk::WriteDescriptorSetAccelerationStructureKHR::default()
            .acceleration_structures(&structures);
        // No buffer or image info: the count is given by hand.
        let write = vk::WriteDescriptorSet::default()
            .dst_set(self.set)
            .dst_binding(STRUCTURE_BINDING)
            .descriptor_type(vk::DescriptorType::ACCELERATION_STRUCTURE_KHR)
            .descriptor_count(1)
            .push_next(&mut info);
        unsafe { device.update_descriptor_sets(&[write], &[]) };
    }

    /// Points the bindings at `buffers` (the same paths as the set was made for): after a
    /// buffer was replaced, the set, its layout and the pipelines built on it stay.
    pub fn write(
        &mut self,
        device: &ash::Device,
        buffers: &[vk::Buffer],
        paths: &[ArrayPath],
    ) -> Result<()> {
        for &v in &self.views {
            unsafe { device.destroy_buffer_view(v, None) };
        }
        self.views.clear();
        let mut views = Vec::new();
        let mut infos = Vec::new();
        for (i, &path) in paths.iter().enumerate() {
            match path {
                ArrayPath::Texel => {
                    let format = match SCENE_ARRAYS[i].texel_bytes {
                        4 => vk::Format::R32_UINT,
                        _ => vk::Format::R32G32B32A32_UINT,
                    };
                    let info = vk::BufferViewCreateInfo::default()
                        .buffer(buffers[i])
                        .format(format)
                        .offset(0)
                        .range(vk::WHOLE_SIZE);
                    let view = unsafe { device.create_buffer_view(&info, None) };
                    let view = view.ctx("creating a texel buffer view")?;
                    self.views.push(view);
                    views.push((i as u32, [view]));
                }
                ArrayPath::Storage => {
                    let info = vk::DescriptorBufferInfo::default()
                        .buffer(buffers[i])
                        .offset(0)
                        .range(vk::WHOLE_SIZE);
                    infos.push((i as u32, [info]));
                }
                ArrayPath::Address => {}
            }
        }
        let mut writes: Vec<vk::WriteDescriptorSet> = infos
            .iter()
            .map(|(i, info)| {
                vk::WriteDescriptorSet::default()
                    .dst_set(self.set)
                    .dst_binding(*i)
                    .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                    .buffer_info(info)
            })
            .collect();
        writes.extend(views.iter().map(|(i, view)| {
            vk::WriteDescriptorSet::default()
                .dst_set(self.set)
                .dst_binding(*i)
                .descriptor_type(vk::DescriptorType::UNIFORM_TEXEL_BUFFER)
                .texel_buffer_view(view)
        }));
        unsafe { device.update_descriptor_sets(&writes, &[]) };
        Ok(())
    }

    pub fn destroy(&self, device: &ash::Device) {
        unsafe {
            for &v in &self.views {
                device.destroy_buffer_view(v, None);
            }
            device.destroy_descriptor_pool(self.pool, None);
            device.destroy_descriptor_set_layout(self.layout, None);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const LAVAPIPE: MemoryLimits = MemoryLimits {
        max_storage_buffer_range: 128 << 20,
        max_texel_buffer_elements: 128 << 20,
        texel_fastest: true,
    };

    #[test]
    fn arrays_past_the_limits_fall_back_to_the_next_path() {
        let mut sizes = [16u64; SCENE_ARRAYS.len()];
        sizes[9] = 149_000_000; // a texel array past lavapipe's 128 MiB storage range
        sizes[4] = 3 << 30; // 192 Mi texels: past the texel limit too
        let auto = choose(&sizes, &LAVAPIPE, MemoryPath::Auto);
        assert_eq!(auto[9], ArrayPath::Texel);
        assert_eq!(auto[4], ArrayPath::Address);
        assert_eq!(
            auto.iter().filter(|&&p| p == ArrayPath::Texel).count(),
            SCENE_ARRAYS.len() - 1
        );
        let storage = choose(&sizes, &LAVAPIPE, MemoryPath::StorageBuffers);
        assert_eq!(storage[9], ArrayPath::Address);
        assert!(!defines(&storage).contains(&"SSBO_TEXELS"));
        assert!(defines(&storage).contains(&"SSBO_VERTICES"));
        let gpu = MemoryLimits {
            texel_fastest: false,
            ..LAVAPIPE
        };
        assert_eq!(choose(&sizes, &gpu, MemoryPath::Auto), storage);
        assert!(choose(&sizes, &LAVAPIPE, MemoryPath::DeviceAddress)
            .iter()
            .all(|&p| p == ArrayPath::Address));
    }

    #[test]
    fn lavapipe_reads_texel_buffers_before_mesa_25_and_storage_buffers_after() {
        assert!(texel_fastest(true, Some((22, 3))));
        assert!(texel_fastest(true, Some((24, 3))));
        assert!(!texel_fastest(true, Some((25, 0))));
        assert!(!texel_fastest(true, Some((26, 1))));
        assert!(texel_fastest(true, None), "a CPU driver not from Mesa");
        assert!(!texel_fastest(false, Some((22, 3))), "RADV");
        assert!(!texel_fastest(false, None));
    }
}

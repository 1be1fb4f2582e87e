//! The device's acceleration structures of a scene (the ray-query traversal, `ray_query.rs`):
//! a bottom level per mesh built straight from the triangle positions the kernel reads (three
//! corners a triangle, in the mesh's BVH leaf order, so a hit's triangle is the mesh's first
//! plus the primitive's index: the instance's custom index holds that first one), and a top
//! level of the scene's instances in their own order (a hit's instance is the query's instance
//! id). Built on the device (lavapipe offers no host builds) when the tracer takes the scene.

use std::collections::HashMap;

use ash::vk;
use gpu_allocator::MemoryLocation;
use platoon_core::flatten::{GpuInstance, GpuScene, MeshRegion};

use crate::buffer::GpuBuffer;
use crate::gpu::Gpu;
use crate::{Error, Result, VkContext};

/// One acceleration structure and the buffer it lives in.
struct Structure {
    handle: vk::AccelerationStructureKHR,
    buffer: GpuBuffer,
}

/// A scene's structures on one device: what the kernels' ray queries traverse.
pub(crate) struct Structures {
    loader: ash::khr::acceleration_structure::Device,
    bottom: Vec<Structure>,
    top: Structure,
    instances: GpuBuffer,
}

/// A custom index holds 24 bits: the ray-query traversal takes scenes of fewer triangles.
const MAX_TRIANGLES: u64 = 1 << 24;

/// The bytes of one triangle's corners in the triangle positions (three vec4).
const TRIANGLE_BYTES: u64 = 48;

/// What the structures are built from, taken from a scene before its large arrays go: its
/// meshes' places, its instances, its triangle count and whether any triangle is alpha-tested.
pub(crate) struct SceneShape {
    regions: Vec<MeshRegion>,
    instances: Vec<GpuInstance>,
    triangles: u64,
    opaque: bool,
}

impl SceneShape {
    pub(crate) fn of(scene: &GpuScene) -> SceneShape {
        SceneShape {
            regions: scene.regions.clone(),
            instances: scene.instances.clone(),
            triangles: scene.triangle_count as u64,
            opaque: !(scene.features.alpha_mask || scene.features.alpha_blend),
        }
    }
}

impl Structures {
    /// The structures of a scene of `shape`, built from its triangle positions at `positions`
    /// (the device address of the tracer's copy, already written). Alpha-tested triangles are
    /// left to the kernel's candidate loop (their geometry is not opaque) where the scene has
    /// any.
    pub(crate) fn build(gpu: &mut Gpu, shape: &SceneShape, positions: u64) -> Result<Structures> {
        if shape.triangles >= MAX_TRIANGLES {
            return Err(Error::Unsupported {
                device: gpu.ctx.info.name.clone(),
                message: format!(
                    "the ray-query traversal takes scenes of fewer than {MAX_TRIANGLES} triangles \
                     (an instance's custom index): this one has {} (use --traversal own)",
                    shape.triangles
                ),
            });
        }
        let loader = ash::khr::acceleration_structure::Device::new(&gpu.ctx.instance, gpu.device());
        let mut s = Structures {
            loader,
            bottom: Vec::new(),
            top: Structure {
                handle: vk::AccelerationStructureKHR::null(),
                buffer: GpuBuffer::empty(),
            },
            instances: GpuBuffer::empty(),
        };
        match s.build_levels(gpu, shape, positions) {
            Ok(()) => Ok(s),
            Err(e) => {
                s.destroy(gpu);
                Err(e)
            }
        }
    }

    /// Every mesh's bottom level, then the top level: one submission each (the fence orders
    /// them), each with its own scratch.
    fn build_levels(&mut self, gpu: &mut Gpu, shape: &SceneShape, positions: u64) -> Result<()> {
        let mut meshes = HashMap::new();
        for region in &shape.regions {
            if region.triangle_count > 0 {
                let first = positions + TRIANGLE_BYTES * region.triangle_base as u64;
                let built = self.build_bottom(gpu, first, region.triangle_count, shape.opaque)?;
                meshes.insert(region.root, (self.bottom.len(), region.triangle_base));
                self.bottom.push(built);
            }
        }
        self.build_top(gpu, &shape.instances, &meshes)
    }

    /// The top level, which the kernels' descriptor set binds.
    pub(crate) fn top(&self) -> vk::AccelerationStructureKHR {
        self.top.handle
    }

    fn build_bottom(
        &self,
        gpu: &mut Gpu,
        first: u64,
        count: u32,
        opaque: bool,
    ) -> Result<Structure> {
        let triangles = vk::AccelerationStructureGeometryTrianglesDataKHR::default()
            .vertex_format(vk::Format::R32G32B32_SFLOAT)
            .vertex_data(vk::DeviceOrHostAddressConstKHR {
                device_address: first,
            })
            .vertex_stride(16)
            .max_vertex(3 * count - 1)
            .index_type(vk::IndexType::NONE_KHR);
        let flags = if opaque {
            vk::GeometryFlagsKHR::OPAQUE
        } else {
            vk::GeometryFlagsKHR::NO_DUPLICATE_ANY_HIT_INVOCATION
        };
        let geometry = vk::AccelerationStructureGeometryKHR::default()
            .geometry_type(vk::GeometryTypeKHR::TRIANGLES)
            .geometry(vk::AccelerationStructureGeometryDataKHR { triangles })
            .flags(flags);
        self.build_one(
            gpu,
            vk::AccelerationStructureTypeKHR::BOTTOM_LEVEL,
            geometry,
            count,
        )
    }

    /// The top level over `instances`, each placing the bottom level of its mesh (`meshes`: by
    /// the root of the mesh's BVH, which the instance names, its bottom level and first
    /// triangle).
    fn build_top(
        &mut self,
        gpu: &mut Gpu,
        instances: &[GpuInstance],
        meshes: &HashMap<u32, (usize, u32)>,
    ) -> Result<()> {
        let addresses: Vec<u64> = self
            .bottom
            .iter()
            .map(|b| unsafe {
                self.loader.get_acceleration_structure_device_address(
                    &vk::AccelerationStructureDeviceAddressInfoKHR::default()
                        .acceleration_structure(b.handle),
                )
            })
            .collect();
        let records: Vec<vk::AccelerationStructureInstanceKHR> = instances
            .iter()
            .map(|inst| {
                // An instance of an empty mesh is kept in its place (the query's instance id is
                // the scene's index) and never hit: mask 0, any structure referenced.
                let (mask, reference, first) = match meshes.get(&inst.blas_root) {
                    Some(&(b, first)) => (0xff, addresses[b], first),
                    None => (0, addresses.first().copied().unwrap_or(0), 0),
                };
                let m = inst.object_to_world;
                vk::AccelerationStructureInstanceKHR {
                    transform: vk::TransformMatrixKHR {
                        matrix: [
                            m[0][0], m[0][1], m[0][2], m[0][3], m[1][0], m[1][1], m[1][2], m[1][3],
                            m[2][0], m[2][1], m[2][2], m[2][3],
                        ],
                    },
                    instance_custom_index_and_mask: vk::Packed24_8::new(first, mask),
                    instance_shader_binding_table_record_offset_and_flags: vk::Packed24_8::new(
                        0,
                        vk::GeometryInstanceFlagsKHR::TRIANGLE_FACING_CULL_DISABLE.as_raw() as u8,
                    ),
                    acceleration_structure_reference: vk::AccelerationStructureReferenceKHR {
                        device_handle: reference,
                    },
                }
            })
            .collect();
        let records: Vec<_> = if addresses.is_empty() {
            Vec::new()
        } else {
            records
        };
        let bytes = std::mem::size_of_val(records.as_slice());
        self.instances = gpu.buffer(
            "structure instances",
            bytes as u64,
            vk::BufferUsageFlags::ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_KHR,
            MemoryLocation::CpuToGpu,
        )?;
        // SAFETY: the records are plain `repr(C)` data the device reads as bytes.
        let raw = unsafe { std::slice::from_raw_parts(records.as_ptr() as *const u8, bytes) };
        self.instances.mapped()[..bytes].copy_from_slice(raw);
        let data = vk::AccelerationStructureGeometryInstancesDataKHR::default()
            .array_of_pointers(false)
            .data(vk::DeviceOrHostAddressConstKHR {
                device_address: self.instances.address,
            });
        let geometry = vk::AccelerationStructureGeometryKHR::default()
            .geometry_type(vk::GeometryTypeKHR::INSTANCES)
            .geometry(vk::AccelerationStructureGeometryDataKHR { instances: data });
        self.top = self.build_one(
            gpu,
            vk::AccelerationStructureTypeKHR::TOP_LEVEL,
            geometry,
            records.len() as u32,
        )?;
        Ok(())
    }

    /// One structure of `ty` over `geometry` of `count` primitives, built and waited for.
    fn build_one(
        &self,
        gpu: &mut Gpu,
        ty: vk::AccelerationStructureTypeKHR,
        geometry: vk::AccelerationStructureGeometryKHR,
        count: u32,
    ) -> Result<Structure> {
        let geometries = [geometry];
        let mut info = vk::AccelerationStructureBuildGeometryInfoKHR::default()
            .ty(ty)
            .flags(vk::BuildAccelerationStructureFlagsKHR::PREFER_FAST_TRACE)
            .mode(vk::BuildAccelerationStructureModeKHR::BUILD)
            .geometries(&geometries);
        let mut sizes = vk::AccelerationStructureBuildSizesInfoKHR::default();
        unsafe {
            self.loader.get_acceleration_structure_build_sizes(
                vk::AccelerationStructureBuildTypeKHR::DEVICE,
                &info,
                &[count],
                &mut sizes,
            )
        };
        let buffer = gpu.buffer(
            "acceleration structure",
            sizes.acceleration_structure_size,
            vk::BufferUsageFlags::ACCELERATION_STRUCTURE_STORAGE_KHR,
            MemoryLocation::GpuOnly,
        )?;
        let create = vk::AccelerationStructureCreateInfoKHR::default()
            .buffer(buffer.buffer)
            .size(sizes.acceleration_structure_size)
            .ty(ty);
        let handle = unsafe { self.loader.create_acceleration_structure(&create, None) }
            .ctx("creating an acceleration structure")?;
        // The scratch's address rounded up to the device's alignment.
        let align = gpu.ctx.scratch_alignment.unwrap_or(256);
        let mut scratch = gpu.buffer(
            "structure scratch",
            sizes.build_scratch_size + align,
            vk::BufferUsageFlags::STORAGE_BUFFER,
            MemoryLocation::GpuOnly,
        )?;
        info = info
            .dst_acceleration_structure(handle)
            .scratch_data(vk::DeviceOrHostAddressKHR {
                device_address: scratch.address.next_multiple_of(align),
            });
        let range = [vk::AccelerationStructureBuildRangeInfoKHR::default().primitive_count(count)];
        let loader = &self.loader;
        let built = gpu.submit(|d, cb| unsafe {
            loader.cmd_build_acceleration_structures(cb, &[info], &[&range]);
            // What the build wrote, for the builds and kernels of later submissions.
            let barrier = vk::MemoryBarrier::default()
                .src_access_mask(vk::AccessFlags::ACCELERATION_STRUCTURE_WRITE_KHR)
                .dst_access_mask(vk::AccessFlags::ACCELERATION_STRUCTURE_READ_KHR);
            d.cmd_pipeline_barrier(
                cb,
                vk::PipelineStageFlags::ACCELERATION_STRUCTURE_BUILD_KHR,
                vk::PipelineStageFlags::ACCELERATION_STRUCTURE_BUILD_KHR
                    | vk::PipelineStageFlags::COMPUTE_SHADER,
                vk::DependencyFlags::empty(),
                &[barrier],
                &[],
                &[],
            );
        });
        gpu.destroy_buffer(&mut scratch);
        built?;
        Ok(Structure { handle, buffer })
    }

    /// Frees the structures and their buffers (the device idle).
    pub(crate) fn destroy(&mut self, gpu: &mut Gpu) {
        for mut s in self
            .bottom
            .drain(..)
            .chain(std::iter::once(std::mem::replace(
                &mut self.top,
                Structure {
                    handle: vk::AccelerationStructureKHR::null(),
                    buffer: GpuBuffer::empty(),
                },
            )))
        {
            if s.handle != vk::AccelerationStructureKHR::null() {
                unsafe { self.loader.destroy_acceleration_structure(s.handle, None) };
            }
            gpu.destroy_buffer(&mut s.buffer);
        }
        gpu.destroy_buffer(&mut self.instances);
    }
}

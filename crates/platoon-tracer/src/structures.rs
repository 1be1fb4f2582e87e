//! The device's acceleration structures of a scene (the ray-query traversal, `ray_query.rs`):
//! a bottom level per mesh built straight from the triangle positions the kernel reads (three
//! corners a triangle, in the mesh's BVH leaf order, so a hit's triangle is the mesh's first
//! plus the primitive's index: the instance's custom index holds that first one), and a top
//! level of the scene's instances in their own order (a hit's instance is the query's instance
//! id). Built on the device (lavapipe offers no host builds) when the tracer takes the scene,
//! and again where a living scene's commit changed what they hold (`follow`).

use std::collections::HashMap;

use ash::vk;
use gpu_allocator::MemoryLocation;
use platoon_core::flatten::arrays::SceneArray;
use platoon_core::flatten::commit::Commit;
use platoon_core::flatten::{GpuInstance, GpuScene, MeshRegion};
use platoon_core::SceneFeatures;

use crate::buffer::GpuBuffer;
use crate::gpu::Gpu;
use crate::ray_query::MAX_TRIANGLES;
use crate::{Error, Result, VkContext};

/// One acceleration structure and the buffer it lives in.
struct Structure {
    handle: vk::AccelerationStructureKHR,
    buffer: GpuBuffer,
}

/// A scene's structures on one device: what the kernels' ray queries traverse, and what they
/// were built from, which a living scene's commits update (`follow`).
pub(crate) struct Structures {
    loader: ash::khr::acceleration_structure::Device,
    /// The scene as the structures hold it: its meshes, its instances (the host's copy, which
    /// a commit's instance bytes change), whether every triangle is opaque.
    shape: SceneShape,
    /// The device address of the triangle positions the bottom levels were built from.
    positions: u64,
    /// Each mesh's bottom level (by its index in the shape's regions); None for an empty mesh.
    bottom: Vec<Option<Structure>>,
    top: Structure,
    instances: GpuBuffer,
}

/// The bytes of one triangle's corners in the triangle positions (three vec4).
const TRIANGLE_BYTES: u64 = 48;

/// What the structures are built from, taken from a scene before its large arrays go: its
/// meshes' places, its instances and whether every triangle is opaque (none alpha-tested).
#[derive(Clone)]
pub(crate) struct SceneShape {
    regions: Vec<MeshRegion>,
    instances: Vec<GpuInstance>,
    opaque: bool,
}

impl SceneShape {
    pub(crate) fn of(scene: &GpuScene) -> SceneShape {
        SceneShape {
            regions: scene.regions.clone(),
            instances: scene.instances.clone(),
            opaque: opaque(&scene.features),
        }
    }

    fn triangles(&self) -> u64 {
        self.regions.iter().map(|r| r.triangle_count as u64).sum()
    }
}

/// Whether a scene of `features` has only opaque triangles (none alpha-tested).
fn opaque(features: &SceneFeatures) -> bool {
    !(features.alpha_mask || features.alpha_blend)
}

impl Structures {
    /// The structures of a scene of `shape`, built from its triangle positions at `positions`
    /// (the device address of the tracer's copy, already written). Alpha-tested triangles are
    /// left to the kernel's candidate loop (their geometry is not opaque) where the scene has
    /// any.
    pub(crate) fn build(gpu: &mut Gpu, shape: SceneShape, positions: u64) -> Result<Structures> {
        let loader = ash::khr::acceleration_structure::Device::new(&gpu.ctx.instance, gpu.device());
        let mut s = Structures {
            loader,
            shape,
            positions,
            bottom: Vec::new(),
            top: Structure::none(),
            instances: GpuBuffer::empty(),
        };
        match s.build_all(gpu) {
            Ok(()) => Ok(s),
            Err(e) => {
                s.destroy(gpu);
                Err(e)
            }
        }
    }

    /// The top level, which the kernels' descriptor set binds.
    pub(crate) fn top(&self) -> vk::AccelerationStructureKHR {
        self.top.handle
    }

    /// Brings the structures to the scene after `commit` (the tracer's arrays written, its
    /// triangle positions now at `positions`): the bottom levels of the meshes whose triangles
    /// changed (a deforming mesh) built again, all of them where the meshes themselves changed
    /// (added, removed, moved in the arrays) or the positions moved to a new buffer, and the top
    /// level again over the instances as they are. Returns whether the top level is a new one
    /// (the descriptor set must name it).
    pub(crate) fn follow(
        &mut self,
        gpu: &mut Gpu,
        commit: &Commit,
        positions: u64,
    ) -> Result<bool> {
        let opaque = opaque(&commit.header.features);
        let all = commit.regions != self.shape.regions
            || positions != self.positions
            || opaque != self.shape.opaque;
        let mut meshes = Vec::new();
        let mut instances = false;
        for a in &commit.arrays {
            if a.array == SceneArray::TrianglePositions.index() && !all {
                for &(offset, length) in &a.ranges {
                    let (first, end) = (
                        offset / TRIANGLE_BYTES,
                        (offset + length).div_ceil(TRIANGLE_BYTES),
                    );
                    meshes.extend(self.shape.regions.iter().enumerate().filter_map(|(i, r)| {
                        let (base, count) = (r.triangle_base as u64, r.triangle_count as u64);
                        (count > 0 && base < end && first < base + count).then_some(i)
                    }));
                }
            }
            if a.array == SceneArray::Instances.index() {
                instances = true;
                let mut bytes: Vec<u8> = bytemuck::cast_slice(&self.shape.instances).to_vec();
                bytes.resize(a.len as usize, 0);
                for (offset, piece) in a.pieces() {
                    bytes[offset as usize..offset as usize + piece.len()].copy_from_slice(piece);
                }
                self.shape.instances = bytemuck::pod_collect_to_vec(&bytes);
            }
        }
        meshes.sort_unstable();
        meshes.dedup();
        if !all && meshes.is_empty() && !instances {
            return Ok(false);
        }
        gpu.wait_idle()?;
        if all {
            self.shape.regions = commit.regions.clone();
            self.shape.opaque = opaque;
            self.positions = positions;
            self.destroy(gpu);
            self.build_all(gpu)?;
        } else {
            for i in meshes {
                if let Some(mut old) = self.bottom[i].take() {
                    self.free(gpu, &mut old);
                }
                self.bottom[i] = Some(self.build_mesh(gpu, i)?);
            }
            self.destroy_top(gpu);
            self.build_top(gpu)?;
        }
        Ok(true)
    }

    /// Every mesh's bottom level, then the top level: one submission each (the fence orders
    /// them), each with its own scratch.
    fn build_all(&mut self, gpu: &mut Gpu) -> Result<()> {
        let triangles = self.shape.triangles();
        if triangles >= MAX_TRIANGLES {
            return Err(Error::Unsupported {
                device: gpu.ctx.info.name.clone(),
                message: format!(
                    "the ray-query traversal takes scenes of fewer than {MAX_TRIANGLES} triangles \
                     (an instance's custom index): this one has {triangles} (use --traversal own)"
                ),
            });
        }
        for i in 0..self.shape.regions.len() {
            let built = match self.shape.regions[i].triangle_count {
                0 => None,
                _ => Some(self.build_mesh(gpu, i)?),
            };
            self.bottom.push(built);
        }
        self.build_top(gpu)
    }

    /// Mesh `i`'s bottom level, from its triangles' corners in the positions.
    fn build_mesh(&self, gpu: &mut Gpu, i: usize) -> Result<Structure> {
        let region = &self.shape.regions[i];
        let first = self.positions + TRIANGLE_BYTES * region.triangle_base as u64;
        let triangles = vk::AccelerationStructureGeometryTrianglesDataKHR::default()
            .vertex_format(vk::Format::R32G32B32_SFLOAT)
            .vertex_data(vk::DeviceOrHostAddressConstKHR {
                device_address: first,
            })
            .vertex_stride(16)
            .max_vertex(3 * region.triangle_count - 1)
            .index_type(vk::IndexType::NONE_KHR);
        let flags = if self.shape.opaque {
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
            region.triangle_count,
        )
    }

    /// The top level over the instances, each placing the bottom level of its mesh (which it
    /// names by the root of the mesh's BVH) with the mesh's first triangle as custom index.
    fn build_top(&mut self, gpu: &mut Gpu) -> Result<()> {
        let address = |b: &Structure| unsafe {
            self.loader.get_acceleration_structure_device_address(
                &vk::AccelerationStructureDeviceAddressInfoKHR::default()
                    .acceleration_structure(b.handle),
            )
        };
        let meshes: HashMap<u32, (u64, u32)> = self
            .shape
            .regions
            .iter()
            .zip(&self.bottom)
            .filter_map(|(r, b)| b.as_ref().map(|b| (r.root, (address(b), r.triangle_base))))
            .collect();
        let any = meshes.values().next().map_or(0, |m| m.0);
        let records: Vec<vk::AccelerationStructureInstanceKHR> = if meshes.is_empty() {
            Vec::new()
        } else {
            self.shape
                .instances
                .iter()
                .map(|inst| instance_record(inst, &meshes, any))
                .collect()
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

    /// Frees one structure and its buffer.
    fn free(&self, gpu: &mut Gpu, s: &mut Structure) {
        if s.handle != vk::AccelerationStructureKHR::null() {
            unsafe { self.loader.destroy_acceleration_structure(s.handle, None) };
        }
        gpu.destroy_buffer(&mut s.buffer);
    }

    fn destroy_top(&mut self, gpu: &mut Gpu) {
        let mut top = std::mem::replace(&mut self.top, Structure::none());
        self.free(gpu, &mut top);
        gpu.destroy_buffer(&mut self.instances);
    }

    /// Frees the structures and their buffers (the device idle).
    pub(crate) fn destroy(&mut self, gpu: &mut Gpu) {
        for mut b in std::mem::take(&mut self.bottom).into_iter().flatten() {
            self.free(gpu, &mut b);
        }
        self.destroy_top(gpu);
    }
}

impl Structure {
    fn none() -> Structure {
        Structure {
            handle: vk::AccelerationStructureKHR::null(),
            buffer: GpuBuffer::empty(),
        }
    }
}

/// `inst` as the top level's record: its object-to-world rows, its mesh's bottom level (by the
/// root the instance names in `meshes`, with the mesh's first triangle as custom index). An
/// instance of an empty mesh is kept in its place (the query's instance id is the scene's
/// index) and never hit: mask 0, `any` structure referenced.
fn instance_record(
    inst: &GpuInstance,
    meshes: &HashMap<u32, (u64, u32)>,
    any: u64,
) -> vk::AccelerationStructureInstanceKHR {
    let (mask, reference, first) = match meshes.get(&inst.blas_root) {
        Some(&(address, first)) => (0xff, address, first),
        None => (0, any, 0),
    };
    let m = inst.object_to_world;
    vk::AccelerationStructureInstanceKHR {
        transform: vk::TransformMatrixKHR {
            matrix: [
                m[0][0], m[0][1], m[0][2], m[0][3], m[1][0], m[1][1], m[1][2], m[1][3], m[2][0],
                m[2][1], m[2][2], m[2][3],
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
}

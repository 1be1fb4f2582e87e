//! The bottom levels' builds on the device: in batches (one submission for many meshes, each
//! with its part of one scratch buffer), compacted after where they will not be refitted, and
//! refitted in place where a deforming mesh's triangles moved (Vulkan's update mode), as the
//! core refits its own BVH of the mesh; built again where the core built its BVH again (its
//! quality fell) or after `MAX_REFITS` refits in a row.

use ash::vk;
use gpu_allocator::MemoryLocation;

use platoon_core::flatten::MeshRegion;

use super::structure::{self, Structure};
use crate::buffer::GpuBuffer;
use crate::gpu::Gpu;
use crate::{Result, VkContext};

/// What is done to one mesh's bottom level.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Job {
    /// Built afresh: compacted after, or kept refittable (`ALLOW_UPDATE`, not compacted) for a
    /// mesh that deforms.
    Build { refittable: bool },
    /// Refitted in place to the mesh's triangles as they are now (a refittable one).
    Refit,
}

impl Job {
    /// Whether the structure it leaves is refittable (built with `ALLOW_UPDATE`): all but a
    /// build meant for compaction.
    fn refittable(self) -> bool {
        self != Job::Build { refittable: false }
    }
}

/// What one job needs: its structure's size (for a build) and its scratch (aligned).
#[derive(Clone, Copy)]
pub(super) struct JobSize {
    structure: u64,
    pub(super) scratch: u64,
}

/// A mesh's bottom level and how it follows the mesh.
pub(super) struct Bottom {
    pub(super) structure: Structure,
    /// Built with `ALLOW_UPDATE`: a deforming mesh's, refitted when it moves.
    pub(super) refittable: bool,
    /// Refits since it was built.
    pub(super) refits: u32,
}

/// What a tracer's bottom levels went through so far (`Tracer::structure_counts`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct StructureCounts {
    /// Bottom levels built, and refitted in place.
    pub built: u64,
    pub refitted: u64,
    /// Bytes of the bottom levels compacted, before and after.
    pub compacted_from: u64,
    pub compacted_to: u64,
}

/// Refits in a row after which a bottom level is built again whatever the core did: the
/// core's own bound on refits in a row (`RefitPolicy::max_refits`).
pub(super) const MAX_REFITS: u32 = 64;

/// Scratch memory one submission of builds may take: a large scene's builds go in several.
const SCRATCH_BUDGET: u64 = 256 << 20;

/// The alignment a build's scratch address needs on `gpu`'s device.
pub(super) fn scratch_alignment(gpu: &Gpu) -> u64 {
    gpu.ctx.scratch_alignment.unwrap_or(256)
}

/// A buffer of `bytes` of scratch, with room to align its start.
pub(super) fn scratch_buffer(gpu: &mut Gpu, bytes: u64) -> Result<GpuBuffer> {
    let align = scratch_alignment(gpu);
    gpu.buffer(
        "structure scratch",
        bytes + align,
        vk::BufferUsageFlags::STORAGE_BUFFER,
        MemoryLocation::GpuOnly,
    )
}

/// The build flags of a bottom level: fast traversal, and either refits or compaction.
fn flags(refittable: bool) -> vk::BuildAccelerationStructureFlagsKHR {
    vk::BuildAccelerationStructureFlagsKHR::PREFER_FAST_TRACE
        | if refittable {
            vk::BuildAccelerationStructureFlagsKHR::ALLOW_UPDATE
        } else {
            vk::BuildAccelerationStructureFlagsKHR::ALLOW_COMPACTION
        }
}

/// What the builds of one submission wrote, for the builds, copies and kernels after them.
pub(super) unsafe fn built_barrier(d: &ash::Device, cb: vk::CommandBuffer) {
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
}

/// The bytes of one triangle's corners in the triangle positions (three vec4).
pub(super) const TRIANGLE_BYTES: u64 = 48;

/// The meshes bottom levels are built over: their places in the triangle positions, whether
/// every triangle is opaque, and the positions' device address.
#[derive(Clone, Copy)]
pub(super) struct Meshes<'a> {
    pub(super) regions: &'a [MeshRegion],
    pub(super) opaque: bool,
    pub(super) positions: u64,
}

/// A scene's bottom levels on one device, a mesh each (by its index in the regions; None for an
/// empty mesh), and what they went through.
pub(super) struct Bottoms {
    loader: ash::khr::acceleration_structure::Device,
    list: Vec<Option<Bottom>>,
    pub(super) counts: StructureCounts,
}

impl Bottoms {
    pub(super) fn new(loader: ash::khr::acceleration_structure::Device) -> Bottoms {
        Bottoms {
            loader,
            list: Vec::new(),
            counts: StructureCounts::default(),
        }
    }

    /// Mesh `i`'s bottom level, if it has one.
    pub(super) fn get(&self, i: usize) -> Option<&Bottom> {
        self.list.get(i).and_then(Option::as_ref)
    }

    /// The device address of mesh `i`'s bottom level, if it has one.
    pub(super) fn address(&self, i: usize) -> Option<u64> {
        self.get(i).map(|b| b.structure.address(&self.loader))
    }

    /// Frees every bottom level and makes room for `meshes` (none built).
    pub(super) fn reset(&mut self, gpu: &mut Gpu, meshes: usize) {
        for mut b in std::mem::take(&mut self.list).into_iter().flatten() {
            b.structure.free(&self.loader, gpu);
        }
        self.list = (0..meshes).map(|_| None).collect();
    }

    /// Mesh `i`'s triangles as a bottom level's geometry: their corners in the positions.
    fn geometry(&self, meshes: &Meshes, i: usize) -> vk::AccelerationStructureGeometryKHR<'static> {
        let region = &meshes.regions[i];
        let first = meshes.positions + TRIANGLE_BYTES * region.triangle_base as u64;
        let triangles = vk::AccelerationStructureGeometryTrianglesDataKHR::default()
            .vertex_format(vk::Format::R32G32B32_SFLOAT)
            .vertex_data(vk::DeviceOrHostAddressConstKHR {
                device_address: first,
            })
            .vertex_stride(16)
            .max_vertex(3 * region.triangle_count - 1)
            .index_type(vk::IndexType::NONE_KHR);
        let flags = if meshes.opaque {
            vk::GeometryFlagsKHR::OPAQUE
        } else {
            vk::GeometryFlagsKHR::NO_DUPLICATE_ANY_HIT_INVOCATION
        };
        vk::AccelerationStructureGeometryKHR::default()
            .geometry_type(vk::GeometryTypeKHR::TRIANGLES)
            .geometry(vk::AccelerationStructureGeometryDataKHR { triangles })
            .flags(flags)
    }

    /// Does `jobs` (meshes with triangles, each once), in batches of `SCRATCH_BUDGET` scratch
    /// at most, each submitted and waited for (the device idle: a refit rewrites a structure
    /// kernels read), the built ones that will not be refitted compacted.
    pub(super) fn run(
        &mut self,
        gpu: &mut Gpu,
        meshes: &Meshes,
        jobs: &[(usize, Job)],
    ) -> Result<()> {
        let sizes = self.sizes(gpu, meshes, jobs);
        let mut start = 0;
        while start < jobs.len() {
            let mut end = start + 1;
            let mut total = sizes[start].scratch;
            while end < jobs.len() && total + sizes[end].scratch <= SCRATCH_BUDGET {
                total += sizes[end].scratch;
                end += 1;
            }
            self.run_batch(gpu, meshes, &jobs[start..end], &sizes[start..end])?;
            start = end;
        }
        Ok(())
    }

    /// What each job needs (the driver asked once a job): its structure's size and its
    /// scratch, rounded up to the device's alignment.
    pub(super) fn sizes(&self, gpu: &Gpu, meshes: &Meshes, jobs: &[(usize, Job)]) -> Vec<JobSize> {
        let align = scratch_alignment(gpu);
        jobs.iter()
            .map(|&(i, job)| {
                let sizes = self.build_sizes(meshes, i, job.refittable());
                let scratch = match job {
                    Job::Refit => sizes.update_scratch_size,
                    Job::Build { .. } => sizes.build_scratch_size,
                };
                JobSize {
                    structure: sizes.acceleration_structure_size,
                    scratch: scratch.next_multiple_of(align),
                }
            })
            .collect()
    }

    /// The sizes of mesh `i`'s bottom level and of its build's and refit's scratch.
    fn build_sizes(
        &self,
        meshes: &Meshes,
        i: usize,
        refittable: bool,
    ) -> vk::AccelerationStructureBuildSizesInfoKHR<'static> {
        structure::build_sizes(
            &self.loader,
            vk::AccelerationStructureTypeKHR::BOTTOM_LEVEL,
            flags(refittable),
            self.geometry(meshes, i),
            meshes.regions[i].triangle_count,
        )
    }

    /// One batch: each built mesh's new structure made (the old one freed), every build and
    /// refit in one submission, then the built ones that will not be refitted compacted.
    fn run_batch(
        &mut self,
        gpu: &mut Gpu,
        meshes: &Meshes,
        batch: &[(usize, Job)],
        sizes: &[JobSize],
    ) -> Result<()> {
        self.prepare(gpu, batch, sizes)?;
        let mut memory = scratch_buffer(gpu, sizes.iter().map(|s| s.scratch).sum())?;
        let compacted: Vec<usize> = batch
            .iter()
            .filter(|(_, job)| !job.refittable())
            .map(|&(i, _)| i)
            .collect();
        let recorded = self.record_batch(gpu, meshes, batch, sizes, memory.address, &compacted);
        gpu.destroy_buffer(&mut memory);
        let pool = recorded?;
        match pool {
            Some(pool) => {
                let compacted_sizes = self.compacted_sizes(gpu, pool, compacted.len());
                unsafe { gpu.device().destroy_query_pool(pool, None) };
                self.compact(gpu, &compacted, &compacted_sizes?)
            }
            None => Ok(()),
        }
    }

    /// Makes the structures `batch` builds (each built mesh's new one, the old one freed) and
    /// counts its builds and refits.
    pub(super) fn prepare(
        &mut self,
        gpu: &mut Gpu,
        batch: &[(usize, Job)],
        sizes: &[JobSize],
    ) -> Result<()> {
        for (&(i, job), size) in batch.iter().zip(sizes) {
            if let Job::Build { refittable } = job {
                let structure = Structure::create(
                    &self.loader,
                    gpu,
                    vk::AccelerationStructureTypeKHR::BOTTOM_LEVEL,
                    size.structure,
                )?;
                let new = Bottom {
                    structure,
                    refittable,
                    refits: 0,
                };
                if let Some(mut old) = self.list[i].replace(new) {
                    old.structure.free(&self.loader, gpu);
                }
                self.counts.built += 1;
            } else if let Some(b) = &mut self.list[i] {
                b.refits += 1;
                self.counts.refitted += 1;
            }
        }
        Ok(())
    }

    /// Records and runs the batch's builds and refits, scratch from `address` on; with
    /// `compacted` meshes, their compacted sizes written to the query pool it returns.
    fn record_batch(
        &self,
        gpu: &mut Gpu,
        meshes: &Meshes,
        batch: &[(usize, Job)],
        sizes: &[JobSize],
        address: u64,
        compacted: &[usize],
    ) -> Result<Option<vk::QueryPool>> {
        let pool = if compacted.is_empty() {
            None
        } else {
            let info = vk::QueryPoolCreateInfo::default()
                .query_type(vk::QueryType::ACCELERATION_STRUCTURE_COMPACTED_SIZE_KHR)
                .query_count(compacted.len() as u32);
            Some(
                unsafe { gpu.device().create_query_pool(&info, None) }
                    .ctx("creating a query pool")?,
            )
        };
        let handles: Vec<vk::AccelerationStructureKHR> =
            compacted.iter().map(|&i| self.handle(i)).collect();
        let align = scratch_alignment(gpu);
        let ran = gpu.submit(|d, cb| unsafe {
            if let Some(pool) = pool {
                d.cmd_reset_query_pool(cb, pool, 0, handles.len() as u32);
            }
            self.record(cb, meshes, batch, sizes, address.next_multiple_of(align));
            built_barrier(d, cb);
            if let Some(pool) = pool {
                self.loader.cmd_write_acceleration_structures_properties(
                    cb,
                    &handles,
                    vk::QueryType::ACCELERATION_STRUCTURE_COMPACTED_SIZE_KHR,
                    pool,
                    0,
                );
            }
        });
        if let Err(e) = ran {
            if let Some(pool) = pool {
                unsafe { gpu.device().destroy_query_pool(pool, None) };
            }
            return Err(e);
        }
        Ok(pool)
    }

    /// Mesh `i`'s bottom level (null for an empty mesh).
    fn handle(&self, i: usize) -> vk::AccelerationStructureKHR {
        self.list[i]
            .as_ref()
            .map_or(vk::AccelerationStructureKHR::null(), |b| b.structure.handle)
    }

    /// Records `batch`'s builds and refits (their structures made by `prepare`), their scratch
    /// from `address` on (aligned), in `sizes`' scratch.
    pub(super) unsafe fn record(
        &self,
        cb: vk::CommandBuffer,
        meshes: &Meshes,
        batch: &[(usize, Job)],
        sizes: &[JobSize],
        address: u64,
    ) {
        let mut at = address;
        let geometries: Vec<[vk::AccelerationStructureGeometryKHR; 1]> = batch
            .iter()
            .map(|&(i, _)| [self.geometry(meshes, i)])
            .collect();
        let infos: Vec<vk::AccelerationStructureBuildGeometryInfoKHR> = batch
            .iter()
            .zip(&geometries)
            .zip(sizes)
            .map(|((&(i, job), g), size)| {
                let info = vk::AccelerationStructureBuildGeometryInfoKHR::default()
                    .ty(vk::AccelerationStructureTypeKHR::BOTTOM_LEVEL)
                    .flags(flags(job.refittable()))
                    .geometries(g)
                    .dst_acceleration_structure(self.handle(i))
                    .scratch_data(vk::DeviceOrHostAddressKHR { device_address: at });
                at += size.scratch;
                match job {
                    Job::Refit => info
                        .mode(vk::BuildAccelerationStructureModeKHR::UPDATE)
                        .src_acceleration_structure(self.handle(i)),
                    Job::Build { .. } => info.mode(vk::BuildAccelerationStructureModeKHR::BUILD),
                }
            })
            .collect();
        let ranges: Vec<[vk::AccelerationStructureBuildRangeInfoKHR; 1]> = batch
            .iter()
            .map(|&(i, _)| {
                [vk::AccelerationStructureBuildRangeInfoKHR::default()
                    .primitive_count(meshes.regions[i].triangle_count)]
            })
            .collect();
        let ranges: Vec<&[vk::AccelerationStructureBuildRangeInfoKHR]> =
            ranges.iter().map(|r| &r[..]).collect();
        if !infos.is_empty() {
            self.loader
                .cmd_build_acceleration_structures(cb, &infos, &ranges);
        }
    }

    /// The compacted sizes the batch's queries wrote.
    fn compacted_sizes(&self, gpu: &Gpu, pool: vk::QueryPool, count: usize) -> Result<Vec<u64>> {
        let mut sizes = vec![0u64; count];
        unsafe {
            gpu.device().get_query_pool_results(
                pool,
                0,
                &mut sizes,
                vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT,
            )
        }
        .ctx("reading the structures' compacted sizes")?;
        Ok(sizes)
    }

    /// Each of `meshes`' bottom levels copied into one of its compacted size (one
    /// submission), the uncompacted ones freed.
    fn compact(&mut self, gpu: &mut Gpu, meshes: &[usize], sizes: &[u64]) -> Result<()> {
        let mut copies = Vec::with_capacity(meshes.len());
        for &size in sizes {
            match Structure::create(
                &self.loader,
                gpu,
                vk::AccelerationStructureTypeKHR::BOTTOM_LEVEL,
                size,
            ) {
                Ok(s) => copies.push(s),
                Err(e) => {
                    for mut s in copies {
                        s.free(&self.loader, gpu);
                    }
                    return Err(e);
                }
            }
        }
        let sources: Vec<vk::AccelerationStructureKHR> =
            meshes.iter().map(|&i| self.handle(i)).collect();
        let loader = &self.loader;
        let copied = gpu.submit(|d, cb| unsafe {
            for (src, dst) in sources.iter().zip(&copies) {
                let copy = vk::CopyAccelerationStructureInfoKHR::default()
                    .src(*src)
                    .dst(dst.handle)
                    .mode(vk::CopyAccelerationStructureModeKHR::COMPACT);
                loader.cmd_copy_acceleration_structure(cb, &copy);
            }
            built_barrier(d, cb);
        });
        if let Err(e) = copied {
            for mut s in copies {
                s.free(&self.loader, gpu);
            }
            return Err(e);
        }
        for (&i, s) in meshes.iter().zip(copies) {
            self.counts.compacted_to += s.buffer.size;
            let old = self.list[i]
                .as_mut()
                .map(|b| std::mem::replace(&mut b.structure, s));
            if let Some(mut old) = old {
                self.counts.compacted_from += old.buffer.size;
                old.free(&self.loader, gpu);
            }
        }
        Ok(())
    }
}

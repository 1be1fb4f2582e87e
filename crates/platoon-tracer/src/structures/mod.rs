//! The device's acceleration structures of a scene (the ray-query traversal, `ray_query.rs`):
//! a bottom level per mesh built straight from the triangle positions the kernel reads (three
//! corners a triangle, in the mesh's BVH leaf order, so a hit's triangle is the mesh's first
//! plus the primitive's index: the instance's custom index holds that first one), and a top
//! level of the scene's instances in their own order (a hit's instance is the query's instance
//! id). Built on the device (lavapipe offers no host builds) when the tracer takes the scene,
//! and brought to a living scene's commits (`follow`): the bottom levels of deforming meshes
//! refitted, the top level built again (`bottom.rs` builds, refits and compacts).

mod behind;
mod bottom;
mod structure;

use std::collections::HashMap;

use ash::vk;
use gpu_allocator::MemoryLocation;
use platoon_core::flatten::arrays::SceneArray;
use platoon_core::flatten::commit::Commit;
use platoon_core::flatten::{GpuInstance, GpuScene, MeshRegion};
use platoon_core::SceneFeatures;

use self::behind::Behind;
pub use self::bottom::StructureCounts;
use self::bottom::{Bottoms, Job, Meshes, MAX_REFITS, TRIANGLE_BYTES};
use self::structure::Structure;
use crate::buffer::GpuBuffer;
use crate::gpu::Gpu;
use crate::ray_query::MAX_TRIANGLES;
use crate::{Error, Result};

const TOP_LEVEL: vk::AccelerationStructureTypeKHR = vk::AccelerationStructureTypeKHR::TOP_LEVEL;

/// A top level made and waiting for its build: its instances and scratch.
struct TopBuild {
    count: u32,
    scratch: GpuBuffer,
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
    /// Each mesh's bottom level (by its index in the shape's regions).
    bottoms: Bottoms,
    top: Structure,
    instances: GpuBuffer,
    /// Where a living scene's builds go without the host waiting (made at the first).
    behind: Option<Behind>,
}

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

    /// Its meshes as bottom levels are built over them, from the positions at `positions`.
    fn meshes(&self, positions: u64) -> Meshes<'_> {
        Meshes {
            regions: &self.regions,
            opaque: self.opaque,
            positions,
        }
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
            bottoms: Bottoms::new(loader.clone()),
            loader,
            shape,
            positions,
            top: Structure::none(),
            instances: GpuBuffer::empty(),
            behind: None,
        };
        match s.build_all(gpu, &[]) {
            Ok(()) => Ok(s),
            Err(e) => {
                s.destroy(gpu);
                Err(e)
            }
        }
    }

    /// What the bottom levels went through.
    pub(crate) fn counts(&self) -> StructureCounts {
        self.bottoms.counts
    }

    /// The top level, which the kernels' descriptor set binds.
    pub(crate) fn top(&self) -> vk::AccelerationStructureKHR {
        self.top.handle
    }

    /// Brings the structures to the scene after `commit` (the tracer's arrays written, its
    /// triangle positions now at `positions`): the bottom levels of the meshes whose triangles
    /// changed (a deforming mesh) refitted or built again, all of them built again where the
    /// meshes themselves changed (added, removed, moved in the arrays) or the positions moved to
    /// a new buffer, and the top level again over the instances as they are. Returns whether
    /// the top level is a new one (the descriptor set must name it).
    pub(crate) fn follow(
        &mut self,
        gpu: &mut Gpu,
        commit: &Commit,
        positions: u64,
    ) -> Result<bool> {
        let opaque = opaque(&commit.header.features);
        // Where the meshes' triangles lie (a region's nodes and root follow its BVH, which a
        // deforming mesh's pose rebuilds: the top level reads the new root).
        let places = |regions: &[MeshRegion]| -> Vec<(u32, u32)> {
            regions
                .iter()
                .map(|r| (r.triangle_base, r.triangle_count))
                .collect()
        };
        let all = places(&commit.regions) != places(&self.shape.regions)
            || positions != self.positions
            || opaque != self.shape.opaque;
        let roots = commit.regions != self.shape.regions;
        self.shape.regions = commit.regions.clone();
        let (meshes, whole) = rewritten_meshes(commit);
        let mut instances = false;
        for a in &commit.arrays {
            if a.array == SceneArray::Instances.index() {
                instances = true;
                let mut bytes: Vec<u8> = bytemuck::cast_slice(&self.shape.instances).to_vec();
                bytes.resize(a.len as usize, 0);
                a.write_into(&mut bytes);
                self.shape.instances = bytemuck::pod_collect_to_vec(&bytes);
            }
        }
        if !all && meshes.is_empty() && !instances && !roots {
            return Ok(false);
        }
        if all {
            gpu.wait_idle()?;
            self.shape.opaque = opaque;
            self.positions = positions;
            // Those of deforming meshes refittable: as the core says, or as the rewritten
            // triangles say where the core does not and they were not rewritten whole.
            let mut deforming: Vec<usize> = commit.deformed.iter().map(|&i| i as usize).collect();
            if !whole {
                deforming.extend(&meshes);
            }
            self.destroy(gpu);
            self.build_all(gpu, &deforming)?;
        } else {
            // A deforming mesh's bottom level is refitted as the core refits its BVH, and built
            // again (refittable from then on) where the core built its BVH again or it was not
            // built to be refitted (its first deformation) or has been refitted long enough.
            let jobs: Vec<(usize, Job)> = meshes
                .into_iter()
                .map(|i| {
                    let refit = self.bottoms.get(i).is_some_and(|b| {
                        b.refittable
                            && b.refits < MAX_REFITS
                            && !commit.rebuilt.contains(&(i as u32))
                    });
                    (
                        i,
                        if refit {
                            Job::Refit
                        } else {
                            Job::Build { refittable: true }
                        },
                    )
                })
                .collect();
            self.follow_behind(gpu, &jobs)?;
        }
        Ok(true)
    }

    /// `jobs` (refits and builds of deforming meshes) and the top level, in one submission the
    /// host does not wait for (`behind.rs`).
    fn follow_behind(&mut self, gpu: &mut Gpu, jobs: &[(usize, Job)]) -> Result<()> {
        let mut behind = match self.behind.take() {
            Some(b) => b,
            None => Behind::new(gpu)?,
        };
        let submitted = self.submit_behind(gpu, &mut behind, jobs);
        self.behind = Some(behind);
        submitted
    }

    fn submit_behind(
        &mut self,
        gpu: &mut Gpu,
        behind: &mut Behind,
        jobs: &[(usize, Job)],
    ) -> Result<()> {
        behind.settle(gpu)?;
        let sizes = self
            .bottoms
            .sizes(gpu, &self.shape.meshes(self.positions), jobs);
        self.bottoms.prepare(gpu, jobs, &sizes)?;
        let bottoms = bottom::scratch_buffer(gpu, sizes.iter().map(|s| s.scratch).sum())?;
        let align = bottom::scratch_alignment(gpu);
        let at = bottoms.address.next_multiple_of(align);
        behind.keep(bottoms);
        let top = self.prepare_top(gpu)?;
        let meshes = self.shape.meshes(self.positions);
        let submitted = behind.submit(gpu, |d, cb| unsafe {
            self.bottoms.record(cb, &meshes, jobs, &sizes, at);
            bottom::built_barrier(d, cb);
            self.record_top(cb, &top, align);
            bottom::built_barrier(d, cb);
        });
        behind.keep(top.scratch);
        submitted
    }

    /// Waits for the builds submitted behind, if any (before the arrays they read are
    /// written again, or the structures they write freed).
    pub(crate) fn settle(&mut self, gpu: &mut Gpu) -> Result<()> {
        match &mut self.behind {
            Some(b) => b.settle(gpu),
            None => Ok(()),
        }
    }

    /// Every mesh's bottom level (in batches, `bottom.rs`), then the top level; those of
    /// `deforming` meshes built to be refitted, the others compacted.
    fn build_all(&mut self, gpu: &mut Gpu, deforming: &[usize]) -> Result<()> {
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
        let jobs: Vec<(usize, Job)> = (self.shape.regions.iter().enumerate())
            .filter(|(_, r)| r.triangle_count > 0)
            .map(|(i, _)| {
                let refittable = deforming.contains(&i);
                (i, Job::Build { refittable })
            })
            .collect();
        self.bottoms.reset(gpu, self.shape.regions.len());
        let meshes = self.shape.meshes(self.positions);
        self.bottoms.run(gpu, &meshes, &jobs)?;
        self.build_top(gpu)
    }

    /// The top level over the instances as they are, built and waited for.
    fn build_top(&mut self, gpu: &mut Gpu) -> Result<()> {
        let mut build = self.prepare_top(gpu)?;
        let align = bottom::scratch_alignment(gpu);
        let built = gpu.submit(|d, cb| unsafe {
            self.record_top(cb, &build, align);
            bottom::built_barrier(d, cb);
        });
        gpu.destroy_buffer(&mut build.scratch);
        built
    }

    /// A new top level made over the instances (the old one freed: the device idle), each
    /// placing the bottom level of its mesh (which it names by the root of the mesh's BVH) with
    /// the mesh's first triangle as custom index: its instance records written, its scratch
    /// made, nothing built yet.
    fn prepare_top(&mut self, gpu: &mut Gpu) -> Result<TopBuild> {
        self.destroy_top(gpu);
        let meshes: HashMap<u32, (u64, u32)> = (self.shape.regions.iter().enumerate())
            .filter_map(|(i, r)| Some((r.root, (self.bottoms.address(i)?, r.triangle_base))))
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
        let count = records.len() as u32;
        let sizes = self.top_sizes(count);
        self.top = Structure::create(
            &self.loader,
            gpu,
            TOP_LEVEL,
            sizes.acceleration_structure_size,
        )?;
        Ok(TopBuild {
            count,
            scratch: bottom::scratch_buffer(gpu, sizes.build_scratch_size)?,
        })
    }

    /// The top level's geometry: the instance records written by `prepare_top`.
    fn top_geometry(&self) -> vk::AccelerationStructureGeometryKHR<'static> {
        let data = vk::AccelerationStructureGeometryInstancesDataKHR::default()
            .array_of_pointers(false)
            .data(vk::DeviceOrHostAddressConstKHR {
                device_address: self.instances.address,
            });
        vk::AccelerationStructureGeometryKHR::default()
            .geometry_type(vk::GeometryTypeKHR::INSTANCES)
            .geometry(vk::AccelerationStructureGeometryDataKHR { instances: data })
    }

    /// The sizes of a top level over `count` instances and of its build's scratch.
    fn top_sizes(&self, count: u32) -> vk::AccelerationStructureBuildSizesInfoKHR<'static> {
        structure::build_sizes(
            &self.loader,
            TOP_LEVEL,
            vk::BuildAccelerationStructureFlagsKHR::PREFER_FAST_TRACE,
            self.top_geometry(),
            count,
        )
    }

    /// Records the build of the top level `prepare_top` made.
    unsafe fn record_top(&self, cb: vk::CommandBuffer, build: &TopBuild, align: u64) {
        let geometries = [self.top_geometry()];
        let info = vk::AccelerationStructureBuildGeometryInfoKHR::default()
            .ty(TOP_LEVEL)
            .flags(vk::BuildAccelerationStructureFlagsKHR::PREFER_FAST_TRACE)
            .mode(vk::BuildAccelerationStructureModeKHR::BUILD)
            .geometries(&geometries)
            .dst_acceleration_structure(self.top.handle)
            .scratch_data(vk::DeviceOrHostAddressKHR {
                device_address: build.scratch.address.next_multiple_of(align),
            });
        let range =
            [vk::AccelerationStructureBuildRangeInfoKHR::default().primitive_count(build.count)];
        self.loader
            .cmd_build_acceleration_structures(cb, &[info], &[&range]);
    }

    fn destroy_top(&mut self, gpu: &mut Gpu) {
        self.top.free(&self.loader, gpu);
        gpu.destroy_buffer(&mut self.instances);
    }

    /// Frees the structures and their buffers (the device idle), and what builds behind.
    pub(crate) fn destroy(&mut self, gpu: &mut Gpu) {
        if let Some(mut b) = self.behind.take() {
            b.destroy(gpu);
        }
        self.bottoms.reset(gpu, 0);
        self.destroy_top(gpu);
    }
}

/// The meshes (by their places after `commit`) whose triangles it rewrote, in order, and
/// whether it rewrote the triangles whole (which says nothing of which meshes moved).
fn rewritten_meshes(commit: &Commit) -> (Vec<usize>, bool) {
    let Some(a) = (commit.arrays.iter()).find(|a| a.array == SceneArray::TrianglePositions.index())
    else {
        return (Vec::new(), false);
    };
    let mut meshes = Vec::new();
    for &(offset, length) in &a.ranges {
        let (first, end) = (
            offset / TRIANGLE_BYTES,
            (offset + length).div_ceil(TRIANGLE_BYTES),
        );
        meshes.extend(commit.regions.iter().enumerate().filter_map(|(i, r)| {
            let (base, count) = (r.triangle_base as u64, r.triangle_count as u64);
            (count > 0 && base < end && first < base + count).then_some(i)
        }));
    }
    meshes.sort_unstable();
    meshes.dedup();
    (meshes, a.is_whole())
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

//! Vertex links (Schmitz, Tavenrath and Kobbelt, "Interactive Global Illumination for Deformable
//! Geometry in CUDA"; `../shared/briefs/links.md`): diffuse indirect light solved per *element*
//! (an instance's welded vertex) over links found by shooting one fixed set of cosine-distributed
//! directions from every element. A hit at barycentrics (u, v, w) on a triangle ABC makes the
//! links x<-A, x<-B, x<-C weighted u, v, w, each over the n_C rays; cosine sampling has absorbed
//! the geometry and area terms, so the weights of an element sum to the fraction of its rays
//! that hit anything, and the gather needs no other factor.
//!
//! This module holds the method's deterministic parts, which run on the CPU between the
//! devices' shooting and the kernels' interpolation:
//! - [`elements`]: a mesh's vertices welded into elements (seams joined, creases kept), with
//!   their one-rings; [`scene_elements`]: those of a flattened scene's instances, in render
//!   space, and the element of a hit's corner;
//! - [`directions`]: the n_C directions every element shoots, in the order rays are numbered;
//! - [`reduce`]: the raw links of each element (ray order) summed per peer into compressed
//!   link groups (CSR), in a fixed order whatever split shot them;
//! - [`gather`]: the Jacobi gather of `n_B` bounces and the feature-preserving smoothing;
//! - [`shoot_cpu`]: link shooting through the CPU ray queries (the devices' oracle).
//!
//! Still to come (issue 22): shooting on the devices, direct
//! light at elements, the kernel's hook, `--method links`.

pub mod directions;
pub mod elements;
pub mod gather;
pub mod reduce;
pub mod scene_elements;
pub mod shoot_cpu;

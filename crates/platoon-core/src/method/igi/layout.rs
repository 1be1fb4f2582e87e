//! The structs IGI's kernels share with the host (std430, mirrored in shaders/igi/igi.glsl): the
//! VPLs, the gathering vertices and what each pixel leaves the filters.

/// A virtual point light as igi/emit.comp writes it (`Vpl` in shaders/igi/igi.glsl, std430).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Vpl {
    /// xyz; w unused.
    pub position: [f32; 4],
    /// The surface's normal, xyz.
    pub normal: [f32; 4],
    /// Flux x albedo / pi, rgb; w 1 in a slot that holds a VPL, all zero where its path ended.
    pub power: [f32; 4],
}

/// A pixel's gathering vertex, what the camera pass leaves the gather passes (`IgiVertex` in
/// shaders/igi/igi.glsl, std430; the field comments there say what each holds).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct IgiVertex {
    pub position: [f32; 4],
    pub ns: [f32; 4],
    pub ng: [f32; 4],
    pub wo: [f32; 4],
    pub albedo: [f32; 4],
    pub f0: [f32; 4],
}

const _: () = {
    assert!(std::mem::size_of::<Vpl>() == 48);
    assert!(std::mem::size_of::<IgiVertex>() == 96);
    assert!(std::mem::size_of::<IgiTexel>() == 48);
};

/// What the IGI kernel leaves per pixel for the filters (sums over the frame's samples; std430
/// layout of three vec4s in the kernel's aux buffer).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct IgiTexel {
    /// Irradiance gathered from the VPLs (gather pixels only; the interleaving subset's
    /// estimate of the whole set's, scaled by the subset count).
    pub irradiance: [f32; 3],
    /// Samples whose first diffuse hit the sums below describe.
    pub diffuse_samples: f32,
    /// Path throughput x diffuse albedo / pi: what turns the irradiance into radiance.
    pub reflectance: [f32; 3],
    /// Distance from the camera to the first diffuse hit.
    pub depth: f32,
    /// Shading normal at the first diffuse hit, facing the camera path.
    pub normal: [f32; 3],
    pub _pad: f32,
}

impl crate::frame::PixelRecord for IgiTexel {
    const KIND: &'static str = "igi.texel";
}

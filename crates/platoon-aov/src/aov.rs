//! Arbitrary output variables: what compositing and denoisers read beside the beauty. Albedo
//! and normal follow Cycles' denoising passes: taken at the first vertex that is not perfectly
//! specular (the camera ray followed through mirrors and clear glass, tinted by them), averaged
//! over the pixel's samples as the beauty is. Position, depth and the ids are of the first hit of
//! the ray through the pixel's centre (not anti-aliased, as Blender's Z and index passes).
//! Each comes from a kernel pass of its own ([`AovPass`], `frame::Output::Aov`) rendered like
//! the beauty, line by line, so it has the same bits whatever the split between devices.
//! The sample count and variance come from the beauty's own batches (`frame::adaptive`).

use super::cryptomatte;
use super::light_pass::{BsdfPart, LightPass};
use super::motion::{self, PreviousFrame};
use super::Crop;
use platoon_accel::{GpuScene, HitNames};
use platoon_image::Film;
pub use platoon_image::Layer;
use platoon_scene::camera::Camera;

/// What one kernel pass writes per pixel (three floats).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum AovPass {
    /// The albedo at the first non-specular vertex times the specular chain's weight (RGB).
    Albedo,
    /// The world-space shading normal there, turned toward the arriving ray.
    Normal,
    /// The first hit's position through the pixel centre, in render space (0 for a miss).
    Position,
    /// (instance + 1, material + 1, triangle + 1) of that hit, 0 for a miss.
    Ids,
    /// The same ids of the first hit of one sample's camera ray (that sample of the beauty's,
    /// the pixel filter's and the lens' draws): Cryptomatte's coverage counts them.
    SampleIds(u32),
    /// A light pass (`light_pass`): the beauty's samples, the light of the pass's kind alone.
    Light(LightPass),
    /// The share of the beauty's camera rays that find a surface: a transparent film's alpha.
    Alpha,
    /// Ambient occlusion at the first hit of the beauty's camera rays: the share of
    /// cosine-distributed rays from it that meet nothing within the frame's AO distance (`FrameOptions`).
    Ao,
    /// A BSDF part's colour at the first hit of the beauty's camera rays: the sampled weight
    /// times the part's share of it (its directional albedo; Cycles' colour passes).
    Color(BsdfPart),
}

const fn sample_id_passes() -> [AovPass; cryptomatte::SAMPLES as usize] {
    let mut passes = [AovPass::Ids; cryptomatte::SAMPLES as usize];
    let mut i = 0;
    while i < passes.len() {
        passes[i] = AovPass::SampleIds(i as u32);
        i += 1;
    }
    passes
}

/// The passes Cryptomatte's coverage is counted from: the ids under each of its camera rays.
pub const SAMPLE_ID_PASSES: [AovPass; cryptomatte::SAMPLES as usize] = sample_id_passes();

const fn light_passes() -> [AovPass; LightPass::ALL.len()] {
    let mut passes = [AovPass::Alpha; LightPass::ALL.len()];
    let mut i = 0;
    while i < passes.len() {
        passes[i] = AovPass::Light(LightPass::ALL[i]);
        i += 1;
    }
    passes
}

/// The kernel passes of the colour AOVs, in `BsdfPart::ALL`'s order.
const COLOR_PASSES: [AovPass; 3] = [
    AovPass::Color(BsdfPart::Diffuse),
    AovPass::Color(BsdfPart::Glossy),
    AovPass::Color(BsdfPart::Transmission),
];

/// The kernel passes of the light passes, in `LightPass::ALL`'s order.
const LIGHT_PASSES: [AovPass; LightPass::ALL.len()] = light_passes();

/// Samples per pixel of the anti-aliased passes (albedo, normal): enough for a denoiser's
/// guide at any beauty spp, and at most the beauty's.
pub const GUIDE_SAMPLES: u32 = 64;

impl AovPass {
    /// Its label in the kernel variant and the define that selects its code
    /// (`method::variant`; `shaders/path/aov.glsl`, a light pass's in `shaders/path/path.glsl`).
    pub fn kernel_option(self) -> (&'static str, &'static str) {
        match self {
            AovPass::Albedo => ("aov-albedo", "OUTPUT_AOV_ALBEDO"),
            AovPass::Normal => ("aov-normal", "OUTPUT_AOV_NORMAL"),
            AovPass::Position => ("aov-position", "OUTPUT_AOV_POSITION"),
            AovPass::Ids => ("aov-ids", "OUTPUT_AOV_IDS"),
            AovPass::SampleIds(_) => ("aov-sample-ids", "OUTPUT_AOV_SAMPLE_IDS"),
            AovPass::Light(pass) => (pass.label(), pass.define()),
            AovPass::Alpha => ("aov-alpha", "OUTPUT_AOV_ALPHA"),
            AovPass::Ao => ("aov-ao", "OUTPUT_AOV_AO"),
            AovPass::Color(part) => (part.color_label(), part.color_define()),
        }
    }

    /// Whether the AOV kernel (`aov_pixel`) renders it: a light pass runs the beauty's own
    /// path loop.
    pub fn in_aov_kernel(self) -> bool {
        !matches!(self, AovPass::Light(_))
    }

    /// Samples per pixel the pass takes when the beauty takes `spp`.
    pub fn spp(self, spp: u32) -> u32 {
        match self {
            AovPass::Albedo | AovPass::Normal | AovPass::Ao | AovPass::Color(_) => {
                spp.clamp(1, GUIDE_SAMPLES)
            }
            AovPass::Light(_) | AovPass::Alpha => spp,
            AovPass::Position | AovPass::Ids | AovPass::SampleIds(_) => 1,
        }
    }
}

/// An AOV as `--aov` names it; each becomes a layer of the EXR output.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Aov {
    Albedo,
    Normal,
    Depth,
    Position,
    InstanceId,
    MaterialId,
    PrimitiveId,
    /// The variance of the pixel's mean (per channel), from its batch means (`adaptive`).
    Variance,
    /// The samples the pixel took (adaptive sampling's; the frame's spp without it).
    SampleCount,
    /// Cryptomatte's object layers (`cryptomatte`): the nodes under each pixel by coverage.
    CryptoObject,
    /// ... its material layers.
    CryptoMaterial,
    /// ... and its asset layers (an object's topmost ancestor in the node tree).
    CryptoAsset,
    /// A light pass (`light_pass`); the eight sum to the beauty.
    Light(LightPass),
    /// How far the surface at the pixel's centre moved on the image since the frame before
    /// (`motion`), in pixels.
    Motion,
    /// Ambient occlusion (Cycles' AO pass): 1 where nothing near occludes the surface.
    Ao,
    /// A BSDF part's colour (Cycles' DiffCol, GlossCol, TransCol).
    Color(BsdfPart),
}

impl Aov {
    pub const ALL: [Aov; 25] = [
        Aov::Albedo,
        Aov::Normal,
        Aov::Depth,
        Aov::Position,
        Aov::InstanceId,
        Aov::MaterialId,
        Aov::PrimitiveId,
        Aov::Variance,
        Aov::SampleCount,
        Aov::CryptoObject,
        Aov::CryptoMaterial,
        Aov::CryptoAsset,
        Aov::Motion,
        Aov::Ao,
        Aov::Color(BsdfPart::Diffuse),
        Aov::Color(BsdfPart::Glossy),
        Aov::Color(BsdfPart::Transmission),
        Aov::Light(LightPass::DiffuseDirect),
        Aov::Light(LightPass::DiffuseIndirect),
        Aov::Light(LightPass::GlossyDirect),
        Aov::Light(LightPass::GlossyIndirect),
        Aov::Light(LightPass::TransmissionDirect),
        Aov::Light(LightPass::TransmissionIndirect),
        Aov::Light(LightPass::Emission),
        Aov::Light(LightPass::Environment),
    ];

    /// The name `--aov` takes for every light pass at once.
    pub const LIGHT_PASSES: &'static str = "light";

    /// Its name on the command line and as the EXR layer.
    pub fn name(self) -> &'static str {
        match self {
            Aov::Albedo => "albedo",
            Aov::Normal => "normal",
            Aov::Depth => "depth",
            Aov::Position => "position",
            Aov::InstanceId => "instance-id",
            Aov::MaterialId => "material-id",
            Aov::PrimitiveId => "primitive-id",
            Aov::Variance => "variance",
            Aov::SampleCount => "sample-count",
            Aov::CryptoObject => "crypto-object",
            Aov::CryptoMaterial => "crypto-material",
            Aov::CryptoAsset => "crypto-asset",
            Aov::Light(pass) => pass.name(),
            Aov::Motion => "motion",
            Aov::Ao => "ao",
            Aov::Color(part) => part.color_name(),
        }
    }

    /// Whether `layer` is one of its layers (a Cryptomatte's are `CryptoObject00`, ...; the
    /// others' are named as it is).
    pub fn owns_layer(self, layer: &str) -> bool {
        match self.cryptomatte() {
            Some(kind) => layer
                .strip_prefix(kind.type_name())
                .is_some_and(|rank| rank.len() == 2 && rank.bytes().all(|b| b.is_ascii_digit())),
            None => layer == self.name(),
        }
    }

    /// The Cryptomatte it is, if it is one.
    pub fn cryptomatte(self) -> Option<cryptomatte::Kind> {
        match self {
            Aov::CryptoObject => Some(cryptomatte::Kind::Object),
            Aov::CryptoMaterial => Some(cryptomatte::Kind::Material),
            Aov::CryptoAsset => Some(cryptomatte::Kind::Asset),
            _ => None,
        }
    }

    /// Its channels in the layer (`albedo.R`, ...).
    pub fn channels(self) -> &'static [&'static str] {
        match self {
            Aov::Albedo | Aov::Variance | Aov::Light(_) | Aov::Ao | Aov::Color(_) => {
                &["R", "G", "B"]
            }
            Aov::Normal | Aov::Position => &["X", "Y", "Z"],
            Aov::Depth => &["Z"],
            Aov::InstanceId | Aov::MaterialId | Aov::PrimitiveId => &["id"],
            Aov::SampleCount => &["N"],
            Aov::CryptoObject | Aov::CryptoMaterial | Aov::CryptoAsset => &["R", "G", "B", "A"],
            Aov::Motion => &["X", "Y"],
        }
    }

    /// The kernel passes it is made from (none: it comes from the beauty's batches).
    pub fn passes(self) -> &'static [AovPass] {
        match self {
            Aov::Albedo => &[AovPass::Albedo],
            Aov::Normal => &[AovPass::Normal],
            // A miss is told by the ids (position 0 could be a hit).
            Aov::Depth | Aov::Motion => &[AovPass::Position, AovPass::Ids],
            Aov::Position => &[AovPass::Position],
            Aov::InstanceId | Aov::MaterialId | Aov::PrimitiveId => &[AovPass::Ids],
            Aov::Variance | Aov::SampleCount => &[],
            Aov::CryptoObject | Aov::CryptoMaterial | Aov::CryptoAsset => &SAMPLE_ID_PASSES,
            Aov::Light(pass) => std::slice::from_ref(&LIGHT_PASSES[pass as usize]),
            Aov::Ao => &[AovPass::Ao],
            Aov::Color(part) => std::slice::from_ref(&COLOR_PASSES[part as usize]),
        }
    }

    /// A comma-separated list (`albedo,normal,depth`), each named once; `light` names every
    /// light pass.
    pub fn parse_list(s: &str) -> Result<Vec<Aov>, String> {
        let mut list = Vec::new();
        for name in s.split(',').map(str::trim).filter(|n| !n.is_empty()) {
            let named: Vec<Aov> = match name {
                Aov::LIGHT_PASSES => Aov::ALL.into_iter().filter(|a| a.is_light()).collect(),
                _ => vec![Aov::ALL
                    .into_iter()
                    .find(|a| a.name() == name)
                    .ok_or_else(|| {
                        let known: Vec<&str> = Aov::ALL.iter().map(|a| a.name()).collect();
                        format!(
                            "unknown AOV {name:?}: one of {}, or {} (every light pass)",
                            known.join(", "),
                            Aov::LIGHT_PASSES
                        )
                    })?],
            };
            for aov in named {
                if list.contains(&aov) {
                    return Err(format!("AOV {:?} is named twice", aov.name()));
                }
                list.push(aov);
            }
        }
        if list.is_empty() {
            return Err("no AOV named".into());
        }
        Ok(list)
    }

    /// Whether it is a light pass.
    pub fn is_light(self) -> bool {
        matches!(self, Aov::Light(_))
    }
}

/// The passes `aovs` need, each once, in a fixed order.
pub fn passes(aovs: &[Aov]) -> Vec<AovPass> {
    let mut out: Vec<AovPass> = Vec::new();
    for p in aovs.iter().flat_map(|a| a.passes()) {
        if !out.contains(p) {
            out.push(*p);
        }
    }
    out
}

/// Depth of a pixel that sees no surface: nothing there, infinitely far.
pub const MISS_DEPTH: f32 = f32::INFINITY;

/// What the layers read beyond their passes' films: the flattened scene the frame was rendered
/// from (Cryptomatte's names, the triangles motion vectors follow), the frame before (motion)
/// and where the frame lies in its camera's image.
#[derive(Clone, Copy)]
pub struct Context<'a> {
    pub scene: Option<&'a GpuScene>,
    pub previous: Option<&'a PreviousFrame>,
    pub crop: Crop,
}

impl Context<'_> {
    /// Nothing beyond the films (the layers that need more are not asked for), for a frame of
    /// `width` x `height`.
    pub fn films_only(width: u32, height: u32) -> Context<'static> {
        Context {
            scene: None,
            previous: None,
            crop: Crop {
                x: 0,
                y: 0,
                image_width: width,
                image_height: height,
            },
        }
    }
}

/// The layers of `aovs` from the films of their passes (`film(pass)`), for `camera` (depth:
/// the distance along its view axis) and the render origin in world space (`origin`: position
/// is written in world coordinates), with what `context` gives the layers that read more.
pub fn layers(
    aovs: &[Aov],
    film: &dyn Fn(AovPass) -> Film,
    camera: &Camera,
    origin: glam::DVec3,
    context: &Context,
) -> Vec<Layer> {
    let films: Vec<(AovPass, Film)> = passes(aovs).into_iter().map(|p| (p, film(p))).collect();
    let of = |pass| &films.iter().find(|(p, _)| *p == pass).expect("rendered").1;
    let plane = |film: &Film, f: &dyn Fn(usize, [f32; 3]) -> f32| -> Vec<f32> {
        film.pixels
            .iter()
            .enumerate()
            .map(|(i, p)| f(i, *p))
            .collect()
    };
    let hit = |i: usize| of(AovPass::Ids).pixels[i][0] > 0.0;
    aovs.iter()
        .filter(|a| !a.passes().is_empty())
        .flat_map(|&aov| {
            if let Some(kind) = aov.cryptomatte() {
                let films: Vec<&Film> = SAMPLE_ID_PASSES.iter().map(|&p| of(p)).collect();
                let names = context.scene.map(|g| &g.hit_names);
                return cryptomatte::layers(kind, &films, names.unwrap_or(&HitNames::default()));
            }
            if aov == Aov::Motion {
                let previous = context
                    .previous
                    .expect("motion vectors need the frame before");
                let scene = context.scene.expect("... and the flattened scene");
                let (position, ids) = (of(AovPass::Position), of(AovPass::Ids));
                return vec![motion::layer(
                    position,
                    ids,
                    scene,
                    camera,
                    context.crop,
                    previous,
                )];
            }
            let planes: Vec<Vec<f32>> = match aov {
                Aov::Albedo | Aov::Normal | Aov::Light(_) | Aov::Ao | Aov::Color(_) => {
                    let f = of(aov.passes()[0]);
                    (0..3).map(|c| plane(f, &|_, p| p[c])).collect()
                }
                Aov::Position => {
                    let f = of(AovPass::Position);
                    (0..3)
                        .map(|c| plane(f, &|_, p| (p[c] as f64 + origin[c]) as f32))
                        .collect()
                }
                Aov::Depth => {
                    let eye = camera.position();
                    let forward = camera.basis(1, 1).forward;
                    let f = of(AovPass::Position);
                    vec![plane(f, &|i, p| {
                        if hit(i) {
                            (glam::Vec3::from(p) - eye).dot(forward)
                        } else {
                            MISS_DEPTH
                        }
                    })]
                }
                Aov::InstanceId | Aov::MaterialId | Aov::PrimitiveId => {
                    let c = match aov {
                        Aov::InstanceId => 0,
                        Aov::MaterialId => 1,
                        _ => 2,
                    };
                    vec![plane(of(AovPass::Ids), &|_, p| p[c])]
                }
                Aov::Variance | Aov::SampleCount => unreachable!("filtered out above"),
                Aov::CryptoObject | Aov::CryptoMaterial | Aov::CryptoAsset | Aov::Motion => {
                    unreachable!("returned above")
                }
            };
            vec![layer(aov, planes)]
        })
        .collect()
}

fn layer(aov: Aov, planes: Vec<Vec<f32>>) -> Layer {
    Layer {
        name: aov.name().into(),
        channels: aov
            .channels()
            .iter()
            .map(|c| c.to_string())
            .zip(planes)
            .collect(),
        attributes: Vec::new(),
        full_float: false,
    }
}

/// The layers of `aovs` that come from the beauty's batches: each pixel's `samples`, and the
/// variance of its mean when it was kept.
pub fn batch_layers(aovs: &[Aov], samples: &[u32], variance: Option<&[[f32; 3]]>) -> Vec<Layer> {
    let mut out = Vec::new();
    for &aov in aovs {
        match aov {
            Aov::SampleCount => out.push(layer(
                aov,
                vec![samples.iter().map(|&n| n as f32).collect()],
            )),
            Aov::Variance => {
                let v = variance.expect("the variance was kept: the frame was batched for it");
                out.push(layer(
                    aov,
                    (0..3).map(|c| v.iter().map(|p| p[c]).collect()).collect(),
                ));
            }
            _ => {}
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lists_parse_and_name_their_passes_once() {
        let l = Aov::parse_list("albedo, depth,instance-id").unwrap();
        assert_eq!(l, vec![Aov::Albedo, Aov::Depth, Aov::InstanceId]);
        assert_eq!(
            passes(&l),
            vec![AovPass::Albedo, AovPass::Position, AovPass::Ids]
        );
        assert!(Aov::parse_list("albedo,albedo").is_err());
        assert!(Aov::parse_list("beauty")
            .unwrap_err()
            .contains("primitive-id"));
        assert!(Aov::parse_list("").is_err());
        let light = Aov::parse_list("albedo,light").unwrap();
        assert_eq!(light.len(), 9);
        assert_eq!(light[1], Aov::Light(LightPass::DiffuseDirect));
        assert!(Aov::parse_list("light,emission")
            .unwrap_err()
            .contains("\"emission\" is named twice"));
    }
}

//! Light passes as Cycles names them: the beauty split by where its light came from. The
//! camera ray's own finds are the emission and environment passes; everything else is split at
//! the first vertex by the BSDF's parts there (diffuse: the diffuse lobe, diffuse transmission
//! and sheen; glossy: the specular, metal and coat lobes and glass' reflection; transmission:
//! glass' refraction), each part's share the mean of its RGB over the whole's, as Cycles weighs
//! its passes; direct is the light the first vertex's next-event estimation and BSDF ray bring,
//! indirect the rest. Each pass is a kernel pass of its own (`shaders/common/bsdf.glsl`,
//! `shaders/path/path.glsl`: LIGHT_PASS) with the beauty's random numbers, so the eight sum to
//! the beauty. Unlike Cycles' the direct and indirect passes hold the light itself, not the
//! light over the part's colour (there are no colour passes to multiply them back by).

/// One light pass.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum LightPass {
    DiffuseDirect,
    DiffuseIndirect,
    GlossyDirect,
    GlossyIndirect,
    TransmissionDirect,
    TransmissionIndirect,
    /// Emitters the camera sees (unlit surfaces too).
    Emission,
    /// The environment the camera sees.
    Environment,
}

impl LightPass {
    /// In the kernel's order (`LIGHT_PASS` 0 to 7).
    pub const ALL: [LightPass; 8] = [
        LightPass::DiffuseDirect,
        LightPass::DiffuseIndirect,
        LightPass::GlossyDirect,
        LightPass::GlossyIndirect,
        LightPass::TransmissionDirect,
        LightPass::TransmissionIndirect,
        LightPass::Emission,
        LightPass::Environment,
    ];

    /// Its name on the command line and as the EXR layer.
    pub fn name(self) -> &'static str {
        match self {
            LightPass::DiffuseDirect => "diffuse-direct",
            LightPass::DiffuseIndirect => "diffuse-indirect",
            LightPass::GlossyDirect => "glossy-direct",
            LightPass::GlossyIndirect => "glossy-indirect",
            LightPass::TransmissionDirect => "transmission-direct",
            LightPass::TransmissionIndirect => "transmission-indirect",
            LightPass::Emission => "emission",
            LightPass::Environment => "environment",
        }
    }

    /// The kernel's define for it (mapped to LIGHT_PASS's number in shaders/common/bsdf.glsl).
    pub fn define(self) -> &'static str {
        match self {
            LightPass::DiffuseDirect => "LIGHT_PASS_DIFFUSE_DIRECT",
            LightPass::DiffuseIndirect => "LIGHT_PASS_DIFFUSE_INDIRECT",
            LightPass::GlossyDirect => "LIGHT_PASS_GLOSSY_DIRECT",
            LightPass::GlossyIndirect => "LIGHT_PASS_GLOSSY_INDIRECT",
            LightPass::TransmissionDirect => "LIGHT_PASS_TRANSMISSION_DIRECT",
            LightPass::TransmissionIndirect => "LIGHT_PASS_TRANSMISSION_INDIRECT",
            LightPass::Emission => "LIGHT_PASS_EMISSION",
            LightPass::Environment => "LIGHT_PASS_ENVIRONMENT",
        }
    }

    /// Its label in the kernel variant (`platoon info`, the metadata).
    pub fn label(self) -> &'static str {
        match self {
            LightPass::DiffuseDirect => "light-pass-diffuse-direct",
            LightPass::DiffuseIndirect => "light-pass-diffuse-indirect",
            LightPass::GlossyDirect => "light-pass-glossy-direct",
            LightPass::GlossyIndirect => "light-pass-glossy-indirect",
            LightPass::TransmissionDirect => "light-pass-transmission-direct",
            LightPass::TransmissionIndirect => "light-pass-transmission-indirect",
            LightPass::Emission => "light-pass-emission",
            LightPass::Environment => "light-pass-environment",
        }
    }
}

/// A part of the BSDF as the light passes split it (and the colour AOVs weigh it).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum BsdfPart {
    Diffuse,
    Glossy,
    Transmission,
}

impl BsdfPart {
    pub const ALL: [BsdfPart; 3] = [BsdfPart::Diffuse, BsdfPart::Glossy, BsdfPart::Transmission];

    /// Its colour AOV's name (Cycles' DiffCol, GlossCol, TransCol).
    pub fn color_name(self) -> &'static str {
        match self {
            BsdfPart::Diffuse => "diffuse-color",
            BsdfPart::Glossy => "glossy-color",
            BsdfPart::Transmission => "transmission-color",
        }
    }

    /// The kernel's define of its colour pass (`shaders/path/aov.glsl`).
    pub fn color_define(self) -> &'static str {
        match self {
            BsdfPart::Diffuse => "OUTPUT_AOV_COLOR_DIFFUSE",
            BsdfPart::Glossy => "OUTPUT_AOV_COLOR_GLOSSY",
            BsdfPart::Transmission => "OUTPUT_AOV_COLOR_TRANSMISSION",
        }
    }

    /// ... and its label in the kernel variant.
    pub fn color_label(self) -> &'static str {
        match self {
            BsdfPart::Diffuse => "aov-diffuse-color",
            BsdfPart::Glossy => "aov-glossy-color",
            BsdfPart::Transmission => "aov-transmission-color",
        }
    }
}

//! The techniques `platoon tradeoff` sweeps: each a way of spending (or saving) time that a
//! renderer might choose, named on the command line and applied to a frame's parameters or to
//! the tracer's estimator. The unbiased ones converge to the reference; the biased ones say so.

use std::fmt;

use anyhow::{bail, Result};
use platoon_core::denoise::Denoiser;
use platoon_core::frame::{FrameParams, KNOBS};
use platoon_core::method::kind::MethodKind;
use platoon_core::method::path::{PathKernel, PathTracing, ResampledLight};
use platoon_core::method::registry;
use platoon_tracer::Sampling;

use super::effects::Effect;
use super::method_technique::{methods_help, MethodTechnique};
use super::variant::Variant;

#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum Technique {
    /// Next-event estimation and BSDF sampling combined by MIS: platoon's default.
    Mis,
    /// BSDF sampling only: emitters are found by chance.
    Bsdf,
    /// Light sampling only: emission found by BSDF rays is ignored after non-delta bounces.
    Light,
    /// A knob of the path loop (`platoon_core::frame::KNOBS`: max depth, Russian roulette,
    /// the clamp, uniform lights, the generic kernel, DPT, one bounce) with its value's word
    /// (`Knob::parse`): its token, value and bias are the knob's own.
    Loop { knob: usize, word: u32 },
    /// One sample per kernel pass: no path regeneration within a pass (Bikker ch. 6).
    NoRegeneration,
    /// NEE by resampled importance sampling over M candidate lights (unbiased; no MIS).
    Ris(u32),
    /// The same combined with BSDF sampling by MIS (Bikker's MIS+RIS; unbiased).
    MisRis(u32),
    /// Resampled direct light: M candidates weighed by their unshadowed contribution (the
    /// BSDF's f cos times radiance: ReSTIR DI's target, no reuse), combined with BSDF sampling
    /// by MIS; unbiased, punctual lights too.
    ResampledLight(u32),
    /// The streaming path tracer (Bikker's RR/SPT): the same estimator as MIS, other kernels.
    Streaming,
    /// Bikker's NOP: the last path of a pass not always completed (biased).
    CutLastPaths,
    /// MIS on the scene without one of its effects (its stand-in instead): what the effect
    /// costs in time and what removing it does to the image.
    Without(Effect),
    /// A rendering method other than the path tracer, with some of its settings (biased).
    Method(MethodTechnique),
    /// MIS, then a denoiser over the assembled image, guided by the frame's albedo, normal and
    /// depth (biased); its time includes the guides' passes and the filter.
    Denoise(Denoiser),
    /// MIS with adaptive sampling at this noise threshold (f32 bits; the spp is each pixel's
    /// most): Cycles' scheme, `platoon_core::frame::adaptive`.
    Adaptive(u32),
}

impl Technique {
    /// What `tradeoff --method NAME` sweeps when no techniques are named: the method's own
    /// comparison (`MethodKind::sweep`).
    pub fn sweep_of(kind: &dyn MethodKind) -> Vec<Technique> {
        kind.sweep()
            .iter()
            .map(|t| Technique::parse(t).expect("a method's sweep parses"))
            .collect()
    }

    /// `mis`, `bsdf`, `light`, `max-depth=N`, `rr-depth=N`, `rr-survival=P` (percent),
    /// `rr-fixed=P` (percent), `clamp=C`, `uniform-lights`, `no-regeneration`,
    /// `generic-kernel`, `ris=M`, `mis-ris=M`, `dpt`, `single-bounce`, `spt`, `nop`, `no-textures`,
    /// `no-normal-maps`, `opaque`, `env-mean`, `no-clearcoat`, `no-diffuse-transmission`, `no-sheen`,
    /// `no-volume`, `no-iridescence`, `no-anisotropy`,
    /// `no-dispersion`,
    /// `denoise=atrous`, `adaptive=T`.
    pub fn parse(s: &str) -> Result<Technique> {
        if let Some(effect) = Effect::parse(s.trim()) {
            return Ok(Technique::Without(effect));
        }
        let (name, value) = match s.split_once('=') {
            Some((n, v)) => (n.trim(), Some(v.trim())),
            None => (s.trim(), None),
        };
        let number = |what: &str| -> Result<u32> {
            match value.map(str::parse::<u32>) {
                Some(Ok(v)) => Ok(v),
                _ => bail!("technique {s:?}: {what} needs a whole number, e.g. {name}=2"),
            }
        };
        if let Some((knob, k)) = KNOBS.iter().enumerate().find(|(_, k)| k.token == name) {
            let word = k
                .parse(value)
                .map_err(|e| anyhow::anyhow!("technique {s:?}: {e}"))?;
            return Ok(Technique::Loop { knob, word });
        }
        if let Some(kind) = registry::kind(name).filter(|k| k.primary().is_some()) {
            return MethodTechnique::parse(kind, s, value.unwrap_or(""))
                .map(Technique::Method)
                .map_err(anyhow::Error::msg);
        }
        Ok(match name {
            "denoise" => match value.unwrap_or("").parse::<Denoiser>() {
                Ok(Denoiser::None) | Err(_) => {
                    bail!("technique {s:?}: denoise needs a denoiser, e.g. denoise=atrous")
                }
                Ok(d) => match d.available() {
                    Ok(()) => Technique::Denoise(d),
                    Err(e) => bail!("technique {s:?}: {e}"),
                },
            },
            "adaptive" => match value.map(str::parse::<f32>) {
                Some(Ok(t)) if t > 0.0 && t.is_finite() => Technique::Adaptive(t.to_bits()),
                _ => bail!("technique {s:?}: adaptive needs a noise threshold, e.g. adaptive=0.01"),
            },
            "mis" => Technique::Mis,
            "bsdf" => Technique::Bsdf,
            "light" => Technique::Light,
            "no-regeneration" => Technique::NoRegeneration,
            "ris" | "mis-ris" | "resampled-light" => match number("ris (candidates)")? {
                0 => bail!("technique {s:?}: RIS needs at least one candidate"),
                m if name == "ris" => Technique::Ris(m),
                m if name == "mis-ris" => Technique::MisRis(m),
                m => Technique::ResampledLight(m),
            },
            "spt" => Technique::Streaming,
            "nop" => Technique::CutLastPaths,
            _ => bail!(
                "unknown technique {s:?}: known are mis, bsdf, light, {}, no-regeneration, \
                 ris=M, mis-ris=M, resampled-light=M, spt, nop, no-textures, \
                 no-normal-maps, opaque, \
                 env-mean, no-clearcoat, no-diffuse-transmission, no-sheen, no-volume, \
                 no-iridescence, no-anisotropy, no-dispersion, denoise=atrous, denoise=oidn, \
                 adaptive=T, and the methods': {}",
                knobs_help(),
                methods_help()
            ),
        })
    }

    /// Converges to something else than the reference.
    pub fn biased(&self) -> bool {
        if let Technique::Loop { knob, .. } = *self {
            return KNOBS[knob].biased;
        }
        matches!(
            self,
            Technique::Without(_)
                | Technique::CutLastPaths
                | Technique::Method(_)
                | Technique::Denoise(_)
                // Stopping on a pixel's own error estimate leans its mean (slightly).
                | Technique::Adaptive(_)
        )
    }

    /// The estimator its tracer is built with.
    pub fn sampling(&self) -> Sampling {
        match self {
            Technique::Bsdf => Sampling::Bsdf,
            Technique::Light => Sampling::Light,
            _ => Sampling::Mis,
        }
    }

    /// The scene it renders when not the sweep's own: without an effect, or subdivided.
    pub fn variant(&self) -> Option<Variant> {
        match *self {
            Technique::Without(e) => Some(Variant::Without(e)),
            Technique::Method(ref t) if t.subdivisions > 0 => {
                Some(Variant::Subdivided(t.subdivisions))
            }
            _ => None,
        }
    }

    /// Sets what it changes on a frame's parameters.
    pub fn apply(&self, params: &mut FrameParams) {
        match *self {
            Technique::Loop { knob, word } => KNOBS[knob].apply(&mut params.path_loop, word),
            Technique::NoRegeneration => params.samples_per_pass = 1,
            Technique::Ris(m) => path(params).resampled_light = Some(by_luminance(m, false)),
            Technique::MisRis(m) => path(params).resampled_light = Some(by_luminance(m, true)),
            Technique::ResampledLight(m) => {
                path(params).resampled_light = Some(ResampledLight::new(m))
            }
            Technique::Streaming => path(params).kernel = PathKernel::Streaming,
            Technique::CutLastPaths => {
                let path = path(params);
                path.kernel = PathKernel::Mega;
                path.cut_last_paths = true;
            }
            Technique::Method(ref t) => params.method = t.method(),
            // Its change is to the scene (`variant`).
            Technique::Without(_) => {}
            // Its change is after assembly, or how the frame is rendered (`mod.rs`).
            Technique::Denoise(_) | Technique::Adaptive(_) => {}
            Technique::Mis | Technique::Bsdf | Technique::Light => {}
        }
    }
}

/// The path loop's knobs as techniques name them (`max-depth=N`, `dpt`...).
fn knobs_help() -> String {
    let written: Vec<String> = KNOBS.iter().map(|k| k.written()).collect();
    written.join(", ")
}

/// The path tracer's state in `params`, which the sweep's techniques start from (only
/// `Technique::Method` renders another way, and it is one technique of its own).
fn path(params: &mut FrameParams) -> &mut PathTracing {
    params
        .method
        .path_mut()
        .expect("a technique's frame starts as the path tracer's")
}

/// Resampled light over `m` candidates weighed by their emitted luminance (Bikker's RIS), with
/// or without MIS against BSDF sampling.
fn by_luminance(m: u32, mis: bool) -> ResampledLight {
    ResampledLight {
        candidates: m,
        mis,
        contribution: false,
    }
}

impl fmt::Display for Technique {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Technique::Mis => write!(f, "mis"),
            Technique::Bsdf => write!(f, "bsdf"),
            Technique::Light => write!(f, "light"),
            Technique::Loop { knob, word } => write!(f, "{}", KNOBS[*knob].format(*word)),
            Technique::NoRegeneration => write!(f, "no-regeneration"),
            Technique::Ris(m) => write!(f, "ris={m}"),
            Technique::MisRis(m) => write!(f, "mis-ris={m}"),
            Technique::ResampledLight(m) => write!(f, "resampled-light={m}"),
            Technique::Streaming => write!(f, "spt"),
            Technique::CutLastPaths => write!(f, "nop"),
            Technique::Without(e) => write!(f, "{}", e.name()),
            Technique::Denoise(d) => write!(f, "denoise={}", format!("{d:?}").to_lowercase()),
            Technique::Adaptive(bits) => write!(f, "adaptive={}", f32::from_bits(*bits)),
            Technique::Method(t) => write!(f, "{t}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_parse_back_and_bad_ones_say_what_is_known() {
        for t in [
            Technique::Mis,
            Technique::Bsdf,
            Technique::Light,
            Technique::parse("max-depth=2").unwrap(),
            Technique::parse("rr-depth=1").unwrap(),
            Technique::parse("rr-survival=30").unwrap(),
            Technique::parse("rr-fixed=80").unwrap(),
            Technique::parse("clamp=2.5").unwrap(),
            Technique::parse("uniform-lights").unwrap(),
            Technique::NoRegeneration,
            Technique::parse("generic-kernel").unwrap(),
            Technique::parse("dpt").unwrap(),
            Technique::parse("single-bounce").unwrap(),
            Technique::Streaming,
            Technique::CutLastPaths,
            Technique::Ris(8),
            Technique::MisRis(4),
            Technique::ResampledLight(8),
            Technique::Without(Effect::Textures),
            Technique::Without(Effect::EnvironmentMap),
            Technique::Without(Effect::Clearcoat),
            Technique::Without(Effect::DiffuseTransmission),
            Technique::parse("links=64+b2+nosmooth+vertex").unwrap(),
            Technique::parse("links=256").unwrap(),
            Technique::parse("lhb=ico80+r64+c2.5+b3+l8+exact").unwrap(),
            Technique::parse("lhb=ico20+rebuild").unwrap(),
            Technique::parse("lhb=halton144").unwrap(),
            Technique::Denoise(Denoiser::Atrous),
            Technique::Adaptive(0.01f32.to_bits()),
        ] {
            assert_eq!(Technique::parse(&t.to_string()).unwrap(), t);
        }
        let e = Technique::parse("mis+ris").unwrap_err().to_string();
        assert!(
            e.contains("unknown technique") && e.contains("max-depth=N"),
            "{e}"
        );
        assert!(Technique::parse("ris").is_err() && Technique::parse("ris=0").is_err());
        assert!(Technique::parse("denoise=none").is_err() && Technique::parse("denoise").is_err());
        assert!(Technique::parse("denoise=atrous").unwrap().biased());
        assert!(Technique::parse("adaptive=0").is_err() && Technique::parse("adaptive").is_err());
        assert!(Technique::parse("max-depth").is_err());
        assert!(Technique::parse("max-depth=0").is_err());
        assert!(Technique::parse("rr-survival=0").is_err());
        assert!(Technique::parse("max-depth=2").unwrap().biased() && !Technique::Bsdf.biased());
        assert!(!Technique::parse("rr-fixed=50").unwrap().biased());
        assert!(Technique::parse("dpt=1").is_err());
        assert!(Technique::parse("clamp=10").unwrap().biased());
        assert!(Technique::parse("clamp=-1").is_err() && Technique::parse("rr-fixed=0").is_err());
        assert!(Technique::parse("links=20").is_err() && Technique::parse("links=16+b0").is_err());
        assert!(Technique::parse("links=16+sideways").is_err());
        assert!(
            Technique::parse("lhb=ico21").is_err() && Technique::parse("lhb=ico20+b9").is_err()
        );
        assert!(Technique::parse("lhb=ico20+sideways").is_err());
        assert!(Technique::parse("lhb=ico20").unwrap().biased());
        assert!(Technique::parse("links=16").unwrap().biased());
    }
}

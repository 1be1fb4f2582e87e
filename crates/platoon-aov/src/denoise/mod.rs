//! Denoising a frame after assembly (so the image is the same whatever the split between
//! devices), guided by its albedo, normal and depth AOVs (`frame::aov`). Denoising is an
//! approximation (biased): the raw image is always kept beside the denoised one.

pub mod atrous;
mod guides;
#[cfg(feature = "oidn")]
pub mod oidn;
pub mod temporal;
#[cfg(test)]
mod test_frames;

use crate::aov::Aov;
use platoon_image::Film;

pub use guides::Guides;

/// Which denoiser `--denoise` names.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Denoiser {
    #[default]
    None,
    /// The edge-avoiding à-trous wavelet filter ([`atrous`]).
    Atrous,
    /// The same filter on a tracer's device (shaders/denoise/atrous.comp), after assembly.
    AtrousDevice,
    /// Intel Open Image Denoise's ray-tracing filter (`oidn`, with the cargo feature `oidn`).
    Oidn,
}

impl std::str::FromStr for Denoiser {
    type Err = String;
    fn from_str(s: &str) -> Result<Denoiser, String> {
        Denoiser::ALL
            .into_iter()
            .find(|d| d.name() == s)
            .ok_or_else(|| format!("unknown denoiser {s:?}: none, atrous, atrous-device or oidn"))
    }
}

impl Denoiser {
    pub const ALL: [Denoiser; 4] = [
        Denoiser::None,
        Denoiser::Atrous,
        Denoiser::AtrousDevice,
        Denoiser::Oidn,
    ];

    /// Its name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Denoiser::None => "none",
            Denoiser::Atrous => "atrous",
            Denoiser::AtrousDevice => "atrous-device",
            Denoiser::Oidn => "oidn",
        }
    }

    /// What the metadata's approximations say of it (None when it is off).
    pub fn describe(self) -> Option<&'static str> {
        match self {
            Denoiser::None => None,
            Denoiser::Atrous => Some(
                "denoised by the edge-avoiding a-trous filter (Dammertz et al. 2010; 5 \
                 iterations, guided by albedo, normal and depth)",
            ),
            Denoiser::AtrousDevice => Some(
                "denoised by the edge-avoiding a-trous filter (Dammertz et al. 2010; 5 \
                 iterations, guided by albedo, normal and depth) on the first tracer's device",
            ),
            Denoiser::Oidn => Some(
                "denoised by Intel Open Image Denoise (the RT filter, HDR, guided by albedo and \
                 normal)",
            ),
        }
    }

    /// Whether this build can run it: OIDN needs the cargo feature `oidn`.
    pub fn available(self) -> Result<(), String> {
        match self {
            Denoiser::Oidn if !cfg!(feature = "oidn") => Err(
                "this platoon was built without Open Image Denoise: build it with \
                 `--features oidn` and OIDN_DIR naming the library's root (tools/oidn.sh \
                 finds or fetches one)"
                    .into(),
            ),
            _ => Ok(()),
        }
    }

    /// The AOVs it is guided by.
    pub const GUIDES: [Aov; 3] = [Aov::Albedo, Aov::Normal, Aov::Depth];

    /// `film` denoised with `guides` (`film` itself when off), the device's filters on
    /// `device`; an error when the denoiser is not in this build (`available`) or fails.
    pub fn apply_on(
        self,
        film: &Film,
        guides: &Guides,
        device: &mut dyn DeviceFilter,
    ) -> Result<Film, String> {
        match self {
            Denoiser::AtrousDevice => device.atrous(film, guides),
            d => d.apply(film, guides),
        }
    }

    /// `film` denoised with `guides` on the CPU (`film` itself when off); an error when the
    /// denoiser is not in this build (`available`), runs on a device (`apply_on`) or fails.
    pub fn apply(self, film: &Film, guides: &Guides) -> Result<Film, String> {
        self.available()?;
        match self {
            Denoiser::None => Ok(film.clone()),
            Denoiser::Atrous => Ok(atrous::filter(film, guides)),
            Denoiser::AtrousDevice => {
                Err("the device a-trous filter runs on a tracer: no device was given".into())
            }
            #[cfg(feature = "oidn")]
            Denoiser::Oidn => oidn::filter(film, guides),
            #[cfg(not(feature = "oidn"))]
            Denoiser::Oidn => unreachable!("refused by available()"),
        }
    }
}

/// What runs a denoiser's kernels: a tracer's device (the renderer's first live tracer).
pub trait DeviceFilter {
    /// `film` filtered by the à-trous kernel with `guides`.
    fn atrous(&mut self, film: &Film, guides: &Guides) -> Result<Film, String>;
}

/// No device: a device denoiser is refused.
pub struct NoDevice;

impl DeviceFilter for NoDevice {
    fn atrous(&mut self, _: &Film, _: &Guides) -> Result<Film, String> {
        Err("the device a-trous filter runs on a tracer: no device was given".into())
    }
}

#[cfg(all(test, not(feature = "oidn")))]
mod tests {
    use super::*;

    /// Without the feature OIDN's own tests (denoise/oidn.rs) are not built: this says so,
    /// and that the refusal tells how to get it (tools/test.sh runs them when it finds OIDN).
    #[test]
    fn without_the_feature_oidn_is_refused_saying_how_to_get_it() {
        eprintln!("Open Image Denoise's tests skipped: built without the feature `oidn`");
        let e = Denoiser::Oidn.available().unwrap_err();
        assert!(
            e.contains("--features oidn") && e.contains("OIDN_DIR"),
            "{e}"
        );
        assert_eq!("oidn".parse::<Denoiser>(), Ok(Denoiser::Oidn));
    }
}

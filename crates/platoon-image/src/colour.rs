//! How scene-linear radiance becomes an 8-bit sRGB image (PNG, the viewer, video frames): an
//! exposure, then a view transform, as Blender's colour management and the glTF ecosystem name
//! them. EXR output stays scene-linear; the view is for display.

use glam::{Mat3, Vec3};

/// The view transform.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ViewTransform {
    /// The sRGB transfer function on values clipped to [0, 1] (Blender's "Standard").
    Standard,
    /// Troy Sobotka's AgX (Blender's default since 4.0) as Benjamin Wrensch's minimal
    /// implementation fits it: inset matrix, log2 encoding over [-12.47, 4.03] EV, the
    /// contrast sigmoid's polynomial, outset matrix.
    Agx,
    /// Khronos PBR Neutral: colours pass unchanged up to 0.76 (less a small offset), only
    /// highlights are compressed and desaturated (the glTF ecosystem's "what the base colour
    /// says").
    PbrNeutral,
    /// Narkowicz's fit of the ACES filmic curve, per channel (platoon's view before there was a
    /// choice, and still the default).
    #[default]
    Aces,
}

impl ViewTransform {
    pub const ALL: [ViewTransform; 4] = [
        ViewTransform::Standard,
        ViewTransform::Agx,
        ViewTransform::PbrNeutral,
        ViewTransform::Aces,
    ];

    pub fn name(self) -> &'static str {
        match self {
            ViewTransform::Standard => "standard",
            ViewTransform::Agx => "agx",
            ViewTransform::PbrNeutral => "pbr-neutral",
            ViewTransform::Aces => "aces",
        }
    }

    pub fn parse(name: &str) -> Result<ViewTransform, String> {
        Self::ALL
            .into_iter()
            .find(|v| v.name() == name)
            .ok_or_else(|| {
                let names: Vec<&str> = Self::ALL.iter().map(|v| v.name()).collect();
                format!(
                    "unknown view transform {name:?} (one of {})",
                    names.join(", ")
                )
            })
    }

    /// Display-linear sRGB in [0, 1] of scene-linear `c` (exposure applied already).
    pub fn apply(self, c: Vec3) -> Vec3 {
        let c = c.max(Vec3::ZERO);
        let d = match self {
            ViewTransform::Standard => c,
            ViewTransform::Agx => agx(c),
            ViewTransform::PbrNeutral => pbr_neutral(c),
            ViewTransform::Aces => c.map(aces_fitted),
        };
        d.clamp(Vec3::ZERO, Vec3::ONE)
    }
}

/// An exposure (in stops) and a view transform.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct View {
    pub transform: ViewTransform,
    /// Stops: the radiance is scaled by 2^exposure before the transform.
    pub exposure: f32,
}

impl View {
    /// The sRGB-encoded pixel of scene-linear `rgb`, each channel in [0, 1].
    pub fn encoded(&self, rgb: [f32; 3]) -> [f32; 3] {
        let scale = self.exposure.exp2();
        let d = self.transform.apply(Vec3::from(rgb) * scale);
        d.to_array().map(srgb_encode)
    }

    /// The 8-bit sRGB-encoded pixel of scene-linear `rgb`.
    pub fn srgb8(&self, rgb: [f32; 3]) -> [u8; 3] {
        self.encoded(rgb).map(|v| (v * 255.0 + 0.5) as u8)
    }

    /// The 16-bit sRGB-encoded pixel of scene-linear `rgb`.
    pub fn srgb16(&self, rgb: [f32; 3]) -> [u16; 3] {
        self.encoded(rgb).map(|v| (v * 65535.0 + 0.5) as u16)
    }

    /// What the image metadata says of it.
    pub fn describe(&self) -> String {
        format!("{}, exposure {}", self.transform.name(), self.exposure)
    }
}

/// The sRGB transfer function (IEC 61966-2-1) of a display-linear value in [0, 1].
pub fn srgb_encode(v: f32) -> f32 {
    if v <= 0.0031308 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    }
}

fn aces_fitted(c: f32) -> f32 {
    let (a, b, cc, d, e) = (2.51, 0.03, 2.43, 0.59, 0.14);
    (c * (a * c + b)) / (c * (cc * c + d) + e)
}

fn agx(c: Vec3) -> Vec3 {
    // Columns, as the published GLSL's mat3 constructors give them.
    const INSET: Mat3 = Mat3::from_cols_array(&[
        0.842_479_06,
        0.042_328_24,
        0.042_375_655,
        0.078_433_6,
        0.878_468_6,
        0.078_433_6,
        0.079_223_745,
        0.079_166_13,
        0.879_143,
    ]);
    const OUTSET: Mat3 = Mat3::from_cols_array(&[
        1.196_879,
        -0.052_896_85,
        -0.052_971_635,
        -0.098_020_88,
        1.151_903_1,
        -0.098_043_45,
        -0.099_029_74,
        -0.098_961_18,
        1.151_073_7,
    ]);
    const MIN_EV: f32 = -12.47393;
    const MAX_EV: f32 = 4.026069;
    let v = INSET * c;
    let v = v
        .max(Vec3::splat(1e-10))
        .map(f32::log2)
        .clamp(Vec3::splat(MIN_EV), Vec3::splat(MAX_EV));
    let x = (v - MIN_EV) / (MAX_EV - MIN_EV);
    let x2 = x * x;
    let x4 = x2 * x2;
    let sigmoid =
        15.5 * x4 * x2 - 40.14 * x4 * x + 31.96 * x4 - 6.868 * x2 * x + 0.4298 * x2 + 0.1191 * x
            - Vec3::splat(0.00232);
    // The sigmoid's output is display-encoded (a 2.2 gamma): made display-linear like the
    // others' before the common sRGB encoding.
    (OUTSET * sigmoid).max(Vec3::ZERO).powf(2.2)
}

fn pbr_neutral(c: Vec3) -> Vec3 {
    const START_COMPRESSION: f32 = 0.8 - 0.04;
    const DESATURATION: f32 = 0.15;
    let x = c.min_element();
    let offset = if x < 0.08 { x - 6.25 * x * x } else { 0.04 };
    let c = c - offset;
    let peak = c.max_element();
    if peak < START_COMPRESSION {
        return c;
    }
    let d = 1.0 - START_COMPRESSION;
    let new_peak = 1.0 - d * d / (peak + d - START_COMPRESSION);
    let c = c * (new_peak / peak);
    let g = 1.0 - 1.0 / (DESATURATION * (peak - new_peak) + 1.0);
    c.lerp(Vec3::splat(new_peak), g)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A ramp of greys and colours over the range a render holds (0 to 64, a few stops over
    /// white), and negative and zero values.
    fn ramp() -> Vec<[f64; 3]> {
        let mut out = Vec::new();
        for i in 0..=96 {
            let v = (2.0f64).powf(i as f64 / 8.0 - 6.0) - 1.0 / 64.0;
            out.push([v, v, v]);
            out.push([v, 0.5 * v, 0.1 * v]);
            out.push([0.05 * v, v, 0.7 * v]);
            out.push([0.3, 0.02 * v, v]);
        }
        out.push([-1.0, 0.5, 2.0]);
        out
    }

    fn srgb8_of(display_linear: [f64; 3]) -> [u8; 3] {
        display_linear.map(|v| {
            let v = v.clamp(0.0, 1.0);
            let s = if v <= 0.0031308 {
                12.92 * v
            } else {
                1.055 * v.powf(1.0 / 2.4) - 0.055
            };
            (s * 255.0 + 0.5) as u8
        })
    }

    /// Within one code value of the reference, and equal on most of the ramp (f32 against f64).
    fn agrees(view: ViewTransform, reference: impl Fn([f64; 3]) -> [f64; 3]) {
        let (mut same, mut all) = (0, 0);
        for c in ramp() {
            let want = srgb8_of(reference(c.map(|v| v.max(0.0))));
            let got = View {
                transform: view,
                exposure: 0.0,
            }
            .srgb8(c.map(|v| v as f32));
            for k in 0..3 {
                assert!(
                    got[k].abs_diff(want[k]) <= 1,
                    "{view:?} of {c:?}: {got:?}, reference {want:?}"
                );
                same += (got[k] == want[k]) as u32;
                all += 1;
            }
        }
        assert!(
            same * 100 >= all * 98,
            "{view:?}: {same} of {all} code values equal"
        );
    }

    #[test]
    fn pbr_neutral_is_khronos_reference() {
        // Khronos' PBR_Neutral reference (KhronosGroup/ToneMapping, the GLSL of the spec).
        let reference = |c: [f64; 3]| {
            let start_compression = 0.8 - 0.04;
            let desaturation = 0.15;
            let x = c[0].min(c[1]).min(c[2]);
            let offset = if x < 0.08 { x - 6.25 * x * x } else { 0.04 };
            let c = c.map(|v| v - offset);
            let peak = c[0].max(c[1]).max(c[2]);
            if peak < start_compression {
                return c;
            }
            let d = 1.0 - start_compression;
            let new_peak = 1.0 - d * d / (peak + d - start_compression);
            let c = c.map(|v| v * new_peak / peak);
            let g = 1.0 - 1.0 / (desaturation * (peak - new_peak) + 1.0);
            c.map(|v| v * (1.0 - g) + new_peak * g)
        };
        agrees(ViewTransform::PbrNeutral, reference);
        // By hand from the spec: greys between 0.08 and 0.8 lose 0.04 and nothing else; white
        // (1.0) peaks at 1 - 0.24^2 / 0.44.
        let t = ViewTransform::PbrNeutral;
        assert!(
            (t.apply(Vec3::splat(0.5)) - Vec3::splat(0.46))
                .abs()
                .max_element()
                < 1e-6
        );
        let white = t.apply(Vec3::ONE).x as f64;
        assert!((white - (1.0 - 0.24 * 0.24 / 0.44)).abs() < 1e-6, "{white}");
    }

    #[test]
    fn agx_is_wrenschs_minimal_reference() {
        // Benjamin Wrensch's minimal AgX (iolite-engine.com, its HLSL, whose float3x3 rows are
        // the GLSL version's columns), then its agxEotf's 2.2 power to display-linear.
        let inset = [
            [0.842479062253094, 0.0784335999999992, 0.0792237451477643],
            [0.0423282422610123, 0.878468636469772, 0.0791661274605434],
            [0.0423756549057051, 0.0784336, 0.879142973793104],
        ];
        let outset = [
            [1.19687900512017, -0.0980208811401368, -0.0990297440797205],
            [-0.0528968517574562, 1.15190312990417, -0.0989611768448433],
            [-0.0529716355144438, -0.0980434501171241, 1.15107367264116],
        ];
        let mul = |m: [[f64; 3]; 3], v: [f64; 3]| {
            [0, 1, 2].map(|r| m[r][0] * v[0] + m[r][1] * v[1] + m[r][2] * v[2])
        };
        let (min_ev, max_ev) = (-12.47393f64, 4.026069f64);
        let reference = |c: [f64; 3]| {
            let v = mul(inset, c).map(|v| {
                let e = v.max(1e-10).log2().clamp(min_ev, max_ev);
                let x = (e - min_ev) / (max_ev - min_ev);
                let (x2, x4) = (x * x, x * x * x * x);
                15.5 * x4 * x2 - 40.14 * x4 * x + 31.96 * x4 - 6.868 * x2 * x
                    + 0.4298 * x2
                    + 0.1191 * x
                    - 0.00232
            });
            mul(outset, v).map(|v| v.max(0.0).powf(2.2))
        };
        agrees(ViewTransform::Agx, reference);
    }

    #[test]
    fn standard_and_aces_are_the_curves_they_were() {
        // The view before there was a choice: ACES-fitted per channel, then sRGB, the PNG
        // bytes unchanged (golden PNGs hold).
        let old = |c: f32| {
            let c = c.max(0.0);
            let t = ((c * (2.51 * c + 0.03)) / (c * (2.43 * c + 0.59) + 0.14)).clamp(0.0, 1.0);
            let s = if t <= 0.0031308 {
                12.92 * t
            } else {
                1.055 * t.powf(1.0 / 2.4) - 0.055
            };
            (s * 255.0 + 0.5) as u8
        };
        for c in ramp() {
            let c = c.map(|v| v as f32);
            assert_eq!(View::default().srgb8(c), c.map(old), "{c:?}");
        }
        let standard = View {
            transform: ViewTransform::Standard,
            exposure: 0.0,
        };
        assert_eq!(standard.srgb8([0.18, 1.0, 4.0]), [118, 255, 255]);
    }

    #[test]
    fn a_stop_of_exposure_is_twice_the_light() {
        for transform in ViewTransform::ALL {
            let up = View {
                transform,
                exposure: 1.0,
            };
            let plain = View {
                transform,
                exposure: 0.0,
            };
            for c in ramp() {
                let c = c.map(|v| v as f32);
                assert_eq!(
                    up.srgb8(c),
                    plain.srgb8(c.map(|v| 2.0 * v)),
                    "{transform:?} {c:?}"
                );
            }
        }
    }

    #[test]
    fn names_round_trip_and_an_unknown_one_lists_them() {
        for v in ViewTransform::ALL {
            assert_eq!(ViewTransform::parse(v.name()), Ok(v));
        }
        let e = ViewTransform::parse("filmic").unwrap_err();
        assert!(e.contains("standard, agx, pbr-neutral, aces"), "{e}");
    }
}

//! Every specular lobe held to the glTF specification's formula, integrated on the CPU by this
//! file's own quadrature (none of the kernel's code): a plane of the material under a uniform
//! sky, seen by an orthographic camera from one direction, shows its directional albedo
//! ∫ f(wo, wi) |cos θi| dωi times the sky (every reflected and refracted ray meets the sky).
//! Rendered with MIS, BSDF sampling alone and light sampling alone, so that an error in the BSDF
//! (its D, G or Fresnel) and one between its sampling and its pdf both show. A double-sided
//! plane is also seen from below (both sides shade alike), and KHR_materials_clearcoat's coat
//! is mixed over every base (its weight from the view alone, so not reciprocal).

#[path = "../common/mod.rs"]
mod common;

use std::f64::consts::PI;

use common::*;
use glam::{DVec3, Vec3, Vec4};
use platoon::core::frame::{FrameParams, Output};
use platoon::core::scene::Material;
use platoon::tracer::Sampling;

/// The glTF 2.0 BRDF (appendix B) with KHR_materials_specular (specular 1, white) and
/// KHR_materials_transmission's rough dielectric interface (Walter et al. 2007, radiance
/// compressed by the squared ratio of indices), written from the formulas, not the kernel.
#[derive(Clone, Copy, Debug)]
struct Lobe {
    base: f64,
    metallic: f64,
    roughness: f64,
    transmission: f64,
    ior: f64,
    /// KHR_materials_clearcoat's factor and roughness (0: a perfect mirror).
    clearcoat: f64,
    coat_roughness: f64,
    /// KHR_materials_diffuse_transmission's factor and (grey) colour.
    diffuse_transmission: f64,
    dt_color: f64,
    /// KHR_materials_sheen's (grey) colour and roughness.
    sheen: f64,
    sheen_roughness: f64,
    /// KHR_materials_iridescence's strength, the film's index and thickness (nm).
    iridescence: f64,
    film_ior: f64,
    film_thickness: f64,
    /// The colour channel compared (a film colours a grey lobe).
    channel: usize,
    /// KHR_materials_anisotropy's strength and rotation (radians from the plane's tangent, +x,
    /// toward its bitangent, +y here).
    anisotropy: f64,
    aniso_rotation: f64,
    /// The plane's tangent, turned by this angle from +x toward the bitangent: the rotation
    /// adds to it (a kernel turning the other way, or taking the bitangent's other side, would
    /// subtract it).
    tangent_angle: f64,
    /// The view's azimuth from +x toward +y (from the kernel's shading frame's x axis: a bug
    /// that mirrors the direction about it is invisible from an azimuth of 0).
    view_azimuth: f64,
}

/// Trowbridge-Reitz (GGX) with alpha = roughness^2.
fn d_ggx(alpha: f64, n_h: f64) -> f64 {
    if n_h <= 0.0 {
        return 0.0;
    }
    let a2 = alpha * alpha;
    let k = n_h * n_h * (a2 - 1.0) + 1.0;
    a2 / (PI * k * k)
}

/// The spec's height-correlated Smith visibility V = G / (4 |n.l| |n.v|).
fn v_smith(alpha: f64, n_l: f64, n_v: f64) -> f64 {
    let a2 = alpha * alpha;
    let l = n_l.abs();
    let v = n_v.abs();
    let ggxv = l * (v * v * (1.0 - a2) + a2).sqrt();
    let ggxl = v * (l * l * (1.0 - a2) + a2).sqrt();
    0.5 / (ggxv + ggxl)
}

fn schlick(f0: f64, v_h: f64) -> f64 {
    f0 + (1.0 - f0) * (1.0 - v_h.abs()).powi(5)
}

/// KHR_materials_iridescence's film (the spec's implementation notes: Belcour and Barla's
/// Airy sum with Schlick interfaces, the first two orders of interference integrated over the
/// spectrum through Gaussian fits of the CIE curves in Fourier space), in linear Rec. 709
/// channel `k`: the reflectance at cos `c1` outside (index `n1`) of a film of index `n2`,
/// `nm` thick, over a base of normal-incidence reflectance `f0`. The optical path difference
/// uses the angle inside the film, as the paper (the spec's text writes the outside angle).
fn thin_film(n1: f64, n2: f64, nm: f64, c1: f64, f0: f64, k: usize) -> f64 {
    let n2 = if nm > 0.03 {
        n2
    } else {
        n1 + (n2 - n1) * smoothstep(nm / 0.03)
    };
    let sin2 = (n1 / n2).powi(2) * (1.0 - c1 * c1);
    if sin2 >= 1.0 {
        return 1.0;
    }
    let c2 = (1.0 - sin2).sqrt();
    let r12 = schlick(((n2 - n1) / (n2 + n1)).powi(2), c1);
    let t121 = 1.0 - r12;
    let n3 = {
        let r = f0.clamp(0.0, 0.9999).sqrt();
        (1.0 + r) / (1.0 - r)
    };
    let r23 = schlick(((n3 - n2) / (n3 + n2)).powi(2), c2);
    let phi12 = if n2 < n1 { PI } else { 0.0 };
    let phi23 = if n3 < n2 { PI } else { 0.0 };
    let phi = (PI - phi12) + phi23;
    let opd = 2.0 * n2 * nm * c2;
    let r123 = (r12 * r23).clamp(1e-5, 0.9999);
    let rs = t121 * t121 * r23 / (1.0 - r123);
    let mut reflectance = r12 + rs;
    let mut cm = rs - t121;
    for m in 1..=2 {
        cm *= r123.sqrt();
        let xyz = sensitivity(m as f64 * opd, m as f64 * phi);
        // CIE XYZ to linear Rec. 709, row k.
        let rgb = [
            [3.2404542, -1.5371385, -0.4985314],
            [-0.9692660, 1.8760108, 0.0415560],
            [0.0556434, -0.2040259, 1.0572252],
        ][k];
        let s = rgb[0] * xyz[0] + rgb[1] * xyz[1] + rgb[2] * xyz[2];
        reflectance += cm * 2.0 * s;
    }
    reflectance.clamp(0.0, 1.0)
}

fn smoothstep(x: f64) -> f64 {
    let x = x.clamp(0.0, 1.0);
    x * x * (3.0 - 2.0 * x)
}

/// The spec's evalSensitivity: X, Y, Z of interference at optical path `opd` nm, phase `shift`.
fn sensitivity(opd: f64, shift: f64) -> [f64; 3] {
    let phase = 2.0 * PI * opd * 1e-9;
    let gauss = |amplitude: f64, centre: f64, variance: f64| {
        amplitude
            * (2.0 * PI * variance).sqrt()
            * (centre * phase + shift).cos()
            * (-phase * phase * variance).exp()
    };
    let x = gauss(5.4856e-13, 1.6810e6, 4.3278e9) + gauss(9.7470e-14, 2.2399e6, 4.5282e9);
    let y = gauss(4.4201e-13, 1.7953e6, 9.3046e9);
    let z = gauss(5.2481e-13, 2.2084e6, 6.6121e9);
    [x / 1.0685e-7, y / 1.0685e-7, z / 1.0685e-7]
}

/// Unpolarised Fresnel reflectance of a dielectric of relative index eta, cos_i > 0.
fn fresnel(cos_i: f64, eta: f64) -> f64 {
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    0.5 * (rs * rs + rp * rp)
}

/// KHR_materials_sheen's lobe of colour 1 times |n.l| (v, l above): the spec's Charlie
/// distribution (alphaG = roughness²) and visibility (Estevez and Kulla's fit of Λ).
fn sheen_f_cos(roughness: f64, v: DVec3, l: DVec3) -> f64 {
    let alpha_g = roughness * roughness;
    let inv_r = 1.0 / alpha_g;
    let n_h = (v + l).normalize().z;
    let sin2h = (1.0 - n_h * n_h).max(0.0);
    let distribution = (2.0 + inv_r) * sin2h.powf(inv_r * 0.5) / (2.0 * PI);
    let w = (1.0 - alpha_g) * (1.0 - alpha_g);
    let lerp = |a: f64, b: f64| a * (1.0 - w) + b * w;
    let numeric = |x: f64| {
        lerp(21.5473, 25.3245) / (1.0 + lerp(3.82987, 3.32435) * x.powf(lerp(0.19823, 0.16801)))
            + lerp(-1.97760, -1.27393) * x
            + lerp(-4.32054, -4.85967)
    };
    let lambda = |cos: f64| match cos.abs() {
        c if c < 0.5 => numeric(c).exp(),
        c => (2.0 * numeric(0.5) - numeric(1.0 - c)).exp(),
    };
    let visibility = 1.0 / ((1.0 + lambda(v.z) + lambda(l.z)) * (4.0 * v.z * l.z));
    distribution * visibility * l.z
}

/// E(cos θ) of the sheen lobe at one roughness: its directional albedo, integrated here at
/// SHEEN_E_POINTS views (midpoint rule in θ and φ) and interpolated linearly between them.
struct SheenAlbedo(Vec<f64>);

const SHEEN_E_POINTS: usize = 129;

impl SheenAlbedo {
    fn new(roughness: f64) -> SheenAlbedo {
        let (nt, np) = (360, 360);
        SheenAlbedo(
            (0..SHEEN_E_POINTS)
                .map(|k| {
                    let c = (k as f64 / (SHEEN_E_POINTS - 1) as f64).max(1e-4);
                    let v = DVec3::new((1.0 - c * c).sqrt(), 0.0, c);
                    let mut sum = 0.0;
                    for i in 0..nt {
                        let theta = (i as f64 + 0.5) / nt as f64 * PI / 2.0;
                        for j in 0..np {
                            let phi = (j as f64 + 0.5) / np as f64 * 2.0 * PI;
                            let l = DVec3::new(
                                theta.sin() * phi.cos(),
                                theta.sin() * phi.sin(),
                                theta.cos(),
                            );
                            sum += sheen_f_cos(roughness, v, l) * theta.sin();
                        }
                    }
                    sum * (PI / 2.0 / nt as f64) * (2.0 * PI / np as f64)
                })
                .collect(),
        )
    }

    fn at(&self, cos: f64) -> f64 {
        let x = cos.abs().min(1.0) * (SHEEN_E_POINTS - 1) as f64;
        let k = (x as usize).min(SHEEN_E_POINTS - 2);
        let t = x - k as f64;
        self.0[k] * (1.0 - t) + self.0[k + 1] * t
    }
}

impl Lobe {
    /// The base's GGX alphas along the anisotropy's direction and across it: the spec's
    /// mix(roughness², 1, strength²) and roughness² (equal without anisotropy).
    fn alphas(&self) -> (f64, f64) {
        let a = self.roughness * self.roughness;
        let s2 = self.anisotropy * self.anisotropy;
        (a * (1.0 - s2) + s2, a)
    }

    /// `w`'s components along the anisotropy's direction, across it and along the normal.
    fn along(&self, w: DVec3) -> DVec3 {
        let (s, c) = (self.aniso_rotation + self.tangent_angle).sin_cos();
        DVec3::new(c * w.x + s * w.y, c * w.y - s * w.x, w.z)
    }

    /// The spec's D_GGX_anisotropic (the isotropic GGX when the alphas are equal).
    fn d(&self, h: DVec3) -> f64 {
        if h.z <= 0.0 {
            return 0.0;
        }
        let (at, ab) = self.alphas();
        let h = self.along(h);
        let a2 = at * ab;
        let f = DVec3::new(ab * h.x, at * h.y, a2 * h.z);
        let w2 = a2 / f.length_squared();
        a2 * w2 * w2 / PI
    }

    /// The spec's V_GGX_anisotropic, height-correlated Smith G / (4 |n.l| |n.v|) (without the
    /// rasteriser's clamp to 1).
    fn v(&self, l: DVec3, v: DVec3) -> f64 {
        let (at, ab) = self.alphas();
        let (l, v) = (self.along(l), self.along(v));
        let ggx_v = l.z.abs() * DVec3::new(at * v.x, ab * v.y, v.z).length();
        let ggx_l = v.z.abs() * DVec3::new(at * l.x, ab * l.y, l.z).length();
        0.5 / (ggx_v + ggx_l)
    }

    /// The index above the film: the coat's 1.5 under a coat, else air's.
    fn film_outside(&self) -> f64 {
        if self.clearcoat > 0.0 {
            1.5
        } else {
            1.0
        }
    }

    /// Schlick's Fresnel of normal-incidence reflectance `f0` at cos `c`, mixed with the film's,
    /// in `channel`.
    fn filmed_in(&self, f0: f64, c: f64, channel: usize) -> f64 {
        let f = schlick(f0, c);
        if self.iridescence == 0.0 {
            return f;
        }
        let film = thin_film(
            self.film_outside(),
            self.film_ior,
            self.film_thickness,
            c,
            f0,
            channel,
        );
        f + (film - f) * self.iridescence
    }

    fn filmed(&self, f0: f64, c: f64) -> f64 {
        self.filmed_in(f0, c, self.channel)
    }

    /// The largest channel's: what the specular layer takes from the diffuse light beneath
    /// (the spec's fresnel_mix weighs the base by 1 - max_value(F)).
    fn filmed_max(&self, f0: f64, c: f64) -> f64 {
        (0..3).map(|k| self.filmed_in(f0, c, k)).fold(0.0, f64::max)
    }

    /// Glass's exact Fresnel at cos `c` from outside, mixed with the film's.
    fn glass_filmed(&self, c: f64) -> f64 {
        let f = fresnel(c, self.ior);
        if self.iridescence == 0.0 {
            return f;
        }
        let f0 = ((self.ior - 1.0) / (self.ior + 1.0)).powi(2);
        let film = thin_film(
            self.film_outside(),
            self.film_ior,
            self.film_thickness,
            c,
            f0,
            self.channel,
        );
        f + (film - f) * self.iridescence
    }

    /// f(v, l) |n.l| with n = +z, v above the surface; `sheen_e` the sheen's albedo E.
    fn f_cos(&self, v: DVec3, l: DVec3, sheen_e: &SheenAlbedo) -> f64 {
        let f0 = ((self.ior - 1.0) / (self.ior + 1.0)).powi(2);
        let mut f = 0.0;
        if l.z > 0.0 {
            let h = (v + l).normalize();
            let spec = self.d(h) * self.v(l, v);
            let metal = self.filmed(self.base, v.dot(h)) * spec;
            let fr = self.filmed(f0, v.dot(h));
            let diffuse = self.base * (1.0 - self.diffuse_transmission);
            let dielectric = (1.0 - self.filmed_max(f0, v.dot(h))) * diffuse / PI + fr * spec;
            let glass_reflect = self.glass_filmed(v.dot(h)) * spec;
            let opaque = (1.0 - self.transmission) * dielectric + self.transmission * glass_reflect;
            f = self.metallic * metal + (1.0 - self.metallic) * opaque;
        } else if self.transmission > 0.0 || self.diffuse_transmission > 0.0 {
            // Diffuse transmission: thin, weighed by the layer's Fresnel at l mirrored up.
            let h = (v + DVec3::new(l.x, l.y, -l.z)).normalize();
            let layer = 1.0 - self.filmed_max(f0, v.dot(h));
            f = (1.0 - self.metallic)
                * (1.0 - self.transmission)
                * layer
                * self.diffuse_transmission
                * self.dt_color
                / PI;
            // Refraction into the index `ior` below: h from the generalised half vector.
            let eta = self.ior;
            let mut h = -(v + eta * l).normalize();
            if h.z < 0.0 {
                h = -h;
            }
            let (vh, lh) = (v.dot(h), l.dot(h));
            if vh > 0.0 && lh < 0.0 {
                let denom = vh + eta * lh;
                let g = 4.0 * self.v(l, v) * l.z.abs() * v.z;
                let t = (1.0 - self.glass_filmed(vh)) * self.d(h) * g * (vh * lh).abs()
                    / (l.z.abs() * v.z * denom * denom);
                f += (1.0 - self.metallic) * self.transmission * self.base * t;
            }
        }
        // The sheen over the base: f_sheen + base * min(1 - c E(v), 1 - c E(l)).
        if self.sheen > 0.0 {
            f *= (1.0 - self.sheen * sheen_e.at(v.z)).min(1.0 - self.sheen * sheen_e.at(l.z));
            if l.z > 0.0 {
                f += self.sheen * sheen_f_cos(self.sheen_roughness, v, l) / l.z;
            }
        }
        // The coat: mix(base, D G / (4 |v.n| |l.n|), clearcoat * Schlick(0.04, v.n)); a perfect
        // mirror's share is added by `albedo`.
        let coat = self.clearcoat * schlick(0.04, v.z);
        f *= 1.0 - coat;
        if l.z > 0.0 && !self.coat_delta() {
            let alpha = self.coat_roughness * self.coat_roughness;
            let h = (v + l).normalize();
            f += coat * d_ggx(alpha, h.z) * v_smith(alpha, l.z, v.z);
        }
        f * l.z.abs()
    }

    fn coat_delta(&self) -> bool {
        self.coat_roughness < 0.01
    }

    /// ∫ f |cos| over the sphere of l, by the midpoint rule in (cos θ, φ) on each hemisphere,
    /// finer near the poles' directions where the lobes peak.
    fn albedo(&self, v: DVec3) -> f64 {
        // Only a sheen needs its albedo (its quadrature takes a while).
        let sheen_e = SheenAlbedo(if self.sheen > 0.0 {
            SheenAlbedo::new(self.sheen_roughness).0
        } else {
            vec![0.0; SHEEN_E_POINTS]
        });
        let (nt, np) = (1600, 720);
        let mut sum = 0.0;
        for side in [1.0, -1.0] {
            for i in 0..nt {
                // cos θ = 1 - s^2 spreads samples toward the horizon and the pole alike.
                let s = (i as f64 + 0.5) / nt as f64;
                let c = 1.0 - s * s;
                let dc = 2.0 * s / nt as f64;
                let st = (1.0 - c * c).max(0.0).sqrt();
                for j in 0..np {
                    let phi = 2.0 * PI * (j as f64 + 0.5) / np as f64;
                    let l = DVec3::new(st * phi.cos(), st * phi.sin(), side * c);
                    sum += self.f_cos(v, l, &sheen_e) * dc * 2.0 * PI / np as f64;
                }
            }
        }
        // A mirror coat reflects all of its weight.
        if self.coat_delta() {
            sum += self.clearcoat * schlick(0.04, v.z);
        }
        sum
    }

    fn material(&self) -> Material {
        Material {
            name: "lobe".into(),
            base_color: Vec4::new(self.base as f32, self.base as f32, self.base as f32, 1.0),
            metallic: self.metallic as f32,
            roughness: self.roughness as f32,
            transmission: self.transmission as f32,
            ior: self.ior as f32,
            specular: 1.0,
            specular_color: Vec3::ONE,
            double_sided: false,
            clearcoat: self.clearcoat as f32,
            clearcoat_roughness: self.coat_roughness as f32,
            diffuse_transmission: self.diffuse_transmission as f32,
            diffuse_transmission_color: Vec3::splat(self.dt_color as f32),
            sheen_color: Vec3::splat(self.sheen as f32),
            sheen_roughness: self.sheen_roughness as f32,
            iridescence: self.iridescence as f32,
            iridescence_ior: self.film_ior as f32,
            iridescence_thickness_max: self.film_thickness as f32,
            anisotropy_strength: self.anisotropy as f32,
            anisotropy_rotation: self.aniso_rotation as f32,
            ..Material::default()
        }
    }
}

/// The plane of the lobe's material seen from cos θ = `cos_view` by an orthographic camera,
/// under a sky of 1; from below (double-sided) when `cos_view` is negative.
fn plane(lobe: &Lobe, cos_view: f64) -> platoon::Prepared {
    let (s, c) = ((1.0 - cos_view * cos_view).sqrt() as f32, cos_view as f32);
    let mut material = lobe.material();
    material.double_sided = cos_view < 0.0;
    // The plane is y = 0 facing +y; the camera looks down at it from (s, c) in the x-y plane,
    // turned by the azimuth about +y (toward -z, the test's +y).
    let (sa, ca) = (lobe.view_azimuth as f32).sin_cos();
    under_unit_sky(
        vec![(tangent_quad(lobe.tangent_angle), Vec3::ZERO, 1000.0)],
        vec![material],
        vec![],
        Vec3::new(s * ca, c, -s * sa) * 10.0,
    )
}

/// The quad facing +y with UVs of 0 and its tangent turned `angle` from +x toward -z, the
/// bitangent n x t of the untilted tangent: the test's frame is x = +x (the view's azimuth),
/// y = -z, z = +y.
fn tangent_quad(angle: f64) -> platoon::core::scene::Mesh {
    let mut mesh = mesh_from(&platoon_scenegen::quad(1.0, 1.0), 0);
    mesh.uvs = vec![glam::Vec2::ZERO; mesh.positions.len()];
    let (s, c) = (angle as f32).sin_cos();
    mesh.tangents = vec![Vec4::new(c, 0.0, -s, 1.0); mesh.positions.len()];
    mesh
}

/// The plane's mean pixel and its standard error, seen along `v` (cos θ = v.z) under a sky of 1.
fn rendered(lobe: &Lobe, cos_view: f64, sampling: Sampling, spp: u32) -> (f64, f64) {
    let prepared = plane(lobe, cos_view);
    let mut params = FrameParams::new(32, 32, spp, prepared.camera);
    params.path_loop.max_depth = 8;
    let film = render(&prepared, &params, sampling);
    mean_and_stderr(film.pixels.iter().map(|p| p[lobe.channel] as f64))
}

fn check(name: &str, lobe: Lobe) {
    check_from(name, lobe, &[0.9, 0.5, 0.15]);
}

/// `check` from the views of cos θ in `views` (negative: from below, where the formula is the
/// one of the mirrored view).
fn check_from(name: &str, lobe: Lobe, views: &[f64]) {
    for &cos_view in views {
        let theta = cos_view.abs().acos();
        let (sa, ca) = lobe.view_azimuth.sin_cos();
        let v = DVec3::new(theta.sin() * ca, theta.sin() * sa, cos_view.abs());
        let expected = lobe.albedo(v);
        for sampling in [Sampling::Mis, Sampling::Bsdf, Sampling::Light] {
            let (m, se) = rendered(&lobe, cos_view, sampling, 512);
            eprintln!(
                "{name} cos {cos_view} {sampling:?}: {m:.5} +- {se:.5}, formula {expected:.5}"
            );
            assert!(
                (m - expected).abs() < 4.0 * se + 0.006 * expected,
                "{name}, cos θ {cos_view}, {sampling:?}: rendered {m:.5} +- {se:.5}, the formula integrates to {expected:.5}"
            );
        }
    }
}

#[test]
fn the_quadrature_gives_a_lambertian_plane_its_albedo() {
    // The reference's own check: roughness 1 dielectric without its specular layer is ρ.
    let lambert = |_v: DVec3, l: DVec3| if l.z > 0.0 { 0.5 / PI * l.z } else { 0.0 };
    let lobe = Lobe {
        base: 0.5,
        metallic: 0.0,
        roughness: 1.0,
        transmission: 0.0,
        ior: 1.5,
        clearcoat: 0.0,
        coat_roughness: 0.0,
        diffuse_transmission: 0.0,
        dt_color: 1.0,
        sheen: 0.0,
        sheen_roughness: 0.5,
        ..DIELECTRIC
    };
    let v = DVec3::new(0.6, 0.0, 0.8);
    let quadrature = {
        let (nt, np) = (1600, 720);
        let mut sum = 0.0;
        for i in 0..nt {
            let s = (i as f64 + 0.5) / nt as f64;
            let c = 1.0 - s * s;
            let st = (1.0 - c * c).sqrt();
            for j in 0..np {
                let phi = 2.0 * PI * (j as f64 + 0.5) / np as f64;
                let l = DVec3::new(st * phi.cos(), st * phi.sin(), c);
                sum += lambert(v, l) * 2.0 * s / nt as f64 * 2.0 * PI / np as f64;
            }
        }
        sum
    };
    assert!((quadrature - 0.5).abs() < 1e-4, "{quadrature}");
    // A white furnace of the rough metal loses energy to single scattering only (< 1).
    let white_metal = Lobe {
        base: 1.0,
        metallic: 1.0,
        roughness: 0.5,
        ..lobe
    };
    let a = white_metal.albedo(v);
    assert!(a < 1.0 && a > 0.85, "{a}");
}

#[test]
fn rough_and_glossy_metals_reflect_as_the_spec_integrates() {
    for roughness in [0.3, 0.6] {
        check(
            &format!("metal r {roughness}"),
            Lobe {
                base: 0.6,
                metallic: 1.0,
                roughness,
                transmission: 0.0,
                ior: 1.5,
                clearcoat: 0.0,
                coat_roughness: 0.0,
                diffuse_transmission: 0.0,
                dt_color: 1.0,
                sheen: 0.0,
                sheen_roughness: 0.5,
                ..DIELECTRIC
            },
        );
    }
}

#[test]
fn the_dielectric_diffuse_and_specular_layer_reflect_as_the_spec_integrates() {
    for roughness in [0.3, 0.7] {
        check(
            &format!("dielectric r {roughness}"),
            Lobe {
                base: 0.5,
                metallic: 0.0,
                roughness,
                transmission: 0.0,
                ior: 1.5,
                clearcoat: 0.0,
                coat_roughness: 0.0,
                diffuse_transmission: 0.0,
                dt_color: 1.0,
                sheen: 0.0,
                sheen_roughness: 0.5,
                ..DIELECTRIC
            },
        );
    }
}

#[test]
fn rough_glass_reflects_and_refracts_as_the_spec_integrates() {
    for roughness in [0.3, 0.6] {
        check(
            &format!("glass r {roughness}"),
            Lobe {
                base: 1.0,
                metallic: 0.0,
                roughness,
                transmission: 1.0,
                ior: 1.5,
                clearcoat: 0.0,
                coat_roughness: 0.0,
                diffuse_transmission: 0.0,
                dt_color: 1.0,
                sheen: 0.0,
                sheen_roughness: 0.5,
                ..DIELECTRIC
            },
        );
    }
}

/// The kernel's BSDF probe (`frame::Output`) of the plane's point, a `w` x `h` image.
fn probe(
    prepared: &platoon::Prepared,
    output: Output,
    w: u32,
    h: u32,
    frame: u32,
) -> Vec<[f32; 3]> {
    let mut params = FrameParams::new(w, h, 1, prepared.camera);
    params.output = output;
    params.frame = frame;
    render(prepared, &params, Sampling::Mis).pixels
}

/// Bins of the sphere of directions: `CT` in cos θ by `CP` in φ, equal solid angles.
const CT: usize = 20;
const CP: usize = 40;
/// The pdf is evaluated at SUB x SUB points of every bin.
const SUB: usize = 24;

fn bin_of(wi: [f32; 3]) -> usize {
    let t = (((1.0 - wi[2] as f64) / 2.0 * CT as f64) as usize).min(CT - 1);
    let phi = (wi[1] as f64).atan2(wi[0] as f64).rem_euclid(2.0 * PI);
    let p = ((phi / (2.0 * PI) * CP as f64) as usize).min(CP - 1);
    t * CP + p
}

/// Wilson and Hilferty's normal approximation of a chi-square statistic of `dof` degrees.
fn chi_square_z(chi2: f64, dof: f64) -> f64 {
    let k = 2.0 / (9.0 * dof);
    ((chi2 / dof).powf(1.0 / 3.0) - (1.0 - k)) / k.sqrt()
}

/// Chi-square goodness of fit of the kernel's sampled directions against its own pdf (Mitsuba's
/// and pbrt-v4's BSDF test), with bins of too few expected samples pooled; the pdf integrates to
/// at most one (the rest is the chance that sampling fails); reflection is reciprocal.
fn sampling_fits_pdf(name: &str, lobe: Lobe, cos_view: f64) {
    let prepared = plane(&lobe, cos_view);
    let values = probe(
        &prepared,
        Output::BsdfValue,
        (CP * SUB) as u32,
        (CT * SUB) as u32,
        0,
    );
    let cell = 4.0 * PI / (CP * SUB * CT * SUB) as f64;
    let mut mass = vec![0.0f64; CT * CP];
    for (k, v) in values.iter().enumerate() {
        let (x, y) = (k % (CP * SUB), k / (CP * SUB));
        mass[(y / SUB) * CP + x / SUB] += v[0] as f64 * cell;
        // Reciprocity of the reflection: f(wo, wi) = f(wi, wo).
        let c = 1.0 - 2.0 * (y as f64 + 0.5) / (CT * SUB) as f64;
        // A coat's weight follows the view alone: the spec's coated BSDF is not reciprocal.
        let side = cos_view.signum();
        if lobe.clearcoat == 0.0 && c * side > 0.05 && v[1] > 1e-3 {
            let rel = ((v[1] - v[2]) / v[1]).abs();
            assert!(
                rel < 2e-3,
                "{name}: f(wo, wi) {} but f(wi, wo) {} at cos {c:.3}",
                v[1],
                v[2]
            );
        }
    }
    let total: f64 = mass.iter().sum();
    assert!(
        total <= 1.0 + 5e-3,
        "{name}, cos {cos_view}: the pdf integrates to {total}"
    );
    let (side, frames) = (256u32, 4u32);
    let mut observed = vec![0.0f64; CT * CP];
    let mut failed = 0.0;
    for frame in 0..frames {
        for wi in probe(&prepared, Output::BsdfSample, side, side, frame) {
            if wi == [0.0; 3] {
                failed += 1.0;
            } else {
                observed[bin_of(wi)] += 1.0;
            }
        }
    }
    let n = (side * side * frames) as f64;
    let mut pairs: Vec<(f64, f64)> = mass.iter().map(|m| m * n).zip(observed).collect();
    pairs.push(((1.0 - total).max(0.0) * n, failed));
    let (mut chi2, mut bins, mut pooled) = (0.0, 0usize, (0.0, 0.0));
    for (e, o) in pairs {
        if e < 5.0 {
            pooled = (pooled.0 + e, pooled.1 + o);
        } else {
            chi2 += (o - e) * (o - e) / e;
            bins += 1;
        }
    }
    if pooled.0 >= 5.0 {
        chi2 += (pooled.1 - pooled.0) * (pooled.1 - pooled.0) / pooled.0;
        bins += 1;
    } else {
        // Too few expected to test apart: at least nothing much may land there.
        assert!(
            pooled.1 < 5.0 + 5.0 * pooled.0.sqrt() + pooled.0,
            "{name}: {} samples where the pdf expects {}",
            pooled.1,
            pooled.0
        );
    }
    let z = chi_square_z(chi2, (bins - 1) as f64);
    eprintln!(
        "{name} cos {cos_view}: chi2 {chi2:.1} over {bins} bins (z {z:.2}), pdf mass {total:.4}"
    );
    assert!(z < 5.0, "{name}, cos {cos_view}: the samples do not follow the pdf (chi2 {chi2:.1} over {bins} bins, z {z:.2})");
}

#[test]
fn every_lobe_samples_as_its_pdf_says() {
    let lobes = [
        (
            "metal r 0.3",
            Lobe {
                base: 0.6,
                metallic: 1.0,
                roughness: 0.3,
                transmission: 0.0,
                ior: 1.5,
                clearcoat: 0.0,
                coat_roughness: 0.0,
                diffuse_transmission: 0.0,
                dt_color: 1.0,
                sheen: 0.0,
                sheen_roughness: 0.5,
                ..DIELECTRIC
            },
        ),
        (
            "metal r 0.7",
            Lobe {
                base: 0.6,
                metallic: 1.0,
                roughness: 0.7,
                transmission: 0.0,
                ior: 1.5,
                clearcoat: 0.0,
                coat_roughness: 0.0,
                diffuse_transmission: 0.0,
                dt_color: 1.0,
                sheen: 0.0,
                sheen_roughness: 0.5,
                ..DIELECTRIC
            },
        ),
        (
            "dielectric r 0.4",
            Lobe {
                base: 0.5,
                metallic: 0.0,
                roughness: 0.4,
                transmission: 0.0,
                ior: 1.5,
                clearcoat: 0.0,
                coat_roughness: 0.0,
                diffuse_transmission: 0.0,
                dt_color: 1.0,
                sheen: 0.0,
                sheen_roughness: 0.5,
                ..DIELECTRIC
            },
        ),
        (
            "glass r 0.3",
            Lobe {
                base: 1.0,
                metallic: 0.0,
                roughness: 0.3,
                transmission: 1.0,
                ior: 1.5,
                clearcoat: 0.0,
                coat_roughness: 0.0,
                diffuse_transmission: 0.0,
                dt_color: 1.0,
                sheen: 0.0,
                sheen_roughness: 0.5,
                ..DIELECTRIC
            },
        ),
        (
            "glass r 0.6",
            Lobe {
                base: 1.0,
                metallic: 0.0,
                roughness: 0.6,
                transmission: 1.0,
                ior: 1.5,
                clearcoat: 0.0,
                coat_roughness: 0.0,
                diffuse_transmission: 0.0,
                dt_color: 1.0,
                sheen: 0.0,
                sheen_roughness: 0.5,
                ..DIELECTRIC
            },
        ),
        (
            "half metal r 0.5",
            Lobe {
                base: 0.7,
                metallic: 0.5,
                roughness: 0.5,
                transmission: 0.0,
                ior: 1.5,
                clearcoat: 0.0,
                coat_roughness: 0.0,
                diffuse_transmission: 0.0,
                dt_color: 1.0,
                sheen: 0.0,
                sheen_roughness: 0.5,
                ..DIELECTRIC
            },
        ),
    ];
    for (name, lobe) in lobes {
        for cos_view in [0.9, 0.4] {
            sampling_fits_pdf(name, lobe, cos_view);
        }
    }
}

/// The base lobes the coat and the back-side tests lay over: a rough dielectric and a metal.
const DIELECTRIC: Lobe = Lobe {
    base: 0.5,
    metallic: 0.0,
    roughness: 0.5,
    transmission: 0.0,
    ior: 1.5,
    clearcoat: 0.0,
    coat_roughness: 0.0,
    diffuse_transmission: 0.0,
    dt_color: 1.0,
    sheen: 0.0,
    sheen_roughness: 0.5,
    iridescence: 0.0,
    film_ior: 1.3,
    film_thickness: 400.0,
    channel: 0,
    anisotropy: 0.0,
    aniso_rotation: 0.0,
    tangent_angle: 0.0,
    view_azimuth: 0.0,
};
const METAL: Lobe = Lobe {
    base: 0.6,
    metallic: 1.0,
    roughness: 0.4,
    ..DIELECTRIC
};

#[test]
fn clearcoats_reflect_as_the_spec_integrates() {
    // A glossy and a rough coat, a partial one over a metal, and a mirror coat (roughness 0,
    // the spec's default) over a diffuse base.
    let lobes = [
        (
            "coat r 0.3 over dielectric",
            Lobe {
                clearcoat: 1.0,
                coat_roughness: 0.3,
                ..DIELECTRIC
            },
        ),
        (
            "coat 0.7 r 0.6 over metal",
            Lobe {
                clearcoat: 0.7,
                coat_roughness: 0.6,
                ..METAL
            },
        ),
        (
            "mirror coat over diffuse",
            Lobe {
                roughness: 1.0,
                clearcoat: 1.0,
                coat_roughness: 0.0,
                diffuse_transmission: 0.0,
                dt_color: 1.0,
                ..DIELECTRIC
            },
        ),
    ];
    for (name, lobe) in lobes {
        check(name, lobe);
    }
}

#[test]
fn a_double_sided_plane_reflects_alike_from_below() {
    // The back side mirrors the view through the origin: a glossy reflection sampled from
    // below must stay a reflection, not turn back toward the viewer.
    for (name, lobe) in [
        ("metal from below", METAL),
        ("dielectric from below", DIELECTRIC),
    ] {
        check_from(name, lobe, &[-0.8, -0.35]);
    }
    let coated = Lobe {
        clearcoat: 1.0,
        coat_roughness: 0.3,
        ..METAL
    };
    check_from("coat from below", coated, &[-0.6]);
}

#[test]
fn coats_and_back_sides_sample_as_their_pdf_says() {
    let coats = [
        (
            "coat r 0.3 over dielectric",
            Lobe {
                clearcoat: 1.0,
                coat_roughness: 0.3,
                ..DIELECTRIC
            },
        ),
        (
            "coat 0.5 r 0.6 over metal",
            Lobe {
                clearcoat: 0.5,
                coat_roughness: 0.6,
                ..METAL
            },
        ),
    ];
    for (name, lobe) in coats {
        for cos_view in [0.9, 0.4] {
            sampling_fits_pdf(name, lobe, cos_view);
        }
    }
    sampling_fits_pdf("metal from below", METAL, -0.6);
    sampling_fits_pdf(
        "coat from below",
        Lobe {
            clearcoat: 1.0,
            coat_roughness: 0.4,
            ..DIELECTRIC
        },
        -0.5,
    );
}

/// A mirror coat over a black base (no diffuse, no specular layer) under a sky of 1 shows
/// exactly its weight, Schlick(0.04, cos) about the normal the coat follows: the mesh's, whatever
/// the base's normal map says (glTF: the coat is not normal-mapped without a map of its own),
/// or its own map's.
#[test]
fn a_coat_follows_its_own_normal_map_not_the_bases() {
    use platoon::core::scene::TextureRef;
    // A map turning the normal 40 degrees toward the bitangent, as 8-bit texels.
    let tilt = 40f32.to_radians();
    let texel = |c: f32| ((c * 0.5 + 0.5) * 255.0).round() as u8;
    let rgba8 = [texel(0.0), texel(tilt.sin()), texel(tilt.cos()), 255];
    // As the kernel decodes it (0 is stored as 128, 0.0039).
    let decoded = (Vec3::new(rgba8[0] as f32, rgba8[1] as f32, rgba8[2] as f32) / 255.0 * 2.0
        - Vec3::ONE)
        .normalize();
    // The quad faces +y with tangent +x; the bitangent is n x t = -z.
    let (t, b, n) = (Vec3::X, Vec3::NEG_Z, Vec3::Y);
    let tilted = (decoded.x * t + decoded.y * b + decoded.z * n).normalize();
    let cos_view = 0.5f32;
    let v = Vec3::new((1.0 - cos_view * cos_view).sqrt(), cos_view, 0.0);
    let schlick = |c: f32| 0.04 + 0.96 * (1.0 - c).powi(5);

    let black = Material {
        name: "coated black".into(),
        base_color: Vec4::new(0.0, 0.0, 0.0, 1.0),
        metallic: 0.0,
        roughness: 1.0,
        specular: 0.0,
        clearcoat: 1.0,
        clearcoat_roughness: 0.0,
        ..Material::default()
    };
    let map = Some(TextureRef::new(0));
    let cases = [
        (
            "the base's map",
            Material {
                normal_texture: map,
                ..black.clone()
            },
            schlick(cos_view),
        ),
        (
            "the coat's map",
            Material {
                clearcoat_normal_texture: map,
                ..black.clone()
            },
            schlick(v.dot(tilted)),
        ),
    ];
    for (name, material, expected) in cases {
        let prepared = under_unit_sky(
            vec![(tangent_quad(0.0), Vec3::ZERO, 1000.0)],
            vec![material],
            vec![one_texel("tilt", rgba8)],
            v * 10.0,
        );
        for sampling in [Sampling::Mis, Sampling::Bsdf] {
            let film = render(
                &prepared,
                &FrameParams::new(8, 8, 4, prepared.camera),
                sampling,
            );
            for p in &film.pixels {
                assert!(
                    (p[0] - expected).abs() < 2e-4,
                    "{name}, {sampling:?}: {} where the coat's Fresnel is {expected}",
                    p[0]
                );
            }
        }
    }
    // The two normals give visibly different Fresnel weights: the test tells them apart.
    assert!((schlick(cos_view) - schlick(v.dot(tilted))).abs() > 0.03);
}

/// A leaf-like dielectric that passes on part of its diffuse light: as much as the spec's
/// formula integrates to over both sides, seen from above and below, and sampled as its pdf says.
#[test]
fn diffuse_transmission_passes_light_as_the_spec_integrates() {
    let leaf = Lobe {
        base: 0.5,
        roughness: 0.5,
        diffuse_transmission: 0.6,
        dt_color: 0.7,
        ..DIELECTRIC
    };
    check_layer("diffuse transmission", leaf, [0.8, 0.3]);
}

/// A lobe over or in the base, held to the formula's albedo from three views above, one below
/// and under a glossy coat, and sampled as its pdf says from `sampled_views` and from below.
fn check_layer(name: &str, lobe: Lobe, sampled_views: [f64; 2]) {
    check(name, lobe);
    check_from(&format!("{name} from below"), lobe, &[-0.5]);
    let coated = Lobe {
        clearcoat: 1.0,
        coat_roughness: 0.3,
        ..lobe
    };
    check_from(&format!("coated {name}"), coated, &[0.6]);
    for cos_view in sampled_views {
        sampling_fits_pdf(name, lobe, cos_view);
    }
    sampling_fits_pdf(&format!("{name} from below"), lobe, -0.6);
}

/// Velvet: a sheen over a rough dielectric and over a metal, seen from above and below, under a
/// coat, and a white sheen over a white diffuse base in the furnace (what the sheen reflects the
/// base loses, so the albedo stays below 1): as much light as the spec's formula integrates to,
/// sampled as the pdf says.
#[test]
fn sheen_reflects_as_the_spec_integrates() {
    let velvet = Lobe {
        sheen: 1.0,
        sheen_roughness: 0.3,
        roughness: 0.8,
        ..DIELECTRIC
    };
    check_layer("sheen r 0.3 over dielectric", velvet, [0.9, 0.3]);
    let sheened_metal = Lobe {
        sheen: 0.6,
        sheen_roughness: 0.7,
        ..METAL
    };
    check("sheen 0.6 r 0.7 over metal", sheened_metal);
    let white = Lobe {
        base: 1.0,
        roughness: 1.0,
        sheen: 1.0,
        sheen_roughness: 0.5,
        ..DIELECTRIC
    };
    for c in [0.95f64, 0.5, 0.1] {
        let a = white.albedo(DVec3::new((1.0 - c * c).sqrt(), 0.0, c));
        assert!(a < 1.0, "the white furnace reflects {a} at cos {c}");
    }
    check_from("white sheen over white", white, &[0.2]);
    sampling_fits_pdf("sheen over metal", sheened_metal, 0.6);
}

/// An oil film (KHR_materials_iridescence) over a dark glossy dielectric: each colour channel
/// reflects as much as the spec's formula integrates to, from above, below and under a coat (the
/// film's outside then the coat's index); sampled as the pdf says. The film must change what
/// the formula gives, or the test would not tell it from its absence.
#[test]
fn a_film_over_a_dielectric_reflects_as_the_spec_integrates() {
    let oil = Lobe {
        base: 0.05,
        roughness: 0.3,
        iridescence: 1.0,
        film_ior: 1.3,
        film_thickness: 400.0,
        ..DIELECTRIC
    };
    let v = DVec3::new(0.6, 0.0, 0.8);
    let bare = Lobe {
        iridescence: 0.0,
        ..oil
    };
    let with: Vec<f64> = (0..3)
        .map(|channel| Lobe { channel, ..oil }.albedo(v))
        .collect();
    assert!(
        with.iter().any(|a| (a - bare.albedo(v)).abs() > 0.02),
        "{with:?} vs {}",
        bare.albedo(v)
    );
    for channel in 0..3 {
        check(
            &format!("film over dielectric, channel {channel}"),
            Lobe { channel, ..oil },
        );
    }
    check_from("film from below", Lobe { channel: 2, ..oil }, &[-0.5]);
    // Over a bright base what a film of high index reflects (its largest channel) the diffuse
    // light loses.
    check_from(
        "film over a bright dielectric",
        Lobe {
            base: 0.8,
            roughness: 0.6,
            film_ior: 2.0,
            channel: 1,
            ..oil
        },
        &[0.7, 0.3],
    );
    check_from(
        "coated film",
        Lobe {
            clearcoat: 1.0,
            coat_roughness: 0.3,
            channel: 1,
            ..oil
        },
        &[0.6],
    );
    sampling_fits_pdf("film over dielectric", oil, 0.5);
}

/// Films over a rough metal and on rough glass (where reflection is sampled by the mean of the
/// film's channels and each channel weighed by its own reflectance): as the formula integrates,
/// channel by channel, and sampled as the pdf says.
#[test]
fn films_over_metal_and_on_glass_reflect_as_the_spec_integrates() {
    let metal = Lobe {
        base: 0.9,
        metallic: 1.0,
        roughness: 0.4,
        iridescence: 0.7,
        film_ior: 1.8,
        film_thickness: 300.0,
        ..DIELECTRIC
    };
    let glass = Lobe {
        base: 1.0,
        transmission: 1.0,
        roughness: 0.3,
        iridescence: 1.0,
        film_ior: 2.0,
        film_thickness: 350.0,
        ..DIELECTRIC
    };
    for channel in 0..3 {
        check_from(
            &format!("film over metal, channel {channel}"),
            Lobe { channel, ..metal },
            &[0.8, 0.3],
        );
        check_from(
            &format!("film on glass, channel {channel}"),
            Lobe { channel, ..glass },
            &[0.8, 0.4],
        );
    }
    sampling_fits_pdf("film on glass", glass, 0.7);
    sampling_fits_pdf("film over metal", metal, 0.4);
}

/// A smooth metal under a film, under a sky of 1, shows exactly the film's Fresnel at the view
/// in each channel (the perfect mirror's weight), and the film colours it.
#[test]
fn a_smooth_filmed_mirror_shows_the_films_fresnel_in_each_channel() {
    let mirror = Lobe {
        base: 0.9,
        metallic: 1.0,
        roughness: 0.0,
        iridescence: 1.0,
        film_ior: 1.8,
        film_thickness: 500.0,
        ..DIELECTRIC
    };
    for cos_view in [0.9, 0.45] {
        let prepared = plane(&mirror, cos_view);
        let expected: Vec<f64> = (0..3).map(|k| mirror.filmed_in(0.9, cos_view, k)).collect();
        assert!(
            expected.iter().fold(0.0f64, |a, &b| a.max(b))
                - expected.iter().fold(1.0f64, |a, &b| a.min(b))
                > 0.05,
            "the film leaves the mirror grey: {expected:?}"
        );
        for sampling in [Sampling::Mis, Sampling::Bsdf] {
            let film = render(
                &prepared,
                &FrameParams::new(8, 8, 4, prepared.camera),
                sampling,
            );
            for p in &film.pixels {
                for k in 0..3 {
                    assert!(
                        (p[k] as f64 - expected[k]).abs() < 2e-4 + 1e-4 * expected[k],
                        "cos {cos_view}, {sampling:?}, channel {k}: {} where the film's Fresnel is {}",
                        p[k],
                        expected[k]
                    );
                }
            }
        }
    }
}

/// The film's textures: the thickness mixes the minimum and maximum by the thickness texture's
/// green channel, the strength is the factor times the strength texture's red channel (both
/// linear, 8-bit): a smooth filmed mirror then shows that film's Fresnel exactly.
#[test]
fn a_films_textures_set_its_thickness_and_strength() {
    use platoon::core::scene::TextureRef;
    let (r, g) = (153u8, 64u8);
    let (strength, mix) = (r as f64 / 255.0, g as f64 / 255.0);
    let (thin, thick) = (150.0, 650.0);
    let mirror = Lobe {
        base: 0.9,
        metallic: 1.0,
        roughness: 0.0,
        iridescence: strength,
        film_ior: 1.6,
        film_thickness: thin + (thick - thin) * mix,
        ..DIELECTRIC
    };
    let cos_view = 0.7f64;
    let mut mesh = mesh_from(&platoon_scenegen::quad(1.0, 1.0), 0);
    mesh.uvs = vec![glam::Vec2::ZERO; mesh.positions.len()];
    let material = Material {
        iridescence: 1.0,
        iridescence_texture: Some(TextureRef::new(0)),
        iridescence_thickness_min: thin as f32,
        iridescence_thickness_max: thick as f32,
        iridescence_thickness_texture: Some(TextureRef::new(0)),
        ..mirror.material()
    };
    let (s, c) = ((1.0 - cos_view * cos_view).sqrt() as f32, cos_view as f32);
    let prepared = under_unit_sky(
        vec![(tangent_quad(0.0), Vec3::ZERO, 1000.0)],
        vec![material],
        vec![one_texel("film", [r, g, 0, 255])],
        Vec3::new(s, c, 0.0) * 10.0,
    );
    assert!(prepared.gpu.features.iridescence_textures);
    let film = render(
        &prepared,
        &FrameParams::new(8, 8, 4, prepared.camera),
        Sampling::Mis,
    );
    // Without the textures (the maximum thickness, full strength) the mirror looks otherwise.
    let untextured = Lobe {
        iridescence: 1.0,
        film_thickness: thick,
        ..mirror
    };
    let mut apart = 0.0f64;
    for k in 0..3 {
        let expected = mirror.filmed_in(0.9, cos_view, k);
        apart = apart.max((expected - untextured.filmed_in(0.9, cos_view, k)).abs());
        for p in &film.pixels {
            assert!(
                (p[k] as f64 - expected).abs() < 2e-4 + 1e-4 * expected,
                "channel {k}: {} where the textured film's Fresnel is {expected}",
                p[k]
            );
        }
    }
    assert!(apart > 0.03, "the textures change the film by only {apart}");
}

/// Smooth filmed glass over a black floor, under a sky of 1: what the camera sees is the
/// reflection alone (the refracted light finds the black floor), exactly the mixed Fresnel in
/// each channel, though reflection is chosen by the channels' mean.
#[test]
fn smooth_filmed_glass_reflects_the_films_fresnel_in_each_channel() {
    let glass = Lobe {
        base: 1.0,
        roughness: 0.0,
        transmission: 1.0,
        iridescence: 0.9,
        film_ior: 1.9,
        film_thickness: 420.0,
        ..DIELECTRIC
    };
    for cos_view in [0.85f64, 0.4] {
        let prepared = over_black_floor(glass.material(), cos_view);
        let (w, h, spp) = (16, 16, 1024);
        let image = render(
            &prepared,
            &FrameParams::new(w, h, spp, prepared.camera),
            Sampling::Mis,
        );
        for k in 0..3 {
            let expected = Lobe {
                channel: k,
                ..glass
            }
            .glass_filmed(cos_view);
            let (m, se) = mean_and_stderr(image.pixels.iter().map(|p| p[k] as f64));
            eprintln!("cos {cos_view} channel {k}: {m:.5} +- {se:.5}, film {expected:.5}");
            assert!(
                (m - expected).abs() < 4.0 * se + 2e-3 * expected,
                "cos {cos_view}, channel {k}: {m:.5} +- {se:.5} where the film's Fresnel is {expected:.5}"
            );
        }
    }
}

/// Brushed metal (KHR_materials_anisotropy): the base's GGX stretched along a direction the
/// rotation turns from the tangent, integrated from the spec's anisotropic D and V on the CPU:
/// along the view's azimuth and turned from it, over a dielectric and on rough glass, from
/// below; the direction must matter (rougher along the view than across it at a grazing view).
#[test]
fn anisotropic_lobes_reflect_as_the_spec_integrates() {
    let brushed = Lobe {
        base: 0.9,
        metallic: 1.0,
        roughness: 0.3,
        anisotropy: 0.8,
        ..DIELECTRIC
    };
    let v = DVec3::new((1.0f64 - 0.09).sqrt(), 0.0, 0.3);
    let across = Lobe {
        aniso_rotation: std::f64::consts::FRAC_PI_2,
        ..brushed
    };
    let (a, b) = (brushed.albedo(v), across.albedo(v));
    assert!((a - b).abs() > 0.02, "along {a} across {b}");
    check("brushed metal along the view", brushed);
    check_from(
        "brushed metal turned 1 rad",
        Lobe {
            aniso_rotation: 1.0,
            ..brushed
        },
        &[0.8, 0.3],
    );
    check_from("brushed metal from below", brushed, &[-0.5]);
    // Seen from an azimuth of 0.4 on a tangent turned 0.5, turned on by 0.9: the direction at
    // 1.4 is 1.0 from the view; turned the other way about the tangent (-0.4) or about the
    // kernel's frame (-1.4) it would be 0.8 or 1.8 from it.
    let turned = Lobe {
        aniso_rotation: 0.9,
        tangent_angle: 0.5,
        view_azimuth: 0.4,
        ..brushed
    };
    let (sa, ca) = 0.4f64.sin_cos();
    let at_azimuth = DVec3::new(v.x * ca, v.x * sa, v.z);
    for wrong in [-0.4, -1.4] {
        let other = Lobe {
            aniso_rotation: wrong - 0.5,
            ..turned
        };
        let (a, b) = (turned.albedo(at_azimuth), other.albedo(at_azimuth));
        assert!((a - b).abs() > 0.01, "turned {a}, at {wrong} {b}");
    }
    check_from("brushed metal on a turned tangent", turned, &[0.3]);
    check_from(
        "brushed dielectric",
        Lobe {
            base: 0.3,
            roughness: 0.4,
            anisotropy: 0.6,
            aniso_rotation: 0.5,
            ..DIELECTRIC
        },
        &[0.7, 0.3],
    );
    check_from(
        "anisotropic rough glass",
        Lobe {
            base: 1.0,
            transmission: 1.0,
            roughness: 0.3,
            anisotropy: 0.7,
            aniso_rotation: 2.0,
            ..DIELECTRIC
        },
        &[0.8, 0.4],
    );
}

#[test]
fn anisotropic_lobes_sample_as_their_pdf_says() {
    let brushed = Lobe {
        base: 0.9,
        metallic: 1.0,
        roughness: 0.3,
        anisotropy: 0.8,
        aniso_rotation: 1.0,
        ..DIELECTRIC
    };
    sampling_fits_pdf("brushed metal", brushed, 0.6);
    sampling_fits_pdf(
        "brushed dielectric",
        Lobe {
            base: 0.3,
            metallic: 0.0,
            roughness: 0.5,
            anisotropy: 0.6,
            ..brushed
        },
        0.4,
    );
    sampling_fits_pdf(
        "anisotropic rough glass",
        Lobe {
            base: 1.0,
            metallic: 0.0,
            transmission: 1.0,
            roughness: 0.4,
            anisotropy: 0.7,
            aniso_rotation: 2.0,
            ..brushed
        },
        0.7,
    );
}

/// The anisotropy texture: its red-green direction in tangent space, turned by the rotation,
/// and its blue strength times the factor (linear, 8-bit) make the lobe of that direction and
/// strength; the texture must matter (the rotation alone gives another albedo).
#[test]
fn an_anisotropy_texture_sets_the_direction_and_strength() {
    use platoon::core::scene::TextureRef;
    let texel = [128u8, 255, 153, 255];
    let d = (
        texel[0] as f64 / 255.0 * 2.0 - 1.0,
        texel[1] as f64 / 255.0 * 2.0 - 1.0,
    );
    let rotation = 0.3;
    let expected_lobe = Lobe {
        base: 0.9,
        metallic: 1.0,
        roughness: 0.3,
        anisotropy: texel[2] as f64 / 255.0,
        aniso_rotation: d.1.atan2(d.0) + rotation,
        ..DIELECTRIC
    };
    let cos_view = 0.35f64;
    let v = DVec3::new((1.0 - cos_view * cos_view).sqrt(), 0.0, cos_view);
    let expected = expected_lobe.albedo(v);
    let untextured = Lobe {
        anisotropy: 1.0,
        aniso_rotation: rotation,
        ..expected_lobe
    }
    .albedo(v);
    let material = Material {
        anisotropy_strength: 1.0,
        anisotropy_rotation: rotation as f32,
        anisotropy_texture: Some(TextureRef::new(0)),
        ..expected_lobe.material()
    };
    let (s, c) = ((1.0 - cos_view * cos_view).sqrt() as f32, cos_view as f32);
    let prepared = under_unit_sky(
        vec![(tangent_quad(0.0), Vec3::ZERO, 1000.0)],
        vec![material],
        vec![one_texel("direction", texel)],
        Vec3::new(s, c, 0.0) * 10.0,
    );
    assert!(prepared.gpu.features.anisotropy_textures);
    let mut params = FrameParams::new(32, 32, 512, prepared.camera);
    params.path_loop.max_depth = 8;
    let film = render(&prepared, &params, Sampling::Mis);
    let (m, se) = mean_and_stderr(film.pixels.iter().map(|p| p[0] as f64));
    eprintln!("textured: {m:.5} +- {se:.5}, formula {expected:.5}, untextured {untextured:.5}");
    assert!(
        (m - expected).abs() < 4.0 * se + 0.006 * expected,
        "rendered {m:.5} +- {se:.5} where the textured lobe integrates to {expected:.5}"
    );
    assert!((expected - untextured).abs() > 20.0 * se + 0.02);
}

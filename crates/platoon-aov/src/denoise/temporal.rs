//! The denoisers over a stream of frames (a game loop, `view`): each frame's own samples join a
//! history reprojected from the previous frame (SVGF's temporal accumulation, Schied et al.
//! 2017, section 4.1), and the spatial denoiser filters that history, so a moving view is
//! denoised from many frames' samples instead of one frame's.
//!
//! Reprojection: a pixel's first hit (its world position through the pixel centre; a miss: its
//! direction, the environment being infinitely far) is projected into the previous camera's
//! image, and the four previous pixels around that point are read bilinearly, each only when it
//! saw the same surface (same instance, normals within 25 degrees, the previous hit within 2%
//! of the depth from the current one's tangent plane). Without any such tap the pixel starts
//! over (a disocclusion). The history is a running mean weighted by samples: while nothing
//! moves every sample weighs the same (the film's exact average), and while anything moves the
//! history counts at most `MOVING_HISTORY_FRAMES` frames, so the new samples weigh at least 1/5
//! (SVGF's alpha = 0.2) and a moving light or object drags at most a few frames behind.
//! Moving objects: where the frame knows where each pixel's hit was in the frame before
//! ([`GBuffer::before`], the hit carried back through its triangle: the motion
//! vectors' own arithmetic), that point is projected instead, and the tests compare it and the
//! normal turned as its surface turned with the previous hits, so a moving, turning or
//! deforming object keeps its history. Without it a moved
//! object's pixels are rejected by the position test, or (sliding along its own surface) kept
//! and updated at the moving rate.

use glam::{DVec3, Quat, Vec3};
use rayon::prelude::*;

use super::{Denoiser, DeviceFilter, Guides};
use crate::aov::{self, Aov, AovPass};
use crate::hit_geometry::Before;
use platoon_image::Film;
use platoon_scene::camera::Camera;

/// While anything moves, the history counts at most this many frames of the current rate.
pub const MOVING_HISTORY_FRAMES: f32 = 4.0;
/// Smallest cosine between a pixel's normal and a previous one it may take history from.
const NORMAL_COS: f32 = 0.9;
/// Largest distance of a previous hit from the current hit's tangent plane, over the depth.
const PLANE_DISTANCE: f32 = 0.02;

/// A frame's geometry, from the AOV kernel passes ([`GBuffer::PASSES`]): the denoiser's guides
/// and what reprojection compares.
#[derive(Clone, Debug)]
pub struct GBuffer {
    pub guides: Guides,
    /// The first hit through the pixel centre, in render space (0 for a miss).
    pub position: Vec<[f32; 3]>,
    /// What names its object: its instance + 1 (or a key that outlives the instances' order:
    /// `HitGeometry::object_key`); 0 for a miss.
    pub instance: Vec<f32>,
    /// Where each pixel's hit was in the frame before (render space then) and how its surface
    /// turned since, when the scene moved: None for a miss or a surface that frame lacked (no
    /// history). None as a whole: the scene stood still, or its motion is unknown (reprojected
    /// by the camera alone).
    pub before: Option<Vec<Option<Before>>>,
}

impl GBuffer {
    /// The kernel passes it is made from.
    pub const PASSES: [AovPass; 4] = [
        AovPass::Albedo,
        AovPass::Normal,
        AovPass::Position,
        AovPass::Ids,
    ];

    /// From the films of [`GBuffer::PASSES`] (`film(pass)`) rendered from `camera`.
    pub fn from_passes(film: &dyn Fn(AovPass) -> Film, camera: &Camera) -> GBuffer {
        let layers = aov::layers(
            &[Aov::Albedo, Aov::Normal, Aov::Depth],
            film,
            camera,
            DVec3::ZERO,
            &aov::Context::films_only(1, 1),
        );
        GBuffer {
            guides: Guides::from_layers(&layers).expect("albedo, normal and depth were asked"),
            position: film(AovPass::Position).pixels,
            instance: film(AovPass::Ids).pixels.iter().map(|p| p[0]).collect(),
            before: None,
        }
    }
}

/// A frame as the history holds it.
struct History {
    camera: Camera,
    width: u32,
    height: u32,
    /// The temporally accumulated radiance, before the spatial filter.
    colour: Vec<[f32; 3]>,
    /// Samples behind each pixel of it.
    samples: Vec<f32>,
    /// The mean of each pixel's frame luminance and of its square, weighed as the colour.
    moments: Vec<[f32; 2]>,
    geometry: GBuffer,
}

/// What a pixel's history holds: its mean radiance, the samples behind it, its moments.
#[derive(Clone, Copy, Debug)]
struct Past {
    colour: [f32; 3],
    samples: f32,
    moments: [f32; 2],
}

/// A history shorter than this many frames leaves the variance to the filter's window (SVGF's
/// rule: two moments of a few frames are no estimate).
const MOMENT_FRAMES: f32 = 4.0;

/// A denoised frame of the stream.
#[derive(Clone, Debug)]
pub struct TemporalFrame {
    pub film: Film,
    /// Pixels that found their history in the previous frame, over all pixels.
    pub reused: f32,
    /// Samples behind the mean pixel of the history the filter read.
    pub mean_samples: f32,
}

/// A denoiser with its history.
pub struct Temporal {
    denoiser: Denoiser,
    history: Option<History>,
}

impl Temporal {
    /// With `denoiser` as the spatial filter (None: the accumulated history unfiltered).
    pub fn new(denoiser: Denoiser) -> Temporal {
        Temporal {
            denoiser,
            history: None,
        }
    }

    pub fn denoiser(&self) -> Denoiser {
        self.denoiser
    }

    /// Joins the frame's own estimate `frame` (the mean of its `spp` new samples a pixel) of
    /// the view from `camera`, whose geometry is `geometry`, to the history and returns the
    /// history denoised. `moved`: whether the camera or the scene changed since the previous
    /// frame. A device denoiser runs on `device`.
    pub fn filter(
        &mut self,
        frame: &Film,
        spp: u32,
        geometry: GBuffer,
        camera: Camera,
        moved: bool,
        device: &mut dyn DeviceFilter,
    ) -> Result<TemporalFrame, String> {
        let (w, h) = (frame.width, frame.height);
        let n = frame.pixels.len();
        let s = spp.max(1) as f32;
        let cap = if moved {
            MOVING_HISTORY_FRAMES * s
        } else {
            f32::INFINITY
        };
        let prior: Vec<Option<Past>> = match &self.history {
            Some(old) if (old.width, old.height) == (w, h) => (0..n)
                .into_par_iter()
                .map(|i| {
                    if moved {
                        reproject(old, &geometry, &camera, i, w, h)
                    } else {
                        Some(Past {
                            colour: old.colour[i],
                            samples: old.samples[i],
                            moments: old.moments[i],
                        })
                    }
                })
                .collect(),
            _ => vec![None; n],
        };
        let reused = prior.iter().filter(|p| p.is_some()).count() as f32 / n.max(1) as f32;
        let now: Vec<Past> = frame
            .pixels
            .iter()
            .zip(&prior)
            .map(|(x, prior)| {
                let l = luminance(*x);
                match *prior {
                    Some(p) => {
                        let total = p.samples.min(cap) + s;
                        let a = s / total;
                        Past {
                            colour: std::array::from_fn(|k| p.colour[k] + (x[k] - p.colour[k]) * a),
                            samples: total,
                            moments: [
                                p.moments[0] + (l - p.moments[0]) * a,
                                p.moments[1] + (l * l - p.moments[1]) * a,
                            ],
                        }
                    }
                    None => Past {
                        colour: *x,
                        samples: s,
                        moments: [l, l * l],
                    },
                }
            })
            .collect();
        let accumulated = Film {
            width: w,
            height: h,
            pixels: now.iter().map(|p| p.colour).collect(),
        };
        let mut geometry = geometry;
        geometry.guides.variance = Some(now.iter().map(|p| variance_of(p, s)).collect());
        let film = self
            .denoiser
            .apply_on(&accumulated, &geometry.guides, device)?;
        let mean_samples = now.iter().map(|p| p.samples).sum::<f32>() / n.max(1) as f32;
        self.history = Some(History {
            camera,
            width: w,
            height: h,
            colour: accumulated.pixels,
            samples: now.iter().map(|p| p.samples).collect(),
            moments: now.iter().map(|p| p.moments).collect(),
            geometry,
        });
        Ok(TemporalFrame {
            film,
            reused,
            mean_samples,
        })
    }
}

/// The variance of the luminance of a pixel's accumulated radiance `p`, from its moments: that
/// of one frame's mean (of `spp` samples) over the frames behind it; NaN under
/// [`MOMENT_FRAMES`] frames.
fn variance_of(p: &Past, spp: f32) -> f32 {
    let frames = p.samples / spp;
    if frames < MOMENT_FRAMES {
        return f32::NAN;
    }
    (p.moments[1] - p.moments[0] * p.moments[0]).max(0.0) / frames
}

fn luminance(c: [f32; 3]) -> f32 {
    0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
}

/// The history of pixel `i` of the new frame, read from where its first hit was in the old
/// one: the mean radiance, the samples and the moments behind it, or None when the old frame
/// did not see it.
fn reproject(
    old: &History,
    new: &GBuffer,
    camera: &Camera,
    i: usize,
    w: u32,
    h: u32,
) -> Option<Past> {
    let (x, y) = ((i % w as usize) as u32, (i / w as usize) as u32);
    let hit = new.instance[i] > 0.0;
    // Where the hit was then: carried back with the scene's motion where it is known.
    let then = match &new.before {
        Some(before) if hit => before[i]?,
        _ => Before {
            position: Vec3::from(new.position[i]),
            turn: Quat::IDENTITY,
        },
    };
    let at = if hit {
        old.camera.project(then.position, w, h)?
    } else if camera.orthographic.is_some() || old.camera.orthographic.is_some() {
        // Parallel rays see the environment in one direction from every pixel.
        glam::Vec2::new(x as f32 + 0.5, y as f32 + 0.5)
    } else {
        // A direction is where a point at unit distance from the old eye along it falls.
        let d = camera.basis(w, h).pixel_centre_direction(x, y, w, h);
        old.camera.project(old.camera.position() + d, w, h)?
    };
    // Pixel centres are at + 0.5: the four around `at`, weighted bilinearly.
    let (fx, fy) = (at.x - 0.5, at.y - 0.5);
    let (x0, y0) = (fx.floor(), fy.floor());
    let (mut sum, mut samples, mut weights) = ([0.0f32; 3], 0.0f32, 0.0f32);
    let mut moments = [0.0f32; 2];
    for (tx, ty) in [
        (x0, y0),
        (x0 + 1.0, y0),
        (x0, y0 + 1.0),
        (x0 + 1.0, y0 + 1.0),
    ] {
        if tx < 0.0 || ty < 0.0 || tx >= w as f32 || ty >= h as f32 {
            continue;
        }
        let weight = (1.0 - (fx - tx).abs()) * (1.0 - (fy - ty).abs());
        let j = ty as usize * w as usize + tx as usize;
        if weight <= 0.0 || !same_surface(new, i, then, &old.geometry, j) {
            continue;
        }
        for (s, c) in sum.iter_mut().zip(old.colour[j]) {
            *s += c * weight;
        }
        samples += old.samples[j] * weight;
        for (m, o) in moments.iter_mut().zip(old.moments[j]) {
            *m += o * weight;
        }
        weights += weight;
    }
    // A sliver of a tap is not history enough to keep.
    (weights > 1e-3).then(|| Past {
        colour: sum.map(|v| v / weights),
        samples: samples / weights,
        moments: moments.map(|m| m / weights),
    })
}

/// Whether pixel `j` of the old frame saw the surface pixel `i` of the new one sees, which was
/// where `then` says in the old frame.
fn same_surface(new: &GBuffer, i: usize, then: Before, old: &GBuffer, j: usize) -> bool {
    if new.instance[i] != old.instance[j] {
        return false;
    }
    if new.instance[i] == 0.0 {
        return true;
    }
    let (ni, nj) = (
        then.turn * Vec3::from(new.guides.normal[i]).normalize_or_zero(),
        Vec3::from(old.guides.normal[j]).normalize_or_zero(),
    );
    if ni != Vec3::ZERO && nj != Vec3::ZERO && ni.dot(nj) < NORMAL_COS {
        return false;
    }
    let off = Vec3::from(old.position[j]) - then.position;
    let plane = if ni == Vec3::ZERO {
        off.length()
    } else {
        off.dot(ni).abs()
    };
    plane <= PLANE_DISTANCE * new.guides.depth[i].abs()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::denoise::NoDevice;

    const W: u32 = 48;
    const H: u32 = 32;

    /// The view from `eye` (looking down -Z) of the plane z = 0 (instance 1, normal +Z) where
    /// `inside(x, y)` of its world point, else of a plane z = -4 (instance 2), radiance
    /// `radiance` of the world point: the frame and its geometry.
    fn view(
        eye: Vec3,
        radiance: &dyn Fn(Vec3) -> f32,
        inside: &dyn Fn(Vec3) -> bool,
    ) -> (Film, GBuffer, Camera) {
        let camera = Camera::look_at(eye, eye - Vec3::Z, 0.8);
        let b = camera.basis(W, H);
        let mut film = Film {
            width: W,
            height: H,
            pixels: Vec::new(),
        };
        let mut g = GBuffer {
            guides: Guides {
                albedo: Vec::new(),
                normal: Vec::new(),
                depth: Vec::new(),
                variance: None,
            },
            position: Vec::new(),
            instance: Vec::new(),
            before: None,
        };
        for y in 0..H {
            for x in 0..W {
                let d = b.pixel_centre_direction(x, y, W, H);
                let front = eye + d * (eye.z / -d.z);
                let (p, id) = if inside(front) {
                    (front, 1.0)
                } else {
                    (eye + d * ((eye.z + 4.0) / -d.z), 2.0)
                };
                film.pixels.push([radiance(p); 3]);
                g.guides.albedo.push([0.5; 3]);
                g.guides.normal.push([0.0, 0.0, 1.0]);
                g.guides.depth.push((p - eye).dot(b.forward));
                g.position.push(p.into());
                g.instance.push(id);
            }
        }
        (film, g, camera)
    }

    fn stripes(p: Vec3) -> f32 {
        1.0 + 0.5 * (1.3 * p.x).sin() * (0.7 * p.y).cos()
    }

    #[test]
    fn the_history_s_variance_keeps_a_shadow_edge_the_window_s_blurs() {
        // One plane, a shadow's edge across it (0.2 left of x = 0, 1.0 right), each frame's
        // pixels off by up to +-0.15 (an LCG's): SVGF's point. The window's variance takes the
        // edge for noise and the filter blurs it; the history's knows the noise alone.
        let eye = Vec3::new(0.0, 0.0, 5.0);
        let truth = |p: Vec3| if p.x < 0.0 { 0.2 } else { 1.0 };
        let mut state = 99u32;
        let mut noise = move || {
            state = state.wrapping_mul(1664525).wrapping_add(1013904223);
            ((state >> 8) as f32 / (1u32 << 24) as f32 - 0.5) * 0.3
        };
        let mut t = Temporal::new(Denoiser::Atrous);
        let (mut sum, mut out) = (vec![[0.0f32; 3]; (W * H) as usize], None);
        let frames = 12;
        for _ in 0..frames {
            let (mut frame, g, camera) = view(eye, &truth, &|_| true);
            for (p, s) in frame.pixels.iter_mut().zip(&mut sum) {
                *p = [p[0] + noise(); 3];
                s.iter_mut()
                    .zip(*p)
                    .for_each(|(s, v)| *s += v / frames as f32);
            }
            out = Some(
                t.filter(&frame, 1, g, camera, false, &mut NoDevice)
                    .unwrap(),
            );
        }
        let (_, g, _) = view(eye, &truth, &|_| true);
        let accumulated = Film {
            width: W,
            height: H,
            pixels: sum,
        };
        let windowed = super::super::atrous::filter(&accumulated, &g.guides);
        let (still, _, _) = view(eye, &truth, &|_| true);
        // The error of the two columns either side of the edge.
        let edge_error = |f: &Film| {
            let (mut e, mut n) = (0.0, 0);
            for i in 0..f.pixels.len() {
                let (x, w) = ((i % W as usize) as i32, W as i32);
                if (x - w / 2).abs() <= 1 || x == w / 2 - 2 {
                    e += (f.pixels[i][0] - still.pixels[i][0]).abs();
                    n += 1;
                }
            }
            e / n as f32
        };
        let (moments, window) = (edge_error(&out.unwrap().film), edge_error(&windowed));
        assert!(
            moments < 0.5 * window,
            "edge error with the history's variance {moments}, the window's {window}"
        );
    }

    #[test]
    fn a_still_view_weighs_every_sample_alike() {
        let mut t = Temporal::new(Denoiser::None);
        let eye = Vec3::new(0.0, 0.0, 5.0);
        let mut last = None;
        // Frames of 1, 3, 4 and 1 samples with means 2, 6, 1 and 12: the mean of all 9 is 4
        // (the last frame past what a moving view's history would count).
        for (spp, value) in [(1, 2.0), (3, 6.0), (4, 1.0), (1, 12.0)] {
            let (mut frame, g, camera) = view(eye, &|_| value, &|_| true);
            frame.pixels.iter_mut().for_each(|p| *p = [value; 3]);
            last = Some(
                t.filter(&frame, spp, g, camera, false, &mut NoDevice)
                    .unwrap(),
            );
        }
        let last = last.unwrap();
        assert_eq!(last.reused, 1.0);
        assert_eq!(last.mean_samples, 9.0);
        for p in &last.film.pixels {
            assert!((p[0] - 4.0).abs() < 1e-5, "{p:?}");
        }
    }

    #[test]
    fn a_moving_camera_finds_each_surface_point_in_the_previous_frame() {
        let mut t = Temporal::new(Denoiser::None);
        let all = |_: Vec3| true;
        let (a, g, camera) = view(Vec3::new(0.0, 0.0, 5.0), &stripes, &all);
        t.filter(&a, 1, g, camera, true, &mut NoDevice).unwrap();
        // The second view, moved sideways and closer, is the truth plus 1: a pixel that found
        // its history right is the mean of the truth and truth + 1 (equal samples).
        let eye = Vec3::new(0.6, -0.3, 4.2);
        let (mut b, g, camera) = view(eye, &stripes, &all);
        let truth = b.clone();
        b.pixels.iter_mut().for_each(|p| *p = p.map(|v| v + 1.0));
        let out = t.filter(&b, 1, g, camera, true, &mut NoDevice).unwrap();
        assert!(out.reused > 0.7, "{}", out.reused);
        let mut kept = 0;
        for (o, want) in out.film.pixels.iter().zip(&truth.pixels) {
            if (o[0] - (want[0] + 1.0)).abs() < 1e-6 {
                continue; // new at the image's edge: this frame alone
            }
            kept += 1;
            // Bilinear reading of the smooth stripes: a small error.
            assert!((o[0] - (want[0] + 0.5)).abs() < 0.02, "{o:?} vs {want:?}");
        }
        assert!(kept as f32 >= 0.7 * (W * H) as f32, "{kept}");
    }

    /// A strip of the plane z = 0 (instance 1) moving right by 0.4 a frame over the back
    /// plane, its stripes moving with it, the camera still: the history of (frame 1, truth)
    /// and (frame 2, truth + 1) of each pixel, with the strip's motion known or not.
    fn moving_strip(known: bool) -> (Film, Film, GBuffer) {
        let eye = Vec3::new(0.0, 0.0, 5.0);
        let frame_at = |shift: f32| {
            let on = move |p: Vec3| (p.x - shift).abs() < 1.5;
            let radiance = move |p: Vec3| {
                if p.z > -1.0 {
                    stripes(p - Vec3::X * shift)
                } else {
                    1.0
                }
            };
            view(eye, &radiance, &on)
        };
        let mut t = Temporal::new(Denoiser::None);
        let (a, g, camera) = frame_at(0.0);
        t.filter(&a, 1, g, camera, true, &mut NoDevice).unwrap();
        let (mut b, mut g, camera) = frame_at(0.4);
        let truth = b.clone();
        b.pixels.iter_mut().for_each(|p| *p = p.map(|v| v + 1.0));
        if known {
            let before = g.position.iter().zip(&g.instance);
            let moved = |p: &[f32; 3], id: f32| Before {
                position: Vec3::from(*p) - Vec3::X * if id == 1.0 { 0.4 } else { 0.0 },
                turn: Quat::IDENTITY,
            };
            g.before = Some(before.map(|(p, &id)| Some(moved(p, id))).collect());
        }
        let out = t
            .filter(&b, 1, g.clone(), camera, true, &mut NoDevice)
            .unwrap();
        (out.film, truth, g)
    }

    #[test]
    fn a_moving_object_keeps_its_history_where_its_motion_is_known() {
        let (out, truth, g) = moving_strip(true);
        let (mut strip, mut revealed) = (0, 0);
        for (i, (o, want)) in out.pixels.iter().zip(&truth.pixels).enumerate() {
            let p = Vec3::from(g.position[i]);
            if g.instance[i] == 1.0 && (p.x - 0.4).abs() < 1.3 {
                strip += 1;
                // Its own point a frame ago: the mean of the truth and truth + 1.
                assert!(
                    (o[0] - (want[0] + 0.5)).abs() < 0.02,
                    "{i}: {o:?} vs {want:?}"
                );
            }
            // The back plane where the strip stood in front of it a frame ago: started over.
            let before = p * (5.0 / 9.0) + Vec3::new(0.0, 0.0, 5.0) * (4.0 / 9.0);
            if g.instance[i] == 2.0 && before.x.abs() < 1.4 {
                revealed += 1;
                assert_eq!(o[0], want[0] + 1.0, "{i}: a history it never had");
            }
        }
        assert!(strip > 200 && revealed > 10, "{strip} {revealed}");
        // The same frames without the motion: the strip's pixels take the history of the
        // world point they show now, which showed another part of the stripes.
        let (out, truth, g) = moving_strip(false);
        let wrong = (0..out.pixels.len())
            .filter(|&i| g.instance[i] == 1.0)
            .filter(|&i| (out.pixels[i][0] - (truth.pixels[i][0] + 0.5)).abs() > 0.05)
            .count();
        assert!(wrong > 100, "{wrong}");
    }

    #[test]
    fn a_disoccluded_pixel_starts_over() {
        let mut t = Temporal::new(Denoiser::None);
        let eye = Vec3::new(0.0, 0.0, 5.0);
        // The front plane covers x < 0, then x < -1: the strip between shows the back plane,
        // which the front plane hid in the first frame.
        let (a, g, camera) = view(eye, &|_| 4.0, &|p| p.x < 0.0);
        t.filter(&a, 1, g, camera, true, &mut NoDevice).unwrap();
        let (b, mut g, camera) = view(eye, &|_| 2.0, &|p| p.x < -1.0);
        // Another object in the back plane's place where x > 2 (coplanar: only its instance
        // tells it apart).
        for i in 0..g.instance.len() {
            if g.instance[i] == 2.0 && g.position[i][0] > 2.0 {
                g.instance[i] = 3.0;
            }
        }
        let out = t
            .filter(&b, 1, g.clone(), camera, true, &mut NoDevice)
            .unwrap();
        let mut revealed = 0;
        for (i, o) in out.film.pixels.iter().enumerate() {
            let p = Vec3::from(g.position[i]);
            // A world point on the back plane the front plane hid before, or the new object.
            let hidden = g.instance[i] == 3.0
                || g.instance[i] == 2.0 && {
                    let front = p + (eye - p) * (4.0 / (4.0 + 5.0));
                    front.x < 0.0
                };
            if hidden {
                revealed += 1;
                assert_eq!(o[0], 2.0, "pixel {i} kept a history it never had");
            } else {
                assert_eq!(o[0], 3.0, "pixel {i} lost its history");
            }
        }
        assert!(revealed > 20, "{revealed}");
    }

    #[test]
    fn a_constant_view_stays_constant_through_motion_and_the_filter() {
        let mut t = Temporal::new(Denoiser::Atrous);
        for k in 0..4 {
            let eye = Vec3::new(0.2 * k as f32, 0.0, 5.0 - 0.3 * k as f32);
            let (frame, g, camera) = view(eye, &|_| 0.7, &|p| p.x < 0.5);
            let out = t.filter(&frame, 2, g, camera, true, &mut NoDevice).unwrap();
            for p in &out.film.pixels {
                assert!((p[0] - 0.7).abs() < 1e-5, "frame {k}: {p:?}");
            }
        }
    }
}

//! The bytes that travel between ranks: a rank's share of a frame, the bands it rendered, a
//! scene commit. Little-endian, length-prefixed, no schema: both ends are the same build
//! (every rank runs the same binary, as `mpirun` starts it), and the frame's fingerprint
//! (`fingerprint`) catches ranks whose settings differ. Bulk arrays (sums, bytes of a commit)
//! are copied as they are.

use std::hash::{Hash, Hasher};
use std::time::Duration;

use platoon_core::flatten::commit::{ArrayCommit, Commit, SceneHeader};
use platoon_core::flatten::MeshRegion;
use platoon_core::frame::{Band, FrameParams, MethodReport, PixelData, Span};
use platoon_core::scene::camera::Camera;
use platoon_schedule::renderer::{TracerFailure, TracerStats};

#[derive(Debug, thiserror::Error)]
#[error("a message between ranks is cut short or malformed: {0}")]
pub struct WireError(pub String);

/// Appends values to a message.
#[derive(Default)]
pub struct Writer(pub Vec<u8>);

impl Writer {
    pub fn u8(&mut self, v: u8) {
        self.0.push(v);
    }
    pub fn u32(&mut self, v: u32) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    pub fn u64(&mut self, v: u64) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    pub fn f32(&mut self, v: f32) {
        self.u32(v.to_bits());
    }
    pub fn f64(&mut self, v: f64) {
        self.u64(v.to_bits());
    }
    pub fn duration(&mut self, d: Duration) {
        self.u64(d.as_nanos().min(u64::MAX as u128) as u64);
    }
    /// A length, then the bytes.
    pub fn bytes(&mut self, b: &[u8]) {
        self.u64(b.len() as u64);
        self.0.extend_from_slice(b);
    }
    /// A plain-data slice as its bytes (bit for bit).
    pub fn pod<T: bytemuck::Pod>(&mut self, v: &[T]) {
        self.bytes(bytemuck::cast_slice(v));
    }
    pub fn str(&mut self, s: &str) {
        self.bytes(s.as_bytes());
    }
    pub fn span(&mut self, s: Span) {
        self.u32(s.begin);
        self.u32(s.end);
    }
    pub fn flag(&mut self, on: bool) {
        self.u8(on as u8);
    }
    pub fn opt_f32(&mut self, v: Option<f32>) {
        self.flag(v.is_some());
        self.f32(v.unwrap_or(0.0));
    }
}

/// Reads values back in the order they were written.
pub struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> Reader<'a> {
    pub fn new(bytes: &'a [u8]) -> Reader<'a> {
        Reader { bytes, at: 0 }
    }
    fn take(&mut self, n: usize) -> Result<&'a [u8], WireError> {
        let end = self.at.checked_add(n).filter(|&e| e <= self.bytes.len());
        let end = end.ok_or_else(|| {
            WireError(format!(
                "{n} bytes wanted at {} of {}",
                self.at,
                self.bytes.len()
            ))
        })?;
        let piece = &self.bytes[self.at..end];
        self.at = end;
        Ok(piece)
    }
    pub fn u8(&mut self) -> Result<u8, WireError> {
        Ok(self.take(1)?[0])
    }
    pub fn u32(&mut self) -> Result<u32, WireError> {
        Ok(u32::from_le_bytes(self.take(4)?.try_into().expect("4")))
    }
    pub fn u64(&mut self) -> Result<u64, WireError> {
        Ok(u64::from_le_bytes(self.take(8)?.try_into().expect("8")))
    }
    pub fn f32(&mut self) -> Result<f32, WireError> {
        Ok(f32::from_bits(self.u32()?))
    }
    pub fn f64(&mut self) -> Result<f64, WireError> {
        Ok(f64::from_bits(self.u64()?))
    }
    pub fn duration(&mut self) -> Result<Duration, WireError> {
        Ok(Duration::from_nanos(self.u64()?))
    }
    pub fn bytes(&mut self) -> Result<&'a [u8], WireError> {
        let n = usize::try_from(self.u64()?).map_err(|_| WireError("length".into()))?;
        self.take(n)
    }
    pub fn pod<T: bytemuck::Pod>(&mut self) -> Result<Vec<T>, WireError> {
        let b = self.bytes()?;
        if b.len() % std::mem::size_of::<T>() != 0 {
            return Err(WireError(format!(
                "{} bytes are not whole values of {} bytes",
                b.len(),
                std::mem::size_of::<T>()
            )));
        }
        // Copied: the message's bytes need not be aligned for T.
        Ok(bytemuck::pod_collect_to_vec(b))
    }
    pub fn string(&mut self) -> Result<String, WireError> {
        String::from_utf8(self.bytes()?.to_vec()).map_err(|e| WireError(e.to_string()))
    }
    pub fn span(&mut self) -> Result<Span, WireError> {
        Ok(Span::new(self.u32()?, self.u32()?))
    }
    pub fn flag(&mut self) -> Result<bool, WireError> {
        Ok(self.u8()? != 0)
    }
    pub fn opt_f32(&mut self) -> Result<Option<f32>, WireError> {
        let some = self.u8()? == 1;
        let v = self.f32()?;
        Ok(some.then_some(v))
    }
    /// Whether every byte was read (a message with bytes left over is not what was sent).
    pub fn finish(&self) -> Result<(), WireError> {
        if self.at == self.bytes.len() {
            Ok(())
        } else {
            Err(WireError(format!(
                "{} bytes left over",
                self.bytes.len() - self.at
            )))
        }
    }
}

/// A camera, bit for bit.
pub fn put_camera(w: &mut Writer, camera: &Camera) {
    let Camera {
        camera_to_world,
        yfov,
        aperture_radius,
        focus_distance,
        orthographic,
    } = camera;
    w.pod(&camera_to_world.to_cols_array());
    w.f32(*yfov);
    w.f32(*aperture_radius);
    w.f32(*focus_distance);
    w.u8(orthographic.is_some() as u8);
    w.pod(&orthographic.unwrap_or_default());
}

pub fn get_camera(r: &mut Reader) -> Result<Camera, WireError> {
    let cols: Vec<f32> = r.pod()?;
    let cols: [f32; 16] = cols
        .try_into()
        .map_err(|_| WireError("the camera's matrix".into()))?;
    Ok(Camera {
        camera_to_world: glam::Mat4::from_cols_array(&cols),
        yfov: r.f32()?,
        aperture_radius: r.f32()?,
        focus_distance: r.f32()?,
        orthographic: {
            let some = r.flag()?;
            let xy: Vec<f32> = r.pod()?;
            let xy: [f32; 2] = xy
                .try_into()
                .map_err(|_| WireError("the orthographic size".into()))?;
            some.then_some(xy)
        },
    })
}

/// A hash of everything in `params` that every rank must agree on (all but the sums and
/// masks rank 0 sends with each share, which are the frame's data, not its settings): ranks
/// that prepared the frame differently would render a different image in their bands. The
/// frame's settings as the wire encodes them, and its method's state, which holds its settings
/// (`MethodKind::state_bytes`: the world cache's table by its bits, where formatting a
/// megabyte each frame would cost more than the frame), or as `Debug` writes the state of a
/// method that has no bytes of it.
pub fn fingerprint(params: &FrameParams) -> u64 {
    let mut h = std::collections::hash_map::DefaultHasher::new();
    let mut settings = Vec::new();
    match ciborium::into_writer(params, &mut settings) {
        Ok(()) => settings.hash(&mut h),
        Err(e) => format!("{e} {params:?}").hash(&mut h),
    }
    let kind = params.method.kind();
    kind.name().hash(&mut h);
    match kind.state_bytes(&params.method) {
        Ok(Some(state)) => state.hash(&mut h),
        _ => format!("{:?}", params.method).hash(&mut h),
    }
    h.finish()
}

/// The film a frame continues, for the pixels `span`: the accumulated sums and the converged
/// mask there, each when the frame has it.
pub fn put_film_span(w: &mut Writer, p: &FrameParams, span: Span) {
    let range = span.begin as usize..span.end as usize;
    match &p.film.accumulated {
        Some(a) => {
            w.u8(1);
            w.pod(&a[range.clone()]);
        }
        None => w.u8(0),
    }
    match &p.film.converged {
        Some(c) => {
            w.u8(1);
            w.bytes(&c[range].iter().map(|&b| b as u8).collect::<Vec<u8>>());
        }
        None => w.u8(0),
    }
}

/// What `put_film_span` wrote, into `p` (a `width` x `height` frame): the sums and mask of
/// `span`, zero and unconverged elsewhere (the rank renders only its span).
pub fn get_film_span(r: &mut Reader, p: &mut FrameParams, span: Span) -> Result<(), WireError> {
    let pixels = p.width as usize * p.height as usize;
    if span.end as usize > pixels || span.begin > span.end {
        return Err(WireError(format!("a span {span:?} outside the frame")));
    }
    let range = span.begin as usize..span.end as usize;
    p.film.accumulated = None;
    if r.u8()? == 1 {
        let sums: Vec<[f32; 3]> = r.pod()?;
        if sums.len() != range.len() {
            return Err(WireError("the film's sums do not fit the span".into()));
        }
        let mut full = vec![[0.0f32; 3]; pixels];
        full[range.clone()].copy_from_slice(&sums);
        p.film.accumulated = Some(full.into());
    }
    p.film.converged = None;
    if r.u8()? == 1 {
        let mask = r.bytes()?;
        if mask.len() != range.len() {
            return Err(WireError("the film's mask does not fit the span".into()));
        }
        let mut full = vec![false; pixels];
        for (dst, &m) in full[range].iter_mut().zip(mask) {
            *dst = m != 0;
        }
        p.film.converged = Some(full.into());
    }
    Ok(())
}

/// A method's per-pixel records: each kind's name, words a record and words.
fn put_pixel_data(w: &mut Writer, d: &PixelData) {
    let streams: Vec<_> = d.streams().collect();
    w.u32(streams.len() as u32);
    for (kind, record_words, words) in streams {
        w.str(kind);
        w.u32(record_words);
        w.pod(words);
    }
}

fn get_pixel_data(r: &mut Reader) -> Result<PixelData, WireError> {
    let mut d = PixelData::default();
    for _ in 0..r.u32()? {
        let kind = r.string()?;
        let record_words = r.u32()?;
        let words: Vec<u32> = r.pod()?;
        d.push_words(&kind, record_words, &words)
            .map_err(WireError)?;
    }
    Ok(d)
}

pub fn put_band(w: &mut Writer, b: &Band) {
    w.span(b.span);
    w.pod(&b.sums);
    w.u32(b.samples);
    w.u64(b.rays);
    w.pod(&b.line_rays);
    w.u64(b.rejected_samples);
    w.u32(b.kernel_fallbacks);
    put_pixel_data(w, &b.per_pixel);
    let (kind, report) = b.method_report.parts();
    w.str(kind);
    w.bytes(report);
    w.duration(b.gpu_time);
    w.duration(b.wall_time);
}

pub fn get_band(r: &mut Reader) -> Result<Band, WireError> {
    Ok(Band {
        span: r.span()?,
        sums: r.pod()?,
        samples: r.u32()?,
        rays: r.u64()?,
        line_rays: r.pod()?,
        rejected_samples: r.u64()?,
        kernel_fallbacks: r.u32()?,
        per_pixel: get_pixel_data(r)?,
        method_report: MethodReport::from_parts(r.string()?, r.bytes()?.to_vec()),
        gpu_time: r.duration()?,
        wall_time: r.duration()?,
    })
}

pub fn put_tracer_stats(w: &mut Writer, s: &TracerStats) {
    w.u32(s.tracer as u32);
    w.span(s.span);
    w.u32(s.pixels);
    w.duration(s.gpu_time);
    w.duration(s.wall_time);
    w.duration(s.idle);
    w.u64(s.rays);
    w.u32(s.pieces);
    w.u32(s.stolen);
}

pub fn get_tracer_stats(r: &mut Reader) -> Result<TracerStats, WireError> {
    Ok(TracerStats {
        tracer: r.u32()? as usize,
        span: r.span()?,
        pixels: r.u32()?,
        gpu_time: r.duration()?,
        wall_time: r.duration()?,
        idle: r.duration()?,
        rays: r.u64()?,
        pieces: r.u32()?,
        stolen: r.u32()?,
    })
}

pub fn put_failure(w: &mut Writer, f: &TracerFailure) {
    w.u32(f.tracer as u32);
    w.u32(f.frame);
    w.str(&f.message);
}

pub fn get_failure(r: &mut Reader) -> Result<TracerFailure, WireError> {
    Ok(TracerFailure {
        tracer: r.u32()? as usize,
        frame: r.u32()?,
        message: r.string()?,
    })
}

/// A commit: every changed range with its bytes, and the scene header.
pub fn put_commit(w: &mut Writer, c: &Commit) {
    w.u32(c.arrays.len() as u32);
    for a in &c.arrays {
        w.u32(a.array as u32);
        w.u64(a.len);
        let flat: Vec<u64> = a.ranges.iter().flat_map(|&(o, l)| [o, l]).collect();
        w.pod(&flat);
        w.bytes(&a.data);
    }
    put_header(w, &c.header);
    let regions: Vec<u32> = c.regions.iter().flat_map(region_words).collect();
    w.pod(&regions);
    w.pod(&c.rebuilt);
    w.pod(&c.deformed);
}

/// A mesh region as the wire sends it: its seven words in field order.
fn region_words(r: &MeshRegion) -> [u32; 7] {
    [
        r.vertex_base,
        r.vertex_count,
        r.triangle_base,
        r.triangle_count,
        r.node_base,
        r.node_capacity,
        r.root,
    ]
}

pub fn get_commit(r: &mut Reader) -> Result<Commit, WireError> {
    let count = r.u32()?;
    let mut arrays = Vec::new();
    for _ in 0..count {
        let array = r.u32()? as usize;
        if array >= platoon_core::flatten::commit::ARRAY_COUNT {
            return Err(WireError(format!("no scene array {array}")));
        }
        let len = r.u64()?;
        let flat: Vec<u64> = r.pod()?;
        let ranges: Vec<(u64, u64)> = flat.chunks_exact(2).map(|p| (p[0], p[1])).collect();
        let data = r.bytes()?.to_vec();
        let covered: u64 = ranges.iter().map(|r| r.1).sum();
        if covered != data.len() as u64 || ranges.iter().any(|&(o, l)| o + l > len) {
            return Err(WireError(format!(
                "array {array}'s ranges do not match its bytes"
            )));
        }
        arrays.push(ArrayCommit {
            array,
            len,
            ranges,
            data,
        });
    }
    let header = get_header(r)?;
    let words: Vec<u32> = r.pod()?;
    if !words.len().is_multiple_of(7) {
        return Err(WireError("mesh regions of a commit cut short".into()));
    }
    let regions = words
        .chunks_exact(7)
        .map(|w| MeshRegion {
            vertex_base: w[0],
            vertex_count: w[1],
            triangle_base: w[2],
            triangle_count: w[3],
            node_base: w[4],
            node_capacity: w[5],
            root: w[6],
        })
        .collect();
    let rebuilt: Vec<u32> = r.pod()?;
    let deformed: Vec<u32> = r.pod()?;
    Ok(Commit {
        arrays,
        header,
        regions,
        rebuilt,
        deformed,
    })
}

fn put_header(w: &mut Writer, h: &SceneHeader) {
    let SceneHeader {
        lights,
        instances,
        tlas_root,
        env_kind,
        env_color,
        env_integral,
        env_size,
        features,
        scene_sphere,
    } = h;
    for v in [lights, instances, tlas_root, env_kind] {
        w.u32(*v);
    }
    w.pod(env_color);
    w.f32(*env_integral);
    w.pod(env_size);
    let mut features = *features;
    let flags: Vec<u8> = features.flags_mut().map(|f| *f as u8).to_vec();
    w.bytes(&flags);
    w.pod(scene_sphere);
}

fn get_header(r: &mut Reader) -> Result<SceneHeader, WireError> {
    let mut h = SceneHeader {
        lights: r.u32()?,
        instances: r.u32()?,
        tlas_root: r.u32()?,
        env_kind: r.u32()?,
        ..Default::default()
    };
    h.env_color = array_of(r.pod()?)?;
    h.env_integral = r.f32()?;
    h.env_size = array_of(r.pod()?)?;
    let flags = r.bytes()?;
    let mut slots = h.features.flags_mut();
    if flags.len() != slots.len() {
        return Err(WireError(format!(
            "{} feature flags, {} expected",
            flags.len(),
            slots.len()
        )));
    }
    for (slot, &f) in slots.iter_mut().zip(flags) {
        **slot = f != 0;
    }
    h.scene_sphere = array_of(r.pod()?)?;
    Ok(h)
}

fn array_of<T: Copy, const N: usize>(v: Vec<T>) -> Result<[T; N], WireError> {
    v.try_into()
        .map_err(|v: Vec<T>| WireError(format!("{} values, {N} expected", v.len())))
}

#[cfg(test)]
mod tests {
    use super::*;
    use platoon_core::method::lhb::LhbBuild;
    use platoon_core::method::links::ShotHit;
    use platoon_core::method::path::world_cache::TrainingRecord;

    #[test]
    fn a_band_comes_back_as_it_was_sent() {
        let band = Band {
            span: Span::new(5, 9),
            sums: vec![[1.0, -0.0, f32::NAN], [2.5, 3.0, 4.0]],
            samples: 3,
            rays: 77,
            line_rays: vec![4, 5],
            rejected_samples: 1,
            kernel_fallbacks: 2,
            // Two kinds of records, one with a NaN (bits travel as they are).
            per_pixel: PixelData::of(&[TrainingRecord {
                key: 9,
                radiance: [0.5, f32::NAN, 1.0],
            }])
            .with(&[ShotHit::default(); 2]),
            method_report: MethodReport::of(&LhbBuild {
                seconds: 0.25,
                kept: Some((false, 2)),
                ..Default::default()
            }),
            gpu_time: Duration::from_nanos(123),
            wall_time: Duration::from_millis(4),
        };
        let mut w = Writer::default();
        put_band(&mut w, &band);
        let mut r = Reader::new(&w.0);
        let back = get_band(&mut r).unwrap();
        r.finish().unwrap();
        let bits = |b: &Band| {
            b.sums
                .iter()
                .flatten()
                .map(|v| v.to_bits())
                .collect::<Vec<_>>()
        };
        assert_eq!(bits(&back), bits(&band));
        assert_eq!(
            format!(
                "{:?}",
                Band {
                    sums: vec![],
                    ..back
                }
            ),
            format!(
                "{:?}",
                Band {
                    sums: vec![],
                    ..band
                }
            )
        );
        // Cut short anywhere, it is an error, not a panic.
        for n in 0..w.0.len() {
            assert!(get_band(&mut Reader::new(&w.0[..n])).is_err(), "{n}");
        }
    }

    #[test]
    fn a_commit_comes_back_as_it_was_sent() {
        let mut header = SceneHeader {
            lights: 3,
            env_color: [0.1, 0.2, 0.3],
            env_size: [8, 4],
            scene_sphere: [1.0, 2.0, 3.0, 4.0],
            ..Default::default()
        };
        header.features.sheen = true;
        header.features.environment_map = true;
        let commit = Commit {
            arrays: vec![ArrayCommit {
                array: 2,
                len: 100,
                ranges: vec![(0, 3), (50, 2)],
                data: vec![1, 2, 3, 4, 5],
            }],
            header,
            regions: vec![MeshRegion {
                vertex_base: 1,
                vertex_count: 2,
                triangle_base: 3,
                triangle_count: 4,
                node_base: 5,
                node_capacity: 6,
                root: 7,
            }],
            rebuilt: vec![0],
            deformed: vec![0, 3],
        };
        let mut w = Writer::default();
        put_commit(&mut w, &commit);
        let mut r = Reader::new(&w.0);
        assert_eq!(get_commit(&mut r).unwrap(), commit);
        r.finish().unwrap();
        // Ranges that do not match the bytes are refused.
        let mut bad = commit.clone();
        bad.arrays[0].data.pop();
        let mut w = Writer::default();
        put_commit(&mut w, &bad);
        assert!(get_commit(&mut Reader::new(&w.0)).is_err());
    }

    #[test]
    fn the_fingerprint_sees_settings_and_not_the_frame_data() {
        let camera =
            platoon_core::scene::camera::Camera::look_at(glam::Vec3::Z, glam::Vec3::ZERO, 1.0);
        let p = FrameParams::new(4, 4, 2, camera);
        let mut q = p.clone();
        q.film.accumulated = Some(vec![[1.0; 3]; 16].into());
        assert_eq!(fingerprint(&p), fingerprint(&q));
        q.options.seed = 1;
        assert_ne!(fingerprint(&p), fingerprint(&q));
    }
}

//! What every device's buffers are built from: the frame, each direction's view, the
//! directional map and the table of placed triangles, packed into one array of words the
//! kernels read (shaders/lhb/lhb.glsl names the offsets). Made once per scene on the CPU and
//! shared by every tracer, so every device builds the same buffers.

use std::hash::Hasher;

use glam::Vec3;

use super::directional_map::DirectionalMap;
use super::frame::{BufferFrame, View};
use super::options::{LhbOptions, FRAME_MARGIN};
use crate::flatten::GpuScene;

/// Words of the header (`LHB_*` in shaders/lhb/lhb.glsl).
pub const HEADER_WORDS: usize = 16;

/// The packed tables and what the host needs of them.
#[derive(Clone, Debug, PartialEq)]
pub struct Tables {
    pub frame: BufferFrame,
    pub views: Vec<View>,
    pub map: DirectionalMap,
    /// Front or back, every triangle where it is placed: (instance, scene triangle), instance
    /// after instance.
    pub placed: Vec<[u32; 2]>,
    /// Each instance's placed triangles: [first, end).
    pub instance_placed: Vec<[u32; 2]>,
    /// A digest of what the rasterizer reads of each instance (its triangles' corners and its
    /// transform): an instance whose digest is unchanged rasterizes into the same layers.
    pub instance_digests: Vec<u64>,
    /// The header, views, map and placed triangles as the kernels read them.
    pub words: Vec<u32>,
}

impl Tables {
    /// The tables of `g` for `options`.
    pub fn of_scene(g: &GpuScene, options: &LhbOptions) -> Tables {
        Tables::after(g, options, None)
    }

    /// The tables of `g` for `options`, in `previous`' frame when `g` still fits in it (a living
    /// scene's frame stays fixed, so the buffers of what did not move stay valid; the margin
    /// leaves room to move).
    pub fn after(g: &GpuScene, options: &LhbOptions, previous: Option<&Tables>) -> Tables {
        let directions = options.directions.directions();
        let fresh = BufferFrame::of_scene(g, FRAME_MARGIN);
        let frame = match previous {
            Some(p)
                if p.views.len() == directions.len()
                    && (Vec3::from(g.scene_center) - p.frame.centre).length()
                        + g.scene_radius as f32
                        <= p.frame.radius =>
            {
                p.frame
            }
            _ => fresh,
        };
        let views: Vec<View> = directions.iter().map(|&d| View::along(d)).collect();
        let map = DirectionalMap::for_directions(&directions);
        let mut placed = Vec::new();
        let mut instance_placed = Vec::with_capacity(g.instances.len());
        let mut instance_digests = Vec::with_capacity(g.instances.len());
        for (instance, gi) in g.instances.iter().enumerate() {
            let first = placed.len() as u32;
            let mut h = std::collections::hash_map::DefaultHasher::new();
            h.write(bytemuck::bytes_of(&gi.object_to_world));
            let triangles = g.instance_triangles(instance);
            let (t, n) = (triangles.start as usize, triangles.len());
            h.write_u32(triangles.start);
            h.write(bytemuck::cast_slice(
                &g.triangle_positions[3 * t..3 * (t + n)],
            ));
            placed.extend(triangles.map(|t| [instance as u32, t]));
            instance_placed.push([first, placed.len() as u32]);
            instance_digests.push(h.finish());
        }
        let words = pack(options, &frame, &views, &map, &placed);
        Tables {
            frame,
            views,
            map,
            placed,
            instance_placed,
            instance_digests,
            words,
        }
    }
}

fn pack(
    o: &LhbOptions,
    frame: &BufferFrame,
    views: &[View],
    map: &DirectionalMap,
    placed: &[[u32; 2]],
) -> Vec<u32> {
    let f = |x: f32| x.to_bits();
    let views_at = HEADER_WORDS;
    let ranges_at = views_at + 9 * views.len();
    let candidates_at = ranges_at + 2 * map.ranges.len();
    let placed_at = candidates_at + map.candidates.len();
    let mut w = vec![
        views.len() as u32,
        o.resolution,
        o.layers,
        placed.len() as u32,
        map.width,
        map.height,
        views_at as u32,
        ranges_at as u32,
        candidates_at as u32,
        placed_at as u32,
        f(frame.centre.x),
        f(frame.centre.y),
        f(frame.centre.z),
        f(frame.radius),
        f(o.cone),
        0,
    ];
    debug_assert_eq!(w.len(), HEADER_WORDS);
    let axis = |v: Vec3| [f(v.x), f(v.y), f(v.z)];
    for v in views {
        w.extend(axis(v.right));
        w.extend(axis(v.up));
        w.extend(axis(v.forward));
    }
    w.extend(map.ranges.iter().flatten());
    w.extend(&map.candidates);
    w.extend(placed.iter().flatten());
    w
}

/// Words of a probe's query: origin xyz, unit direction xyz, the jitter's two uniform numbers.
pub const QUERY_WORDS: usize = 8;

impl Tables {
    /// These tables carrying `queries` (origin, direction, jitter numbers): a frame rendered
    /// with them is a probe, whose pixel i answers query i by a lookup and leaves the hit's
    /// point as its radiance (1e30 where nothing was found) for tests to hold against the
    /// CPU's `lookup::Buffers::lookup`. Header word 15 says where they start.
    pub fn with_queries(&self, queries: &[[f32; QUERY_WORDS]]) -> Tables {
        let mut t = self.clone();
        t.words[15] = t.words.len() as u32;
        t.words.push(queries.len() as u32);
        t.words
            .extend(queries.iter().flatten().map(|x| x.to_bits()));
        t
    }

    /// Whether frames with these tables are probes (`with_queries`).
    pub fn probes(&self) -> bool {
        self.words[15] != 0
    }

    /// Per direction, per texel, the layers a device built (`work`: each texel's word; `layers`:
    /// the layer words), sorted as the oracle's (depth, then instance and triangle).
    pub fn device_lists(
        &self,
        options: &LhbOptions,
        work: &[u32],
        layers: &[[u32; 2]],
    ) -> Vec<Vec<Vec<super::oracle::Layer>>> {
        let r2 = (options.resolution * options.resolution) as usize;
        let exact = options.variant == super::options::RasterVariant::Exact;
        let capacity = options.layers as usize;
        (0..self.views.len())
            .map(|d| {
                (0..r2)
                    .map(|k| {
                        let t = d * r2 + k;
                        let range = if exact {
                            (if t == 0 { 0 } else { work[t - 1] as usize })..work[t] as usize
                        } else {
                            t * capacity..t * capacity + (work[t] as usize).min(capacity)
                        };
                        let mut list: Vec<super::oracle::Layer> = layers[range]
                            .iter()
                            .map(|&[depth, id]| {
                                let [instance, triangle] = self.placed[id as usize];
                                super::oracle::Layer {
                                    depth: f32::from_bits(depth),
                                    instance,
                                    triangle,
                                }
                            })
                            .collect();
                        list.sort_by(|p, q| {
                            p.depth
                                .total_cmp(&q.depth)
                                .then(p.instance.cmp(&q.instance))
                                .then(p.triangle.cmp(&q.triangle))
                        });
                        list
                    })
                    .collect()
            })
            .collect()
    }
}

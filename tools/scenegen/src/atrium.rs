//! A Sponza-sized interior (issue 39's bench at real scale): a two-storey arcaded courtyard of
//! about 250k triangles, built the way such assets are: fluted columns whose sides are one
//! segment tall and whose caps are fans (triangles a hundred times longer than wide), arches
//! swept along semicircles with fan-filled spandrels, rows of balusters, hanging curtains with
//! folds, a textured floor, and potted plants whose leaves are alpha-tested quads. Lit by a sun
//! through the open roof, a sky (the bench adds a constant one), lanterns of emissive triangles
//! and point lights under the arcades.

use std::f32::consts::PI;

use serde_json::{json, Value};

use crate::bench::facing;
use crate::{cut_quads, flat_box, grid, grid_rect, icosphere, MeshData, NodeData, SceneData};

/// Half the courtyard's length (x) and width (z), metres.
const HALF_LENGTH: f32 = 18.0;
const HALF_WIDTH: f32 = 8.0;
/// The arcade's column line (|z|), the columns' spacing and radius.
const ARCADE_Z: f32 = 6.0;
const SPACING: f32 = 4.0;
const COLUMN_RADIUS: f32 = 0.3;
/// Each storey: its floor, column height; arches of radius SPACING / 2 spring from the columns.
const STOREYS: [(f32, f32); 2] = [(0.0, 3.5), (6.0, 3.0)];
const SLAB: f32 = 0.5;

/// A vertical cylinder of `segments` flat facets about +y from y = 0 to `height`: each facet is
/// one quad the cylinder's height (two long thin triangles), each cap a fan from its centre.
pub fn fluted_column(segments: u32, radius: f32, height: f32) -> MeshData {
    let mut m = MeshData::default();
    let ring = |k: u32| {
        let a = 2.0 * PI * k as f32 / segments as f32;
        (a.cos(), a.sin())
    };
    for k in 0..segments {
        let ((c0, s0), (c1, s1)) = (ring(k), ring(k + 1));
        let b = m.positions.len() as u32;
        // The facet's normal, at its middle angle.
        let a = PI * (2 * k + 1) as f32 / segments as f32;
        let n = [a.cos(), 0.0, a.sin()];
        m.positions.extend([
            [radius * c0, 0.0, radius * s0],
            [radius * c1, 0.0, radius * s1],
            [radius * c1, height, radius * s1],
            [radius * c0, height, radius * s0],
        ]);
        m.normals.extend([n; 4]);
        // Counter-clockwise seen from outside.
        m.indices.extend([b, b + 3, b + 2, b, b + 2, b + 1]);
    }
    for (y, ny) in [(0.0f32, -1.0f32), (height, 1.0)] {
        let centre = m.positions.len() as u32;
        m.positions.push([0.0, y, 0.0]);
        m.normals.push([0.0, ny, 0.0]);
        for k in 0..segments {
            let (c, s) = ring(k);
            m.positions.push([radius * c, y, radius * s]);
            m.normals.push([0.0, ny, 0.0]);
        }
        for k in 0..segments {
            let (a, b) = (centre + 1 + k, centre + 1 + (k + 1) % segments);
            if ny > 0.0 {
                m.indices.extend([centre, b, a]);
            } else {
                m.indices.extend([centre, a, b]);
            }
        }
    }
    m
}

/// An arch of `segments` steps in the xy plane: a band between radii `inner` and `outer` about
/// the origin, from angle 0 to pi, `depth` deep along z, with its inner, outer, front and back
/// faces; and the spandrels that fill the square above it (up to y = `outer`, x in +-`outer`),
/// front and back, as fans from the square's top corners.
pub fn arch(segments: u32, inner: f32, outer: f32, depth: f32) -> MeshData {
    let mut m = MeshData::default();
    let at = |k: u32, r: f32| {
        let a = PI * k as f32 / segments as f32;
        (r * a.cos(), r * a.sin(), a)
    };
    let (zf, zb) = (depth / 2.0, -depth / 2.0);
    let quad = |m: &mut MeshData, p: [[f32; 3]; 4], n: [f32; 3]| {
        let b = m.positions.len() as u32;
        m.positions.extend(p);
        m.normals.extend([n; 4]);
        m.indices.extend([b, b + 1, b + 2, b, b + 2, b + 3]);
    };
    for k in 0..segments {
        let ((xi0, yi0, a0), (xi1, yi1, a1)) = (at(k, inner), at(k + 1, inner));
        let ((xo0, yo0, _), (xo1, yo1, _)) = (at(k, outer), at(k + 1, outer));
        let mid = (a0 + a1) / 2.0;
        let radial = [mid.cos(), mid.sin(), 0.0];
        // The soffit faces the arch's centre; the extrados faces away; front +z, back -z.
        quad(
            &mut m,
            [
                [xi0, yi0, zf],
                [xi1, yi1, zf],
                [xi1, yi1, zb],
                [xi0, yi0, zb],
            ],
            [-radial[0], -radial[1], 0.0],
        );
        quad(
            &mut m,
            [
                [xo0, yo0, zb],
                [xo1, yo1, zb],
                [xo1, yo1, zf],
                [xo0, yo0, zf],
            ],
            radial,
        );
        quad(
            &mut m,
            [
                [xi0, yi0, zf],
                [xo0, yo0, zf],
                [xo1, yo1, zf],
                [xi1, yi1, zf],
            ],
            [0.0, 0.0, 1.0],
        );
        quad(
            &mut m,
            [
                [xi1, yi1, zb],
                [xo1, yo1, zb],
                [xo0, yo0, zb],
                [xi0, yi0, zb],
            ],
            [0.0, 0.0, -1.0],
        );
    }
    // Spandrels: the right half fans from (outer, outer), the left from (-outer, outer).
    for (z, nz) in [(zf, 1.0f32), (zb, -1.0)] {
        for k in 0..segments {
            let corner = if 2 * k < segments { outer } else { -outer };
            let ((x0, y0, _), (x1, y1, _)) = (at(k, outer), at(k + 1, outer));
            let b = m.positions.len() as u32;
            m.positions
                .extend([[corner, outer, z], [x0, y0, z], [x1, y1, z]]);
            m.normals.extend([[0.0, 0.0, nz]; 3]);
            // (corner, p0, p1) winds clockwise seen from +z.
            if nz > 0.0 {
                m.indices.extend([b, b + 2, b + 1]);
            } else {
                m.indices.extend([b, b + 1, b + 2]);
            }
        }
    }
    m
}

/// A curtain `width` x `height` metres in the xy plane hanging down from y = 0, facing +z, in
/// `cols` x `rows` quads, pleated in `folds` folds of `amplitude` metres.
pub fn curtain(
    cols: u32,
    rows: u32,
    width: f32,
    height: f32,
    folds: f32,
    amplitude: f32,
) -> MeshData {
    let mut m = MeshData::default();
    let phase = |u: f32| 2.0 * PI * folds * u;
    for j in 0..=rows {
        for i in 0..=cols {
            let (u, v) = (i as f32 / cols as f32, j as f32 / rows as f32);
            // The folds open a little towards the hem.
            let a = amplitude * (0.6 + 0.4 * v);
            let z = a * phase(u).sin();
            let dz = a * 2.0 * PI * folds / width * phase(u).cos();
            let l = (1.0 + dz * dz).sqrt();
            m.positions.push([(u - 0.5) * width, -v * height, z]);
            m.normals.push([-dz / l, 0.0, 1.0 / l]);
            m.uvs.push([u * folds, v]);
        }
    }
    for j in 0..rows {
        for i in 0..cols {
            let a = j * (cols + 1) + i;
            let (b, c, d) = (a + 1, a + cols + 2, a + cols + 1);
            // Counter-clockwise seen from +z (rows go down).
            m.indices.extend([a, d, c, a, c, b]);
        }
    }
    m
}

/// A surface of revolution about +y through the (radius, height) `profile`, `segments` around.
pub fn lathe(profile: &[(f32, f32)], segments: u32) -> MeshData {
    let mut m = MeshData::default();
    let row = segments + 1;
    for (j, &(r, y)) in profile.iter().enumerate() {
        // The profile's tangent gives the normal's slope.
        let (pr, py) = profile[j.saturating_sub(1)];
        let (nr, ny) = profile[(j + 1).min(profile.len() - 1)];
        let (dr, dy) = (nr - pr, ny - py);
        let l = (dr * dr + dy * dy).sqrt().max(1e-6);
        let (n_out, n_up) = (dy / l, -dr / l);
        for k in 0..=segments {
            let a = 2.0 * PI * k as f32 / segments as f32;
            m.positions.push([r * a.cos(), y, r * a.sin()]);
            m.normals.push([n_out * a.cos(), n_up, n_out * a.sin()]);
        }
    }
    for j in 0..profile.len() as u32 - 1 {
        for k in 0..segments {
            let a = j * row + k;
            let (b, c, d) = (a + 1, a + row + 1, a + row);
            // Counter-clockwise seen from outside (angle grows from +x towards +z).
            m.indices.extend([a, d, c, a, c, b]);
        }
    }
    m
}

/// A bush of `leaves` leaf quads (each 0.25 m long) around the origin within `radius`, facing
/// every way, at pseudo-random places (a fixed sequence: the same scene every time); UVs span
/// each quad for the leaf's alpha-masked texture.
pub fn bush(leaves: u32, radius: f32) -> MeshData {
    let mut m = MeshData::default();
    let mut state = 0x2545_f491u32;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 17;
        state ^= state << 5;
        state as f32 / u32::MAX as f32
    };
    for _ in 0..leaves {
        let (u, v, w) = (next(), next(), next());
        let (theta, phi) = (2.0 * PI * u, (2.0 * v - 1.0).acos());
        let dir = [
            phi.sin() * theta.cos(),
            phi.cos().abs(),
            phi.sin() * theta.sin(),
        ];
        let r = radius * w.cbrt();
        let c = [dir[0] * r, dir[1] * r, dir[2] * r];
        // The leaf's long axis along dir, its width across it in the horizontal.
        let side = {
            let s = [-dir[2], 0.0, dir[0]];
            let l = (s[0] * s[0] + s[2] * s[2]).sqrt().max(1e-3);
            [s[0] / l, 0.0, s[2] / l]
        };
        // side x dir: the way the quad below winds.
        let n = [
            side[1] * dir[2] - side[2] * dir[1],
            side[2] * dir[0] - side[0] * dir[2],
            side[0] * dir[1] - side[1] * dir[0],
        ];
        let (len, half) = (0.25f32, 0.06f32);
        let b = m.positions.len() as u32;
        for (s, t) in [(-1.0f32, 0.0f32), (1.0, 0.0), (1.0, 1.0), (-1.0, 1.0)] {
            m.positions.push(std::array::from_fn(|k| {
                c[k] + side[k] * half * s + dir[k] * len * t
            }));
            m.normals.push(n);
            m.uvs.push([(s + 1.0) / 2.0, 1.0 - t]);
        }
        m.indices.extend([b, b + 1, b + 2, b, b + 2, b + 3]);
    }
    m
}

/// A leaf's alpha mask: an RGBA PNG, green, opaque inside a pointed ellipse and transparent
/// outside (alpha 0 or 255 only, so a MASK cutoff and an opacity read it alike).
pub fn leaf_png(size: u32) -> Vec<u8> {
    let mut px = Vec::with_capacity((size * size * 4) as usize);
    for y in 0..size {
        for x in 0..size {
            let (u, v) = (
                (x as f32 + 0.5) / size as f32 * 2.0 - 1.0,
                (y as f32 + 0.5) / size as f32,
            );
            // Widest a third of the way up, pointed at the tip.
            let width = (PI * v).sin().powf(0.8) * (1.0 - 0.3 * v);
            let inside = u.abs() < width * 0.95;
            let shade = (120.0 + 80.0 * v) as u8;
            px.extend([40, shade, 30, if inside { 255 } else { 0 }]);
        }
    }
    crate::twins::png(size, size, px)
}

/// Vertical stripes in two colours, for the curtains.
fn stripes_png(a: [u8; 3], b: [u8; 3]) -> Vec<u8> {
    let n = 64u32;
    let mut px = Vec::with_capacity((n * n * 4) as usize);
    for _ in 0..n {
        for x in 0..n {
            let c = if (x / 8) % 2 == 0 { a } else { b };
            px.extend([c[0], c[1], c[2], 255]);
        }
    }
    crate::twins::png(n, n, px)
}

fn material(name: &str, colour: [f32; 3], roughness: f32) -> Value {
    json!({"name": name, "pbrMetallicRoughness": {"baseColorFactor": [colour[0], colour[1], colour[2], 1], "metallicFactor": 0, "roughnessFactor": roughness}})
}

/// The atrium: see the module's documentation. About 250k triangles, 20 materials' worth of
/// objects under one node each, a sun, eight point lights and four emissive lanterns; render it
/// under a sky (`--env-color 0.5,0.6,0.8`, as `platoon bench scenes` does).
pub fn atrium() -> SceneData {
    let mut materials = vec![
        json!({"name": "floor", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0, "roughnessFactor": 0.7}}),
        material("stone", [0.62, 0.57, 0.5], 0.8),
        material("plaster", [0.75, 0.7, 0.62], 1.0),
        material("terracotta", [0.6, 0.3, 0.18], 0.9),
        json!({"name": "leaves", "alphaMode": "MASK", "alphaCutoff": 0.5, "doubleSided": true,
               "pbrMetallicRoughness": {"baseColorTexture": {"index": 1}, "metallicFactor": 0, "roughnessFactor": 0.6}}),
        json!({"name": "lantern", "emissiveFactor": [1.0, 0.8, 0.55], "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1]},
               "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 40}}}),
    ];
    let fabric = [
        ([150, 30, 30], [120, 20, 20]),
        ([30, 90, 40], [20, 70, 30]),
        ([40, 50, 130], [30, 40, 100]),
    ];
    for (k, _) in fabric.iter().enumerate() {
        materials.push(json!({"name": format!("curtain {k}"), "doubleSided": true,
            "pbrMetallicRoughness": {"baseColorTexture": {"index": 2 + k}, "metallicFactor": 0, "roughnessFactor": 1}}));
    }
    let (floor, stone, plaster, terracotta, leaves, lantern, curtain0) = (0, 1, 2, 3, 4, 5, 6);
    let mut meshes: Vec<(MeshData, usize)> = Vec::new();
    let mut nodes: Vec<NodeData> = Vec::new();
    let mut add = |mesh: MeshData, material: usize| {
        meshes.push((mesh, material));
        meshes.len() - 1
    };
    let place =
        |nodes: &mut Vec<NodeData>, mesh: usize, at: [f32; 3], turn: f32, scale: [f32; 3]| {
            let (s, c) = (turn / 2.0).sin_cos();
            nodes.push(NodeData {
                mesh: Some(mesh),
                translation: at.map(f64::from),
                rotation: [0.0, s, 0.0, c],
                scale,
                ..NodeData::new()
            });
        };
    let (hl, hw) = (HALF_LENGTH, HALF_WIDTH);
    let top = STOREYS[1].0 + STOREYS[1].1 + SPACING / 2.0 + SLAB;

    // The floor: stone flags of a metre (the checker repeats every 2 m).
    let floor_mesh = {
        let mut g = grid_rect(256, 128);
        g.uvs = g
            .positions
            .iter()
            .map(|p| [p[0] * hl / 2.0, p[2] * hw / 2.0])
            .collect();
        g
    };
    let m = add(floor_mesh, floor);
    place(&mut nodes, m, [0.0, 0.0, 0.0], 0.0, [hl, 1.0, hw]);

    // The outer walls: long ones behind the arcades, short ones at the ends (facing inward).
    let long_wall = add(cut_quads(&quad_of(&grid(1)), 48), plaster);
    let end_wall = add(cut_quads(&quad_of(&grid(1)), 32), plaster);
    for side in [-1.0f32, 1.0] {
        // grid(1) faces +y; turned to face -side z, standing up.
        nodes.push(NodeData {
            mesh: Some(long_wall),
            translation: [0.0, (top / 2.0) as f64, (side * hw) as f64],
            rotation: quat_x(side * -PI / 2.0),
            scale: [hl, 1.0, top / 2.0],
            ..NodeData::new()
        });
        nodes.push(NodeData {
            mesh: Some(end_wall),
            translation: [(side * hl) as f64, (top / 2.0) as f64, 0.0],
            rotation: quat_z(side * PI / 2.0),
            scale: [top / 2.0, 1.0, hw],
            ..NodeData::new()
        });
    }

    // Each storey: columns, arches, the slab above; the upper one has a balustrade.
    let columns: Vec<usize> = STOREYS
        .iter()
        .map(|&(_, h)| add(fluted_column(128, COLUMN_RADIUS, h), stone))
        .collect();
    let arch_mesh = add(arch(48, SPACING / 2.0 - 0.3, SPACING / 2.0, 0.6), stone);
    let capital = add(cut_quads(&flat_box(), 2), stone);
    let slab = add(cut_quads(&flat_box(), 16), plaster);
    let baluster = add(fluted_column(24, 0.05, 0.9), stone);
    let rail = add(cut_quads(&flat_box(), 4), stone);
    let count = (2.0 * hl / SPACING) as i32 - 1; // columns per row
    for (s, &(y0, h)) in STOREYS.iter().enumerate() {
        for side in [-1.0f32, 1.0] {
            let z = side * ARCADE_Z;
            for k in 0..count {
                let x = -hl + SPACING * (k + 1) as f32;
                place(&mut nodes, columns[s], [x, y0, z], 0.0, [1.0; 3]);
                place(&mut nodes, capital, [x, y0 + h, z], 0.0, [0.4, 0.1, 0.4]);
                if k + 1 < count {
                    place(
                        &mut nodes,
                        arch_mesh,
                        [x + SPACING / 2.0, y0 + h, z],
                        0.0,
                        [1.0; 3],
                    );
                }
            }
            // The slab over the arcade, from the arches' crown to the wall.
            let y = y0 + h + SPACING / 2.0 + SLAB / 2.0;
            let zc = side * (ARCADE_Z + hw) / 2.0 - side * 0.3;
            place(
                &mut nodes,
                slab,
                [0.0, y, zc],
                0.0,
                [hl, SLAB / 2.0, (hw - ARCADE_Z) / 2.0 + 0.3],
            );
            if s == 1 {
                continue;
            }
            // The upper storey's balustrade along the slab's edge: balusters every 0.25 m and
            // a handrail.
            let yb = y + SLAB / 2.0;
            let zb = side * (ARCADE_Z - 0.35);
            let mut x = -hl + 0.5;
            while x < hl - 0.5 {
                place(&mut nodes, baluster, [x, yb, zb], 0.0, [1.0; 3]);
                x += 0.25;
            }
            place(
                &mut nodes,
                rail,
                [0.0, yb + 0.95, zb],
                0.0,
                [hl - 0.5, 0.05, 0.08],
            );
        }
    }

    // Curtains in the lower arcade's openings on one side and the upper one's on the other,
    // pleated, three fabrics.
    let curtain_mesh: Vec<usize> = (0..fabric.len())
        .map(|k| add(curtain(48, 64, SPACING - 0.8, 4.6, 5.0, 0.08), curtain0 + k))
        .collect();
    let upper_curtain: Vec<usize> = (0..fabric.len())
        .map(|k| add(curtain(48, 48, SPACING - 0.8, 3.6, 5.0, 0.08), curtain0 + k))
        .collect();
    for k in 0..count - 1 {
        let x = -hl + SPACING * (k + 1) as f32 + SPACING / 2.0;
        let y = STOREYS[1].0 + STOREYS[1].1 + SPACING / 2.0 - 0.2;
        place(
            &mut nodes,
            upper_curtain[(k as usize + 1) % fabric.len()],
            [x, y, ARCADE_Z - 0.4],
            PI,
            [1.0; 3],
        );
    }
    for k in 0..count - 1 {
        let x = -hl + SPACING * (k + 1) as f32 + SPACING / 2.0;
        let y = STOREYS[0].1 + SPACING / 2.0 - 0.2;
        place(
            &mut nodes,
            curtain_mesh[k as usize % fabric.len()],
            [x, y, -ARCADE_Z + 0.4],
            0.0,
            [1.0; 3],
        );
    }

    // Potted plants down the courtyard.
    let pot = add(
        lathe(
            &[
                (0.0, 0.0),
                (0.25, 0.0),
                (0.3, 0.1),
                (0.42, 0.5),
                (0.45, 0.8),
                (0.5, 0.85),
                (0.48, 0.9),
                (0.4, 0.88),
            ],
            96,
        ),
        terracotta,
    );
    let bush_mesh = add(bush(1200, 0.9), leaves);
    for k in 0..10 {
        let x = -15.0 + 30.0 * k as f32 / 9.0;
        let z = if k % 2 == 0 { -3.2 } else { 3.2 };
        place(&mut nodes, pot, [x, 0.0, z], 0.0, [1.0; 3]);
        place(&mut nodes, bush_mesh, [x, 0.85, z], k as f32, [1.0; 3]);
    }

    // Lanterns (emissive triangles) hanging in the lower arcade, and point lights beside them.
    let lantern_mesh = add(icosphere(2), lantern);
    let mut lights = Vec::new();
    for (k, x) in [-10.0f32, -2.0, 6.0, 14.0].into_iter().enumerate() {
        let side = if k % 2 == 0 { -1.0 } else { 1.0 };
        place(
            &mut nodes,
            lantern_mesh,
            [x, 3.2, side * (ARCADE_Z + 1.0)],
            0.0,
            [0.12; 3],
        );
    }
    for k in 0..8 {
        let x = -14.0 + 4.0 * k as f32;
        let side = if k % 2 == 0 { 1.0 } else { -1.0 };
        lights.push(json!({"type": "point", "color": [1.0, 0.85, 0.65], "intensity": 8.0}));
        nodes.push(NodeData {
            translation: [x as f64, 3.0, (side * (ARCADE_Z + 1.0)) as f64],
            light: Some(lights.len() - 1),
            ..NodeData::new()
        });
    }
    lights.push(json!({"type": "directional", "color": [1.0, 0.95, 0.85], "intensity": 3.0}));
    nodes.push(NodeData {
        rotation: facing([0.35, -1.0, 0.25]),
        light: Some(lights.len() - 1),
        ..NodeData::new()
    });

    let mut camera = NodeData::new();
    camera.translation = [-16.0, 2.0, 0.0];
    camera.rotation = facing([1.0, 0.12, 0.0]);
    camera.camera_yfov = Some(1.0);
    nodes.push(camera);
    let mut images = vec![crate::bench::checker_png(2, 32), leaf_png(64)];
    images.extend(fabric.iter().map(|&(a, b)| stripes_png(a, b)));
    SceneData {
        meshes,
        materials,
        nodes,
        lights,
        extensions_used: vec!["KHR_materials_emissive_strength".into()],
        images,
    }
}

/// grid(1)'s quad rewritten as (a, b, c, a, c, d) for [`cut_quads`].
fn quad_of(g: &MeshData) -> MeshData {
    // grid(1) writes (a, d, c, a, c, b) with a = (-1, -1), b = (1, -1), c = (1, 1), d = (-1, 1).
    let [a, b, c, d] = [0usize, 1, 3, 2].map(|i| g.positions[i]);
    MeshData {
        positions: vec![a, d, c, b],
        normals: vec![[0.0, 1.0, 0.0]; 4],
        indices: vec![0, 1, 2, 0, 2, 3],
        ..Default::default()
    }
}

fn quat_x(angle: f32) -> [f32; 4] {
    let (s, c) = (angle / 2.0).sin_cos();
    [s, 0.0, 0.0, c]
}

fn quat_z(angle: f32) -> [f32; 4] {
    let (s, c) = (angle / 2.0).sin_cos();
    [0.0, 0.0, s, c]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_atrium_is_sponza_sized_with_thin_triangles_and_alpha_tested_leaves() {
        let a = atrium();
        let tris = a.triangle_count();
        assert!((220_000..290_000).contains(&tris), "{tris} triangles");
        assert!(a.materials.iter().any(|m| m["alphaMode"] == "MASK"));
        assert!(a.lights.len() >= 9);
        // Long thin triangles: a column facet is over a hundred times longer than wide.
        let c = fluted_column(128, 0.3, 3.5);
        let p = &c.positions;
        let width = ((p[1][0] - p[0][0]).powi(2) + (p[1][2] - p[0][2]).powi(2)).sqrt();
        assert!(3.5 / width > 100.0);
        assert!(crate::to_glb(&a).starts_with(b"glTF"));
    }

    /// Each generator winds its triangles to face the way its normals point.
    #[test]
    fn the_pieces_wind_the_way_their_normals_point() {
        for (name, m) in [
            ("column", fluted_column(16, 0.3, 2.0)),
            ("arch", arch(8, 1.7, 2.0, 0.6)),
            ("curtain", curtain(8, 8, 3.0, 4.0, 2.0, 0.1)),
            ("lathe", lathe(&[(0.2, 0.0), (0.4, 0.5), (0.3, 1.0)], 12)),
            ("bush", bush(20, 0.5)),
            ("rect", grid_rect(3, 2)),
            ("wall", quad_of(&grid(1))),
        ] {
            for t in m.indices.chunks(3) {
                let [p0, p1, p2] = [t[0], t[1], t[2]].map(|i| m.positions[i as usize]);
                let e1: [f32; 3] = std::array::from_fn(|k| p1[k] - p0[k]);
                let e2: [f32; 3] = std::array::from_fn(|k| p2[k] - p0[k]);
                let n = [
                    e1[1] * e2[2] - e1[2] * e2[1],
                    e1[2] * e2[0] - e1[0] * e2[2],
                    e1[0] * e2[1] - e1[1] * e2[0],
                ];
                let s: [f32; 3] = std::array::from_fn(|k| {
                    t.iter().map(|&i| m.normals[i as usize][k]).sum::<f32>()
                });
                let d = n[0] * s[0] + n[1] * s[1] + n[2] * s[2];
                let area = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
                assert!(
                    area < 1e-9 || d > 0.0,
                    "{name}: triangle {t:?} winds against its normals"
                );
            }
        }
    }
}

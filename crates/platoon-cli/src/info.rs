//! `platoon info`: a scene's contents and the kernel it compiles to.

use std::fmt::Write as _;

use anyhow::Result;
use platoon::core::flatten::{
    GpuScene, LIGHT_DIRECTIONAL, LIGHT_ENVIRONMENT, LIGHT_POINT, LIGHT_SPOT, LIGHT_TRIANGLE,
};
use platoon::tracer::Traversal;
use platoon::Prepared;

use crate::scene_args::SceneArgs;

pub fn run(scene: SceneArgs) -> Result<()> {
    let prepared = scene.prepare()?;
    print!("{}", describe(&prepared));
    Ok(())
}

/// The text of `platoon info`.
pub fn describe(p: &Prepared) -> String {
    let s = &p.scene;
    let g = &p.gpu;
    let count = |kind: u32| g.lights.iter().filter(|l| l.ids[0] == kind).count();
    let mut out = String::new();
    let source = s
        .source
        .as_ref()
        .map(|p| p.display().to_string())
        .unwrap_or_else(|| "built-in Cornell box".into());
    let _ = writeln!(out, "scene:        {source}");
    let instanced: usize = p
        .posed
        .instances
        .iter()
        .map(|i| p.posed.meshes[i.mesh].triangle_count())
        .sum();
    let _ = writeln!(
        out,
        "triangles:    {} in meshes, {} in the rendered scene",
        g.triangle_count, instanced
    );
    let _ = writeln!(out, "meshes:       {}", s.meshes.len());
    let _ = writeln!(out, "instances:    {}", g.instances.len());
    let _ = writeln!(out, "materials:    {}", s.materials.len());
    let _ = writeln!(out, "textures:     {}", s.textures.len());
    if !s.variants.is_empty() {
        let _ = writeln!(
            out,
            "variants:     {} (KHR_materials_variants; render one with --variant NAME)",
            s.variants.join(", ")
        );
    }
    let _ = writeln!(
        out,
        "lights:       {} emissive triangles, {} point, {} spot, {} directional, {} environment",
        count(LIGHT_TRIANGLE),
        count(LIGHT_POINT),
        count(LIGHT_SPOT),
        count(LIGHT_DIRECTIONAL),
        count(LIGHT_ENVIRONMENT)
    );
    let _ = writeln!(out, "environment:  {}", p.env_label);
    let _ = writeln!(out, "cameras:      {}", s.cameras.len());
    let o = p.posed.origin;
    let _ = writeln!(
        out,
        "render space: centred on {}, {}, {} (floating origin near the camera)",
        o.x, o.y, o.z
    );
    let _ = writeln!(
        out,
        "animations:   {} ({} channels, {:.3} s)",
        s.animations.len(),
        s.animations.iter().map(|a| a.channels.len()).sum::<usize>(),
        s.animations
            .iter()
            .map(|a| a.duration())
            .fold(0.0, f32::max)
    );
    let _ = writeln!(out, "skins:        {}", s.skins.len());
    let b = g.bvh_report();
    let _ = writeln!(
        out,
        "bvh:          SAH cost {:.1} (bottom levels, by triangles; the largest {:.1} over {} \
         triangles), top level {:.1} over {} instances, {} nodes, built in {:.1} ms",
        b.bottom,
        b.largest,
        b.largest_triangles,
        b.top,
        b.instances,
        b.nodes,
        g.build_times.meshes.as_secs_f64() * 1e3
    );
    let _ = writeln!(out, "features:     {}", g.features);
    let _ = writeln!(
        out,
        "kernel:       {}",
        platoon::tracer::kernel_label(g.features)
    );
    let _ = writeln!(out, "memory:       {}", memory_paths(g));
    let _ = writeln!(out, "traversal:    {}", traversals(g));
    for w in &s.warnings {
        let _ = writeln!(out, "warning:      {w}");
    }
    if let Some(n) = &p.note {
        let _ = writeln!(out, "note:         {n}");
    }
    out
}

/// What `--traversal auto` resolves to on each device for this scene.
fn traversals(g: &GpuScene) -> String {
    let Ok(devices) = platoon::tracer::list_devices() else {
        return "decided per device (no Vulkan device found)".into();
    };
    let each: Vec<String> = devices
        .iter()
        .map(|d| {
            let t = Traversal::Auto.resolved(d, g.triangle_count as u64);
            format!("{} on {}", t.name(), d.name)
        })
        .collect();
    format!("{}: {}", Traversal::Auto.label(), each.join(", "))
}

/// How device 0 would read the scene arrays under the default policy.
fn memory_paths(g: &GpuScene) -> String {
    let Some(device) = platoon::tracer::list_devices()
        .ok()
        .and_then(|d| d.into_iter().next())
    else {
        return "decided per device (no Vulkan device found)".into();
    };
    let bytes = platoon::tracer::scene_array_bytes(g);
    let sizes: Vec<u64> = bytes.iter().map(|b| b.len() as u64).collect();
    let paths =
        platoon::tracer::choose_memory_paths(&sizes, &device.memory_limits(), Default::default());
    let mut groups: Vec<(platoon::tracer::ArrayPath, Vec<String>)> = Vec::new();
    for ((array, size), path) in platoon::tracer::SCENE_ARRAYS.iter().zip(&sizes).zip(&paths) {
        let entry = format!("{} ({:.1} MB)", array.name, *size as f64 / 1e6);
        match groups.iter_mut().find(|(p, _)| p == path) {
            Some((_, list)) => list.push(entry),
            None => groups.push((*path, vec![entry])),
        }
    }
    let parts: Vec<String> = groups
        .iter()
        .map(|(path, list)| {
            if list.len() == sizes.len() {
                format!("{}s for all {} scene arrays", path.describe(), list.len())
            } else {
                format!("{}s: {}", path.describe(), list.join(", "))
            }
        })
        .collect();
    format!("{} on {}", parts.join("; "), device.name)
}

//! One frame of `platoon render` (no --frames): rendered with a progress bar, written, reported.

use std::path::PathBuf;

use anyhow::{bail, Result};
use indicatif::{ProgressBar, ProgressStyle};
use platoon::core::frame::FrameParams;
use platoon::Tracers;

use super::checkpoint;
use super::frame_log::FrameLog;
use super::outputs;
use super::setup::Setup;

/// The still render of `run`.
pub(super) fn still(setup: Setup, out: PathBuf, log: FrameLog, resume: bool) -> Result<()> {
    let speaks = setup.speaks();
    let ranks = setup.ranks();
    let Setup {
        started,
        request,
        image,
        scene,
        load_time,
        ..
    } = setup;
    let mut prepared =
        super::stage::during("building BVHs and flattening", || request.prepare(scene))?;
    if speaks {
        for w in &prepared.scene.warnings {
            eprintln!("warning: {w}");
        }
        if let Some(note) = &prepared.note {
            eprintln!("note: {note}");
        }
    }
    // Before the upload, which may give up the host's copy of the large arrays.
    let content = prepared.gpu.content_hash();
    let uploading = std::time::Instant::now();
    let mut tracers = super::stage::during("uploading to the devices", || {
        request.still_tracers(&mut prepared.gpu, ranks)
    })?;
    let mut cost = platoon::cost::RenderCost {
        load: load_time,
        prepare: prepared.prepare_time,
        bvh: prepared.gpu.build_times.meshes + prepared.gpu.build_times.instances,
        upload: uploading.elapsed(),
        triangles: prepared.gpu.triangle_count,
        instances: prepared.gpu.instances.len(),
        ..Default::default()
    };
    let mut params = request.frame_params(request.camera_in(&prepared));
    let (sampling, batching) = (request.sampling.name(), request.batching());
    let asked = params.spp;
    let key = checkpoint::key(&params, content, sampling);
    let plain = batching.adaptive.is_none() && !batching.variance;
    let resumed = match resume {
        true if !plain => bail!(
            "--resume continues a plain render: not with --adaptive-threshold or the variance AOV"
        ),
        true => checkpoint::resume(&out, &mut params, &key)?,
        false => 0,
    };
    let mut first_pass = None;
    let frame = Frame {
        request: &request,
        gpu: &prepared.gpu,
        params: &params,
    };
    let mut rendered = render_frame(&mut tracers, &frame, &mut || {
        first_pass.get_or_insert(started.elapsed());
    })?;
    cost.first_pixel = first_pass.unwrap_or(started.elapsed());
    cost.render = rendered.wall_time;
    cost.device_bytes = tracers.device_bytes();
    cost.peak_host_bytes = platoon::cost::peak_host_bytes();
    if resumed > 0 {
        // The sums hold the checkpoint's samples too: the image is of all of them.
        rendered.average_over(rendered.spp + resumed);
        params.spp = asked;
        params.first_sample = 0;
        params.film.accumulated = None;
    }
    let interrupted = platoon::tracer::stop::requested();
    let mut more = outputs::entries(&image, &out);
    if interrupted {
        more.push(("interrupted".into(), "Ctrl-C: the samples so far".into()));
    }
    if resumed > 0 {
        more.push(("resumed".into(), format!("from {resumed} samples a pixel")));
    }
    let told = match (speaks, plain) {
        (true, true) => checkpoint::keep(
            &out,
            key,
            &params,
            asked,
            rendered.spp,
            &rendered.sums,
            tracers.count() == 1 && tracers.ranks() == 1,
        )?,
        _ => None,
    };
    let shown = prepared.shown(request.frame_interval);
    let still = request.outputs(&mut tracers, &shown, &params, rendered, more)?;
    if !speaks {
        return Ok(());
    }
    outputs::write(&still, &out, &image)?;
    let rendered = &still.rendered;
    let secs = rendered.wall_time.as_secs_f64();
    let spp = match rendered.batched.as_ref().and_then(|b| b.adaptive) {
        Some(_) => format!(
            "{:.1} spp on average (adaptive, at most {})",
            rendered.mean_spp(),
            rendered.spp
        ),
        None => format!("{} spp", rendered.spp),
    };
    // The render's own time first (what samples/s are of), then the command's whole time:
    // reading the scene, building its BVH and compiling kernels are often most of a small
    // render's wait (issue 41, defect 6).
    eprintln!(
        "{}: {}x{} at {spp} in {:.2} s on {} ({:.2} M samples/s, {:.2} M rays/s, {} rejected samples); {:.2} s in all with loading and preparing",
        out.display(),
        params.width,
        params.height,
        secs,
        rendered.device,
        (params.width as f64 * params.height as f64 * rendered.mean_spp()) / secs / 1e6,
        rendered.rays() as f64 / secs / 1e6,
        rendered.rejected_samples(),
        started.elapsed().as_secs_f64()
    );
    eprintln!("  {}", cost.line());
    report_method(rendered, &params.method);
    if let Some(told) = told {
        eprintln!("note: {told}");
    }
    let samples = params.width as f64 * params.height as f64 * rendered.mean_spp();
    if let Some(line) = log.still(serde_json::json!({
        "status": if interrupted { "interrupted" } else { "ok" },
        "file": out,
        "seconds": secs,
        "spp": rendered.mean_spp(),
        "width": params.width,
        "height": params.height,
        "samples_per_second": samples / secs,
        "cost": super::frame_log::cost_json(&cost),
    })) {
        println!("{line}");
    }
    if interrupted {
        anyhow::bail!(
            "interrupted (Ctrl-C): {} holds the {} samples a pixel rendered before it",
            out.display(),
            rendered.spp
        );
    }
    Ok(())
}

/// The frame a still renders: the request's, of the scene `gpu`.
struct Frame<'a> {
    request: &'a platoon::Request,
    gpu: &'a platoon::core::flatten::GpuScene,
    params: &'a FrameParams,
}

/// Renders a frame with a progress bar over its samples (one tracer) or a spinner (several,
/// which render on their own threads), then prints the tracers' shares. `passed` hears each
/// pass of samples one tracer finishes (several tracers: none).
fn render_frame(
    tracers: &mut Tracers,
    frame: &Frame,
    passed: &mut dyn FnMut(),
) -> Result<platoon::Rendered> {
    let Frame {
        request,
        gpu,
        params,
    } = *frame;
    let rendered = if tracers.rank() != 0 {
        request.render_frame(tracers, gpu, params, &mut |_| {})?
    } else if tracers.count() == 1 && tracers.ranks() == 1 {
        let bar = ProgressBar::new(params.spp as u64);
        bar.set_style(
            ProgressStyle::with_template("{elapsed_precise} [{bar:40}] {pos}/{len} spp {msg}")
                .unwrap(),
        );
        let r = request.render_frame(tracers, gpu, params, &mut |done| {
            if done > 0 {
                passed();
            }
            bar.set_position(done as u64)
        });
        bar.finish_and_clear();
        r?
    } else {
        let spinner = ProgressBar::new_spinner();
        spinner.set_message(match tracers.ranks() {
            1 => format!("rendering on {} tracers", tracers.count()),
            n => format!("rendering on {n} ranks"),
        });
        spinner.enable_steady_tick(std::time::Duration::from_millis(200));
        let r = request.render_frame(tracers, gpu, params, &mut |_| {});
        spinner.finish_and_clear();
        r?
    };
    if tracers.rank() != 0 {
        return Ok(rendered);
    }
    if let Some(report) = &rendered.ranks {
        report_ranks(report, params.width);
        return Ok(rendered);
    }
    for t in &rendered.tracers {
        eprintln!(
            "  tracer {}: lines {:.2}..{:.2} ({} pixels rendered), {:.3} s, idle {:.3} s",
            t.tracer,
            t.span.begin as f64 / params.width as f64,
            t.span.end as f64 / params.width as f64,
            t.pixels,
            t.wall_time.as_secs_f64(),
            t.idle.as_secs_f64()
        );
    }
    for m in &rendered.validation_messages {
        eprintln!("validation: {m}");
    }
    Ok(rendered)
}

/// Each rank's share and devices, and what crossed between the ranks.
fn report_ranks(report: &platoon::distributed::RanksReport, width: u32) {
    for p in &report.parts {
        eprintln!(
            "  rank {}: lines {:.2}..{:.2}, {:.3} s on {} device(s)",
            p.rank,
            p.span.begin as f64 / width as f64,
            p.span.end as f64 / width as f64,
            p.wall_time.as_secs_f64(),
            p.tracers.len()
        );
    }
    let c = &report.communication;
    eprintln!(
        "  {} ranks under {}: {} bytes sent, {} received, {:.1} ms in exchanges, {:.1} ms waiting \
         for the slowest rank (rank 0)",
        report.ranks,
        report.balancer,
        c.sent,
        c.received,
        c.time.as_secs_f64() * 1e3,
        c.waiting.as_secs_f64() * 1e3
    );
}

/// What the method says a user should read after its render.
fn report_method(rendered: &platoon::Rendered, method: &platoon::core::Method) {
    let report = method.unit().report(&rendered.method_report);
    for line in &report.lines {
        eprintln!("  {line}");
    }
    for warning in &report.warnings {
        eprintln!("warning: {warning}");
    }
}

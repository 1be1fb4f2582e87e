//! What `render` says of each frame on standard output: a line of text (`frame N: ok ...`), or
//! with `--log-json` one JSON object a line, for farm tools: `frame`, `status` (ok, skipped,
//! failed; a still's: ok or interrupted), `file`, `seconds`, `rank` over a farm's ranks,
//! `error` of a failure, and a still's `spp`, `width`, `height`, `samples_per_second` and `cost`
//! (its stages and memory, [`cost_json`]).

use std::path::Path;

use serde_json::{json, Value};

/// How frames are reported.
#[derive(Clone, Copy, Debug)]
pub struct FrameLog {
    pub json: bool,
}

impl FrameLog {
    /// Frame `f` written to `path` in `seconds` (by `rank` of a farm).
    pub fn ok(&self, f: i64, path: &Path, seconds: f64, rank: Option<usize>) -> String {
        if self.json {
            let mut v = json!({"frame": f, "status": "ok", "file": path, "seconds": seconds});
            with_rank(&mut v, rank);
            return v.to_string();
        }
        let by = rank.map_or(String::new(), |r| format!(" (rank {r})"));
        format!("frame {f}: ok, {} in {seconds:.2} s{by}", path.display())
    }

    /// Frame `f` left as it is: `path` holds it already.
    pub fn skipped(&self, f: i64, path: &Path) -> String {
        if self.json {
            return json!({"frame": f, "status": "skipped", "file": path}).to_string();
        }
        format!("frame {f}: skipped, {} is done", path.display())
    }

    /// Frame `f` failed with `error` (on `rank` of a farm).
    pub fn failed(&self, f: i64, error: &anyhow::Error, rank: Option<usize>) -> String {
        if self.json {
            let mut v = json!({"frame": f, "status": "failed", "error": format!("{error:#}")});
            with_rank(&mut v, rank);
            return v.to_string();
        }
        match rank {
            Some(r) => format!("frame {f}: failed on rank {r}: {error:#}"),
            None => format!("frame {f}: failed: {error:#}"),
        }
    }

    /// A still's line (JSON only: the text report goes to standard error).
    pub fn still(&self, fields: Value) -> Option<String> {
        self.json.then(|| fields.to_string())
    }
}

/// What a render cost, stage by stage, as a still's `cost` field (seconds and bytes; what
/// `platoon bench scale` reads).
pub fn cost_json(c: &platoon::cost::RenderCost) -> Value {
    json!({
        "load_seconds": c.load.as_secs_f64(),
        "prepare_seconds": c.prepare.as_secs_f64(),
        "bvh_seconds": c.bvh.as_secs_f64(),
        "upload_seconds": c.upload.as_secs_f64(),
        "first_pixel_seconds": c.first_pixel.as_secs_f64(),
        "render_seconds": c.render.as_secs_f64(),
        "peak_host_bytes": c.peak_host_bytes,
        "device_bytes": c.device_bytes,
        "triangles": c.triangles,
        "instances": c.instances,
    })
}

fn with_rank(v: &mut Value, rank: Option<usize>) {
    if let (Some(r), Some(o)) = (rank, v.as_object_mut()) {
        o.insert("rank".into(), json!(r));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_lines_stay_as_they_were_and_json_lines_parse() {
        let (text, json) = (FrameLog { json: false }, FrameLog { json: true });
        let p = Path::new("shots/f_0007.exr");
        assert_eq!(
            text.ok(7, p, 1.234, None),
            "frame 7: ok, shots/f_0007.exr in 1.23 s"
        );
        assert_eq!(
            text.ok(7, p, 1.0, Some(2)),
            "frame 7: ok, shots/f_0007.exr in 1.00 s (rank 2)"
        );
        assert_eq!(
            text.skipped(7, p),
            "frame 7: skipped, shots/f_0007.exr is done"
        );
        let e = anyhow::anyhow!("no space");
        assert_eq!(
            text.failed(7, &e, Some(1)),
            "frame 7: failed on rank 1: no space"
        );
        let v: Value = serde_json::from_str(&json.ok(7, p, 1.5, Some(2))).unwrap();
        assert_eq!(v["frame"], 7);
        assert_eq!(v["status"], "ok");
        assert_eq!(v["file"], "shots/f_0007.exr");
        assert_eq!(v["seconds"], 1.5);
        assert_eq!(v["rank"], 2);
        let v: Value = serde_json::from_str(&json.failed(8, &e, None)).unwrap();
        assert_eq!(
            (v["status"].as_str(), v["error"].as_str()),
            (Some("failed"), Some("no space"))
        );
        assert!(v.get("rank").is_none());
        assert!(text.still(json!({})).is_none());
    }
}

//! `mpirun -np 3 platoon render ... --mpi` (issue 26): frames split between three processes,
//! each with two tracers, are the one-process render bit for bit, for two balancers (one of
//! them over adaptive batches, whose shares carry the film's sums and converged pixels) and
//! for a living scene over three generations (rank 0's commits broadcast). Needs the feature
//! `mpi` (tools/test.sh builds it) and Open MPI's mpirun (tools/install-deps.sh installs it):
//! without mpirun the tests fail saying so.

#[path = "../common/mod.rs"]
mod common;
mod support;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use common::shared;
use platoon::core::output::read_exr;
use support::*;

fn mpirun() -> PathBuf {
    std::env::split_paths(&std::env::var_os("PATH").unwrap_or_default())
        .map(|d| d.join("mpirun"))
        .find(|p| p.is_file())
        .expect(
            "MPI is missing: no mpirun on PATH. This build has the feature `mpi`; install \
             Open MPI (tools/install-deps.sh openmpi-bin libopenmpi-dev) to run its tests",
        )
}

/// mpirun with what every rank needs: more ranks than cores allowed, root allowed (a
/// container's CI; harmless otherwise).
fn mpirun_command() -> Command {
    common::init();
    let mut c = Command::new(mpirun());
    c.args(["--oversubscribe", "--allow-run-as-root"]);
    c
}

/// The arguments of one program of a job: `np` ranks with one lavapipe thread each (as this
/// machine's 2 cores allow) and the test's Vulkan driver and kernel cache.
fn program(c: &mut Command, np: usize, args: &[&str]) {
    c.args(["-np", &np.to_string(), "-x", "LP_NUM_THREADS=1"]);
    for var in ["VK_DRIVER_FILES", "VK_ICD_FILENAMES", "PLATOON_CACHE_DIR"] {
        if std::env::var_os(var).is_some() {
            c.args(["-x", var]);
        }
    }
    c.arg(env!("CARGO_BIN_EXE_platoon")).args(args);
}

/// `cli` with --mpi on `programs.len()` ranks, rank i running `programs[i]`'s arguments
/// (MPI's several-programs form).
fn over_ranks(programs: &[&Cli]) -> Output {
    let mut c = mpirun_command();
    for (i, cli) in programs.iter().enumerate() {
        if i > 0 {
            c.arg(":");
        }
        program(&mut c, 1, &[&cli.strs()[..], &["--mpi"]].concat());
    }
    c.output().expect("run mpirun")
}

fn pixels(path: &Path) -> Vec<u32> {
    read_exr(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .0
        .pixels
        .iter()
        .flatten()
        .map(|v| v.to_bits())
        .collect()
}

fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

#[test]
fn three_ranks_render_the_one_process_image_bit_for_bit_under_two_balancers() {
    let dir = tempfile::tempdir().unwrap();
    let scene = shared("scenes/teapot.gltf");
    for (balancer, extra) in [
        ("cost-aware", &[][..]),
        ("perfect", &["--adaptive-threshold", "0.2"][..]),
    ] {
        let render = |out: &Path| {
            let mut cli = Cli::new("render")
                .arg(&scene)
                .flag("--env", shared("envmaps/courtyard.exr"))
                .spp(32)
                .size(24, 20)
                .flag("--balancer", balancer)
                .out(out);
            for a in extra {
                cli = cli.arg(a);
            }
            cli
        };
        let one = dir.path().join(format!("one_{balancer}.exr"));
        let o = render(&one).run();
        assert!(o.status.success(), "{}", stderr(&o));
        let ranks = dir.path().join(format!("ranks_{balancer}.exr"));
        let cli = render(&ranks).flag("--devices", "lavapipe:1,1");
        let o = over_ranks(&[&cli, &cli, &cli]);
        assert!(o.status.success(), "{}", text(&o));
        let said = text(&o);
        assert!(
            said.contains(&format!("3 ranks under {balancer}")),
            "{said}"
        );
        for rank in 0..3 {
            assert!(said.contains(&format!("rank {rank}: lines")), "{said}");
        }
        assert!(
            pixels(&ranks) == pixels(&one),
            "{balancer}: three ranks differ from one process"
        );
        let (_, meta) = read_exr(&ranks).unwrap();
        assert_eq!(metadata_value(&meta, "mpi_ranks"), "3", "{meta:?}");
    }
}

#[test]
fn a_living_scene_over_three_generations_is_the_one_process_animation() {
    let dir = tempfile::tempdir().unwrap();
    let man = shared("scenes/CesiumMan.glb");
    let frames = |out: PathBuf| {
        Cli::new("render")
            .arg(&man)
            .flag("--frames", "0..8:4")
            .spp(4)
            .size(24, 24)
            .flag("--balancer", "cost-aware")
            .out(out)
    };
    let o = frames(dir.path().join("one_#.exr")).run();
    assert!(o.status.success(), "{}", stderr(&o));
    let cli = frames(dir.path().join("ranks_#.exr")).flag("--devices", "lavapipe:1,1");
    let o = over_ranks(&[&cli, &cli, &cli]);
    assert!(o.status.success(), "{}", text(&o));
    let said = String::from_utf8_lossy(&o.stdout);
    for f in [0, 4, 8] {
        // Rank 0 alone reports and writes.
        assert_eq!(said.matches(&format!("frame {f}: ok")).count(), 1, "{said}");
        assert!(
            pixels(&dir.path().join(format!("ranks_{f}.exr")))
                == pixels(&dir.path().join(format!("one_{f}.exr"))),
            "frame {f}: three ranks differ from one process"
        );
    }
    assert!(
        pixels(&dir.path().join("ranks_0.exr")) != pixels(&dir.path().join("ranks_8.exr")),
        "the animation moved nothing"
    );
}

#[test]
fn a_rank_given_other_arguments_stops_the_job_naming_the_difference() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("never.exr");
    let cli = |seed: &str| {
        Cli::new("render")
            .spp(2)
            .size(16, 16)
            .flag("--seed", seed)
            .out(&out)
    };
    let o = over_ranks(&[&cli("0"), &cli("1")]);
    assert!(!o.status.success(), "{}", text(&o));
    assert!(
        text(&o).contains("rank 1 prepared a different frame than rank 0"),
        "{}",
        text(&o)
    );
    assert!(!out.exists(), "a job that stopped wrote its image");
}

#[test]
fn a_farm_deals_every_frame_once_each_the_one_process_frame_and_a_rerun_skips_them() {
    let dir = tempfile::tempdir().unwrap();
    let man = shared("scenes/CesiumMan.glb");
    let cli = |flag: &str, out: PathBuf| {
        Cli::new("render")
            .arg(&man)
            .flag(flag, "0..10:2")
            .spp(2)
            .size(16, 16)
            .out(out)
    };
    let o = cli("--frames", dir.path().join("one_#.exr")).run();
    assert!(o.status.success(), "{}", stderr(&o));
    // --mpi-frames joins the job itself: no --mpi.
    let farm = |c: &Cli| {
        let mut command = mpirun_command();
        program(&mut command, 3, &c.strs());
        command.output().expect("run mpirun")
    };
    let job = cli("--mpi-frames", dir.path().join("farm_#.exr"));
    let o = farm(&job);
    assert!(o.status.success(), "{}", text(&o));
    let said = String::from_utf8_lossy(&o.stdout).into_owned();
    let mut ranks = std::collections::BTreeSet::new();
    for f in (0..=10).step_by(2) {
        let lines: Vec<&str> = said
            .lines()
            .filter(|l| l.starts_with(&format!("frame {f}: ok")))
            .collect();
        assert_eq!(lines.len(), 1, "frame {f} dealt other than once: {said}");
        ranks.insert(lines[0].rsplit("(rank ").next().unwrap().to_string());
        assert!(
            pixels(&dir.path().join(format!("farm_{f}.exr")))
                == pixels(&dir.path().join(format!("one_{f}.exr"))),
            "frame {f}: the farm's differs from one process's"
        );
    }
    assert!(ranks.len() >= 2, "one rank rendered everything: {said}");
    let again = farm(&job);
    assert!(again.status.success(), "{}", text(&again));
    assert!(
        text(&again).contains("every frame is done"),
        "{}",
        text(&again)
    );
}

#[test]
fn the_game_bench_over_three_ranks_reports_its_communication_per_frame() {
    let dir = tempfile::tempdir().unwrap();
    let cli = Cli::new("bench")
        .arg("game")
        .flag("--frames", "20")
        .flag("--size", "32x24")
        .flag("--devices", "lavapipe:1")
        .flag("--out", dir.path())
        .arg("--json");
    let o = over_ranks(&[&cli, &cli, &cli]);
    assert!(o.status.success(), "{}", text(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("over 3 ranks:"), "{out}");
    let json: serde_json::Value = out
        .lines()
        .find_map(|l| serde_json::from_str(l).ok())
        .unwrap_or_else(|| panic!("no JSON line: {out}"));
    assert_eq!(json["frames"], 20, "{json}");
    let mpi = &json["mpi"];
    assert_eq!(mpi["ranks"], 3, "{json}");
    // Every frame sends the ranks their bands' parameters and gets their bands back; the
    // game's characters walk, so commits travel too.
    for key in [
        "sent_bytes_per_frame",
        "received_bytes_per_frame",
        "messages_per_frame",
    ] {
        assert!(mpi[key].as_f64().unwrap() > 0.0, "{key}: {json}");
    }
    assert!(
        mpi["sent_bytes_per_frame"].as_f64().unwrap() > 10_000.0,
        "{json}"
    );
    // With stealing (issue 44) the ranks that finish first take pieces of the others' bands
    // through rank 0: more messages a frame, the idle beside them.
    let stealing = cli.flag("--balancer", "cost-aware+steal");
    let o = over_ranks(&[&stealing, &stealing, &stealing]);
    assert!(o.status.success(), "{}", text(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    let stolen: serde_json::Value = out
        .lines()
        .find_map(|l| serde_json::from_str(l).ok())
        .unwrap_or_else(|| panic!("no JSON line: {out}"));
    assert_eq!(stolen["balancer"], "cost-aware+steal", "{stolen}");
    assert!(stolen["idle_percent_median"].as_f64().is_some(), "{stolen}");
    assert!(
        stolen["mpi"]["messages_per_frame"].as_f64().unwrap()
            > mpi["messages_per_frame"].as_f64().unwrap(),
        "{stolen} against {json}"
    );
}

#[test]
fn a_time_limit_is_refused_over_ranks_before_mpi_starts() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("never.png");
    let cli = Cli::new("render")
        .size(16, 16)
        .flag("--time-limit", "1")
        .out(&out);
    let o = over_ranks(&[&cli, &cli]);
    assert!(!o.status.success(), "{}", text(&o));
    let said = text(&o);
    assert!(
        said.contains("--time-limit renders on one device"),
        "{said}"
    );
    // Refused by every rank alike, before any exchange: no rank aborts the others.
    assert!(!said.contains("MPI_ABORT"), "{said}");
    assert!(!out.exists());
}

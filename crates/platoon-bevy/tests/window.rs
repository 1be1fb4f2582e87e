//! The example game (`examples/walk.rs`) in a real window under Xvfb: Bevy opens it on
//! lavapipe, platoon's frames arrive (the title counts them), and what the screen shows is
//! not black.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

fn tool(name: &str) -> PathBuf {
    let path = Path::new("/usr/bin").join(name);
    assert!(
        path.exists(),
        "{name} is missing: run tools/install-deps.sh"
    );
    path
}

/// The example's binary, which `cargo test` builds beside the tests.
fn example() -> PathBuf {
    let deps = std::env::current_exe().unwrap();
    let path = deps
        .parent()
        .unwrap()
        .parent()
        .unwrap()
        .join("examples/walk");
    assert!(
        path.exists(),
        "{} is missing: run `cargo test` without a target filter (it builds the examples)",
        path.display()
    );
    path
}

fn wait_for<T>(limit: Duration, mut f: impl FnMut() -> Option<T>) -> T {
    let start = Instant::now();
    loop {
        if let Some(v) = f() {
            return v;
        }
        assert!(start.elapsed() < limit, "timed out after {limit:?}");
        std::thread::sleep(Duration::from_millis(100));
    }
}

/// An X server of its own with its screen in a file (`-fbdir`); killed on drop.
struct Xvfb {
    child: Child,
    display: String,
    screen: PathBuf,
    _dir: tempfile::TempDir,
}

impl Xvfb {
    /// The first free display from :300 (the viewer's test takes :90 on).
    fn start() -> Xvfb {
        for n in 300..400 {
            if Path::new(&format!("/tmp/.X{n}-lock")).exists() {
                continue;
            }
            let dir = tempfile::tempdir().unwrap();
            let mut child = Command::new(tool("Xvfb"))
                .arg(format!(":{n}"))
                .args([
                    "-screen",
                    "0",
                    "400x240x24",
                    "-br",
                    "-noreset",
                    "-nolisten",
                    "tcp",
                ])
                .arg("-fbdir")
                .arg(dir.path())
                .stdout(Stdio::null())
                .stderr(Stdio::null())
                .spawn()
                .unwrap();
            let socket = PathBuf::from(format!("/tmp/.X11-unix/X{n}"));
            let ours = wait_for(Duration::from_secs(20), || {
                if child.try_wait().unwrap().is_some() {
                    return Some(false);
                }
                socket.exists().then_some(true)
            });
            if ours {
                let x = Xvfb {
                    child,
                    display: format!(":{n}"),
                    screen: dir.path().join("Xvfb_screen0"),
                    _dir: dir,
                };
                wait_for(Duration::from_secs(20), || {
                    x.xdotool(&["getdisplaygeometry"]).is_some().then_some(())
                });
                return x;
            }
        }
        panic!("no free X display number in :300..:399");
    }

    fn xdotool(&self, args: &[&str]) -> Option<String> {
        let o = Command::new(tool("xdotool"))
            .args(args)
            .env("DISPLAY", &self.display)
            .output()
            .ok()?;
        o.status
            .success()
            .then(|| String::from_utf8_lossy(&o.stdout).trim().to_string())
    }

    /// Pixels of the screen that are not black (the root window is black with -br); a pixel's
    /// fourth byte is padding (a presented surface writes its alpha there).
    fn lit_pixels(&self) -> usize {
        let xwd = std::fs::read(&self.screen).unwrap();
        let field = |i: usize| u32::from_be_bytes(xwd[4 * i..4 * i + 4].try_into().unwrap());
        let (header, bits, ncolors) = (field(0) as usize, field(11), field(19) as usize);
        assert_eq!(bits, 32, "a 24-bit screen is stored 32 bits a pixel");
        xwd[header + 12 * ncolors..]
            .chunks_exact(4)
            .filter(|p| p[..3].iter().any(|&c| c > 8))
            .count()
    }
}

impl Drop for Xvfb {
    fn drop(&mut self) {
        // SIGTERM, so the server removes its lock file and socket.
        let _ = Command::new("kill")
            .arg(self.child.id().to_string())
            .status();
        let _ = self.child.wait();
    }
}

#[test]
fn the_example_game_shows_platoons_frames_in_a_window() {
    let x = Xvfb::start();
    assert_eq!(x.lit_pixels(), 0, "the screen starts black");
    let mut game = Command::new(example())
        .args(["--devices", "lavapipe:1", "--size", "160x90"])
        .env("DISPLAY", &x.display)
        .env(
            "VK_DRIVER_FILES",
            "/usr/share/vulkan/icd.d/lvp_icd.x86_64.json",
        )
        // wgpu's own validation of Bevy's rendering is not what this tests.
        .env("WGPU_VALIDATION", "0")
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Until the title has counted 30 of platoon's frames.
    let frames = wait_for(Duration::from_secs(180), || {
        if let Some(status) = game.try_wait().unwrap() {
            let err = std::io::read_to_string(game.stderr.take().unwrap()).unwrap();
            panic!("the game ended before showing frames ({status}): {err}");
        }
        let id = x.xdotool(&["search", "--name", "^platoon walk:"])?;
        let title = x.xdotool(&["getwindowname", id.lines().next()?])?;
        let frames: u64 = title.split_whitespace().nth(2)?.parse().ok()?;
        (frames >= 30).then_some(frames)
    });
    // The window (320 x 180, platoon's 160 x 90 image at twice its size) is mostly lit.
    let lit = x.lit_pixels();
    let _ = game.kill();
    let _ = game.wait();
    assert!(
        lit > 320 * 180 / 2,
        "{lit} lit pixels after {frames} frames"
    );
}

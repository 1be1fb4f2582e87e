//! An X server of a test's own (Xvfb, its screen mirrored to a file) and the tools the window
//! tests drive it with: `platoon view`'s (tests/cli/view.rs) and the Bevy example's
//! (crates/platoon-bevy/tests/window.rs, another Cargo workspace, which includes this file).
#![allow(dead_code)]

use std::ops::Range;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// A tool from Debian's packages, which tools/install-deps.sh installs.
pub fn tool(name: &str) -> PathBuf {
    let path = Path::new("/usr/bin").join(name);
    assert!(
        path.exists(),
        "{name} is missing: run tools/install-deps.sh"
    );
    path
}

/// Polls `f` every 100 ms until it gives a value, failing after `limit`.
pub fn wait_for<T>(limit: Duration, mut f: impl FnMut() -> Option<T>) -> T {
    let start = Instant::now();
    loop {
        if let Some(v) = f() {
            return v;
        }
        assert!(start.elapsed() < limit, "timed out after {limit:?}");
        std::thread::sleep(Duration::from_millis(100));
    }
}

/// An X server of its own, its screen mirrored to a file, killed on drop.
pub struct Xvfb {
    child: Child,
    pub display: String,
    _dir: tempfile::TempDir,
    screen: PathBuf,
}

impl Xvfb {
    /// Takes the first free display number of `displays` (a server that exits before its
    /// socket appears lost the number to another process: the next one is tried), with a
    /// screen of `size` ("320x240x24"), and returns once a client gets in. `-noreset`: by
    /// default the server resets when its last client leaves, and a window opened during the
    /// reset finds no server ("Failed to open connection to X server": the viewer's windows
    /// failed so in 3 suite runs of 7, and in 1 run of 6 under load).
    pub fn start(displays: Range<u32>, size: &str) -> Xvfb {
        let xvfb = tool("Xvfb");
        for n in displays.clone() {
            if Path::new(&format!("/tmp/.X{n}-lock")).exists() {
                continue;
            }
            let dir = tempfile::tempdir().unwrap();
            let mut child = Command::new(&xvfb)
                .arg(format!(":{n}"))
                .args([
                    "-screen",
                    "0",
                    size,
                    "-br",
                    "-noreset",
                    "-nolisten",
                    "tcp",
                    "-fbdir",
                ])
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
                // The socket appears before the server takes clients: wait for one to get in.
                wait_for(Duration::from_secs(20), || x.answers().then_some(()));
                return x;
            }
        }
        panic!("no free X display number in :{displays:?}");
    }

    /// A client can connect and ask the server something.
    fn answers(&self) -> bool {
        Command::new(tool("xdotool"))
            .arg("getdisplaygeometry")
            .env("DISPLAY", &self.display)
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .status()
            .is_ok_and(|s| s.success())
    }

    /// xdotool's output on this display (empty when it found nothing).
    pub fn xdotool(&self, args: &[&str]) -> String {
        let o = Command::new(tool("xdotool"))
            .args(args)
            .env("DISPLAY", &self.display)
            .output()
            .unwrap();
        String::from_utf8_lossy(&o.stdout).trim().to_string()
    }

    /// Pixels of the screen that are not black (the root window is black with -br); a pixel's
    /// fourth byte is padding (a presented Vulkan surface writes its alpha there).
    pub fn lit_pixels(&self) -> usize {
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
        // SIGTERM, so the server removes its lock file and socket (SIGKILL leaves them).
        let _ = Command::new("kill")
            .arg(self.child.id().to_string())
            .status();
        let _ = self.child.wait();
    }
}

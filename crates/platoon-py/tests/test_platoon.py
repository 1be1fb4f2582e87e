"""platoon's Python module against the CLI and against bad input (run by tools/test.sh on
lavapipe, forced through VK_DRIVER_FILES)."""

import os
import resource
import subprocess
from pathlib import Path

import numpy as np
import pytest

import platoon

SMALL = dict(width=24, height=16, spp=4, devices="lavapipe:1")


def cli() -> Path:
    """The CLI binary the suite built (tools/test.sh says where)."""
    path = Path(os.environ.get("PLATOON_CLI", ""))
    assert path.is_file(), f"PLATOON_CLI does not name the built CLI: {path!s}"
    return path


def test_a_render_is_a_linear_float_image_with_its_metadata():
    r = platoon.render(**SMALL)
    assert r.image.shape == (16, 24, 3) and r.image.dtype == np.float32
    assert np.isfinite(r.image).all() and r.image.mean() > 0.01
    assert r.spp == 4 and r.metadata["spp"] == "4"
    assert "llvmpipe" in r.metadata["device"]


def test_a_python_render_equals_the_clis_bit_for_bit(tmp_path):
    out = tmp_path / "cli.exr"
    args = ["render", "--width", "24", "--height", "16", "--spp", "4", "--devices",
            "lavapipe:1", "--method", "igi", "--vpls", "30", "--igi-interleave", "2x2",
            "--aov", "albedo,depth", "--out", str(out)]
    subprocess.run([str(cli()), *args], check=True, capture_output=True)
    cli_image, cli_meta = platoon.read_exr(out)
    r = platoon.render(**SMALL, method="igi", vpls=30, interleave=(2, 2),
                       aovs=["albedo", "depth"])
    assert np.array_equal(r.image, cli_image)
    assert r.metadata["method"] == cli_meta["method"]
    assert "30 VPLs" in r.metadata["method"]
    assert sorted(r.aovs) == ["albedo", "depth"]
    assert r.aovs["albedo"].shape == (16, 24, 3) and r.aovs["depth"].shape == (16, 24, 1)


def test_the_same_bits_on_three_tracers():
    one = platoon.render(**SMALL)
    three = platoon.render(**{**SMALL, "devices": "lavapipe:1,1,1"})
    assert np.array_equal(one.image, three.image)


def test_the_environments_strength_and_rotation_equal_the_clis(tmp_path):
    sky = Path(__file__).resolve().parents[3] / ".." / "shared" / "envmaps" / "sunset.exr"
    man = sky.parent.parent / "scenes" / "CesiumMan.glb"
    out = tmp_path / "cli.exr"
    args = ["render", str(man), "--width", "24", "--height", "16", "--spp", "4", "--devices",
            "lavapipe:1", "--env", str(sky), "--env-strength", "0.5", "--env-rotation", "45",
            "--out", str(out)]
    subprocess.run([str(cli()), *args], check=True, capture_output=True)
    cli_image, _ = platoon.read_exr(out)
    r = platoon.render(man, **SMALL, env=sky, env_strength=0.5, env_rotation=45)
    assert np.array_equal(r.image, cli_image)
    plain = platoon.render(man, **SMALL, env=sky)
    assert not np.array_equal(r.image, plain.image)
    with pytest.raises(ValueError, match="env_strength"):
        platoon.render(**SMALL, env_strength=-1.0)


def test_a_pixel_filter_equals_the_clis(tmp_path):
    out = tmp_path / "cli.exr"
    args = ["render", "--width", "24", "--height", "16", "--spp", "4", "--devices",
            "lavapipe:1", "--filter", "blackman-harris", "--out", str(out)]
    subprocess.run([str(cli()), *args], check=True, capture_output=True)
    cli_image, meta = platoon.read_exr(out)
    r = platoon.render(**SMALL, filter="blackman-harris")
    assert np.array_equal(r.image, cli_image)
    assert r.metadata["filter"].startswith("blackman-harris")
    assert not np.array_equal(r.image, platoon.render(**SMALL).image)


def test_the_path_tracers_options_equal_the_clis(tmp_path):
    out = tmp_path / "cli.exr"
    args = ["render", "--width", "24", "--height", "16", "--spp", "4", "--devices",
            "lavapipe:1", "--resampled-light", "8", "--kernel", "spt", "--out", str(out)]
    subprocess.run([str(cli()), *args], check=True, capture_output=True)
    cli_image, meta = platoon.read_exr(out)
    r = platoon.render(**SMALL, resampled_light=8, kernel="spt")
    assert np.array_equal(r.image, cli_image)
    assert r.metadata["light_selection"] == meta["light_selection"]
    assert r.metadata["light_selection"].startswith("MIS+RIS over 8 candidates")
    assert r.metadata["path_kernel"] == "spt"
    assert not np.array_equal(r.image, platoon.render(**SMALL).image)
    assert set(platoon.methods()["path"]) == {"kernel", "resampled_light"}


def test_a_crop_is_the_whole_renders_window():
    whole = platoon.render(**SMALL)
    crop = platoon.render(**SMALL, crop=(5, 3, 13, 9))
    assert crop.image.shape == (9, 13, 3)
    assert np.array_equal(crop.image, whole.image[3:12, 5:18])
    assert crop.metadata["crop"] == "5,3,13,9 of 24 x 16"


def test_textures_by_ray_cone_and_in_a_budget_say_so_in_the_metadata():
    man = Path(__file__).resolve().parents[3] / ".." / "shared" / "scenes" / "CesiumMan.glb"
    r = platoon.render(man, **SMALL, texture_lod="ray-cone", texture_budget=64 << 10)
    assert r.metadata["texture_lod"] == "ray-cone"
    assert "texture budget of 64.00 KiB" in r.metadata["approximations"]
    plain = platoon.render(man, **SMALL)
    assert plain.metadata["texture_lod"] == "off"
    assert not np.array_equal(r.image, plain.image)


def test_a_cryptomatte_names_its_ids_in_the_metadata():
    import json
    import struct
    r = platoon.render(**SMALL, aovs=["crypto-material"])
    layer = r.aovs["CryptoMaterial00"]
    assert layer.shape == (16, 24, 4) and sorted(r.aovs) == [
        "CryptoMaterial00", "CryptoMaterial01", "CryptoMaterial02"]
    [manifest] = [v for k, v in r.metadata.items() if k.endswith("/manifest")]
    names = {h: n for n, h in json.loads(manifest).items()}
    top = {names["%08x" % struct.unpack("<I", struct.pack("<f", v))[0]]
           for v, c in zip(layer[..., 0].ravel(), layer[..., 1].ravel()) if c > 0}
    assert {"white", "red", "green"} <= top <= {"white", "red", "green", "light"}


def test_display_pixels_are_the_srgb_encoding_under_the_view():
    grey = np.full((1, 2, 3), 0.5, dtype=np.float32)
    # The standard view is the sRGB curve alone: 0.5 encodes to 0.7354, 188 of 255.
    assert (platoon.display(grey, view_transform="standard") == 188).all()
    # A stop up is twice the light: 1.0, the curve's top.
    assert (platoon.display(grey, view_transform="standard", exposure=1.0) == 255).all()
    assert abs(int(platoon.display(grey, view_transform="standard", bits=16)[0, 0, 0]) - 48192) <= 1
    shown = platoon.display(platoon.render(**SMALL).image, view_transform="agx")
    assert shown.dtype == np.uint8 and shown.shape == (16, 24, 3) and shown.max() > 0
    for kwargs, says in [(dict(view_transform="filmic"), "view_transform"),
                         (dict(bits=12), "bits"), (dict(exposure=float("nan")), "exposure")]:
        with pytest.raises(ValueError, match=says):
            platoon.display(grey, **kwargs)


def test_a_transparent_film_has_an_alpha_and_leaves_the_sky_out():
    r = platoon.render(**SMALL, transparent_film=True)
    assert r.alpha.shape == (16, 24) and r.alpha[0, 0] == 0.0 and r.alpha[8, 12] == 1.0
    assert (r.image[r.alpha == 0.0] == 0.0).all()
    assert platoon.render(**SMALL).alpha is None


def test_the_light_passes_sum_to_the_image():
    r = platoon.render(**SMALL, aovs=["light"])
    assert len(r.aovs) == 8
    total = sum(r.aovs.values())
    assert np.allclose(total, r.image, rtol=1e-5, atol=1e-6)
    assert r.aovs["diffuse-direct"].mean() > 0 and r.aovs["emission"].mean() > 0


@pytest.mark.parametrize("kwargs, error, says", [
    (dict(crop=(20, 0, 5, 4)), ValueError, "crop: the window 20,0,5,4 reaches past"),
    (dict(width=0), ValueError, "width: must be positive"),
    (dict(filter="mitchell"), ValueError, "filter: unknown pixel filter"),
    (dict(max_depth=0), ValueError, "max_depth"),
    (dict(method="photons"), ValueError, "unknown method"),
    (dict(vplz=30), ValueError, "vplz: not an argument of render"),
    (dict(method="igi", vpls="many"), ValueError, "vpls: expects a whole number"),
    (dict(method="igi", bounces=20), ValueError, "bounces"),
    (dict(method="igi", resampled_light=8), ValueError,
     "resampled_light: not an argument of render, nor an option of method \"igi\""),
    (dict(resampled_light=0), ValueError, "resampled_light: resampled light needs at least one"),
    (dict(kernel="warp"), ValueError, "kernel: unknown kernel warp: one of auto, mega, spt"),
    (dict(balancer="fastest"), ValueError, "balancer: unknown balancer fastest"),
    (dict(denoise="magic"), ValueError, "denoise: unknown denoiser \"magic\""),
    # The module is built without the feature `oidn` (tools/test.sh builds the CLI with it).
    (dict(denoise="oidn"), ValueError, "denoise: this platoon was built without Open Image Denoise"),
    (dict(spp=-1), ValueError, "spp: expects a whole number"),
    (dict(aovs=["beauty"]), ValueError, "unknown AOV"),
    (dict(devices="lavapipe:1,1", time_limit=1.0), ValueError, "time_limit"),
    (dict(time_limit=-1.0), ValueError, "time_limit: must be a positive number of seconds"),
    (dict(scene="/nonexistent/man.glb"), platoon.PlatoonError, "/nonexistent/man.glb"),
    (dict(device_memory_limit=1024), platoon.PlatoonError, "device-memory limit of 1.00 KiB"),
    (dict(texture_lod="trilinear"), ValueError, "texture_lod: trilinear: expected one of off"),
])
def test_bad_input_raises_naming_the_argument_or_file(kwargs, error, says):
    with pytest.raises(error, match=None) as caught:
        platoon.render(**{**SMALL, **kwargs})
    assert says in str(caught.value)


def test_a_file_that_is_no_gltf_names_itself(tmp_path):
    bad = tmp_path / "garbage.gltf"
    bad.write_text("not json")
    with pytest.raises(platoon.PlatoonError) as caught:
        platoon.render(str(bad), **SMALL)
    assert "garbage.gltf" in str(caught.value)


def rss_kib() -> int:
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * resource.getpagesize() // 1024


def test_a_hundred_renders_keep_memory_flat():
    tiny = dict(width=8, height=8, spp=1, devices="lavapipe:1")
    for _ in range(10):
        platoon.render(**tiny)
    before = rss_kib()
    for _ in range(100):
        platoon.render(**tiny)
    grown = rss_kib() - before
    assert grown < 16 * 1024, f"resident memory grew {grown} KiB over 100 renders"


def test_devices_and_methods_describe_themselves():
    found = platoon.devices()
    assert found and found[0]["index"] == 0 and "llvmpipe" in found[0]["name"]
    # Debian 12's lavapipe offers no ray queries, and auto takes the own traversal on a CPU.
    assert found[0]["ray_queries"] is False and found[0]["auto_traversal"] == "own"
    m = platoon.methods()
    assert list(m)[0] == "path" and "vpls" in m["igi"]


def test_every_option_of_the_table_is_a_keyword_of_render_and_its_stub():
    stub = (Path(platoon.__file__).parent / "__init__.pyi").read_text()
    signature = stub[stub.index("def render("):stub.index(") -> Rendered:")]
    table = platoon.options()
    assert {"spp", "width", "filter", "max_depth", "denoise", "devices"} <= set(table)
    for key in table:
        assert f"    {key}:" in signature, f"the stub's render has no {key}"
    # Each is taken by render (an unknown keyword would raise naming it).
    r = platoon.render(**SMALL, seed=3, validation=False, ao_distance=2.0, sampling="mis",
                       balancer="cost-aware", denoise="none", aperture=0.0)
    assert r.image.shape == (16, 24, 3)


# Every keyword `render` took when the frame's options became a table (issue 60), with a value
# of its kind: each must still be taken (a width of 0 is then what the request refuses).
KEYWORDS_OF_TODAY = dict(
    spp=4, method="path", devices="lavapipe:1", aovs=["albedo"], denoise="none", seed=1,
    filter="box", crop=None, transparent_film=False, ao_distance=1.0, max_depth=4,
    time_limit=None, env=None, env_color=(1.0, 1.0, 1.0), env_strength=1.0, env_rotation=0.0,
    time=0.0, frame_interval=0.04, camera=None, aperture=0.0, focus_distance=1.0,
    balancer="cost-aware", sampling="mis", device_memory_limit=None, texture_lod="off",
    texture_budget=None, adaptive_threshold=None, variant=None, allow_external_files=False,
    height=8, kernel="mega", resampled_light=4, validation=False, vpls=None,
)


@pytest.mark.parametrize("key", sorted(KEYWORDS_OF_TODAY))
def test_every_keyword_of_today_is_still_taken(key):
    kwargs = {key: KEYWORDS_OF_TODAY[key], "width": 0}
    if key == "vpls":
        kwargs.update(method="igi", vpls=30)
    with pytest.raises(ValueError) as caught:
        platoon.render(**kwargs)
    assert "width: must be positive" in str(caught.value), str(caught.value)


def interrupted(code):
    """Runs `code` in a Python of its own, sends it SIGINT 1.5 s after it prints `rendering`,
    and returns its exit status and output; it must end within 20 s of the signal."""
    import signal
    import sys
    import time
    # Ctrl-C as at a terminal: a runner started in the background (nohup, `cmd &` in a script)
    # passes SIGINT on ignored, and a Python started so never raises KeyboardInterrupt.
    def default_sigint():
        signal.signal(signal.SIGINT, signal.SIG_DFL)
    p = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True,
                         preexec_fn=default_sigint)
    assert p.stdout.readline().strip() == "rendering"
    time.sleep(1.5)
    sent = time.monotonic()
    p.send_signal(signal.SIGINT)
    try:
        out, _ = p.communicate(timeout=60)
    except subprocess.TimeoutExpired:
        # Not left rendering behind the tests.
        p.kill()
        p.communicate()
        raise
    assert time.monotonic() - sent < 20, "Ctrl-C waited for the render"
    return p.returncode, out


def test_ctrl_c_returns_from_a_long_render_at_once():
    code = ("import platoon, sys\n"
            "print('rendering', flush=True)\n"
            "try:\n"
            "    platoon.render(width=256, height=256, spp=100000, devices='lavapipe:1')\n"
            "except KeyboardInterrupt:\n"
            "    print('interrupted', flush=True)\n"
            "    # The interrupted render stopped on the devices too: the next one does not\n"
            "    # wait for its 100000 samples behind it.\n"
            "    r = platoon.render(width=16, height=16, spp=4, devices='lavapipe:1')\n"
            "    print('then', r.spp, flush=True)\n"
            "    sys.exit(3)\n")
    returncode, out = interrupted(code)
    assert returncode == 3 and "interrupted" in out and "then 4" in out, out


def test_a_renderer_continues_its_film_bit_for_bit():
    whole = platoon.render(**{**SMALL, "spp": 7})
    for devices in ["lavapipe:1", "lavapipe:1,1,1"]:
        r = platoon.Renderer(width=24, height=16, devices=devices)
        r.render(3)
        last = r.render(4)
        assert r.spp == 7 and last.spp == 7
        assert np.array_equal(last.image, whole.image)
    with pytest.raises(ValueError) as caught:
        platoon.Renderer(width=24, height=16, time_limit=1.0)
    assert "time_limit" in str(caught.value)
    with pytest.raises(platoon.PlatoonError) as caught:
        platoon.Renderer("/nonexistent/box.glb")
    assert "/nonexistent/box.glb" in str(caught.value)


CAMERA = ((0.0, 1.0, 3.4), (0.0, 1.0, 0.0), 40.0)


def game_image(edits=lambda g: None, frames=3, **kwargs):
    g = platoon.Game(**{**SMALL, "spp": 2, **kwargs})
    edits(g)
    for _ in range(frames):
        g.frame(CAMERA)
    return g.finish()


def test_a_game_of_a_still_view_is_one_render_of_its_samples():
    last = game_image(frames=4, spp=3, devices="lavapipe:1,1")
    assert last.film_samples == 12 and last.frame == 3
    whole = platoon.render(**{**SMALL, "spp": 12}, camera=CAMERA)
    assert np.array_equal(last.image, whole.image)


def test_a_living_scenes_edits_reach_the_image():
    plain = game_image().image
    at = lambda x: (lambda g: g.add_instance(0, (x, 0.6, 0.0), scale=(0.3, 0.3, 0.3)))
    here, there = game_image(at(-0.3)).image, game_image(at(0.3)).image
    assert not np.array_equal(here, plain) and not np.array_equal(here, there)

    def add_then_move(g):
        g.move(g.add_instance(0, (-0.3, 0.6, 0.0), scale=(0.3, 0.3, 0.3)), (0.3, 0.6, 0.0),
               scale=(0.3, 0.3, 0.3))
    assert np.array_equal(game_image(add_then_move).image, there)
    assert np.array_equal(game_image(lambda g: g.remove(g.add_instance(0, (0.3, 0.6, 0.0)))).image,
                          plain)
    with pytest.raises(platoon.PlatoonError):
        game_image(lambda g: g.move(999, (0.0, 0.0, 0.0)))


def test_a_living_scenes_frames_equal_the_rust_loops(tmp_path):
    # crates/platoon/examples/scripted_game.rs runs this script through the facade's game loop
    # (built by the suite beside the CLI) and writes its last frame's film.
    example = cli().parent / "examples" / "scripted_game"
    assert example.is_file(), f"the suite did not build {example}"
    out = tmp_path / "last.f32"
    subprocess.run([str(example), str(out)], check=True)
    rust = np.fromfile(out, dtype="<f4").reshape(16, 24, 3)
    g = platoon.Game(width=24, height=16, spp=2, devices="lavapipe:1,1")
    prop = g.add_instance(0, (-0.3, 0.6, 0.0), scale=(0.3, 0.3, 0.3))
    g.frame(CAMERA)
    g.frame(CAMERA)
    g.move(prop, (0.3, 0.6, 0.0), scale=(0.3, 0.3, 0.3))
    g.frame(CAMERA)
    g.frame(CAMERA)
    last = g.finish()
    assert last.frame == 3
    assert np.array_equal(last.image, rust)


def test_ctrl_c_in_a_renderer_keeps_none_of_the_calls_samples():
    code = ("import platoon, sys, numpy as np\n"
            "r = platoon.Renderer(width=64, height=64, devices='lavapipe:1')\n"
            "r.render(2)\n"
            "print('rendering', flush=True)\n"
            "try:\n"
            "    r.render(100000)\n"
            "except KeyboardInterrupt:\n"
            "    print('interrupted', r.spp, flush=True)\n"
            "    # The film goes on as if the interrupted call had not been made.\n"
            "    after = r.render(2)\n"
            "    whole = platoon.render(width=64, height=64, spp=4, devices='lavapipe:1')\n"
            "    print('then', after.spp, np.array_equal(after.image, whole.image), flush=True)\n"
            "    sys.exit(3)\n")
    returncode, out = interrupted(code)
    assert returncode == 3 and "interrupted 2" in out and "then 4 True" in out, out

"""Type stubs of platoon's Python module (the Rust extension `platoon._platoon`)."""

from os import PathLike
from typing import Any

import numpy as np
import numpy.typing as npt

class PlatoonError(Exception):
    """A render that failed: a scene that cannot be read, a device that cannot be made."""

class Rendered:
    """A rendered still."""

    @property
    def image(self) -> npt.NDArray[np.float32]:
        """Linear radiance, H x W x 3 (denoised when a denoiser was asked for)."""
    @property
    def alpha(self) -> npt.NDArray[np.float32] | None:
        """A transparent film's coverage, H x W (the image is premultiplied by it)."""
    @property
    def raw(self) -> npt.NDArray[np.float32] | None:
        """The render before the denoiser, when one ran."""
    @property
    def aovs(self) -> dict[str, npt.NDArray[np.float32]]:
        """Each AOV asked for, H x W x C."""
    @property
    def metadata(self) -> dict[str, str]:
        """What platoon writes into its EXR files: scene, method, approximations, devices..."""
    @property
    def spp(self) -> int: ...
    @property
    def seconds(self) -> float:
        """Until the last device was done."""
    @property
    def rays(self) -> int: ...
    @property
    def width(self) -> int: ...
    @property
    def height(self) -> int: ...

def render(
    scene: str | PathLike[str] | None = None,
    *,
    # <made from the request's table: PLATOON_BLESS=1 cargo test -p platoon --test request python_stub>
    spp: int = 64,
    time_limit: float | None = None,
    width: int = 512,
    height: int = 512,
    crop: tuple[int, int, int, int] | None = None,
    ao_distance: float = 10.0,
    transparent_film: bool = False,
    max_depth: int | None = None,
    seed: int = 0,
    filter: str = "box",
    aperture: float = 0.0,
    focus_distance: float | None = None,
    sampling: str = "mis",
    traversal: str = "auto",
    devices: str = "auto",
    balancer: str = "cost-aware",
    validation: bool = False,
    denoise: str = "none",
    adaptive_threshold: float | None = None,
    # </made from the request's table>
    method: str = "path",
    aovs: list[str] | None = None,
    env: str | PathLike[str] | None = None,
    env_color: tuple[float, float, float] | None = None,
    env_strength: float = 1.0,
    env_rotation: float = 0.0,
    time: float = 0.0,
    frame_interval: float = 1 / 24,
    camera: int | str | tuple[tuple[float, float, float], tuple[float, float, float], float] | None = None,
    device_memory_limit: int | None = None,
    texture_lod: str = "off",
    texture_budget: int | None = None,
    variant: str | None = None,
    allow_external_files: bool = False,
    **options: Any,
) -> Rendered:
    """Renders a glTF scene (the built-in Cornell box when None).

    `devices`: "auto" (every GPU, or lavapipe where there is none), "all", indices like "0,1",
    or "lavapipe:T1,T2" (software tracers of Ti threads). `aovs`: albedo, normal, depth, position, instance-id, material-id, primitive-id,
    variance, sample-count, crypto-object, crypto-material, crypto-asset (layers
    CryptoObject00..02, the manifest in `metadata`), the light passes by name or "light" for all eight (they sum to
    the image), motion (pixels moved since the frame `frame_interval` seconds before), ao (ambient
    occlusion within `ao_distance`), diffuse-color, glossy-color, transmission-color. `denoise`: none, atrous, atrous-device (on the first device), oidn. `env_strength` scales the
    environment's radiance, `env_rotation` turns its map about +Y (degrees, counter-clockwise
    seen from above). `filter`: the pixel filter, box, gaussian (sigma 0.5 px) or
    blackman-harris (1.5 px). `transparent_film`: the environment seen directly left out, `Rendered.alpha` the
    coverage (the image premultiplied by it). `crop`: a border render, the window (x, y, width, height) of
    the image in its pixels, the same bits as the whole render's there. `camera`: a scene camera's index or
    name, or (eye, target, vertical fov in degrees) in world space. `device_memory_limit`: the
    bytes the scene may take on each device; a scene over it (or over what a device has) raises
    before upload, naming the device and the sizes. `texture_lod`: "off" (textures read at full
    resolution) or "ray-cone" (mip maps, the level by the camera path's ray cone: less aliasing,
    blurred at grazing angles). `texture_budget`: the bytes all textures may take, the largest
    halved until they fit. The method's options by name (`methods()`),
    e.g. method="igi", vpls=180, or the path tracer's kernel="spt" and resampled_light=8.
    """

class Renderer:
    """A render that goes on: the scene prepared and the tracers made once (the arguments of
    `render` but spp), each `render(spp)` adding samples to the film. After any number of calls
    the image is the same bits as one render of all their samples."""

    def __init__(self, scene: str | PathLike[str] | None = None, **kwargs: Any) -> None: ...
    def render(self, spp: int) -> Rendered:
        """Adds `spp` samples to every pixel; the still of all the samples so far. Ctrl-C
        raises KeyboardInterrupt at once and keeps none of this call's samples."""
    @property
    def spp(self) -> int:
        """Samples per pixel the film holds (also after an interrupted call)."""

Vec3 = tuple[float, float, float]
LookAt = tuple[Vec3, Vec3, float]

class Frame:
    """A finished frame of a `Game`."""

    @property
    def image(self) -> npt.NDArray[np.float32]:
        """The film after this frame joined it, H x W x 3."""
    @property
    def denoised(self) -> npt.NDArray[np.float32] | None: ...
    @property
    def frame(self) -> int:
        """The game frame, counting calls from 0."""
    @property
    def spp(self) -> int:
        """Samples per pixel this frame took."""
    @property
    def film_samples(self) -> int | None:
        """Samples behind the film when it holds exact sums (None after a blend)."""
    @property
    def busy_ms(self) -> float: ...
    @property
    def idle(self) -> float:
        """The share of the frame the devices waited for each other."""

class Game:
    """The game loop over a living scene: the arguments of `render` (spp: samples a frame,
    1 by default), and `target_ms` to hold a frame time by scaling them."""

    def __init__(
        self, scene: str | PathLike[str] | None = None, target_ms: float | None = None,
        **kwargs: Any,
    ) -> None: ...
    def frame(self, camera: LookAt) -> Frame | None:
        """Renders this frame from (eye, target, fov_degrees) in world space while the game
        goes on; returns the previous frame (None on the first call)."""
    def finish(self) -> Frame | None:
        """Waits for the last frame and returns it."""
    def add_instance(
        self, mesh: int, position: Vec3, rotation: tuple[float, float, float, float] | None = None,
        scale: Vec3 | None = None,
    ) -> int:
        """A new instance of the scene's mesh `mesh`; its node."""
    def move(
        self, node: int, position: Vec3, rotation: tuple[float, float, float, float] | None = None,
        scale: Vec3 | None = None,
    ) -> None: ...
    def remove(self, node: int) -> None: ...
    def set_time(self, seconds: float) -> None:
        """The scene's animation time."""

def devices() -> list[dict[str, Any]]:
    """The Vulkan devices, in the order `devices="0,1"` numbers them: index, name, type, driver,
    api, ray_queries (whether the device offers them) and auto_traversal (what
    `traversal="auto"` takes on it: "own" or "ray-query")."""

def options() -> dict[str, str]:
    """The frame's options `render` takes as keyword arguments: {keyword: help}."""

def methods() -> dict[str, dict[str, str]]:
    """Each rendering method and the options it takes: {method: {option: help}}."""

def read_exr(path: str | PathLike[str]) -> tuple[npt.NDArray[np.float32], dict[str, str]]:
    """An EXR's first RGB(A) layer (H x W x 3) and its metadata."""

def display(
    image: npt.NDArray[np.float32],
    view_transform: str = "aces",
    exposure: float = 0.0,
    bits: int = 8,
) -> npt.NDArray[np.uint8] | npt.NDArray[np.uint16]:
    """A linear H x W x 3 image as sRGB display pixels under a view transform (standard,
    agx, pbr-neutral, aces) after `exposure` stops: the values platoon's PNG of it holds."""

"""platoon: a physically based path tracer on every Vulkan device of a machine at once.

    >>> import platoon
    >>> r = platoon.render(spp=16, width=256, height=256)   # the built-in Cornell box
    >>> r.image.shape, r.image.dtype
    ((256, 256, 3), dtype('float32'))
    >>> r = platoon.render("scene.glb", method="igi", vpls=180, aovs=["albedo", "normal"])

`render` returns a `Rendered`: `.image` (linear radiance, float32 H x W x 3), `.aovs`
({name: float32 H x W x C}), `.metadata` (what platoon writes into its EXR files). Bad
arguments raise ValueError naming the argument; a scene or device that fails raises
PlatoonError naming the file and the problem. `devices()` lists the Vulkan devices,
`options()` the frame's options `render` takes as keyword arguments, `methods()` the rendering
methods and the options each takes as keyword arguments;
`display(image, view_transform="aces", exposure=0.0, bits=8)` gives the sRGB pixels platoon's
PNG of an image holds.
`Renderer(scene, **the same arguments)` keeps its tracers: each `.render(spp)` adds samples
to the film (the same bits as one render of all of them). `Game(scene, target_ms=None,
**the same arguments)` is the game loop over a living scene: `frame((eye, target, fov))`
renders this frame and returns the previous one, `add_instance`, `move`, `remove` and
`set_time` change the scene for the next.
"""

from ._platoon import (
    Frame,
    Game,
    PlatoonError,
    Rendered,
    Renderer,
    devices,
    display,
    methods,
    options,
    read_exr,
    render,
)

__all__ = [
    "Frame",
    "Game",
    "PlatoonError",
    "Rendered",
    "Renderer",
    "devices",
    "display",
    "methods",
    "options",
    "read_exr",
    "render",
]

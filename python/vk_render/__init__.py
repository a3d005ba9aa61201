"""vk_render: classic BRDFs rendered through a real Vulkan rasterizer (Mesa's lavapipe, or any GPU), with
numpy arrays in and out.

    >>> import vk_render
    >>> image = vk_render.render("assets/scenes/fig1-lambert.toml", set={"material.grey.kd": 0.8})
    >>> image.shape, image.dtype
    ((400, 600, 3), dtype('uint8'))

The arrays are exactly the bytes of the PNG that `vk-render render` writes for the same arguments (or,
with ``hdr=True``, the float32 values of its EXR). A `Renderer` keeps its device, shaders, pipelines and
meshes between calls; `vk_render.render` uses one made on first use. `sweep` renders the product of a few
parameters' values, here or on a Dask cluster.
"""

import os
import threading

import numpy as np

from . import _native
from ._errors import DeviceError, Error, SceneError, SceneWarning
from ._native import Grid, Scene, devices
from ._sweep import sweep

__all__ = [
    "Error",
    "SceneError",
    "DeviceError",
    "SceneWarning",
    "Renderer",
    "Scene",
    "Grid",
    "render",
    "brdf",
    "albedo",
    "sample",
    "sampling_test",
    "reference",
    "check",
    "sweep",
    "devices",
    "default_renderer",
]
__version__ = _native.__version__

_default = None
_default_lock = threading.Lock()


def default_renderer():
    """The process-wide Renderer of `render`, `brdf`, `albedo` and `check`, made on first use.

    Its device is the default one, or the one named by the environment variable VK_RENDER_DEVICE (as
    ``--device``); VK_RENDER_VALIDATE=1 turns the validation layer on.
    """
    global _default
    with _default_lock:
        if _default is None:
            _default = Renderer(
                device=os.environ.get("VK_RENDER_DEVICE") or None,
                validate=os.environ.get("VK_RENDER_VALIDATE", "") not in ("", "0"),
            )
        return _default


def render(scene, *, set=None, width=None, height=None, samples=None, view=None, hdr=False):
    """Renders a scene with the process-wide renderer: see `Renderer.render`."""
    return default_renderer().render(
        scene, set=set, width=width, height=height, samples=samples, view=view, hdr=hdr
    )


def _directions(name, directions):
    array = np.ascontiguousarray(directions, dtype=np.float32)
    if array.ndim == 1:
        array = array.reshape(1, -1)
    if array.ndim != 2 or array.shape[1] != 3:
        raise ValueError(f"{name}: expected unit directions of shape (N, 3), got {np.shape(directions)}")
    return array


def _rgb_image(image):
    if isinstance(image, (str, os.PathLike)):
        return image
    array = np.asarray(image)
    if array.ndim != 3 or array.shape[2] != 3:
        raise ValueError(f"image: expected a (height, width, 3) array, got shape {array.shape}")
    if array.dtype != np.uint8:
        raise ValueError(f"image: expected uint8 levels, got {array.dtype}")
    return np.ascontiguousarray(array)


class Renderer(_native.Renderer):
    __doc__ = _native.Renderer.__doc__

    def brdf(self, material, wi, wo):
        """f_r(wi, wo) evaluated on the GPU by the shaders' own brdf_eval (the probe pass), as float32 (N, 3).

        `material` is a dict in the scene format's words ({"brdf": "cook-torrance", "kd": [...], ...}) or a
        pair (scene, "name"). `wi` and `wo` are unit directions, (N, 3) or (3,) of any float dtype, in the
        frame whose normal is +z.
        """
        return super().brdf(material, _directions("wi", wi), _directions("wo", wo))

    def albedo(self, material, theta_o_degrees):
        """The directional albedo at each theta_o (degrees, in [0, 90)), as `vk-render plot albedo` computes
        it (adaptive Gauss-Kronrod cubature of brdf_eval on the GPU): (albedo float64 (N, 3), the largest
        error bound reached)."""
        angles = np.atleast_1d(np.asarray(theta_o_degrees, dtype=np.float64)).tolist()
        return super().albedo(material, angles)

    def check(self, image, scene, *, set=None):
        """Checks an image against a scene rendered at its size, as `vk-render check` does: see
        `vk_render.check`."""
        return super().check(_rgb_image(image), scene, set=set)


def brdf(material, wi, wo, *, renderer=None):
    """f_r(wi, wo) on the GPU with the process-wide renderer (or `renderer`): see `Renderer.brdf`."""
    return (renderer or default_renderer()).brdf(material, wi, wo)


def albedo(material, theta_o_degrees, *, renderer=None):
    """The directional albedo with the process-wide renderer (or `renderer`): see `Renderer.albedo`."""
    return (renderer or default_renderer()).albedo(material, theta_o_degrees)


def sample(material, wo, n, *, seed=1, renderer=None):
    """`n` draws of a material's own importance sampler (the exact mode's, or a .brdf file's sampleBRDF) seen
    from the unit direction `wo` (normal +z, tangent X +x), from the random stream `seed`, with the
    process-wide renderer (or `renderer`): (directions float32 (n, 3), densities per solid angle float32
    (n,)). A direction below the surface is no sample, its density 0.

        >>> directions, pdf = vk_render.sample({"brdf": "phong", "kd": 0.35, "ks": 0.15, "shininess": 16},
        ...                                     [0.0, 0.0, 1.0], 100_000)
    """
    wo = np.asarray(wo, dtype=np.float64).reshape(-1)
    if wo.shape != (3,):
        raise ValueError(f"wo: expected one direction of 3 numbers, got shape {wo.shape}")
    return (renderer or default_renderer()).sample(material, [float(v) for v in wo], int(n), seed=seed)


def sampling_test(material, *, theta_o=None, phi_o=None, samples=1_000_000, seed=1, level=0.01, renderer=None):
    """`vk-render sampling`'s tests of a material's own importance sampler, with the process-wide renderer
    (or `renderer`): Pearson's chi-square per view, the density's integral and support, the estimator
    f cos / pdf against the albedo, energy and reciprocity, at the level `level` for them all. A dict:
    "passed", "level_each", "verdicts" (test, theta_o, phi_o, passed, detail) and "views" (per view: theta_o,
    phi_o, chi_square, degrees_of_freedom, p_value, density_integral, no_sample, estimate, standard_error,
    albedo, and the upper hemisphere's "histogram" and "expected" counts, (40, 160) arrays of the equal-area
    grid: cos theta by rows from 0 up, phi by columns from -180 degrees).
    """
    return (renderer or default_renderer()).sampling_test(
        material,
        theta_o=None if theta_o is None else [float(t) for t in np.atleast_1d(theta_o)],
        phi_o=None if phi_o is None else [float(p) for p in np.atleast_1d(phi_o)],
        samples=int(samples),
        seed=seed,
        level=level,
    )


def reference(scene, *, set=None, width=None, height=None, samples=None, hdr=False):
    """The CPU ray tracer (vk-render's independent reference): the scene as a (height, width, 3) array,
    uint8 after the output transform like `render`, or float32 with ``hdr=True``."""
    return _native.reference(scene, set=set, width=width, height=height, samples=samples, hdr=hdr)


def check(image, scene, *, set=None, renderer=None):
    """Checks an image against a scene rendered at its size, as `vk-render check` does.

    `image` is a (height, width, 3) uint8 array or a PNG/JPEG path; `scene` one of the practical's images
    by name ("fig2-oren-nayar-sigma-0.4"), a scene file or a Scene. Returns a dict: "matches" (bool),
    "verdict" ("matches", "mistake", "tie" or "unexplained"), "mistakes" (each with its name, explanation,
    should_be and looks_like), "statistics" (rms, mean, p99 and over, in 8-bit levels, as check prints),
    "regions" (the same per object and part), "tells_apart" (for a tie, the scene to render next),
    "tells_apart_levels" (how far apart the tied mistakes' renders are there, in levels), "wrong_parameters"
    (when no mistake explains it: each object whose own model explains its pixels with other parameters,
    with its "object", "material", "model", the "fitted" and the "scene" values of the parameters that
    differ, and the residuals in levels of both) and "exact" (the exact image). The same keys and values as
    the server's `POST /api/check` (one summary, read from its JSON).
    """
    return (renderer or default_renderer()).check(image, scene, set=set)

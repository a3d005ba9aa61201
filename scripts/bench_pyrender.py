#!/usr/bin/env python3
"""The peer of vk-render's benchmark: pyrender 0.1.45 (OpenGL 4.5 through EGL, surfaceless, on Mesa's
llvmpipe) drawing Figure 1 (assets/scenes/fig1-lambert.toml) and Figure 5 (fig5-golden-bunny.toml).

Prints one `name value` line per result on stdout, medians all:
    fig1_frame_ms   one OffscreenRenderer.render() of Figure 1, colour (and depth) read back
    bunny_frame_ms  the same for Figure 5
    first_image_s   from starting a Python process to its first Figure 1 image read back: this script is
                    run again with --first-image (import, build Figure 1, render once, exit) and the
                    whole child process is timed, as a shell's `time` would
Anything else (the GL renderer, progress) goes to stderr.

The scenes follow the project's conventions (src/scene/): a right-handed look-at camera with a vertical
fov_y, point lights whose radiance at distance d is power / d^2 (pyrender's PointLight intensity / d^2, the
same), sphere = centre and radius, a mesh placed by translate * Rz * Ry * Rx * scale. pyrender cannot draw
vk-render's infinite plane (vertices at w = 0), so the plane is a 1000-unit square of 2 triangles. Shading
differs and is not the point: pyrender evaluates its glTF metallic-roughness BRDF with sRGB-ish gamma for
every material, vk-render the scene's BRDF. pyrender 0.1.45 draws no shadows here: point-light shadows
are not implemented (RenderFlags.SHADOWS_POINT raises NotImplementedError in renderer.py), while vk-render
gives every light a shadow cube unless `--set light.N.shadows=false`: time it that way for like for like.

Usage: bench_pyrender.py [--frames N] [--first-image-runs N] [--save DIR]
       bench_pyrender.py --first-image
Run it with the python of scripts/bench-pyrender-env.sh.
"""
import os

# Before pyrender (and PyOpenGL) are imported: EGL, no X display. pyrender takes the first EGL device, so
# on a machine with a GPU: only Mesa's EGL vendor (not NVIDIA's), and Mesa's software rasterizer even on a
# DRM device. main() refuses any GL renderer but llvmpipe.
os.environ["PYOPENGL_PLATFORM"] = "egl"
os.environ.setdefault("LIBGL_ALWAYS_SOFTWARE", "1")
MESA_EGL_VENDOR = "/usr/share/glvnd/egl_vendor.d/50_mesa.json"
if os.path.exists(MESA_EGL_VENDOR):
    os.environ.setdefault("__EGL_VENDOR_LIBRARY_FILENAMES", MESA_EGL_VENDOR)

import argparse
import math
import statistics
import subprocess
import sys
import time

import numpy as np
import pyrender
import trimesh

WIDTH, HEIGHT = 600, 400
BUNNY = "/usr/share/glmark2/models/bunny.obj"  # Debian's glmark2-data, as vk-render's "bunny"
WARM_UP = 3  # the first render uploads the meshes and compiles the shaders


def look_at_pose(eye, target, up):
    """Camera to world. pyrender's camera looks down its -z with +y up and +x right; right is
    normalize(cross(forward, up)), as glam's right-handed look-at that vk-render uses."""
    eye, target, up = (np.asarray(v, dtype=float) for v in (eye, target, up))
    forward = target - eye
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, up)
    right /= np.linalg.norm(right)
    pose = np.eye(4)
    pose[:3, 0], pose[:3, 1], pose[:3, 2], pose[:3, 3] = right, np.cross(right, forward), -forward, eye
    return pose


def translation(v):
    pose = np.eye(4)
    pose[:3, 3] = v
    return pose


def material(rgb, metallic, roughness):
    return pyrender.MetallicRoughnessMaterial(
        baseColorFactor=[*rgb, 1.0], metallicFactor=metallic, roughnessFactor=roughness
    )


def plane_mesh(y, rgb):
    """The infinite plane y = const as a 1000-unit square, wound counter-clockwise seen from +y (pyrender
    culls back faces)."""
    h = 500.0
    positions = np.array([[-h, y, -h], [-h, y, h], [h, y, h], [h, y, -h]], dtype=np.float32)
    normals = np.tile(np.float32([0, 1, 0]), (4, 1))
    return pyrender.Mesh([pyrender.Primitive(positions=positions, normals=normals, indices=[[0, 1, 2], [0, 2, 3]],
                                             material=material(rgb, 0.0, 1.0))])


def base_scene(look_at, lights):
    # bg_color is the clear colour, written as is (pyrender's gamma applies to shaded fragments only).
    scene = pyrender.Scene(bg_color=[0.5, 0.5, 0.5, 1.0], ambient_light=[0.0, 0.0, 0.0])
    camera = pyrender.PerspectiveCamera(yfov=math.radians(60.0), aspectRatio=WIDTH / HEIGHT)
    scene.add(camera, pose=look_at_pose([0, 0, 0], look_at, [0, 1, 0]))
    for position, power in lights:
        scene.add(pyrender.PointLight(color=[1.0, 1.0, 1.0], intensity=power), pose=translation(position))
    scene.add(plane_mesh(-2.0, [1.0, 0.0, 0.0]))
    return scene


def uv_sphere(segments=256, rings=128):
    """vk-render's unit sphere (src/mesh/mod.rs, uv_sphere): the same grid, exact normals, 65,024
    triangles. trimesh.creation.uv_sphere's grid is not the same (its count=[256, 128] makes 130,048
    triangles, count=[128, 128] 64,512)."""
    theta = np.pi * np.arange(rings + 1) / rings
    phi = 2.0 * np.pi * np.arange(segments + 1) / segments
    t, p = np.meshgrid(theta, phi, indexing="ij")
    normals = np.stack([np.sin(t) * np.cos(p), np.cos(t), np.sin(t) * np.sin(p)], axis=-1).reshape(-1, 3)
    ring, segment = np.meshgrid(np.arange(rings), np.arange(segments), indexing="ij")
    a = ring * (segments + 1) + segment
    b = a + segments + 1
    # The pole rows are single points: no zero-area triangles there.
    upper = np.stack([a, a + 1, b], axis=-1)[1:].reshape(-1, 3)
    lower = np.stack([a + 1, b + 1, b], axis=-1)[:-1].reshape(-1, 3)
    return normals.astype(np.float32), np.concatenate([upper, lower]).astype(np.uint32)


def fig1_scene():
    positions, triangles = uv_sphere()
    grey = material([0.5] * 3, 0.0, 1.0)
    sphere = pyrender.Mesh([pyrender.Primitive(positions=positions, normals=positions, indices=triangles,
                                               material=grey)])
    scene = base_scene([0, 0, 1], [([0, 0, -2], 60.0)])
    scene.add(sphere, pose=translation([0, 0, 3]))  # radius 1: the unit sphere as is
    return scene


def bunny_scene():
    # process=False: the OBJ's own 34,835 shared vertices. The OBJ has no normals: trimesh computes smooth
    # ones, as vk-render does (weighted by corner angle there, by area in vk-render).
    bunny = trimesh.load(BUNNY, force="mesh", process=False)
    # translate * Ry(-50 deg) * scale 1.1 (Shape::mesh_transform; no x or z rotation here).
    model = translation([0, -0.91, 3.6]) @ trimesh.transformations.rotation_matrix(
        math.radians(-50.0), [0, 1, 0]) @ np.diag([1.1, 1.1, 1.1, 1.0])
    scene = base_scene([0, -0.8, 3], [([0, 0, -2], 60.0), ([3, 3, 1.5], 40.0)])
    gold = material([1.0, 0.85, 0.57], 1.0, 0.3)
    scene.add(pyrender.Mesh.from_trimesh(bunny, material=gold), pose=model)
    return scene, len(bunny.faces)


def renderer():
    # pyrender's OffscreenRenderer draws into a 4x multisampled framebuffer (renderer.py,
    # _configure_main_framebuffer: glRenderbufferStorageMultisample(GL_RENDERBUFFER, 4, ...)) and
    # glBlitFramebuffer-resolves it before glReadPixels: vk-render's scenes ask for samples = 4 too.
    # render() reads back the colour (RGB) and the depth (linearised in numpy) every frame; there is no
    # flag to skip the depth.
    return pyrender.OffscreenRenderer(WIDTH, HEIGHT)


def median_frame_ms(r, scene, frames):
    for _ in range(WARM_UP):
        colour, _depth = r.render(scene)
    times = []
    for _ in range(frames):
        start = time.perf_counter()
        colour, _depth = r.render(scene)
        times.append((time.perf_counter() - start) * 1e3)
    return statistics.median(times), colour


def save(colour, directory, name):
    from PIL import Image

    os.makedirs(directory, exist_ok=True)
    path = os.path.join(directory, name)
    Image.fromarray(colour).save(path)
    print(f"wrote {path}", file=sys.stderr)


def first_image_s(runs):
    """The median wall time of `runs` child processes in --first-image mode, interpreter start included."""
    times = []
    for _ in range(runs):
        start = time.perf_counter()
        subprocess.run([sys.executable, os.path.abspath(__file__), "--first-image"], check=True)
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--frames", type=int, default=30, help="timed frames per scene (default 30)")
    parser.add_argument("--first-image-runs", type=int, default=5,
                        help="child processes timed for first_image_s (default 5; 0 skips it)")
    parser.add_argument("--first-image", action="store_true",
                        help="only render Figure 1 once and exit (the process that first_image_s times)")
    parser.add_argument("--save", metavar="DIR", help="write fig1.png and bunny.png there")
    args = parser.parse_args()
    if args.frames < 1:
        parser.error("--frames must be at least 1")

    if args.first_image:
        renderer().render(fig1_scene())
        return

    r = renderer()
    from OpenGL import GL

    gl_renderer = GL.glGetString(GL.GL_RENDERER).decode()
    print(f"pyrender {pyrender.__version__}, GL {GL.glGetString(GL.GL_VERSION).decode()} on {gl_renderer}",
          file=sys.stderr)
    if "llvmpipe" not in gl_renderer:
        sys.exit(f"the peer must run on Mesa's llvmpipe, as vk-render on lavapipe; EGL gave {gl_renderer}")

    ms, colour = median_frame_ms(r, fig1_scene(), args.frames)
    print(f"fig1_frame_ms {ms:.1f}", flush=True)
    if args.save:
        save(colour, args.save, "fig1.png")

    scene, triangles = bunny_scene()
    print(f"bunny: {triangles} triangles", file=sys.stderr)
    ms, colour = median_frame_ms(r, scene, args.frames)
    print(f"bunny_frame_ms {ms:.1f}", flush=True)
    if args.save:
        save(colour, args.save, "bunny.png")
    r.delete()

    if args.first_image_runs > 0:
        print(f"first_image_s {first_image_s(args.first_image_runs):.2f}", flush=True)


if __name__ == "__main__":
    main()

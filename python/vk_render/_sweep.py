"""Sweeps: the product of a few parameters' values rendered here, or spread over a Dask cluster.

The grid itself (the order of the combinations, shards, labels and tile names) is vk-render's own
(`vk_render.Grid`, the one `vk-render sweep` renders), so a sweep here and one on the command line name
and order their tiles alike, and `vk-render sheet` assembles tiles from either.
"""

import os
import threading

from . import _native
from ._errors import Error

# The Renderer of this process for sweep tasks, by its options: a Dask worker process makes one for its
# first task and keeps it for every later one (its device, shaders, pipelines and meshes).
_renderers = {}
_renderers_lock = threading.Lock()
# How many renderers this process made for sweep tasks (the tests read it on each worker).
renderers_made = 0


def _renderer(options):
    global renderers_made
    key = tuple(sorted(options.items()))
    with _renderers_lock:
        if key not in _renderers:
            from . import Renderer

            _renderers[key] = Renderer(**options)
            renderers_made += 1
        return _renderers[key]


def _render_one(scene, overrides, tile, options, renderer=None):
    """One combination: its image, or the path of its tile once written."""
    renderer = renderer or _renderer(options)
    image = renderer.render(scene, set=overrides)
    if tile is None:
        return image
    _native.write_png(image, tile)
    return tile


def _whole(tile, scene):
    """Whether a tile on disk is whole: a PNG of the scene's size (tiles are renamed into place once
    written, so a killed sweep leaves none half-written; this also refuses a stranger's file)."""
    if not os.path.isfile(tile):
        return False
    try:
        image = _native.read_image(tile)
    except Exception:
        return False
    return image.shape == (scene.height, scene.width, 3)


def sweep(
    scene,
    grid,
    *,
    set=None,
    client=None,
    out=None,
    name="sweep",
    shard=None,
    resume=False,
    renderer=None,
    device=None,
    validate=False,
    retries=3,
):
    """Renders the scene for every combination of the grid's values.

    `grid` maps scene keys to lists of values, ``{"material.grey.kd": [0.2, 0.5, 0.8], "light.0.power":
    [30, 60]}``: the product is rendered, the first key varying slowest (as `vk-render sweep` with
    ``--param``/``--values`` pairs in that order). `set` applies to every image, before the grid's values.
    Every combination's scene is checked before anything renders: a bad value raises SceneError and
    nothing is rendered or written.

    Returns one record per combination, in order: ``{"params": {key: value}, "label": ..., "image":
    array}``, or with `out` (a folder, made if missing; on a cluster, one every worker can write: a shared
    file system) ``"path"`` instead of ``"image"``: the tile written
    there as ``NAME-VALUE.png`` (one key) or ``NAME-key=value-key=value.png``, the names `vk-render sweep -o
    OUT/NAME.png` gives, so that ``vk-render sheet`` assembles them. With `resume`, tiles already whole in
    `out` are not rendered again. `shard=(k, n)` renders only the k-th of n fixed shares (``--shard K/N``).

    With `client` (a ``dask.distributed.Client``) the combinations are spread over its workers; each
    worker process keeps one Renderer for all its tasks. A worker lost in the middle costs nothing: Dask
    runs its tasks again elsewhere (up to `retries` times each), and the images are the same bytes.
    Without a client, they render here on `renderer` (default: the process-wide one).
    """
    from . import Scene, default_renderer

    base = scene if isinstance(scene, Scene) else Scene.load(scene)
    values = {key: list(given) for key, given in grid.items()}
    combinations = _native.Grid(values)
    if shard is None:
        indices = range(len(combinations))
    else:
        k, n = shard
        indices = combinations.shard(k, n)
    if out is not None:
        out = os.fspath(out)
        if os.path.exists(out) and not os.path.isdir(out):
            raise Error(f"out: {out} is not a folder")
    sheet = os.path.join(out or ".", f"{name}.png")

    jobs = []
    for index in indices:
        combination = combinations.combination(index, sheet)
        params = {key: values[key][position] for key, position in zip(combinations.keys, combination["positions"])}
        overrides = dict(set or {})
        overrides.update(params)
        checked = base.with_set(overrides)  # SceneError here, before anything renders
        tile = os.fspath(combination["tile"]) if out is not None else None
        jobs.append((params, combination["label"], overrides, checked, tile))
    if out is not None:
        os.makedirs(out, exist_ok=True)

    def record(params, label, result):
        entry = {"params": params, "label": label}
        entry["path" if out is not None else "image"] = result
        return entry

    pending = []
    records = [None] * len(jobs)
    for position, (params, label, _, checked, tile) in enumerate(jobs):
        if resume and tile is not None and _whole(tile, checked):
            records[position] = record(params, label, tile)
        else:
            pending.append(position)

    options = {"device": device, "validate": validate}
    if client is None:
        renderer = renderer or (default_renderer() if device is None and not validate else _renderer(options))
        for position in pending:
            params, label, _, checked, tile = jobs[position]
            records[position] = record(params, label, _render_one(checked, None, tile, options, renderer))
        return records

    # Each task is the base scene and its combination's overrides, keyed by both (tokenized once for the
    # base): the same combination has the same key, so a task lost with its worker runs again as itself. A
    # tile's path is absolute, as workers may run in another folder.
    from dask.base import tokenize

    base_token = tokenize(base.to_toml(), os.fspath(base.path), options)
    futures = []
    for position in pending:
        _, _, overrides, _, tile = jobs[position]
        tile = None if tile is None else os.path.abspath(tile)
        key = f"vk-render-{name}-{position}-{tokenize(base_token, overrides)}"
        futures.append(client.submit(_render_one, base, overrides, tile, options, key=key, retries=retries))
    for position, result in zip(pending, client.gather(futures)):
        params, label, _, _, tile = jobs[position]
        records[position] = record(params, label, result if tile is None else tile)
    return records


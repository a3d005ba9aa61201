"""The GIL is released while the GPU works: two threads with a renderer each render at the same time."""

import threading
import time

import numpy as np

import vk_render
from conftest import FIG1, SCENES

BUNNY = SCENES / "fig5-golden-bunny.toml"


def test_two_threads_render_at_once_and_python_runs_meanwhile():
    scenes = [(FIG1, {"material.grey.kd": 0.3}), (BUNNY, {"image.width": 300, "image.height": 200})]
    alone = [vk_render.Renderer(validate=True).render(scene, set=sets) for scene, sets in scenes]
    renderers = [vk_render.Renderer(validate=True) for _ in scenes]
    results = [None, None]
    inside = [[], []]

    def work(i):
        scene, sets = scenes[i]
        for _ in range(4):
            start = time.monotonic()
            results[i] = renderers[i].render(scene, set=sets)
            inside[i].append((start, time.monotonic()))

    threads = [threading.Thread(target=work, args=(i,)) for i in range(2)]
    ticks = 0
    for thread in threads:
        thread.start()
    while any(thread.is_alive() for thread in threads):
        ticks += 1  # pure Python: runs only while no render holds the GIL
    for thread in threads:
        thread.join()
    for result, expected in zip(results, alone):
        assert np.array_equal(result, expected)
    # The two threads' renders overlapped in time, and the main thread ran Python all along.
    overlap = any(a0 < b1 and b0 < a1 for a0, a1 in inside[0] for b0, b1 in inside[1])
    assert overlap
    assert ticks > 10_000, ticks


def test_one_renderer_shared_by_threads_renders_for_one_at_a_time(renderer):
    expected = renderer.render(FIG1, width=80, height=60)
    results = []
    threads = [threading.Thread(target=lambda: results.append(renderer.render(FIG1, width=80, height=60)))
               for _ in range(4)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert len(results) == 4 and all(np.array_equal(r, expected) for r in results)

"""Sweeps of several parameters, here and on a Dask cluster: every image the serial render's bytes, a
worker killed in the middle costs nothing, and tiles from anywhere make the command line's sheet."""

import importlib
import os
import signal
import subprocess
import threading
import time

import numpy as np
import pytest

import vk_render
from conftest import BIN, FIG1, ROOT, cli

SMALL = {"image.width": 64, "image.height": 48, "image.samples": 1}
GRID = {"material.grey.kd": [0.2, 0.5, 0.8], "image.tonemap": ["clamp", "reinhard"], "light.0.power": [30, 60]}


def test_a_grid_renders_the_product_in_the_command_lines_order(renderer, tmp_path):
    records = vk_render.sweep(FIG1, GRID, set=SMALL, renderer=renderer)
    assert len(records) == 12
    assert records[0]["params"] == {"material.grey.kd": 0.2, "image.tonemap": "clamp", "light.0.power": 30}
    assert records[1]["params"]["light.0.power"] == 60 and records[2]["params"]["image.tonemap"] == "reinhard"
    assert records[0]["label"] == "kd = 0.2, tonemap = clamp, power = 30"
    for record in records:
        assert np.array_equal(record["image"], renderer.render(FIG1, set={**SMALL, **record["params"]}))
    # As tiles: the names and bytes of the command line's sweep of the same grid.
    files = vk_render.sweep(FIG1, GRID, set=SMALL, out=tmp_path / "py", renderer=renderer)
    cli("sweep", FIG1, *grid_args(GRID), *set_args(SMALL), "-o", tmp_path / "sweep.png")
    for record in files:
        tile = record["path"]
        assert os.path.dirname(tile) == str(tmp_path / "py")
        assert open(tile, "rb").read() == (tmp_path / os.path.basename(tile)).read_bytes()


def test_every_value_is_checked_before_anything_renders(tmp_path):
    with pytest.raises(vk_render.SceneError, match=r"material.grey.kd.*-0.5"):
        vk_render.sweep(FIG1, {"light.0.power": [10, 20], "material.grey.kd": [0.5, -0.5]}, set=SMALL,
                        out=tmp_path / "out")
    assert not (tmp_path / "out").exists()
    with pytest.raises(vk_render.SceneError, match="light.0.power"):
        vk_render.sweep(FIG1, {"light.0.power": [], "material.grey.kd": [0.5]})


def grid_args(grid):
    return [arg for key, values in grid.items() for arg in ("--param", key, "--values", ",".join(map(str, values)))]


def set_args(sets):
    return [arg for key, value in sets.items() for arg in ("--set", f"{key}={value}")]


def test_shards_from_python_and_the_command_line_make_one_processs_sheet(renderer, tmp_path):
    grid = {"material.grey.kd": [0.2, 0.5, 0.8], "light.0.power": [30, 45, 60]}
    whole = tmp_path / "whole"
    shards = tmp_path / "shards"
    whole.mkdir()
    cli("sweep", FIG1, *grid_args(grid), *set_args(SMALL), "-o", whole / "sweep.png")
    # Shard 1 of 3 on the command line, 2 and 3 from Python, then the sheet assembled from the tiles.
    shards.mkdir()
    cli("sweep", FIG1, *grid_args(grid), *set_args(SMALL), "-o", shards / "sweep.png", "--shard", "1/3")
    written = []
    for k in (2, 3):
        written += vk_render.sweep(FIG1, grid, set=SMALL, out=shards, shard=(k, 3), renderer=renderer)
    assert len(written) == 6
    cli("sheet", FIG1, *grid_args(grid), *set_args(SMALL), "-o", shards / "sweep.png")
    for name in os.listdir(whole):
        assert (shards / name).read_bytes() == (whole / name).read_bytes(), name


def test_resume_after_a_killed_sweep_makes_the_same_files(tmp_path):
    grid = {"material.grey.kd": [round(0.05 * i, 2) for i in range(1, 13)], "light.0.power": [30, 60]}
    args = [str(BIN), "sweep", str(FIG1), *grid_args(grid), *set_args(SMALL)]
    clean = tmp_path / "clean"
    killed = tmp_path / "killed"
    clean.mkdir()
    killed.mkdir()
    subprocess.run(args + ["-o", str(clean / "sweep.png")], check=True, capture_output=True)
    sweep = subprocess.Popen(args + ["-o", str(killed / "sweep.png")], stdout=subprocess.DEVNULL,
                             stderr=subprocess.DEVNULL, env={**os.environ, "VK_RENDER_TEST_WRITE_PAUSE_MS": "100"})
    deadline = time.monotonic() + 60
    while len([n for n in os.listdir(killed) if n.endswith(".png")]) < 3:
        assert time.monotonic() < deadline and sweep.poll() is None, "the sweep ended before it was killed"
        time.sleep(0.01)
    sweep.send_signal(signal.SIGKILL)
    sweep.wait()
    before = {n for n in os.listdir(killed) if n.endswith(".png")}
    assert 3 <= len(before) < 24
    # Python goes on where the command line stopped, then the command line makes the sheet.
    records = vk_render.sweep(FIG1, grid, set=SMALL, out=killed, resume=True)
    assert len(records) == 24
    cli("sheet", FIG1, *grid_args(grid), *set_args(SMALL), "-o", killed / "sweep.png")
    for name in os.listdir(clean):
        assert (killed / name).read_bytes() == (clean / name).read_bytes(), name


@pytest.fixture(scope="module")
def cluster():
    distributed = pytest.importorskip("dask.distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                                  env={"LP_NUM_THREADS": "1", "VK_RENDER_VALIDATE": "1"}) as cluster:
        with distributed.Client(cluster) as client:
            yield client


def test_a_grid_on_dask_is_the_serial_grid_with_one_renderer_per_worker(cluster, renderer):
    serial = vk_render.sweep(FIG1, GRID, set=SMALL, renderer=renderer)
    spread = vk_render.sweep(FIG1, GRID, set=SMALL, client=cluster, validate=True)
    assert [r["params"] for r in spread] == [r["params"] for r in serial]
    for a, b in zip(spread, serial):
        assert np.array_equal(a["image"], b["image"])
    # (A lambda: Dask's pickle sends it by value; the workers cannot import this test module.)
    made = cluster.run(lambda: importlib.import_module("vk_render._sweep").renderers_made)
    assert sorted(made.values()) == [1, 1], made


def test_a_worker_killed_in_the_middle_costs_nothing(cluster, renderer, tmp_path):
    grid = {"material.grey.kd": [round(0.04 * i, 2) for i in range(1, 21)], "light.0.power": [30, 60]}
    # Larger images than the other tests', so that the kill lands while tasks are still to run.
    sets = {"image.width": 200, "image.height": 150, "image.samples": 4}
    serial = vk_render.sweep(FIG1, grid, set=sets, renderer=renderer)
    pids = cluster.run(os.getpid)
    out = tmp_path / "tiles"
    done = {}

    def spread():
        done["records"] = vk_render.sweep(FIG1, grid, set=sets, client=cluster, out=out, validate=True)

    sweeping = threading.Thread(target=spread)
    sweeping.start()
    deadline = time.monotonic() + 60
    while not out.exists() or len(os.listdir(out)) < 4:
        assert time.monotonic() < deadline and sweeping.is_alive()
        time.sleep(0.005)
    victim = sorted(pids.values())[0]
    os.kill(victim, signal.SIGKILL)
    written_before_the_kill = len(os.listdir(out))
    sweeping.join(timeout=120)
    assert not sweeping.is_alive()
    records = done["records"]
    assert len(records) == 40
    assert written_before_the_kill < 40, "the sweep was over before the kill"
    for record, expected in zip(records, serial):
        assert np.array_equal(vk_render._native.read_image(record["path"]), expected["image"]), record["path"]
    # The killed worker is gone and was replaced.
    assert victim not in cluster.run(os.getpid).values()

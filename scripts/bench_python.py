"""vk_render (Python) against the vk-render command line, in one run on one machine: the ratios the
Python package promises (scripts/bench-python.sh runs it in the package's venv). Medians throughout; the
machine is shared and noisy, so only the ratios measured side by side matter.

  render loop     Renderer.render in a loop over Figure 1's grey kd (arrays), per image, against one more
                  image of `vk-render sweep` over the same values (its tiles and sheet written):
                  (sweep of 2 + N values - sweep of 2) / N. Asked: at most 1.1x.
  dask sweep      vk_render.sweep of 64 combinations on a LocalCluster of 2 single-threaded workers
                  (LP_NUM_THREADS=1 each), its images returned, against `vk-render sweep` of the same 64 on
                  the same machine, both whole (the workers' renderers made in it): throughput, asked at
                  least 0.8x.
  first array     `python3 -c "import vk_render; vk_render.render(FIG1)"` against `vk-render render FIG1 -o
                  x.png`, whole processes.
"""

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
FIG1 = ROOT / "assets" / "scenes" / "fig1-lambert.toml"
BIN = Path(os.environ.get("CARGO_TARGET_DIR") or ROOT / "target") / "release" / "vk-render"


def seconds(command, **kwargs):
    start = time.perf_counter()
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, **kwargs)
    return time.perf_counter() - start


def median_seconds(command, runs, **kwargs):
    return statistics.median(seconds(command, **kwargs) for _ in range(runs))


def kd_values(count, first=0.31):
    return [f"{first + 0.01 * i:.2f}" for i in range(count)]


def cli_sweep(values, out):
    return [str(BIN), "sweep", str(FIG1), "--param", "material.grey.kd", "--values", ",".join(values), "-o", str(out)]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--extra", type=int, default=20)
    args = parser.parse_args()
    import vk_render
    from dask.distributed import Client, LocalCluster

    rows = []
    with tempfile.TemporaryDirectory() as work:
        work = Path(work)
        # 1. Renderer.render in a loop against the command line's sweep, per image.
        two = median_seconds(cli_sweep(["0.3", "0.6"], work / "a.png"), args.runs)
        more = median_seconds(cli_sweep(["0.3", "0.6", *kd_values(args.extra)], work / "b.png"), args.runs)
        sweep_ms = 1000 * (more - two) / args.extra
        renderer = vk_render.Renderer()
        renderer.render(FIG1)  # its pipelines built, as the sweep's are before its further images
        loops = []
        for _ in range(args.runs):
            start = time.perf_counter()
            for value in kd_values(args.extra):
                renderer.render(FIG1, set={"material.grey.kd": float(value)})
            loops.append(1000 * (time.perf_counter() - start) / args.extra)
        loop_ms = statistics.median(loops)
        rows.append(("Renderer.render, per image (fig1)", loop_ms, "ms", sweep_ms, "ms", loop_ms / sweep_ms, "<= 1.10"))

        # 2. A LocalCluster of 2 single-threaded workers over 64 combinations, against the CLI's sweep.
        grid = {"material.grey.kd": [round(0.1 + 0.1 * i, 2) for i in range(8)],
                "light.0.power": [30 + 5 * i for i in range(8)]}
        cli_grid = [str(BIN), "sweep", str(FIG1), "--param", "material.grey.kd", "--values",
                    ",".join(map(str, grid["material.grey.kd"])), "--param", "light.0.power", "--values",
                    ",".join(map(str, grid["light.0.power"])), "-o", str(work / "grid.png")]
        cli_s = median_seconds(cli_grid, max(3, args.runs // 2))
        dask_runs = []
        for _ in range(max(3, args.runs // 2)):
            with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                              env={"LP_NUM_THREADS": "1"}) as cluster, Client(cluster) as client:
                client.wait_for_workers(2)
                start = time.perf_counter()
                records = vk_render.sweep(FIG1, grid, client=client)
                dask_runs.append(time.perf_counter() - start)
                assert len(records) == 64
        dask_s = statistics.median(dask_runs)
        rows.append(("Dask sweep, 64 images/s (2 workers x 1 thread)", 64 / dask_s, "/s", 64 / cli_s, "/s",
                     (64 / dask_s) / (64 / cli_s), ">= 0.80"))

        # 3. import vk_render to the first array, against the CLI's first PNG.
        first_py = median_seconds([sys.executable, "-c", f"import vk_render; vk_render.render({str(FIG1)!r})"], args.runs)
        first_cli = median_seconds([str(BIN), "render", str(FIG1), "-o", str(work / "first.png")], args.runs)
        rows.append(("import vk_render to the first array", 1000 * first_py, "ms", 1000 * first_cli, "ms",
                     first_py / first_cli, "(shown)"))

    print(f"vk_render {vk_render.__version__} against vk-render on {os.cpu_count()} cores, "
          f"{vk_render.Renderer().device}; medians, ratio = Python / command line")
    print()
    print(f"| {'what':<48} | {'Python':>12} | {'command line':>12} | {'ratio':>6} | {'target':>8} |")
    print(f"|{'-' * 50}|{'-' * 14}|{'-' * 14}|{'-' * 8}|{'-' * 10}|")
    for what, a, ua, b, ub, ratio, target in rows:
        print(f"| {what:<48} | {a:9.1f} {ua:<2} | {b:9.1f} {ub:<2} | {ratio:6.2f} | {target:>8} |")


if __name__ == "__main__":
    main()

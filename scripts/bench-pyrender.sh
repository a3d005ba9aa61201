#!/usr/bin/env bash
# vk-render against its peer, pyrender 0.1.45 (OpenGL through EGL on the same Mesa llvmpipe), on the same
# scenes, in one run on one machine: prints each measure of both and their ratio, against the target in its
# last column. Medians throughout; the machine is shared and noisy, so only the ratios matter.
#
#   sweep image     one more image of `vk-render sweep` over Figure 1's grey kd (600 x 400, 4 samples,
#                   shadows on, each image written to a PNG): (sweep of 2 + N values - sweep of 2) / N
#   preview fig1    one frame of `vk-render preview` while the camera orbits (--keys Orbit*N, under Xvfb),
#   preview bunny   from its own "presented N frames in T s" line; Figure 5 is the bunny, both lights
#                   casting shadows
#   render process  `vk-render render` of Figure 1 to a PNG, the whole process
#   figures         `vk-render figures`, the whole process (make render's work: 15 images, 6 sheets)
# against pyrender's Figure 1 frame, Figure 5 frame and its process to a first Figure 1 image
# (scripts/bench_pyrender.py says how each is taken, and why pyrender draws no shadows).
#
# Usage: scripts/bench-pyrender.sh          (make bench-peer; scripts/stage-current.sh bench-peer on Debian 13)
# Environment: RUNS (whole-process runs per measure, default 5), FRAMES (frames per preview, default 60).
set -euo pipefail

project=$(cd "$(dirname "$0")/.." && pwd)
cd "$project"
runs=${RUNS:-5}
frames=${FRAMES:-60}
bin=${CARGO_TARGET_DIR:-target}/release/vk-render
fig1=assets/scenes/fig1-lambert.toml
bunny=assets/scenes/fig5-golden-bunny.toml
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

scripts/install-packages.sh xvfb xauth >&2
cargo build --release --locked >&2
python=$(VK_RENDER_PYRENDER_VENV=${VK_RENDER_PYRENDER_VENV:-${CARGO_TARGET_DIR:-target}/pyrender-venv} \
    scripts/bench-pyrender-env.sh)

# The median of the numbers on stdin.
median() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }

# Seconds one run of a command takes, its output discarded.
seconds() {
    local start=$EPOCHREALTIME
    "$@" >/dev/null 2>&1 || { echo "failed: $*" >&2; return 1; }
    awk -v a="$start" -v b="$EPOCHREALTIME" 'BEGIN { printf "%.4f\n", b - a }'
}

# The median of $runs runs of a command, in seconds.
median_seconds() { for _ in $(seq "$runs"); do seconds "$@"; done | median; }

# Milliseconds per frame of a preview orbiting for $frames frames: its motion frames, from the frame pace
# line it prints ("...; N moving frames, X ms each", each from the frame before it).
preview_ms() {
    xvfb-run -a -s "-screen 0 1280x1024x24" "$bin" preview "$1" --frames "$frames" --keys "Orbit*$frames" 2>&1 |
        sed -n 's/^presented .*; [0-9]* moving frames, \([0-9.]*\) ms each$/\1/p'
}

echo "pyrender: $("$python" -c 'import pyrender; print(pyrender.__version__)'), vk-render: $("$bin" --version)" >&2
declare -A peer
while read -r name value; do peer[$name]=$value; done < <("$python" scripts/bench_pyrender.py --frames 30 --first-image-runs "$runs")

sweep() { "$bin" sweep "$fig1" --param material.grey.kd --values "$1" -o "$work/sheet.png"; }
extra=20
sweep_two=$(median_seconds sweep 0.3,0.6)
sweep_more=$(median_seconds sweep "0.3,0.6,$(LC_ALL=C seq -f %.2f -s, 0.31 0.01 0.$((30 + extra)))")
sweep_ms=$(awk -v a="$sweep_two" -v b="$sweep_more" -v n=$extra 'BEGIN { printf "%.2f\n", 1000 * (b - a) / n }')
fig1_ms=$(for _ in $(seq 3); do preview_ms "$fig1"; done | median)
bunny_ms=$(for _ in $(seq 3); do preview_ms "$bunny"; done | median)
render_s=$(median_seconds "$bin" render "$fig1" -o "$work/fig1.png")
figures_s=$(median_seconds "$bin" figures -o "$work/figures")

device=$("$bin" devices 2>/dev/null | sed -n 's/^\* *//p' | head -1)
echo
echo "vk-render against pyrender on $(nproc) cores, $device; medians, ratio = vk-render / pyrender"
echo
printf '| %-34s | %12s | %12s | %6s | %7s |\n' "what" "vk-render" "pyrender" "ratio" "target"
printf '|%s|%s|%s|%s|%s|\n' "$(printf -- '-%.0s' {1..36})" "$(printf -- '-%.0s' {1..14})" "$(printf -- '-%.0s' {1..14})" "--------" "---------"
row() { # what, vk-render value, unit, pyrender value, unit, target ratio
    awk -v what="$1" -v a="$2" -v ua="$3" -v b="$4" -v ub="$5" -v t="$6" 'BEGIN {
        r = a / b; printf "| %-34s | %9.1f %-2s | %9.1f %-2s | %6.2f | <= %4.2f |%s\n", what, a, ua, b, ub, r, t, (r <= t ? "" : " missed")
    }'
}
row "sweep image (fig1, shadows)" "$sweep_ms" ms "${peer[fig1_frame_ms]}" ms 0.5
row "preview frame, fig1 orbiting" "$fig1_ms" ms "${peer[fig1_frame_ms]}" ms 0.5
row "preview frame, bunny orbiting" "$bunny_ms" ms "${peer[bunny_frame_ms]}" ms 0.5
row "render fig1 to PNG, whole process" "$(awk -v s="$render_s" 'BEGIN { print 1000 * s }')" ms \
    "$(awk -v s="${peer[first_image_s]}" 'BEGIN { print 1000 * s }')" ms 0.25
row "figures, whole process" "$(awk -v s="$figures_s" 'BEGIN { print 1000 * s }')" ms "${peer[fig1_frame_ms]}" ms 20

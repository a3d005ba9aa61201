#!/usr/bin/env bash
# `make test`'s tests: cargo builds every test binary, then they run side by side, one more at once than
# the machine has cores, the longest first, each binary's output shown whole when it ends; then the doc tests.
# With VK_RENDER_TEST_PYTHON=1 the Python package's tests are one more of them (scripts/test-python.sh), its
# wheel built and installed before any test starts. The tests that must have the machine to themselves run
# alone at the end: those that bound a latency, and those whose shader never ends on purpose (on a GPU its
# process's end resets the device, and the other processes rendering then lose theirs: seen on an H200).
#
# Why not one `cargo test`: it runs the binaries one after another, and on 2 cores a third of the machine
# stood idle while a binary waited (the server's timeouts, a child process, a binary with one long test
# left): 984 s of CPU in 616 s of wall-clock time, cold, on 2 cores. Side by side the cores stay busy.
# Each binary still runs its tests on its own threads as cargo runs them (same working directory, same
# arguments), so `cargo test` gives the same results, one binary at a time. pytest, which runs its tests one
# after another, took 59 s after the binaries' 435 s; beside them it fills what they leave of the cores.
#
# With --long first, the long tests instead (`make test-long`): those marked #[ignore = "long: ..."], the
# statistical runs over whole ranges (the samplers' chi-square at 10^6 samples from sharp to rough, every
# catalogue scene in the browser), run as the others are, each binary with `--ignored`; no Python, no doc
# tests.
#
# Usage: scripts/run-tests.sh [--long] [CARGO-ARGS...]     (e.g. --release --locked)
# Environment: CARGO (default cargo), VK_RENDER_TEST_JOBS (binaries at once; default: the cores and one),
# VK_RENDER_TEST_TIMEOUT (seconds a binary may take; default 1200), VK_RENDER_TEST_PYTHON (1: the Python
# tests too; VK_RENDER_WHEEL as scripts/python-env.sh).
set -euo pipefail

project=$(cd "$(dirname "$0")/.." && pwd)
cd "$project"
cargo=${CARGO:-cargo}
long_run=0
if [ "${1:-}" = --long ]; then
    long_run=1
    shift
fi
# One more than the cores: each binary waits part of its time (on a browser, a server's timeouts, a child
# process), and a machine busy with other work shares its cores among the processes that want them. On 2
# cores beside two processes that keep both busy (2026-12-06): 900 s with 2 at once, 748 s with 3; with
# nothing else running, 553 s either way.
jobs=${VK_RENDER_TEST_JOBS:-$(($(nproc) + 1))}
limit=${VK_RENDER_TEST_TIMEOUT:-1200}

# The tests that take longest, by their time side by side on 2 cores (3 at once: tests/serve_browser.rs
# 320 s, sampling.rs 222 s, serve.rs 183 s, docs.rs 162 s, measured.rs 131 s, pytest 129 s, environment.rs
# 122 s):
# started first, so that no long one is left running alone at the end.
longest_first=(tests/serve_browser.rs tests/sampling.rs tests/serve.rs python/tests tests/docs.rs
    tests/environment.rs tests/measured.rs tests/analytic_fit.rs tests/cli.rs tests/preview.rs tests/analytic_cli.rs
    tests/check.rs)

logs=$(mktemp -d)
trap 'rm -rf "$logs"' EXIT
# The packages with tests: vk-render, and the crates the browser runs as WebAssembly (whose tests run here,
# natively). The Python binding's are pytest's.
packages=(-p vk-render -p vk-render-brdf-file -p vk-render-check-rules -p vk-render-cubature -p vk-render-web)

# Every test harness cargo builds (the library's, the binary's, each tests/*.rs), as Cargo's JSON lists them:
# its source file, as `cargo test` names it (tests/environment.rs), a tab, and its executable.
"$cargo" test "$@" "${packages[@]}" --no-run --message-format=json-render-diagnostics >"$logs/build.json"
mapfile -t built < <(grep '"profile":{[^}]*"test":true' "$logs/build.json" |
    sed -n 's|.*"src_path":"\([^"]*\)".*"executable":"\([^"]*\)".*|\1\t\2|p' | sed "s|^$project/||")
[ ${#built[@]} -gt 0 ] || { echo "cargo built no test binary" >&2; exit 1; }
if [ "$long_run" = 0 ] && [ "${VK_RENDER_TEST_PYTHON:-0}" = 1 ]; then
    VK_RENDER_PYTHON=$(scripts/python-env.sh)
    export VK_RENDER_PYTHON
    # pytest, its tests that run alone left for the end (below).
    export PYTEST_ADDOPTS="-m 'not alone'"
    built+=("python/tests"$'\t'"$project/scripts/test-python.sh")
fi

# The long run: only the binaries that have long tests.
if [ "$long_run" = 1 ]; then
    with_long=()
    for entry in "${built[@]}"; do
        if "${entry#*$'\t'}" --list --ignored 2>/dev/null | grep -q ': test$'; then
            with_long+=("$entry")
        fi
    done
    built=("${with_long[@]}")
fi

# The longest first, then the rest in cargo's order.
ordered=()
declare -A placed
for long in "${longest_first[@]}"; do
    for entry in "${built[@]}"; do
        if [ "${entry%%$'\t'*}" = "$long" ]; then
            ordered+=("$entry")
            placed[$entry]=1
        fi
    done
done
for entry in "${built[@]}"; do
    [ -n "${placed[$entry]:-}" ] || ordered+=("$entry")
done

# Runs one binary (ENTRY: its source, a tab, its executable) into its log; prints its result line (cargo's
# harness's, or pytest's last), or all of its output.
# Its time is the wall-clock time and the CPU time (user and system) of the binary and the children it
# waited for (the vk-render processes its tests start), as bash's `time` reports them.
run_one() {
    local source=${1%%$'\t'*} exe=${1#*$'\t'} logs=$2 limit=$3 log status=0 took TIMEFORMAT='%R %U %S' selection=()
    log="$logs/$(basename "$exe").log"
    if [ "$LONG" = 1 ]; then
        selection=(--ignored)
    elif [ "$source" != python/tests ]; then
        selection=(--skip "$ALONE")
    fi
    { time timeout --kill-after=10 "$limit" "$exe" "${selection[@]}" >"$log" 2>&1; } 2>"$log.time" || status=$?
    took=$(awk '{ printf "%.0f s, %.0f s of CPU", $1, $2 + $3 }' "$log.time")
    if [ "$status" -eq 0 ]; then
        echo "== $source: $(grep -E '^test result:|^[0-9]+ passed' "$log" | tail -n 1) ($took)"
    else
        [ "$status" -ne 124 ] || echo "(killed after $limit s)" >>"$log"
        echo "== $source FAILED (status $status, $took):"
        cat "$log"
        echo "$source" >"$log.failed"
    fi
}
export -f run_one
# The Rust test whose shader never ends (tests/analytic_cli.rs), skipped beside the others and run at the end.
export ALONE=a_brdf_that_never_ends_is_given_up_at_the_timeout_naming_its_file
export LONG=$long_run

started=$(date +%s)
printf '%s\0' "${ordered[@]}" | xargs -0 -n 1 -P "$jobs" bash -c 'run_one "$3" "$1" "$2"' run_one "$logs" "$limit" ||
    true
mapfile -t failed < <(cat "$logs"/*.failed 2>/dev/null)
cpu=$(cat "$logs"/*.time | awk '{ s += $2 + $3 } END { printf "%.0f", s }')
echo "== ${#ordered[@]} test runs, $jobs at once: $(($(date +%s) - started)) s, $cpu s of CPU"
if [ ${#failed[@]} -gt 0 ]; then
    echo "failed: ${failed[*]}" >&2
    exit 1
fi

[ "$long_run" = 0 ] || exit 0

# The tests that run alone: the shader that never ends, and the Python tests marked so (Ctrl-C within a
# second: beside another test binary on Debian 13 an interrupted exact render took 1.01 to 1.37 s).
for entry in "${ordered[@]}"; do
    if [ "${entry%%$'\t'*}" = tests/analytic_cli.rs ]; then
        "${entry#*$'\t'}" --exact "$ALONE"
    fi
done
if [ "${VK_RENDER_TEST_PYTHON:-0}" = 1 ]; then
    PYTEST_ADDOPTS= scripts/test-python.sh -m alone
fi

"$cargo" test "$@" "${packages[@]}" --doc

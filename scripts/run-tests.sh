#!/usr/bin/env bash
# `make test`'s Rust tests: cargo builds every test binary, then they run side by side, as many at once as
# the machine has cores, the longest first, each binary's output shown whole when it ends; then the doc tests.
#
# Why not one `cargo test`: it runs the binaries one after another, and on 2 cores a third of the machine
# stood idle while a binary waited (the server's timeouts, a child process, a binary with one long test
# left): 984 s of CPU in 616 s of wall-clock time, cold, on 2 cores. Side by side the cores stay busy.
# Each binary still runs its tests on its own threads as cargo runs them (same working directory, same
# arguments), so `cargo test` gives the same results, one binary at a time.
#
# Usage: scripts/run-tests.sh [CARGO-ARGS...]     (e.g. --release --locked)
# Environment: CARGO (default cargo), VK_RENDER_TEST_JOBS (binaries at once; default: the cores),
# VK_RENDER_TEST_TIMEOUT (seconds a binary may take; default 1200).
set -euo pipefail

project=$(cd "$(dirname "$0")/.." && pwd)
cd "$project"
cargo=${CARGO:-cargo}
jobs=${VK_RENDER_TEST_JOBS:-$(nproc)}
limit=${VK_RENDER_TEST_TIMEOUT:-1200}

# The binaries that took longest (tests/environment.rs 131 s, analytic_fit.rs 89 s, serve.rs 68 s alone on
# 2 cores): started first, so that no long one is left running alone at the end.
longest_first=(environment analytic_fit serve docs preview cli analytic_cli measured check)

logs=$(mktemp -d)
trap 'rm -rf "$logs"' EXIT

# Every test harness cargo builds (the library's, the binary's, each tests/*.rs), as Cargo's JSON lists them:
# its source file, as `cargo test` names it (tests/environment.rs), a tab, and its executable.
"$cargo" test "$@" --no-run --message-format=json-render-diagnostics >"$logs/build.json"
mapfile -t built < <(grep '"profile":{[^}]*"test":true' "$logs/build.json" |
    sed -n 's|.*"src_path":"\([^"]*\)".*"executable":"\([^"]*\)".*|\1\t\2|p' | sed "s|^$project/||")
[ ${#built[@]} -gt 0 ] || { echo "cargo built no test binary" >&2; exit 1; }

# The longest first, then the rest in cargo's order.
ordered=()
declare -A placed
for long in "${longest_first[@]}"; do
    for entry in "${built[@]}"; do
        if [ "${entry%%$'\t'*}" = "tests/$long.rs" ]; then
            ordered+=("$entry")
            placed[$entry]=1
        fi
    done
done
for entry in "${built[@]}"; do
    [ -n "${placed[$entry]:-}" ] || ordered+=("$entry")
done

# Runs one binary (ENTRY: its source, a tab, its executable) into its log; prints its result line, or all of
# its output.
# Its time is the wall-clock time and the CPU time (user and system) of the binary and the children it
# waited for (the vk-render processes its tests start), as bash's `time` reports them.
run_one() {
    local source=${1%%$'\t'*} exe=${1#*$'\t'} logs=$2 limit=$3 log status=0 took TIMEFORMAT='%R %U %S'
    log="$logs/$(basename "$exe").log"
    { time timeout --kill-after=10 "$limit" "$exe" >"$log" 2>&1; } 2>"$log.time" || status=$?
    took=$(awk '{ printf "%.0f s, %.0f s of CPU", $1, $2 + $3 }' "$log.time")
    if [ "$status" -eq 0 ]; then
        echo "== $source: $(grep -E '^test result:' "$log" | tail -n 1) ($took)"
    else
        [ "$status" -ne 124 ] || echo "(killed after $limit s)" >>"$log"
        echo "== $source FAILED (status $status, $took):"
        cat "$log"
        echo "$source" >"$log.failed"
    fi
}
export -f run_one

started=$(date +%s)
printf '%s\0' "${ordered[@]}" | xargs -0 -n 1 -P "$jobs" bash -c 'run_one "$3" "$1" "$2"' run_one "$logs" "$limit" ||
    true
mapfile -t failed < <(cat "$logs"/*.failed 2>/dev/null)
cpu=$(cat "$logs"/*.time | awk '{ s += $2 + $3 } END { printf "%.0f", s }')
echo "== ${#ordered[@]} test binaries, $jobs at once: $(($(date +%s) - started)) s, $cpu s of CPU"
if [ ${#failed[@]} -gt 0 ]; then
    echo "failed: ${failed[*]}" >&2
    exit 1
fi

"$cargo" test "$@" --doc

#!/usr/bin/env bash
# The interpreter against Lua 5.4 and Python 3 on the benchmark set: every benchmark folder
# below holds the same algorithm for pacer (a machine folder, or one per dialect in pt/ and
# mb/), bench.lua and bench.py. The script checks that all of them compute the same results,
# then times them interleaved (each round runs every program once, so a slow moment of the
# machine hits all of them alike) and prints the best of RUNS rounds (default 5) and the ratios
# pacer/Lua and pacer/Python. The rounds differ in the size of the environment they pass
# (BENCH_PAD), so that the stack's place is sampled, not fixed (see the timing loop).
#
#   bash bench/run.sh                 # the whole set
#   RUNS=3 bash bench/run.sh int      # a quicker look at some benchmarks
#   PACER_BEFORE=/path/to/old/pacer bash bench/run.sh   # also time an older pacer, same rounds
#
# Results: Lua and Python print `NAME=value …`; pacer's values are read from the last row of a
# `--csv` of the variables its `results` file names (one line each: NAME, variable, printf
# format), written by an untimed run.
set -euo pipefail

RUNS="${RUNS:-5}"
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
PACER="${PACER:-${CARGO_TARGET_DIR:-$ROOT/target}/release/pacer}"
BEFORE="${PACER_BEFORE:-}"
BENCHES=("$@")
if [ ${#BENCHES[@]} -eq 0 ]; then
    BENCHES=(arith loop unseen int branch pattern filter call kernel array strings)
fi

# --- tools ------------------------------------------------------------------------------------
# shellcheck source=bench/common.sh
source "$ROOT/bench/common.sh"
need_lua
command -v python3 >/dev/null 2>&1 || { echo "python3 is needed" >&2; exit 1; }
build_pacer

echo "lua:    $(lua5.4 -v 2>&1 | head -n 1)" >&2
echo "python: $(python3 --version 2>&1)" >&2

# The pacer machine folders of a benchmark, each with its label: `DIR LABEL` lines.
variants() {
    local b="bench/$1"
    if [ -f "$b/machine.toml" ]; then echo "$b $1"; fi
    for d in pt mb; do
        if [ -f "$b/$d/machine.toml" ]; then echo "$b/$d $1 ($d)"; fi
    done
}

# --- results ----------------------------------------------------------------------------------
echo
echo "results:"
for b in "${BENCHES[@]}"; do
    lua_out="$(lua5.4 "bench/$b/bench.lua")"
    py_out="$(python3 "bench/$b/bench.py")"
    printf '  %-14s %-8s %s\n' "$b" lua "$lua_out" "" python "$py_out"
    if [ "$lua_out" != "$py_out" ]; then
        echo "MISMATCH in $b: Lua and Python differ" >&2
        exit 1
    fi
    while read -r dir label; do
        out="$(pacer_results "$dir")"
        printf '  %-14s %-8s %s\n' "" "pacer" "$out  [$label]"
        if [ "$out" != "$lua_out" ]; then
            echo "MISMATCH in $label: pacer differs from Lua and Python" >&2
            exit 1
        fi
    done < <(variants "$b")
done
echo "  all agree"

# --- timing -----------------------------------------------------------------------------------
echo
echo "timing (best of $RUNS, interleaved, wall clock) ..." >&2
for ((round = 0; round < RUNS; round++)); do
    # Each round pads the environment by another size, spread over 4 KiB: where the stack lands
    # modulo a page moves an interpreter's time (by 20 % and more for one pacer binary here),
    # and one fixed size would make a layout's luck, good or bad, part of every figure. All the
    # programs of a round get the same padding; the best of the rounds is taken as before.
    export BENCH_PAD
    BENCH_PAD="$(head -c $((round * 4096 / RUNS / 16 * 16)) /dev/zero | tr '\0' x)"
    for b in "${BENCHES[@]}"; do
        while read -r dir label; do
            keep "pacer $label" "$(seconds "$PACER" run -q "$dir")"
            if [ -n "$BEFORE" ]; then
                keep "before $label" "$(seconds "$BEFORE" run -q "$dir")"
            fi
        done < <(variants "$b")
        keep "lua $b" "$(seconds lua5.4 "bench/$b/bench.lua")"
        keep "python $b" "$(seconds python3 "bench/$b/bench.py")"
    done
done

if [ -n "$BEFORE" ]; then
    printf '| %-14s | %8s | %8s | %8s | %8s | %9s | %12s |\n' benchmark before pacer "Lua 5.4" "Python 3" pacer/Lua pacer/Python
    printf '|%s|%s:|%s:|%s:|%s:|%s:|%s:|\n' ---------------- --------- --------- --------- --------- ---------- -------------
else
    printf '| %-14s | %8s | %8s | %8s | %9s | %12s |\n' benchmark pacer "Lua 5.4" "Python 3" pacer/Lua pacer/Python
    printf '|%s|%s:|%s:|%s:|%s:|%s:|\n' ---------------- --------- --------- --------- ---------- -------------
fi
for b in "${BENCHES[@]}"; do
    while read -r dir label; do
        awk -v name="$label" -v p="${best[pacer $label]}" -v l="${best[lua $b]}" \
            -v y="${best[python $b]}" -v o="${best[before $label]:-}" 'BEGIN {
            before = (o == "") ? "" : sprintf(" %6.3f s |", o)
            printf "| %-14s |%s %6.3f s | %6.3f s | %6.3f s | %9.2f | %12.2f |\n", name, before, p, l, y, p / l, p / y
        }'
    done < <(variants "$b")
done

#!/usr/bin/env bash
# Times the arithmetic benchmark (bench/arith) on pacer, Lua 5.4 and Python 3: the best wall
# clock time of RUNS runs each (default 5), the ratios pacer/lua and pacer/python, and a check
# that all three computed the same results.
#
#   bash bench/run.sh            # RUNS=3 bash bench/run.sh for a quicker look
set -euo pipefail

RUNS="${RUNS:-5}"
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
BENCH=bench/arith
PACER="$ROOT/target/release/pacer"

# --- tools ------------------------------------------------------------------------------------
if ! command -v lua5.4 >/dev/null 2>&1; then
    echo "installing Lua 5.4 ..." >&2
    SUDO=""
    if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
    $SUDO apt-get update -qq
    $SUDO apt-get install -y -qq lua5.4 >/dev/null
fi
command -v python3 >/dev/null 2>&1 || { echo "python3 is needed" >&2; exit 1; }

echo "building pacer (release) ..." >&2
cargo build --release --quiet

echo "lua:    $(lua5.4 -v 2>&1 | head -n 1)" >&2
echo "python: $(python3 --version 2>&1)" >&2

# --- results ----------------------------------------------------------------------------------
# Lua and Python print their results. pacer prints none: its results are read from a trace
# (with `--trace-writes` every write is a `change` event; the program writes each result once more after its loop,
# so the last events hold them all). This run is for checking only and is not timed.
lua_out="$(lua5.4 "$BENCH/bench.lua")"
py_out="$(python3 "$BENCH/bench.py")"
pacer_out="$("$PACER" run -q "$BENCH" --trace-writes --trace /dev/stdout | tail -n 40 | awk '
    /"kind":"change"/ {
        name = $0; sub(/.*"name":"Var\./, "", name); sub(/".*/, "", name)
        value = $0; sub(/.*"value":/, "", value); sub(/[},].*/, "", value)
        v[name] = value
    }
    END {
        printf "N=%d Acc=%d Hits=%d Odd=%d Chk=%d Mix=%d Ema=%.6f Harm=%.6f\n",
            v["N"], v["Acc"], v["Hits"], v["Odd"], v["Chk"], v["Mix"], v["Ema"], v["Harm"]
    }')"

echo
echo "results:"
printf '  %-7s %s\n' pacer "$pacer_out" lua "$lua_out" python "$py_out"
if [ "$pacer_out" != "$lua_out" ] || [ "$pacer_out" != "$py_out" ]; then
    echo "MISMATCH: the three results differ" >&2
    exit 1
fi
echo "  all three agree"

# --- timing -----------------------------------------------------------------------------------
# best_of CMD...: the least wall clock time, in seconds, of $RUNS runs (output discarded).
best_of() {
    local best="" start end t i
    for ((i = 0; i < RUNS; i++)); do
        start=$(date +%s.%N)
        "$@" >/dev/null
        end=$(date +%s.%N)
        t=$(awk -v s="$start" -v e="$end" 'BEGIN { printf "%.3f", e - s }')
        if [ -z "$best" ] || awk -v t="$t" -v b="$best" 'BEGIN { exit !(t < b) }'; then
            best=$t
        fi
    done
    echo "$best"
}

echo
echo "timing (best of $RUNS, wall clock) ..." >&2
t_pacer=$(best_of "$PACER" run -q "$BENCH")
t_lua=$(best_of lua5.4 "$BENCH/bench.lua")
t_py=$(best_of python3 "$BENCH/bench.py")

awk -v p="$t_pacer" -v l="$t_lua" -v y="$t_py" -v runs="$RUNS" 'BEGIN {
    printf "%-10s %10s\n", "runtime", "seconds"
    printf "%-10s %10.3f\n", "pacer", p
    printf "%-10s %10.3f\n", "lua5.4", l
    printf "%-10s %10.3f\n", "python3", y
    printf "\n"
    printf "pacer/lua    = %.2f\n", p / l
    printf "pacer/python = %.2f\n", p / y
}'

# --- the counting loop (bench/loop): dispatch cost alone ---------------------------------------
LOOP=bench/loop
loop_lua="$(lua5.4 "$LOOP/bench.lua")"
loop_py="$(python3 "$LOOP/bench.py")"
loop_pacer="$("$PACER" run -q "$LOOP" --trace-writes --trace /dev/stdout | tail -n 8 | awk '
    /"kind":"change"/ {
        name = $0; sub(/.*"name":"Var\./, "", name); sub(/".*/, "", name)
        value = $0; sub(/.*"value":/, "", value); sub(/[},].*/, "", value)
        v[name] = value
    }
    END { printf "S=%d T=%d\n", v["S"], v["T"] }')"
echo
echo "counting loop results:"
printf '  %-7s %s\n' pacer "$loop_pacer" lua "$loop_lua" python "$loop_py"
if [ "$loop_pacer" != "$loop_lua" ] || [ "$loop_pacer" != "$loop_py" ]; then
    echo "MISMATCH: the three results differ" >&2
    exit 1
fi
t_pacer=$(best_of "$PACER" run -q "$LOOP")
t_lua=$(best_of lua5.4 "$LOOP/bench.lua")
t_py=$(best_of python3 "$LOOP/bench.py")
awk -v p="$t_pacer" -v l="$t_lua" -v y="$t_py" 'BEGIN {
    printf "%-10s %10s\n", "runtime", "seconds"
    printf "%-10s %10.3f\n", "pacer", p
    printf "%-10s %10.3f\n", "lua5.4", l
    printf "%-10s %10.3f\n", "python3", y
    printf "\npacer/lua    = %.2f\npacer/python = %.2f\n", p / l, p / y
}'

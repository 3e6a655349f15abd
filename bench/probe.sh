#!/usr/bin/env bash
# Programs outside the benchmark set, written from the manuals to find where the interpreter is
# still slower than Lua 5.4 (bench/run.sh times the set itself). Each bench/probe/NAME holds a
# machine folder (p.mb or p.pt, machine.toml) and the same algorithm in bench.lua; the script
# checks that both give the same numbers (what the program prints, or the variables a `signals`
# file names), then prints the best of RUNS (default 5) CPU times of each and the ratio.
#
#   bash bench/probe.sh              # every probe
#   RUNS=3 bash bench/probe.sh gcd   # some
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
PACER="${PACER:-${CARGO_TARGET_DIR:-$ROOT/target}/release/pacer}"
# shellcheck source=bench/common.sh
source bench/common.sh
need_lua
cargo build --release --quiet
python3 bench/probe.py "$PACER" "${RUNS:-5}" "$@"

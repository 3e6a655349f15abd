#!/usr/bin/env bash
# What exporting costs on the hour-long labeler (programs/labeling with bench/labeling/hour.toml,
# 1 ms update): wall time, peak memory and file size with no export, with --vcd, with --csv and
# with --plot, and --vcd over 600 s against 3,600 s (memory must not grow with the run: the
# exporters stream to their files).
#
#   bash bench/export.sh            # OUT=/some/dir keeps the files (default: a temp dir)
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
cargo build --release --quiet
PACER="$ROOT/target/release/pacer"
if [ -n "${OUT:-}" ]; then
    mkdir -p "$OUT"
else
    OUT="$(mktemp -d)"
    trap 'rm -rf "$OUT"' EXIT
fi

# run LABEL SECONDS [pacer options…]: one timed run, one line of figures.
run() {
    local label="$1" secs="$2"
    shift 2
    rm -f "$OUT"/hour.*
    local out
    out="$( { /usr/bin/time -f '%e %M' "$PACER" run -q programs/labeling \
        --scenario bench/labeling/hour.toml --for "$secs" "$@"; } 2>&1 )"
    local wall kib bytes
    read -r wall kib <<<"$(echo "$out" | tail -n 1)"
    bytes=$( (cat "$OUT"/hour.* 2>/dev/null || true) | wc -c)
    awk -v l="$label" -v s="$secs" -v w="$wall" -v k="$kib" -v b="$bytes" 'BEGIN {
        printf "%-22s %5d s simulated  %7.2f s wall  peak %6.1f MiB  files %8.1f MiB\n",
            l, s, w, k / 1024, b / 1048576
    }'
}

run "no export" 3600
run "--vcd" 600 --vcd "$OUT/hour.vcd"
run "--vcd" 3600 --vcd "$OUT/hour.vcd"
run "--csv (every update)" 3600 --csv "$OUT/hour.csv"
run "--csv --sample 10ms" 3600 --csv "$OUT/hour.csv" --sample 10ms
run "--plot" 600 --plot "$OUT/hour.svg"
run "--plot" 3600 --plot "$OUT/hour.svg"

#!/usr/bin/env bash
# Speed of the whole labeler: one simulated hour (trace off) at a 1 ms and a 125 µs update, with
# wall time, updates per second, real-time factor and peak memory.
#
#   bash bench/labeling.sh
#   PACER=/path/to/pacer bash bench/labeling.sh   # another build (default: this tree's release)
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
cargo build --release --quiet
PACER="${PACER:-${CARGO_TARGET_DIR:-$ROOT/target}/release/pacer}"
TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT
cp programs/labeling/*.pt "$TMP/"
printf 'update 1ms 125us\n' >/dev/null
for update in 1ms 125us; do
    sed "s/^update = \"1ms\"/update = \"$update\"/" programs/labeling/machine.toml > "$TMP/machine.toml"
    out="$( { /usr/bin/time -f '%e %M' "$PACER" run -q "$TMP" --scenario bench/labeling/hour.toml; } 2>&1 )"
    read -r secs kib <<<"$(echo "$out" | tail -n 1)"
    awk -v u="$update" -v s="$secs" -v k="$kib" 'BEGIN {
        per = (u == "1ms") ? 1000 : 8000
        ticks = 3600 * per
        printf "update %-6s  %7.2f s wall  %12.0f updates/s  %8.0f× real time  peak %6.1f MiB\n", u, s, ticks / s, 3600 / s, k / 1024
    }'
done

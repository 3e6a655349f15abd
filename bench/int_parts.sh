#!/usr/bin/env bash
# The statements of bench/int one at a time, pacer (MotionBASIC) against Lua 5.4: each in a
# counted loop of N iterations (default 20,000,000), and the empty loop, best of RUNS rounds
# (default 7), the two timed alternately. Shows which integer operations cost pacer more than
# Lua (docs/benchmarks.md, the paragraph on `int`).
#
#   bash bench/int_parts.sh
#   N=4000000 RUNS=3 bash bench/int_parts.sh
set -euo pipefail

RUNS="${RUNS:-7}"
N="${N:-20000000}"
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
PACER="${PACER:-${CARGO_TARGET_DIR:-$ROOT/target}/release/pacer}"
command -v lua5.4 >/dev/null 2>&1 || { echo "lua5.4 is needed (bench/run.sh installs it)" >&2; exit 1; }
echo "building pacer (release) ..." >&2
cargo build --release --quiet

WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT

# One case: a name, the MotionBASIC statement, the Lua statement.
CASES=(
    "empty||"
    "lcg|A& = (A& * 75 + 74) MOD 65537|a = (a * 75 + 74) % 65537"
    "quotient|Q& = A& \\ 3|q = a // 3"
    "xor-and|X& = X& XOR (A& AND 255)|x = x ~ (a & 255)"
    "not-and|B& = (NOT A&) AND 65535|b = (~a) & 65535"
    "add-or-mod|H& = (H& + (B& OR (I& AND 1023))) MOD 1000003|h = (h + (b | (i & 1023))) % 1000003"
    "if|IF Q& > 1000000000 THEN Q& = Q& - 1000000000|if q > 1000000000 then q = q - 1000000000 end"
)

ms() {
    local start end
    start=$(date +%s%N)
    "$@" >/dev/null || { echo "failed: $*" >&2; exit 1; }
    end=$(date +%s%N)
    echo $(((end - start) / 1000000))
}

printf '| %-10s | %9s | %9s | %9s |\n' statement "pacer ms" "Lua ms" pacer/Lua
printf '|%s|%s|%s|%s|\n' ------------ ----------: ----------: ----------:
for case in "${CASES[@]}"; do
    IFS='|' read -r name mb lua <<<"$case"
    dir="$WORK/$name"
    mkdir -p "$dir"
    printf '[machine]\nname = "int-part"\nbudget = 1000000\n\n[[program]]\nnumber = 0\nfile = "b.mb"\n' \
        >"$dir/machine.toml"
    printf 'N& = %s\nA& = 12345\nQ& = 0\nX& = 0\nH& = 7\nB& = 5\nFOR I& = 1 TO N&\n  %s\nNEXT\n' \
        "$N" "$mb" >"$dir/b.mb"
    printf 'local n = %s\nlocal a, q, x, h, b = 12345, 0, 0, 7, 5\nfor i = 1, n do\n  %s\nend\nprint(a, q, x, h, b)\n' \
        "$N" "$lua" >"$dir/b.lua"
    best_p=""
    best_l=""
    for _ in $(seq "$RUNS"); do
        p=$(ms "$PACER" run -q "$dir")
        l=$(ms lua5.4 "$dir/b.lua")
        if [ -z "$best_p" ] || [ "$p" -lt "$best_p" ]; then best_p=$p; fi
        if [ -z "$best_l" ] || [ "$l" -lt "$best_l" ]; then best_l=$l; fi
    done
    ratio=$(awk -v p="$best_p" -v l="$best_l" 'BEGIN { printf "%.2f", (l > 0) ? p / l : 0 }')
    printf '| %-10s | %9s | %9s | %9s |\n' "$name" "$best_p" "$best_l" "$ratio"
done

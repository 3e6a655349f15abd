#!/usr/bin/env bash
# The statements of bench/int one at a time, pacer (MotionBASIC) against Lua 5.4: each in a
# counted loop of N iterations (default 20,000,000), and the empty loop. Both compute the same
# values (checked first, as bench/run.sh checks its set), then are timed alternately, best of
# RUNS rounds (default 7). Shows which integer operations cost pacer more than Lua
# (docs/benchmarks.md, the paragraph on `int`).
#
#   bash bench/int_parts.sh
#   N=4000000 RUNS=3 bash bench/int_parts.sh
set -euo pipefail

RUNS="${RUNS:-7}"
N="${N:-20000000}"
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
PACER="${PACER:-${CARGO_TARGET_DIR:-$ROOT/target}/release/pacer}"
# shellcheck source=bench/common.sh
source "$ROOT/bench/common.sh"
need_lua
build_pacer

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

printf '| %-10s | %9s | %9s | %9s |\n' statement "pacer s" "Lua s" pacer/Lua
printf '|%s|%s|%s|%s|\n' ------------ ----------: ----------: ----------:
for case in "${CASES[@]}"; do
    IFS='|' read -r name mb lua <<<"$case"
    dir="$WORK/$name"
    mkdir -p "$dir"
    printf '[machine]\nname = "int-part"\nbudget = 1000000\n\n[[program]]\nnumber = 0\nfile = "b.mb"\n' \
        >"$dir/machine.toml"
    printf 'N& = %s\nA& = 12345\nQ& = 0\nX& = 0\nH& = 7\nB& = 5\nFOR I& = 1 TO N&\n  %s\nNEXT\n' \
        "$N" "$mb" >"$dir/b.mb"
    printf 'local n = %s\nlocal a, q, x, h, b = 12345, 0, 0, 7, 5\nfor i = 1, n do\n  %s\nend\n%s\n' \
        "$N" "$lua" 'print(string.format("A=%d Q=%d X=%d H=%d B=%d", a, q, x, h, b))' >"$dir/b.lua"
    printf 'A A& %%d\nQ Q& %%d\nX X& %%d\nH H& %%d\nB B& %%d\n' >"$dir/results"
    lua_out="$(lua5.4 "$dir/b.lua")"
    pacer_out="$(pacer_results "$dir")"
    if [ "$pacer_out" != "$lua_out" ]; then
        echo "MISMATCH in $name: pacer $pacer_out, Lua $lua_out" >&2
        exit 1
    fi
    for _ in $(seq "$RUNS"); do
        keep "pacer $name" "$(seconds "$PACER" run -q "$dir")"
        keep "lua $name" "$(seconds lua5.4 "$dir/b.lua")"
    done
    awk -v name="$name" -v p="${best[pacer $name]}" -v l="${best[lua $name]}" 'BEGIN {
        printf "| %-10s | %9.3f | %9.3f | %9.2f |\n", name, p, l, (l > 0) ? p / l : 0 }'
done

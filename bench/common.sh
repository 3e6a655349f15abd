# Shared by bench/run.sh and bench/int_parts.sh (sourced, not run): the tools they need, pacer's
# results in the format Lua and Python print theirs, and wall-clock timing. The caller sets
# PACER (the pacer binary) and runs from the project root.

# Lua 5.4, installed from the distribution when missing.
need_lua() {
    if ! command -v lua5.4 >/dev/null 2>&1; then
        echo "installing Lua 5.4 ..." >&2
        local sudo=""
        if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
        $sudo apt-get update -qq
        $sudo apt-get install -y -qq lua5.4 >/dev/null
    fi
}

# Build pacer in release mode and say how its interpreter loop was compiled: one indirect jump
# per instruction handler when .cargo/config.toml's code generation took effect, a handful
# without it (docs/decisions.md, "The interpreter").
build_pacer() {
    echo "building pacer (release) ..." >&2
    cargo build --release --quiet
    if command -v objdump >/dev/null 2>&1; then
        local jumps
        jumps="$(objdump -d --no-show-raw-insn "$PACER" |
            awk '/<_ZN5pacer2vm4exec3run/,/^$/' | grep -c 'jmp  *\*' || true)"
        echo "indirect jumps in the interpreter loop: $jumps" >&2
    fi
}

# pacer's results for machine folder $1, formatted as Lua and Python print theirs: its
# `results` file names them, a line each (NAME, variable, printf format).
pacer_results() {
    local dir="$1" csv signals
    csv="$(mktemp)"
    signals="$(awk '{ print $2 }' "$dir/results" | paste -sd, -)"
    "$PACER" run -q "$dir" --csv "$csv" --signals "$signals" >/dev/null
    tail -n 1 "$csv" | awk -F, -v spec="$dir/results" '{
        n = 0
        while ((getline line < spec) > 0) {
            split(line, f, " ")
            n++
            out = out (n > 1 ? " " : "") f[1] "=" sprintf(f[3], $(n + 2))
        }
        print out
    }'
    rm -f "$csv"
}

# seconds CMD...: the wall clock time of one run, output discarded; a failing run stops the
# script (a time of a run that failed would be compared as if it had done the work).
seconds() {
    local start end
    start=$(date +%s.%N)
    "$@" >/dev/null || { echo "failed: $*" >&2; exit 1; }
    end=$(date +%s.%N)
    awk -v s="$start" -v e="$end" 'BEGIN { printf "%.3f", e - s }'
}

declare -A best
# keep KEY SECONDS: the least so far, in best[KEY].
keep() {
    if [ -z "${best[$1]:-}" ] || awk -v t="$2" -v b="${best[$1]}" 'BEGIN { exit !(t < b) }'; then
        best[$1]=$2
    fi
}

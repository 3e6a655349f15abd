#!/usr/bin/env bash
# The real-time runner (issues 8 and 22), three measurements:
#  1. the labeler on real I/O: `pacer run programs/labeling --io modbus://127.0.0.1:PORT` against
#     the pymodbus server of the tests, 1 ms updates for PACER_IO_SECONDS (default 60): requests
#     per update of the labeler's map, start jitter p50/p99/max, worst update time, overruns;
#  2. the checkweigher as it is, through a 2 s stall, exception answers and a server restart,
#     with a `cargo build` beside it (bench/io_faults.py): exchange cycle and update jitter;
#  3. the pacing alone (no network): the same kind of plan on the in-memory device for
#     PACER_PACE_SECONDS (default 60).
set -euo pipefail
cd "$(dirname "$0")/.."
export PACER_PYTOOLS="$PWD/target/pytools"
if ! PYTHONPATH="$PACER_PYTOOLS" python3 -c \
    'import importlib.metadata as m, sys; sys.exit(m.version("pymodbus") != "3.16.1")' 2>/dev/null; then
    python3 -m pip install --quiet --disable-pip-version-check --root-user-action=ignore \
        --upgrade --target "$PACER_PYTOOLS" pymodbus==3.16.1
fi
cargo build --release --locked
echo "== the labeler on Modbus TCP (pymodbus, 127.0.0.1)"
PYTHONPATH="$PACER_PYTOOLS" python3 bench/io_modbus.py
echo "== the checkweigher on Modbus TCP through a stall, busy answers and a restart, a cargo build beside it"
PYTHONPATH="$PACER_PYTOOLS" python3 bench/io_faults.py
echo "== pacing alone (in-memory device)"
cargo bench --bench io_pace

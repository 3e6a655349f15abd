#!/usr/bin/env bash
# The whole test suite, from a fresh machine: installs what the tests need, then checks
# formatting and lints, and runs every test.
set -euo pipefail
cd "$(dirname "$0")/.."

# Rust components used below (present on the standard toolchain; added if missing).
rustup component add rustfmt clippy >/dev/null 2>&1 || true

# pyvcd, the independent VCD parser tests/export_vcd.rs reads pacer's VCD with: pinned, and
# installed beside the build (target/pytools), not into the system's Python.
export PACER_PYTOOLS="$PWD/target/pytools"
if ! PYTHONPATH="$PACER_PYTOOLS" python3 -c \
    'import importlib.metadata as m, sys; sys.exit(m.version("pyvcd") != "0.5.1")' 2>/dev/null; then
    python3 -m pip install --quiet --disable-pip-version-check --root-user-action=ignore \
        --upgrade --target "$PACER_PYTOOLS" pyvcd==0.5.1
fi
# pymodbus, the independent Modbus TCP server the test peer tests/peers/modbus_server.py runs:
# pinned, installed beside pyvcd.
if ! PYTHONPATH="$PACER_PYTOOLS" python3 -c \
    'import importlib.metadata as m, sys; sys.exit(m.version("pymodbus") != "3.16.1")' 2>/dev/null; then
    python3 -m pip install --quiet --disable-pip-version-check --root-user-action=ignore \
        --upgrade --target "$PACER_PYTOOLS" pymodbus==3.16.1
fi

# A clean clone builds once: incremental state would only take disk (1.8 GB of it).
export CARGO_INCREMENTAL=0
df -h . | tail -1 | awk '{print "disk before the build: " $4 " free"}'

cargo fmt --all -- --check
cargo clippy --all-targets --locked -- -D warnings
cargo test --locked
du -sh target | awk '{print "build output: " $1}'

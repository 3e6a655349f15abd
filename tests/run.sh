#!/usr/bin/env bash
# The whole test suite, from a fresh machine: installs what the tests need, then checks
# formatting and lints, and runs every test.
set -euo pipefail
cd "$(dirname "$0")/.."

# Rust components used below (present on the standard toolchain; added if missing).
rustup component add rustfmt clippy >/dev/null 2>&1 || true

cargo fmt --all -- --check
cargo clippy --all-targets --locked -- -D warnings
cargo test --locked

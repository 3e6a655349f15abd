#!/usr/bin/env bash
# Pacing of the real-time runner (issue 8): a 1 ms update for PACER_PACE_SECONDS (default 60)
# running the labeler's Modbus poll plan against the in-memory device. Prints jitter
# p50/p99/max, requests per update and the worst update time.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo bench --bench io_pace

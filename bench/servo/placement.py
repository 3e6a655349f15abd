#!/usr/bin/env python3
"""Label placement error of programs/labeling-servo against line speed, with and without
velocity feedforward: the labeler's three programs on its servo, at constant line speeds.

The placement error of a label is the feedback position less the command position at the update
Index.0 (the label feed) ends, from the `feedback` the trace's `motion` `done` events carry with a
servo model: where the web really is when the label should be complete. Also the largest
|FollowingError| of each run, from the CSV export.

    python3 bench/servo/placement.py            # PACER=path/to/pacer (default: the release build)
"""
import csv
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
TARGET = os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))
PACER = os.environ.get("PACER", os.path.join(TARGET, "release", "pacer"))
SPEEDS = [5, 10, 20, 30, 45]
PRODUCTS = 200

SCENARIO = """[run]
duration = {duration}
seed = 2026

[master]
speed = {speed}

[[products]]
sensor = "ModuleInput.2"
first = 30.0
pitch = 1.0
length = 0.2
jitter = 0.2
count = {count}

[[axis_marks]]
sensor = "DriveInput.1"
first = 1.0
width = 1000000.0

[[press]]
name = "ModuleInput.1"
at = 0.01
length = 0.05
"""


def run(folder, speed, feedforward):
    machine = open(os.path.join(ROOT, "programs/labeling-servo/machine.toml")).read()
    machine, n = re.subn(r"(?m)^velocity_feedforward = [0-9.]+",
                         f"velocity_feedforward = {feedforward:.1f}", machine)
    assert n == 1, "the machine file sets velocity_feedforward once"
    open(os.path.join(folder, "machine.toml"), "w").write(machine)
    duration = (30.0 + PRODUCTS + 12.0) / speed + 1.0
    open(os.path.join(folder, "scenario.toml"), "w").write(
        SCENARIO.format(duration=duration, speed=float(speed), count=PRODUCTS))
    trace = os.path.join(folder, "t.jsonl")
    data = os.path.join(folder, "c.csv")
    subprocess.run([PACER, "run", "-q", folder, "--trace", trace, "--csv", data,
                    "--signals", "FollowingError"], check=True)
    errors = []
    with open(trace) as f:
        for line in f:
            e = json.loads(line)
            if (e["kind"] == "motion" and e.get("object") == "Index.0"
                    and e.get("event") == "done"):
                errors.append(e["feedback"] - e["position"])
    with open(data) as f:
        worst = max(abs(float(r["FollowingError"])) for r in csv.DictReader(f))
    return errors, worst


def main():
    folder = tempfile.mkdtemp()
    try:
        for name in ("program0.pt", "program1.pt", "program2.pt"):
            shutil.copy(os.path.join(ROOT, "programs/labeling-servo", name), folder)
        print("| line speed (units/s) | velocity feedforward | labels | placement error: mean | "
              "worst | largest \\|FollowingError\\| |")
        print("|---:|---:|---:|---:|---:|---:|")
        for feedforward in (0.0, 100.0):
            for speed in SPEEDS:
                errors, worst = run(folder, speed, feedforward)
                if not errors:
                    print(f"no labels at {speed}", file=sys.stderr)
                    continue
                mean = sum(errors) / len(errors)
                far = max(errors, key=abs)
                print(f"| {speed} | {feedforward:.0f} % | {len(errors)} | {mean:+.4f} | "
                      f"{far:+.4f} | {worst:.4f} |")
    finally:
        shutil.rmtree(folder)


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Label placement error of programs/labeling-servo against line speed, with and without
velocity feedforward: the labeler's three programs on its servo, at constant line speeds.

The placement error of a label is the feedback position less the command position at the update
Index.0 (the label feed) ends, from the `feedback` the trace's `motion` `done` events carry with a
servo model: where the web really is when the label should be complete. Also the largest
|FollowingError| of each run, from the CSV export.

    python3 bench/servo/placement.py            # PACER=path/to/pacer (default: the release build)
    python3 bench/servo/placement.py --svg docs/servo-placement.svg   # and draw it
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


def svg(rows, path):
    """Placement error (mean) and largest |FollowingError| against line speed, with and without
    velocity feedforward, as a small SVG line chart."""
    w, h, left, right, top, bottom = 760, 360, 70, 250, 30, 50
    xs = [r[0] for r in rows]
    ys = [v for r in rows for v in (r[3], r[5])]
    x0, x1 = 0.0, max(xs)
    y0, y1 = min(0.0, min(ys)), max(ys)
    pad = 0.05 * (y1 - y0)
    y0, y1 = y0 - pad, y1 + pad

    def px(x):
        return left + (x - x0) / (x1 - x0) * (w - left - right)

    def py(y):
        return top + (y1 - y) / (y1 - y0) * (h - top - bottom)

    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" '
           f'font-family="sans-serif" font-size="11">',
           f'<rect width="{w}" height="{h}" fill="white"/>',
           f'<text x="{left}" y="18" font-size="13">labeling-servo: label placement error and '
           'following error against line speed</text>']
    step = 0.05
    k = int(y0 / step) - 1
    while k * step <= y1:
        y = k * step
        if y >= y0:
            out.append(f'<line x1="{left}" x2="{w - right}" y1="{py(y):.1f}" y2="{py(y):.1f}" '
                       f'stroke="{"#888" if k == 0 else "#ddd"}"/>')
            out.append(f'<text x="{left - 6}" y="{py(y) + 4:.1f}" text-anchor="end">{y:+.2f}</text>')
        k += 1
    for x in xs:
        out.append(f'<line x1="{px(x):.1f}" x2="{px(x):.1f}" y1="{top}" y2="{h - bottom}" '
                   'stroke="#eee"/>')
        out.append(f'<text x="{px(x):.1f}" y="{h - bottom + 16}" text-anchor="middle">{x}</text>')
    out.append(f'<text x="{(left + w - right) / 2}" y="{h - 12}" text-anchor="middle">'
               'line speed, units/s</text>')
    out.append(f'<text x="16" y="{(top + h - bottom) / 2}" text-anchor="middle" '
               f'transform="rotate(-90 16 {(top + h - bottom) / 2})">units of web</text>')
    series = [
        ("placement error, no feedforward", 0.0, 3, "#c0392b", ""),
        ("placement error, 100 % feedforward", 100.0, 3, "#2471a3", ""),
        ("largest |FollowingError|, no feedforward", 0.0, 5, "#c0392b", "5,4"),
        ("largest |FollowingError|, 100 % feedforward", 100.0, 5, "#2471a3", "5,4"),
    ]
    for n, (name, ff, col, colour, dash) in enumerate(series):
        pts = [(px(r[0]), py(r[col])) for r in rows if r[1] == ff]
        path_d = " ".join(f"{x:.1f},{y:.1f}" for x, y in pts)
        dashes = f' stroke-dasharray="{dash}"' if dash else ""
        out.append(f'<polyline points="{path_d}" fill="none" stroke="{colour}" '
                   f'stroke-width="2"{dashes}/>')
        for x, y in pts:
            out.append(f'<circle cx="{x:.1f}" cy="{y:.1f}" r="3" fill="{colour}"/>')
        ly = top + 10 + 18 * n
        out.append(f'<line x1="{w - right + 10}" x2="{w - right + 34}" y1="{ly}" y2="{ly}" '
                   f'stroke="{colour}" stroke-width="2"{dashes}/>')
        out.append(f'<text x="{w - right + 38}" y="{ly + 4}" font-size="9">{name}</text>')
    out.append("</svg>")
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


def main():
    draw = sys.argv[2] if len(sys.argv) == 3 and sys.argv[1] == "--svg" else None
    rows = []
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
                rows.append((speed, feedforward, len(errors), mean, far, worst))
    finally:
        shutil.rmtree(folder)
    if draw:
        svg(rows, draw)


if __name__ == "__main__":
    main()

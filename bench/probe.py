"""Time the programs of bench/probe against Lua 5.4 (see bench/probe.sh).

Usage: probe.py PACER RUNS [NAME ...]
"""
import math
import os
import re
import resource
import subprocess
import sys
import tempfile

NUMBER = re.compile(r"-?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?")


def numbers(text):
    return [float(x) for x in NUMBER.findall(text)]


def pacer_output(pacer, folder):
    """What the program prints, or (a folder with a `signals` file) the last values of the
    variables it names, read from a CSV."""
    signals = os.path.join(folder, "signals")
    if not os.path.exists(signals):
        return subprocess.run([pacer, "run", "-q", folder], capture_output=True, text=True,
                              check=True).stdout
    with open(signals) as f:
        names = f.read().strip()
    with tempfile.TemporaryDirectory() as tmp:
        csv = os.path.join(tmp, "out.csv")
        subprocess.run([pacer, "run", "-q", folder, "--csv", csv, "--signals", names],
                       capture_output=True, text=True, check=True)
        with open(csv) as f:
            last = f.read().strip().splitlines()[-1]
    # The first columns are the time and the update.
    return " ".join(last.split(",")[2:])


def cpu(cmd):
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run(cmd, stdout=subprocess.DEVNULL, check=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def main():
    pacer, runs, names = sys.argv[1], int(sys.argv[2]), sys.argv[3:]
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "probe")
    names = names or sorted(os.listdir(root))
    print(f"| probe      |   pacer |     Lua | pacer/Lua |")
    print(f"|------------|--------:|--------:|----------:|")
    worst = 0.0
    for name in names:
        folder = os.path.join(root, name)
        lua_script = os.path.join(folder, "bench.lua")
        got = numbers(pacer_output(pacer, folder))
        want = numbers(subprocess.run(["lua5.4", lua_script], capture_output=True, text=True,
                                      check=True).stdout)
        # MotionBASIC prints a SINGLE with 7 significant digits.
        same = len(got) == len(want) and all(
            math.isclose(a, b, rel_tol=1e-6, abs_tol=1e-9) for a, b in zip(got, want))
        if not same:
            sys.exit(f"{name}: pacer gives {got}, Lua {want}")
        best_p = best_l = math.inf
        for _ in range(runs):
            best_p = min(best_p, cpu([pacer, "run", "-q", folder]))
            best_l = min(best_l, cpu(["lua5.4", lua_script]))
        ratio = best_p / best_l
        worst = max(worst, ratio)
        print(f"| {name:10s} | {best_p:5.3f} s | {best_l:5.3f} s | {ratio:9.2f} |", flush=True)
    print(f"worst pacer/Lua: {worst:.2f} (best of {runs} CPU times each; results checked equal)")


if __name__ == "__main__":
    main()

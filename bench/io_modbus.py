#!/usr/bin/env python3
"""The labeler on real I/O (issue 8): `pacer run programs/labeling --io modbus://…` in real time,
1 ms updates, against the pymodbus server of the tests (tests/peers/modbus_server.py) on
127.0.0.1, for PACER_IO_SECONDS (default 60). The script plays the machine: it switches the
start input on, then the product sensor 10 times a second, so the programs capture, queue
and label while the updates are timed. It prints pacer's own end-of-run summary: requests per
update of the labeler's map, jitter p50/p99/max against the absolute deadlines, the worst
update time, overruns; then the products shown and the labels the programs applied. The
labeler's machine file is used as it is but for `overrun_limit = 0`, so a streak of slow answers
from the Python server does not end the measurement.

Run with `bash bench/io.sh` (which builds pacer and installs pymodbus like tests/run.sh).
"""

import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SECONDS = float(os.environ.get("PACER_IO_SECONDS", "60"))


def main() -> int:
    peer = subprocess.Popen(
        [sys.executable, str(ROOT / "tests/peers/modbus_server.py"), "--port", "0"],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        text=True,
    )

    def cmd(line: str) -> dict:
        assert peer.stdin and peer.stdout
        peer.stdin.write(line + "\n")
        peer.stdin.flush()
        return json.loads(peer.stdout.readline())

    assert peer.stdout
    port = json.loads(peer.stdout.readline())["ready"]
    with tempfile.TemporaryDirectory() as tmp:
        # The labeler as it is, but with no overrun limit: a measurement must not stop at the
        # first streak of slow answers from a Python server.
        folder = Path(tmp) / "labeling"
        shutil.copytree(ROOT / "programs/labeling", folder)
        machine = (folder / "machine.toml").read_text()
        assert 'timeout = "20ms"\n' in machine
        machine = machine.replace('timeout = "20ms"\n', 'timeout = "20ms"\noverrun_limit = 0\n')
        (folder / "machine.toml").write_text(machine)
        trace = Path(os.environ.get("PACER_IO_TRACE", Path(tmp) / "labeling.trace.jsonl"))
        run = subprocess.Popen(
            [
                str(ROOT / "target/release/pacer"),
                "run",
                str(folder),
                "--io",
                f"modbus://127.0.0.1:{port}",
                "--for",
                str(SECONDS),
                "--trace",
                str(trace),
            ],
            cwd=ROOT,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        while cmd("requests")["requests"] == 0 and run.poll() is None:
            time.sleep(0.01)
        # ModuleInput.1 (input 6) starts Program 0, which homes on the web's reference sensor
        # DriveInput.1 (input 0): shown once. Then the product sensor, ModuleInput.2 (input
        # 7): on for 20 ms every 100 ms.
        cmd("set di 6 1")
        time.sleep(0.3)
        cmd("set di 0 1")
        time.sleep(0.05)
        cmd("set di 0 0")
        start = time.monotonic()
        products = 0
        while run.poll() is None and time.monotonic() - start < SECONDS + 5:
            cmd("set di 7 1")
            time.sleep(0.02)
            cmd("set di 7 0")
            # Drain the server's request log: left to grow, its garbage collection pauses the
            # Python server past the labeler's 20 ms timeout.
            cmd("log")
            products += 1
            time.sleep(0.08)
        out, err = run.communicate()
        requests = cmd("requests")["requests"]
        labels = sum(
            1
            for line in trace.read_text().splitlines()
            if '"kind":"motion","object":"Index.0","event":"start"' in line
        )
    cmd("quit")
    peer.wait()
    sys.stdout.write(out)
    sys.stderr.write(err)
    print(
        f"bench: {SECONDS:g} s on 127.0.0.1:{port} (pymodbus); {products} products shown to "
        f"the sensor, {labels} labels applied; the server answered {requests} requests"
    )
    return run.returncode


if __name__ == "__main__":
    sys.exit(main())

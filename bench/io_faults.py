#!/usr/bin/env python3
"""The checkweigher on real I/O through faults (issue 22): `pacer run programs/checkweigher
--io modbus://…` exactly as the example is (its overrun limit of 10 included), 1 ms updates, for
PACER_IO_SECONDS (default 60), against the pymodbus server of the tests on 127.0.0.1, with a
`cargo build --release` of pacer running beside it (into target/io-load, started from clean, so
it compiles for the whole run; PACER_IO_LOAD=0 leaves it out).

The script plays the line: a product on the scale every 400 ms, and at 1/6, 2/6 and 3/6 of the
run a 2 s stall of the server, 1 s of exception answers ("server device busy"), and the server
killed and restarted 300 ms later. It prints pacer's own end-of-run summary (the `exchange:`
line: the exchange cycle p50/p99/max; the `timing:` line: the update deadline jitter), then the
faults and reconnections in the trace, and exits non-zero when pacer did not end with exit 0 or
reported a real-time fault.

Run with `bash bench/io.sh` (which builds pacer and installs pymodbus like tests/run.sh).
"""

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SECONDS = float(os.environ.get("PACER_IO_SECONDS", "60"))
LOAD = os.environ.get("PACER_IO_LOAD", "1") != "0"


class Peer:
    """The pymodbus test server, driven over its stdin/stdout."""

    def __init__(self, port: int) -> None:
        self.proc = subprocess.Popen(
            [sys.executable, str(ROOT / "tests/peers/modbus_server.py"), "--port", str(port)],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            text=True,
        )
        assert self.proc.stdout
        self.port = json.loads(self.proc.stdout.readline())["ready"]

    def cmd(self, line: str) -> dict:
        assert self.proc.stdin and self.proc.stdout
        self.proc.stdin.write(line + "\n")
        self.proc.stdin.flush()
        return json.loads(self.proc.stdout.readline())

    def kill(self) -> None:
        self.proc.kill()
        self.proc.wait()


def main() -> int:
    load = None
    if LOAD:
        subprocess.run(["rm", "-rf", str(ROOT / "target/io-load/release")], check=False)
        load = subprocess.Popen(
            ["cargo", "build", "--release", "--quiet"],
            cwd=ROOT,
            env={**os.environ, "CARGO_TARGET_DIR": str(ROOT / "target/io-load")},
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
    peer = Peer(0)
    port = peer.port
    peer.cmd("set ir 0 2475")
    with tempfile.TemporaryDirectory() as tmp:
        trace = Path(tmp) / "checkweigher.jsonl"
        run = subprocess.Popen(
            [
                str(ROOT / "target/release/pacer"),
                "run",
                str(ROOT / "programs/checkweigher"),
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
        start = time.monotonic()
        events = [
            (SECONDS / 6, "stall"),
            (2 * SECONDS / 6, "busy"),
            (3 * SECONDS / 6, "restart"),
        ]
        products = 0
        while run.poll() is None and time.monotonic() - start < SECONDS + 10:
            now = time.monotonic() - start
            if events and now >= events[0][0]:
                _, what = events.pop(0)
                if what == "stall":
                    peer.cmd("stall 2")
                    time.sleep(2)
                    peer.cmd("stall 0")
                elif what == "busy":
                    peer.cmd("busy on")
                    time.sleep(1)
                    peer.cmd("busy off")
                else:
                    peer.kill()
                    time.sleep(0.3)
                    peer = Peer(port)
                    peer.cmd("set ir 0 2475")
                continue
            peer.cmd("set di 0 1")
            time.sleep(0.2)
            peer.cmd("set di 0 0")
            peer.cmd("log")
            products += 1
            time.sleep(0.2)
        out, err = run.communicate()
        kinds: dict[str, int] = {}
        causes = []
        for line in trace.read_text().splitlines():
            e = json.loads(line)
            if e["kind"] in ("io_fault", "io_reconnect"):
                kinds[e["kind"]] = kinds.get(e["kind"], 0) + 1
            if e["kind"] == "io_fault":
                causes.append(f"  t={e['t']} {e['cause']}")
    peer.kill()
    if load is not None:
        load.kill()
        load.wait()
    sys.stdout.write(out)
    sys.stderr.write(err)
    print(
        f"bench: {SECONDS:g} s on 127.0.0.1:{port} (pymodbus), "
        f"{'with' if LOAD else 'without'} a cargo build beside it; {products} products shown; "
        f"exit {run.returncode}; {kinds.get('io_fault', 0)} io_fault, "
        f"{kinds.get('io_reconnect', 0)} io_reconnect:"
    )
    print("\n".join(causes))
    return 0 if run.returncode == 0 and "real-time fault" not in err else 1


if __name__ == "__main__":
    sys.exit(main())

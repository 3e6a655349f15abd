#!/usr/bin/env python3
"""Independent Modbus TCP test peer, built on pymodbus's own async TCP server.

Usage: modbus_server.py --port PORT [--size N]

Serves Modbus TCP on 127.0.0.1:PORT (PORT 0 picks a free port) for any unit id. Four tables
(coils "co", discrete inputs "di", holding registers "hr", input registers "ir"), each holding
Modbus protocol addresses 0..N-1 (the addresses a client puts on the wire), all initially 0.
A request touching an address >= N is answered by pymodbus with exception 2 (illegal data
address).

Once listening it prints one line {"ready": PORT} on stdout, then answers each command line
read from stdin with exactly one line of JSON on stdout:

    set co|di|hr|ir ADDR V...   -> {"ok": true}        (not logged: only client requests are)
    get co|di|hr|ir ADDR COUNT  -> {"co": [...]} etc.
    log                         -> {"log": [ENTRY, ...]} requests served since the last `log`
    stall SECONDS               -> {"ok": true}        answer each client request SECONDS
                                                       after its arrival (0: at once)
    requests                    -> {"requests": TOTAL} requests served since start
    busy on|off                 -> {"ok": true}        answer every client request with
                                                       exception 6 (server device busy) or not
    quit                        -> {"ok": true}, then exit 0 (EOF on stdin exits 0 as well)
    anything malformed          -> {"error": "message"}

A log ENTRY is one per client request, in arrival order:
    {"op": "read", "table": T, "start": A, "count": C}          function codes 1, 2, 3, 4
    {"op": "write", "table": T, "start": A, "values": [...]}    function codes 5, 6, 15, 16
    {"op": "other", "fc": F}                                    any other function code
plus "exception": CODE when the request was answered with a Modbus exception.

The command reader runs on its own thread, so it keeps answering while the server is stalled.
"""

from __future__ import annotations

import argparse
import asyncio
import json
import logging
import math
import os
import sys
import threading
import time

from pymodbus import pymodbus_apply_logging_config
from pymodbus.constants import ExcCodes
from pymodbus.datastore import ModbusServerContext
from pymodbus.pdu import ExceptionResponse
from pymodbus.server import ModbusTcpServer
from pymodbus.server.requesthandler import ServerRequestHandler

TABLES = ("co", "di", "hr", "ir")
BIT_TABLES = ("co", "di")

# Function code -> table it reads or writes.
READ_FC = {1: "co", 2: "di", 3: "hr", 4: "ir"}
WRITE_FC = {5: "co", 15: "co", 6: "hr", 16: "hr"}
# Function codes pymodbus hands to the datastore (22 mask write and 23 read/write work on hr).
DATASTORE_FC = {**READ_FC, **WRITE_FC, 22: "hr", 23: "hr"}


class Tables(ModbusServerContext):
    """The datastore: four plain lists indexed by protocol address, guarded by one lock.

    pymodbus 3.16.1 turns its own datastores into a SimCore whose bit tables are sized in
    16-bit steps; this context keeps one slot per address instead, so that every address >= N
    is rejected. The server uses a ModbusServerContext whose `old_simulator` is set as the
    datastore itself, calling only async_getValues / async_setValues / device_ids. The base
    __init__ is deliberately not called: it only wraps device contexts (and logs a deprecation
    warning), none of which this context has.
    """

    def __init__(self, size: int) -> None:  # pylint: disable=super-init-not-called
        self.simdevices: list = []
        self.old_simulator = True
        self.size = size
        self.busy = False
        self.lock = threading.Lock()
        self.data = {table: [0] * size for table in TABLES}

    def device_ids(self) -> list[int]:
        """Device ids (only used by pymodbus for broadcasts, which are off)."""
        return [0]

    def _range_ok(self, address: int, count: int) -> bool:
        return 0 <= address and 0 <= count and address + count <= self.size

    async def async_getValues(self, device_id, func_code, address, count=1):
        """Read for a client request (any device id)."""
        table = DATASTORE_FC.get(func_code)
        if table is None:
            return ExcCodes.ILLEGAL_FUNCTION
        if self.busy:
            return ExcCodes.DEVICE_BUSY
        if not self._range_ok(address, count):
            return ExcCodes.ILLEGAL_ADDRESS
        with self.lock:
            values = self.data[table][address : address + count]
        if table in BIT_TABLES:
            return [bool(v) for v in values]
        return values

    async def async_setValues(self, device_id, func_code, address, values):
        """Write for a client request (any device id)."""
        table = DATASTORE_FC.get(func_code)
        if table is None or table not in ("co", "hr"):
            return ExcCodes.ILLEGAL_FUNCTION
        if self.busy:
            return ExcCodes.DEVICE_BUSY
        values = list(values)
        if not self._range_ok(address, len(values)):
            return ExcCodes.ILLEGAL_ADDRESS
        if table in BIT_TABLES:
            values = [1 if v else 0 for v in values]
        elif not all(0 <= int(v) <= 0xFFFF for v in values):
            return ExcCodes.ILLEGAL_VALUE
        with self.lock:
            self.data[table][address : address + len(values)] = [int(v) for v in values]
        return None

    # Access from the command thread (protocol addresses, no logging).
    def get(self, table: str, address: int, count: int) -> list[int]:
        with self.lock:
            return list(self.data[table][address : address + count])

    def set(self, table: str, address: int, values: list[int]) -> None:
        with self.lock:
            self.data[table][address : address + len(values)] = values


class Monitor:
    """Request log, request counter and stall setting.

    Logging uses pymodbus's trace_pdu hook: trace_pdu(False, request) runs when a request has
    been decoded, trace_pdu(True, response) when its answer is about to be sent. A request is
    logged (and counted) when its answer goes out, with "exception" if the answer is an
    exception response. Entries are built from the request PDU, so pymodbus's internal
    read-backs (e.g. after a single-coil write) never show up as extra entries.
    """

    def __init__(self, loop: asyncio.AbstractEventLoop) -> None:
        self.loop = loop
        self.lock = threading.Lock()
        self.pending: list[tuple[tuple[int, int, int], dict]] = []
        self.log: list[dict] = []
        self.total = 0
        self.stall_seconds = 0.0
        self.stall_changed = asyncio.Event()  # replaced on every change (event loop only)

    @staticmethod
    def describe(pdu) -> dict:
        fc = pdu.function_code
        if fc in READ_FC:
            return {"op": "read", "table": READ_FC[fc], "start": pdu.address, "count": pdu.count}
        if fc in (5, 15):
            values = [1 if b else 0 for b in pdu.bits]
            return {"op": "write", "table": "co", "start": pdu.address, "values": values}
        if fc in (6, 16):
            values = [int(r) for r in pdu.registers]
            return {"op": "write", "table": "hr", "start": pdu.address, "values": values}
        return {"op": "other", "fc": fc}

    def set_stall(self, seconds: float) -> None:
        """Change the stall (command thread); wakes requests already waiting."""
        self.stall_seconds = seconds
        self.loop.call_soon_threadsafe(self._stall_changed)

    def _stall_changed(self) -> None:
        self.stall_changed.set()
        self.stall_changed = asyncio.Event()

    async def wait_stall(self, arrival: float) -> None:
        """Wait until `arrival` + the stall (re-read whenever `stall` changes) has passed."""
        while (remaining := arrival + self.stall_seconds - time.monotonic()) > 0:
            changed = self.stall_changed
            try:
                await asyncio.wait_for(changed.wait(), remaining)
            except asyncio.TimeoutError:
                pass

    def trace_pdu(self, sending: bool, pdu):
        try:
            if not sending:
                key = (pdu.dev_id, pdu.transaction_id, pdu.function_code)
                with self.lock:
                    self.pending.append((key, self.describe(pdu)))
            else:
                fc = pdu.function_code & 0x7F
                key = (pdu.dev_id, pdu.transaction_id, fc)
                with self.lock:
                    entry = None
                    for i, (pending_key, pending_entry) in enumerate(self.pending):
                        if pending_key == key:
                            entry = pending_entry
                            del self.pending[i]
                            break
                    if entry is None:  # a request pymodbus could not decode
                        entry = {"op": "other", "fc": fc}
                    if isinstance(pdu, ExceptionResponse):
                        entry["exception"] = int(pdu.exception_code)
                    self.log.append(entry)
                    self.total += 1
        except Exception as exc:  # pylint: disable=broad-except
            print(f"modbus_server.py: trace_pdu: {exc!r}", file=sys.stderr, flush=True)
        return pdu

    def forget(self, pdu) -> None:
        """Drop a request that will not be answered (its connection closed first)."""
        key = (pdu.dev_id, pdu.transaction_id, pdu.function_code)
        with self.lock:
            for i, (pending_key, _entry) in enumerate(self.pending):
                if pending_key == key:
                    del self.pending[i]
                    break

    def take_log(self) -> list[dict]:
        with self.lock:
            log, self.log = self.log, []
        return log

    def requests(self) -> int:
        with self.lock:
            return self.total


class PeerRequestHandler(ServerRequestHandler):
    """pymodbus's per-connection request handler, with requests queued instead of raced.

    In pymodbus 3.16.1 the handler keeps only the newest decoded request (`last_pdu`), handles
    it from a task started two loop turns later, handles one frame per received chunk, and
    clears its receive buffer whenever it sends. Requests that follow each other closely
    (a client retrying after a timeout while the server is stalled) then get lost, answered
    twice, or answered with the wrong transaction id. Here every frame of a chunk is decoded
    at once and queued with its arrival time; one task per connection answers them in order,
    each after the stall, through pymodbus's own handle_request. That never suspends (the
    datastore's coroutines do not await), so `last_pdu` stays the request being answered.
    """

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        self.queue: asyncio.Queue = asyncio.Queue()
        self.worker: asyncio.Task | None = None

    def callback_data(self, data: bytes, addr: tuple | None = None) -> int:
        used = 0
        while used < len(data):
            # Decodes one frame (or answers an undecodable one with exception 1).
            step = super().callback_data(data[used:], addr)
            if self.last_pdu:
                self.queue.put_nowait((self.last_pdu, self.last_addr, time.monotonic()))
                if self.worker is None:
                    self.worker = self.loop.create_task(self.work())
            if step <= 0:
                break
            used += step
        return used

    def handle_later(self) -> None:
        """Replaced by the queue (the base class would handle `last_pdu` whenever it runs)."""

    async def work(self) -> None:
        monitor: Monitor = self.server.monitor
        while True:
            pdu, addr, arrival = await self.queue.get()
            await monitor.wait_stall(arrival)
            if not self.transport:
                monitor.forget(pdu)
                continue
            self.last_pdu, self.last_addr = pdu, addr
            await self.handle_request()

    def send(self, data: bytes, addr: tuple | None = None) -> None:
        """Send, keeping any received bytes not yet decoded (the base class drops them)."""
        keep = self.recv_buffer
        super().send(data, addr)
        self.recv_buffer = keep

    def callback_disconnected(self, exc: Exception | None) -> None:
        super().callback_disconnected(exc)
        if self.worker is not None:
            self.worker.cancel()
            self.worker = None
        while not self.queue.empty():
            self.server.monitor.forget(self.queue.get_nowait()[0])


class PeerServer(ModbusTcpServer):
    """pymodbus's TCP server, with PeerRequestHandler for each connection."""

    def __init__(self, context, monitor: Monitor, **kwargs) -> None:
        super().__init__(context, **kwargs)
        self.monitor = monitor

    def callback_new_connection(self):
        return PeerRequestHandler(self, self.trace_packet, self.trace_pdu, self.trace_connect)


OUT_LOCK = threading.Lock()


def emit(obj) -> None:
    with OUT_LOCK:
        sys.stdout.write(json.dumps(obj) + "\n")
        sys.stdout.flush()


def parse_int(text: str, what: str) -> int:
    try:
        return int(text, 10)
    except ValueError:
        raise ValueError(f"{what} is not an integer: {text!r}") from None


def handle_command(line: str, tables: Tables, monitor: Monitor):
    """Run one command; return the JSON object to answer with."""
    words = line.split()
    if not words:
        raise ValueError("empty command")
    cmd, args = words[0], words[1:]
    if cmd in ("set", "get"):
        if len(args) < 2 or args[0] not in TABLES:
            raise ValueError(f"usage: {cmd} co|di|hr|ir ADDR ...")
        table = args[0]
        address = parse_int(args[1], "ADDR")
        if cmd == "get":
            if len(args) != 3:
                raise ValueError("usage: get co|di|hr|ir ADDR COUNT")
            count = parse_int(args[2], "COUNT")
            if address < 0 or count < 0 or address + count > tables.size:
                raise ValueError(f"range {address}+{count} outside 0..{tables.size - 1}")
            return {table: tables.get(table, address, count)}
        values = [parse_int(v, "value") for v in args[2:]]
        if not values:
            raise ValueError("usage: set co|di|hr|ir ADDR V1 V2 ...")
        if address < 0 or address + len(values) > tables.size:
            raise ValueError(f"range {address}+{len(values)} outside 0..{tables.size - 1}")
        limit = 1 if table in BIT_TABLES else 0xFFFF
        for v in values:
            if not 0 <= v <= limit:
                raise ValueError(f"value {v} outside 0..{limit}")
        tables.set(table, address, values)
        return {"ok": True}
    if cmd == "log" and not args:
        return {"log": monitor.take_log()}
    if cmd == "requests" and not args:
        return {"requests": monitor.requests()}
    if cmd == "stall" and len(args) == 1:
        try:
            seconds = float(args[0])
        except ValueError:
            raise ValueError(f"SECONDS is not a number: {args[0]!r}") from None
        if not math.isfinite(seconds) or seconds < 0:
            raise ValueError(f"SECONDS must be finite and >= 0: {args[0]!r}")
        monitor.set_stall(seconds)
        return {"ok": True}
    if cmd == "busy" and len(args) == 1 and args[0] in ("on", "off"):
        tables.busy = args[0] == "on"
        return {"ok": True}
    if cmd == "quit" and not args:
        return {"ok": True}
    raise ValueError(f"unknown or malformed command: {line.strip()!r}")


def command_loop(tables: Tables, monitor: Monitor) -> None:
    """Read stdin until `quit` or EOF, then end the whole process with status 0."""
    try:
        while line := sys.stdin.readline():
            try:
                answer = handle_command(line, tables, monitor)
            except Exception as exc:  # pylint: disable=broad-except
                answer = {"error": str(exc)}
            emit(answer)
            if line.split() == ["quit"]:
                break
    finally:
        # os._exit: ends at once, whatever the event loop is doing.
        sys.stdout.flush()
        os._exit(0)


async def serve(port: int, size: int) -> None:
    tables = Tables(size)
    monitor = Monitor(asyncio.get_running_loop())
    server = PeerServer(
        tables,
        monitor,
        address=("127.0.0.1", port),
        trace_pdu=monitor.trace_pdu,
    )
    # Listens via loop.create_server(..., reuse_address=True): immediate restart after kill -9.
    await server.serve_forever(background=True)
    bound_port = server.transport.sockets[0].getsockname()[1]
    emit({"ready": bound_port})
    threading.Thread(target=command_loop, args=(tables, monitor), daemon=True).start()
    await asyncio.Event().wait()  # the command thread ends the process


def main() -> None:
    parser = argparse.ArgumentParser(description="Modbus TCP test peer (pymodbus)")
    parser.add_argument("--port", type=int, required=True)
    parser.add_argument("--size", type=int, default=100)
    args = parser.parse_args()
    if not 0 <= args.port <= 65535:
        parser.error("--port must be 0..65535")
    if not 1 <= args.size <= 65536:
        parser.error("--size must be 1..65536")
    pymodbus_apply_logging_config(logging.WARNING)
    try:
        asyncio.run(serve(args.port, args.size))
    except Exception as exc:  # pylint: disable=broad-except
        print(f"modbus_server.py: {exc}", file=sys.stderr, flush=True)
        sys.exit(1)


if __name__ == "__main__":
    main()

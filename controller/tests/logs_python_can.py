#!/usr/bin/env python3
"""meter's ASC, BLF and TRC readers and its ASC and BLF writers against python-can (python3-can, the
independent reference), frame for frame, and `decode` of each format against the candump of the
same frames.

A slice of the real ft86 drive (candump -L) plus a few frames of every other kind (extended ids,
remote, error and CAN FD frames with BRS/ESI, a second channel) is written by python-can's own ASC,
BLF and TRC (2.1 and 1.0) writers; meter reads each (`convert-log X slice.log` gives its frames as
candump lines) and its frames must equal python-can's reading of the same file: time (to the
microsecond), id, extended, remote, error, FD, BRS, ESI, length, data bytes and channel. Then
meter's own ASC and BLF writers' files are read by python-can and must equal meter's frames.
Vector dates are local wall times: both sides run in one zone (Europe/Berlin, summer time then).

usage: logs_python_can.py METER_CONTROLLER FT86_LOG FT86_DBC [--frames N]
"""
import os
import subprocess
import sys
import tempfile
import time

os.environ["TZ"] = "Europe/Berlin" if os.path.exists("/usr/share/zoneinfo/Europe/Berlin") else "UTC"
time.tzset()

import can  # noqa: E402  (after the zone is set)
from can.io.trc import TRCFileVersion  # noqa: E402

# Frames of every kind the ft86 drive lacks, on can0 and can1, after the slice (seconds after its end).
EXTRA = [
    (0.001, "can1", "18FEF100#0102030405060708"),  # extended id, second channel
    (0.002, "can0", "7DF#R"),                      # remote, no length
    (0.003, "can1", "123#R4"),                     # remote, length 4
    (0.004, "can0", "20000080#0000000000000000"),  # error frame (bus error)
    (0.005, "can1", "3A0##1" + "11" * 12),         # CAN FD, BRS, 12 bytes
    (0.006, "can0", "1ABCDEF0##3" + "A5" * 64),    # CAN FD, BRS and ESI, extended, 64 bytes
    (0.007, "can1", "5F0##0" + "01" * 8),          # CAN FD without BRS, 8 bytes
    (0.008, "can0", "0D2#00"),                     # one byte
    (0.009, "can1", "100#"),                       # no data
]


def key(ts_us, channel, error, remote, arb_id, ext, fd, brs, esi, dlc, data):
    """One frame as compared: an error frame by its time and channel (its class is each tool's own)."""
    if error:
        return ("error", ts_us, channel)
    if remote:
        return ("remote", ts_us, channel, arb_id, ext, dlc)
    return ("data", ts_us, channel, arb_id, ext, fd, brs, esi, bytes(data))


def python_frames(messages, channel_base):
    out = []
    for m in messages:
        ch = m.channel
        ch = int(ch[3:]) if isinstance(ch, str) else (ch if ch is not None else 0) - channel_base
        out.append(key(round(m.timestamp * 1e6), ch, m.is_error_frame, m.is_remote_frame, m.arbitration_id,
                       m.is_extended_id, m.is_fd, m.bitrate_switch, m.error_state_indicator, m.dlc, m.data))
    return out


def candump_frames(text):
    """meter's frames as its candump writer prints them: (sec.usec) canN ID#DATA."""
    out = []
    for line in text.splitlines():
        ts, iface, frame = line.split()
        sec, usec = ts[1:-1].split(".")
        ts_us = int(sec) * 1000000 + int(usec)
        ident, data = frame.split("#", 1)
        raw = int(ident, 16)
        error = len(ident) == 8 and bool(raw & 0x20000000)
        fd = data.startswith("#")
        flags = int(data[1], 16) if fd else 0
        data = data[2:] if fd else data
        remote = data[:1] == "R"
        dlc = int(data[1:] or "0", 16) if remote else len(data) // 2
        out.append(key(ts_us, int(iface[3:]), error, remote, raw & 0x1FFFFFFF, len(ident) == 8, fd, bool(flags & 1),
                       bool(flags & 2), dlc, bytes.fromhex(data) if not remote else b""))
    return out


def meter(binary, *args):
    r = subprocess.run([binary, *args], capture_output=True, text=True)
    if r.returncode != 0:
        raise SystemExit(f"FAIL: meter-controller {' '.join(args)} exited {r.returncode}: {r.stderr.strip()[:2000]}")
    return r


def meter_frames(binary, path, work):
    out = os.path.join(work, "meter-frames.log")
    meter(binary, "convert-log", path, out)
    with open(out) as f:
        return candump_frames(f.read())


def same(a, b, tolerance_us):
    return a == b or (a[0] == b[0] and a[2:] == b[2:] and abs(a[1] - b[1]) <= tolerance_us)


def compare(what, got, want, failures, tolerance_us=0):
    if len(got) == len(want) and all(same(a, b, tolerance_us) for a, b in zip(got, want)):
        off = sum(a[1] != b[1] for a, b in zip(got, want))
        print(f"ok   {what}: {len(got)} frames equal" + (f" ({off} a microsecond apart)" if off else ""))
        return
    n = next((i for i, (a, b) in enumerate(zip(got, want)) if not same(a, b, tolerance_us)), min(len(got), len(want)))
    failures.append(what)
    print(f"FAIL {what}: meter {len(got)} frames, python-can {len(want)}; first difference at frame {n}:\n"
          f"     meter      {got[n] if n < len(got) else None}\n     python-can {want[n] if n < len(want) else None}")


def write_with(writer, messages):
    with writer as w:
        for m in messages:
            w.on_message_received(m)


def decode_rows(binary, dbc, path):
    """`decode` rows with each row's time taken from the first row's (the formats' clocks start apart)."""
    rows = meter(binary, "decode", "--dbc", dbc, path).stdout.splitlines()[1:]
    def us(ts):
        sec, frac = ts.split(".")
        return int(sec) * 1000000 + int(frac)
    t0 = us(rows[0].split(",", 1)[0])
    return [(us(r.split(",", 1)[0]) - t0, r.split(",", 1)[1]) for r in rows]


def main():
    binary, ft86, dbc = sys.argv[1:4]
    n = int(sys.argv[sys.argv.index("--frames") + 1]) if "--frames" in sys.argv else 3000
    failures = []
    with tempfile.TemporaryDirectory(prefix="meter-logs-") as work:
        with open(ft86) as f:
            lines = [next(f) for _ in range(n)]
        end = float(lines[-1].split()[0][1:-1])
        lines += [f"({end + dt:.6f}) {iface} {frame}\n" for dt, iface, frame in EXTRA]
        slice_log = os.path.join(work, "slice.log")
        with open(slice_log, "w") as f:
            f.writelines(lines)
        messages = list(can.CanutilsLogReader(slice_log))
        classic = [m for m in messages if not (m.is_fd or m.is_remote_frame or m.is_error_frame)]

        # python-can writes, meter reads.
        asc, blf, trc21, trc10 = (os.path.join(work, name) for name in ("py.asc", "py.blf", "py21.trc", "py10.trc"))
        write_with(can.ASCWriter(asc), messages)
        write_with(can.BLFWriter(blf), messages)
        write_with(can.TRCWriter(trc21), classic)  # its TRC writer leaves out FD, remote and error frames
        w = can.TRCWriter(trc10)
        w.file_version = TRCFileVersion.V1_0
        write_with(w, [m for m in classic if m.channel == "can0"])
        compare("ASC written by python-can", meter_frames(binary, asc, work),
                python_frames(can.ASCReader(asc, relative_timestamp=False), 0), failures)
        # python-can's BLF writer stores each time as (t - t0) in floating point, truncated to the
        # nanosecond (1 us is often 999 ns): meter keeps those nanoseconds and writes whole
        # microseconds as candump does, python-can's float rounds them; so the two may be 1 us apart.
        compare("BLF written by python-can", meter_frames(binary, blf, work), python_frames(can.BLFReader(blf), 0), failures, 1)
        # python-can's TRC reader gives the bus number itself (1..), not 0-based as for ASC and BLF.
        compare("TRC 2.1 written by python-can", meter_frames(binary, trc21, work), python_frames(can.TRCReader(trc21), 1), failures)
        compare("TRC 1.0 written by python-can", meter_frames(binary, trc10, work), python_frames(can.TRCReader(trc10), 1), failures)

        # meter writes, python-can reads.
        ours = meter_frames(binary, slice_log, work)
        compare("candump slice, meter vs python-can", ours, python_frames(messages, 0), failures)
        for ext in ("asc", "blf"):
            path = os.path.join(work, "meter." + ext)
            meter(binary, "convert-log", slice_log, path)
            reader = can.ASCReader(path, relative_timestamp=False) if ext == "asc" else can.BLFReader(path)
            compare(f"{ext.upper()} written by meter, read by python-can", python_frames(reader, 0), ours, failures)

        # decode of each format = decode of the candump of the same frames.
        want = decode_rows(binary, dbc, slice_log)
        for path in (asc, blf, trc21, os.path.join(work, "meter.asc"), os.path.join(work, "meter.blf")):
            got = decode_rows(binary, dbc, path)
            name = f"decode {os.path.basename(path)} = decode of the candump slice"
            slack = 1 if path == blf else 0  # python-can's nanoseconds, as above
            if len(got) == len(want) and all(g[1] == w[1] and abs(g[0] - w[0]) <= slack for g, w in zip(got, want)):
                print(f"ok   {name}: {len(got)} rows")
            else:
                failures.append(name)
                n = next((i for i, (a, b) in enumerate(zip(got, want)) if a[1] != b[1] or abs(a[0] - b[0]) > slack),
                         min(len(got), len(want)))
                print(f"FAIL {name}: {len(got)} rows vs {len(want)}; first difference at row {n}: "
                      f"{got[n] if n < len(got) else None} vs {want[n] if n < len(want) else None}")
    if failures:
        raise SystemExit(f"{len(failures)} comparison(s) failed: {', '.join(failures)}")


if __name__ == "__main__":
    main()

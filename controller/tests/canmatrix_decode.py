#!/usr/bin/python3
"""Decode a candump -L log with python3-canmatrix: the independent reference for the controller.

usage: canmatrix_decode.py DBC LOG [--every N] [--bench] [--dbc-length-only]
Writes CSV rows "timestamp,message,signal,physical" (like meter-controller decode, without raw,
unit and status). --every N decodes only every Nth frame; --bench prints "frames seconds" instead
(frames held in memory, timing covers decoding only); --dbc-length-only leaves out the frames
whose length is not their message's DBC size (canmatrix refuses to decode them).
"""
import sys
import time

import canmatrix.formats


def load_frames(path):
    frames = []
    with open(path) as f:
        for line in f:
            parts = line.split()
            if len(parts) < 3 or "#" not in parts[2]:
                continue
            ts = parts[0].strip("()")
            ident, data = parts[2].split("#", 1)
            if data.startswith("R") or data.startswith("#"):
                continue
            frames.append((ts, int(ident, 16), len(ident) == 8, bytes.fromhex(data.replace(".", ""))))
    return frames


def main():
    dbc, log = sys.argv[1], sys.argv[2]
    every = 1
    bench = "--bench" in sys.argv
    if "--every" in sys.argv:
        every = int(sys.argv[sys.argv.index("--every") + 1])
    db = list(canmatrix.formats.loadp(dbc).values())[0]
    frames = load_frames(log)[::every]
    by_id = {}
    for fr in db.frames:
        by_id[(fr.arbitration_id.id, fr.arbitration_id.extended)] = fr
    if "--dbc-length-only" in sys.argv:
        frames = [f for f in frames if (f[1], f[2]) not in by_id or len(f[3]) == by_id[(f[1], f[2])].size]
    if bench:
        t0 = time.perf_counter()
        n = 0
        for ts, ident, ext, data in frames:
            fr = by_id.get((ident, ext))
            if fr is None:
                continue
            fr.decode(data)
            n += 1
        print(n, time.perf_counter() - t0)
        return
    out = sys.stdout
    out.write("timestamp,message,signal,physical\n")
    for ts, ident, ext, data in frames:
        fr = by_id.get((ident, ext))
        if fr is None:
            continue
        for name, v in fr.decode(data).items():
            out.write("%s,%s,%s,%r\n" % (ts, fr.name, name, float(v.phys_value)))


main()

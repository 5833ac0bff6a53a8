"""CAN frame -> frame drawn, per gear step, from one end-to-end run (tests/vcan/e2e.py's Run: the
controller in the VM on vcan0, meter-view on the host, both with --trace). Shared by
bench/latency/run and the vcan latency test.

The stimulus is a window of the ft86 log with the gear field of every ID_141 frame rewritten to
step 1, 2, ... 6, 1, ... every `step` seconds; with `gear_only` every other frame is left out, so
the gear is the only value that changes (sparse changes: what a latency-aware view draws at once,
where a view on a fixed frame clock makes each change wait for its next tick). The gear readout is
a text the view draws exactly, so "the first frame showing the value" is the first frames.csv row
whose gear text is the new gear. Per step:

  rx -> decode     kernel SO_TIMESTAMPNS of the frame -> the controller's model has it
  decode -> set    -> the next model tick hands the changed output to the publisher (10 ms ticks)
  set -> sent      -> the link wrote the DELTA to the socket
  link             -> meter-view applied it (guest TCP, qemu user-net, host TCP)
  wait for frame   -> the view's next frame starts
  render           -> drawn and read back
  png              -> PNG written (every frame is dumped, on meter-view's writer thread)

Guest and host clocks: both traces are CLOCK_REALTIME, the link's send stamps CLOCK_MONOTONIC of
the guest (mapped by the controller trace's 'c' row). The guest's wall clock is only set from the
emulated RTC, so the host-guest offset is estimated as the smallest (view applied - sent) over the
run; the 'link' stage is therefore the time above the fastest transfer seen (the fastest one-way
time itself, under a millisecond on loopback, is folded into the offset). Stages on one side of
the link are exact.
"""
import csv
import os
import subprocess

import numpy as np

import vcanlib as v

GEAR_ID = 0x141          # ID_141: GEAR at bit 48, 4 bits, Intel (sample_can_spec.dbc)
GEAR_SIGNAL = 5          # protocol catalog id of Vehicle.Powertrain.Transmission.CurrentGear
STAMP_SLACK_NS = 5_000_000
STAGES = ["rx -> decode", "decode -> set", "set -> sent", "link", "wait for frame", "render", "png"]


def make_stimulus(out, start, seconds, step, gear_only=False):
    """The ft86 window with its gear field stepping; returns the path and [(rel_s, gear)] per
    ID_141 frame in play order."""
    window = os.path.join(out, "window.log")
    subprocess.run([os.path.join(v.SOURCE_DIR, "vcan", "replay"), "-o", window, "--start", str(start),
                    "--duration", str(seconds), v.FT86_LOG], check=True)
    path = os.path.join(out, "stimulus.log")
    gears = []
    t0 = None
    with open(window) as f, open(path, "w") as o:
        for line in f:
            ts, iface, frame = line.split()
            t = float(ts[1:-1])
            t0 = t if t0 is None else t0
            cid, _, data = frame.partition("#")
            if int(cid, 16) == GEAR_ID:
                b = bytearray.fromhex(data)
                gear = 1 + int((t - t0) / step) % 6
                b[6] = (b[6] & 0xF0) | gear
                data = b.hex().upper()
                gears.append((t - t0, gear))
            elif gear_only:
                continue
            o.write(f"{ts} {iface} {cid}#{data}\n")
    return path, gears


def read_rows(path):
    rows = []
    with open(path) as f:
        next(f)
        for line in f:
            rows.append(line.rstrip("\n").split(","))
    return rows


def pct(x, q):
    x = np.asarray(x, dtype=float)
    x = x[~np.isnan(x)]
    return float(np.percentile(x, q)) if len(x) else float("nan")


def measure(run, viewdir, gears, dumped_only=True):
    """Per gear step the stage durations in ms, columns STAGES + [to frame drawn, to PNG];
    returns (array, steps missed: coalesced in the controller or never seen in a dumped frame).
    dumped_only: the frame showing the step is the first DUMPED frame whose gear text is the new
    gear (every frame must be dumped: --dump-policy block). Otherwise it is the first frame that
    began after the change was applied (each frame draws the newest state), dumped or not (a
    --dump-policy drop run; its frames.csv row, when it has one, must show the gear); its PNG
    column is NaN when that frame was dropped."""
    ctrl = read_rows(os.path.join(run.out, "controller-trace-1.csv"))
    c = next(r for r in ctrl if r[0] == "c")
    real0, mono0 = int(c[1]), int(c[2])
    frames = [(int(r[1]), int(r[2])) for r in ctrl if r[0] == "f" and int(r[3]) == GEAR_ID]
    sets = [(int(r[1]), float(r[3])) for r in ctrl if r[0] == "p" and int(r[2]) == GEAR_SIGNAL]
    sent = np.array([int(r[1]) for r in ctrl if r[0] == "s"])
    view = read_rows(os.path.join(viewdir, "view-trace.csv"))
    applied = np.array([(int(r[1]), int(r[2]) - mono0 + real0) for r in view if r[0] == "a"])
    written = {int(r[2]): int(r[1]) for r in view if r[0] == "w"}
    renders = {int(r[2]): (int(r[1]), int(r[3]), written.get(int(r[2]), 0)) for r in view if r[0] == "r"}
    with open(os.path.join(viewdir, "frames.csv"), newline="") as f:
        gear_text = {int(r["frame"]): r["Text_Gear.text"] for r in csv.DictReader(f)}
    if len(frames) != len(gears):
        raise AssertionError(f"the controller saw {len(frames)} ID_141 frames, {len(gears)} were played")
    offset = int((applied[:, 0] - applied[:, 1]).min())     # host - guest, plus the fastest transfer

    steps, missed = [], 0
    frame_order = sorted(renders)
    for i in range(1, len(gears)):
        if gears[i][1] == gears[i - 1][1]:
            continue
        gear = gears[i][1]
        decoded, kernel = frames[i]
        # The first output the model set after the frame: another gear means a later step's frame
        # reached the same model tick (the guest stalled for a whole step): coalesced, never drawn.
        s = next(((t, x) for t, x in sets if t >= decoded), None)
        if s is None or s[1] != gear:
            missed += 1
            continue
        s = s[0]
        k = np.searchsorted(sent, s)
        # The DELTA's sender stamp is taken inside the publish that follows the set, but the 'p' row
        # is written after it and the guest's monotonic->realtime mapping ('c' row) is read once:
        # stamps come out up to a few ms before the set time. Without the slack a sparse change
        # (the only DELTA for hundreds of ms) was matched to the next step's DELTA.
        a = np.searchsorted(applied[:, 1], s - STAMP_SLACK_NS)
        if k >= len(sent) or a >= len(applied):
            missed += 1
            continue
        t_sent, t_applied = int(sent[k]), int(applied[a, 0]) - offset     # both on the guest clock now
        if dumped_only:
            shown = next((n for n in frame_order if renders[n][0] - offset >= t_applied and renders[n][2]
                          and gear_text.get(n) == str(gear)), None)
        else:
            shown = next((n for n in frame_order if renders[n][0] - offset >= t_applied), None)
            if shown is not None and gear_text.get(shown, str(gear)) != str(gear):
                shown = None   # the frame after the change does not show it: not this step's
        if shown is None:
            missed += 1
            continue
        upd, rend, png = (x - offset for x in renders[shown])
        if not renders[shown][2]:
            png = float("nan")
        steps.append([decoded - kernel, s - decoded, t_sent - s, t_applied - t_sent, upd - t_applied,
                      rend - upd, png - rend, rend - kernel, png - kernel])
    return np.array(steps) / 1e6, missed


def report(st, label):
    """The stage table as bench/latency prints it."""
    lines = [f"{label}: {'stage':<16} {'p50 ms':>8} {'p99 ms':>8} {'max ms':>8} {'share of p50 sum':>17}"]
    p50s = [pct(st[:, j], 50) for j in range(len(STAGES))]
    for j, name in enumerate(STAGES):
        lines.append(f"{label}: {name:<16} {p50s[j]:8.2f} {pct(st[:, j], 99):8.2f} {np.nanmax(st[:, j]):8.2f} "
                     f"{p50s[j] / sum(p50s):17.2f}")
    shown_ms, e2e_ms = st[:, -2], st[:, -1]
    # What a display would show (the frame drawn) and what the tests see (the PNG on disk).
    lines.append(f"{label}: {'to frame drawn':<16} {pct(shown_ms, 50):8.2f} {pct(shown_ms, 99):8.2f} {shown_ms.max():8.2f}")
    lines.append(f"{label}: {'to PNG (e2e)':<16} {pct(e2e_ms, 50):8.2f} {pct(e2e_ms, 99):8.2f} {np.nanmax(e2e_ms):8.2f}")
    return "\n".join(lines)

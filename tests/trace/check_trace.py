#!/usr/bin/env python3
"""Checks meter-controller's and meter-view's --trace-json files: valid JSON in the Chrome
trace-event object format, every complete event with the fields Perfetto/chrome://tracing need,
the stages each process must show, and one time base across both processes.

usage: check_trace.py CONTROLLER.json VIEW.json   (exit 0 when all checks pass; else the reasons)
       check_trace.py --overrun VIEW_OVERRUN.json  (meter-view --trace-on-overrun's file: valid, the
                                                    frame's stages present, the render loop named,
                                                    every event within the ring's 5 s)
"""
import json
import sys

CONTROLLER_STAGES = {"receive", "decode", "condition", "publish"}
VIEW_STAGES = {"intake", "evaluate", "render", "update", "submit", "readback", "encode"}


def load(path, problems):
    try:
        with open(path, encoding="utf-8") as f:
            doc = json.load(f)
    except (OSError, ValueError) as e:
        problems.append(f"{path}: not valid JSON: {e}")
        return []
    if not isinstance(doc, dict) or not isinstance(doc.get("traceEvents"), list):
        problems.append(f"{path}: expected an object with a traceEvents list")
        return []
    events = []
    for i, e in enumerate(doc["traceEvents"]):
        where = f"{path}: traceEvents[{i}]"
        if not isinstance(e, dict) or e.get("ph") not in ("X", "M"):
            problems.append(f"{where}: expected ph X (complete) or M (metadata), got {e!r:.80}")
            continue
        for key, kind in (("name", str), ("pid", int), ("tid", int)):
            if not isinstance(e.get(key), kind):
                problems.append(f"{where}: field {key} must be {kind.__name__}, got {e.get(key)!r}")
        if e["ph"] == "X":
            for key in ("ts", "dur"):
                if not isinstance(e.get(key), (int, float)) or isinstance(e.get(key), bool):
                    problems.append(f"{where}: field {key} must be a number (microseconds), got {e.get(key)!r}")
            if isinstance(e.get("dur"), (int, float)) and e["dur"] < 0:
                problems.append(f"{where}: negative dur {e['dur']}")
            if not isinstance(e.get("cat"), str):
                problems.append(f"{where}: field cat must be a string")
            events.append(e)
    return events


RING_US = 5_000_000
OVERRUN_STAGES = {"evaluate", "render", "update", "submit", "readback"}


def check_overrun(path):
    problems = []
    events = load(path, problems)
    if not problems:
        with open(path, encoding="utf-8") as f:
            doc = json.load(f)
        threads = {e["args"]["name"] for e in doc["traceEvents"] if e.get("ph") == "M" and e["name"] == "thread_name"}
        if "render loop" not in threads:
            problems.append(f"{path}: the render loop's thread is not named (has: {sorted(threads)})")
        names = {e["name"] for e in events}
        if OVERRUN_STAGES - names:
            problems.append(f"{path}: no {', '.join(sorted(OVERRUN_STAGES - names))} events")
        if events:
            newest = max(e["ts"] + e["dur"] for e in events)
            old = [e for e in events if e["ts"] + e["dur"] < newest - RING_US - 0.001]
            if old:
                problems.append(f"{path}: {len(old)} events ended more than 5 s before the newest")
    for p in problems:
        print(p)
    if not problems:
        print(f"ok: {len(events)} events in the overrun file")
    return 1 if problems else 0


def main(argv):
    if len(argv) == 3 and argv[1] == "--overrun":
        return check_overrun(argv[2])
    if len(argv) != 3:
        print(__doc__)
        return 2
    problems = []
    ctl = load(argv[1], problems)
    view = load(argv[2], problems)
    for path, events, stages in ((argv[1], ctl, CONTROLLER_STAGES), (argv[2], view, VIEW_STAGES)):
        names = {e["name"] for e in events}
        if stages - names:
            problems.append(f"{path}: no {', '.join(sorted(stages - names))} events (has: {', '.join(sorted(names))})")
        if len({e["pid"] for e in events}) > 1:
            problems.append(f"{path}: events of more than one pid")
    if ctl and view and {e["pid"] for e in ctl} == {e["pid"] for e in view}:
        problems.append("both files claim the same pid")

    # One clock: every DELTA/SNAPSHOT the view applied was sent (its sender stamp, on the
    # controller's CLOCK_MONOTONIC) before the view's intake of it ended, and the stamps of the
    # controller's deltas fall inside its publish slices. Stamps are exact to the ns and ts to the
    # ns as well (3 decimals), so the only slack is the 0.001 us of the printed rounding.
    publishes = sorted((e["ts"], e["ts"] + e["dur"]) for e in ctl if e["name"] == "publish")
    intakes = [e for e in view if e["name"] == "intake" and e.get("args", {}).get("sent_ns", 0) > 0]
    if not intakes:
        problems.append(f"{argv[2]}: no intake event with a sender stamp (sent_ns)")
    inside = 0
    for e in intakes:
        sent_us = e["args"]["sent_ns"] / 1000.0
        if sent_us > e["ts"] + e["dur"] + 0.001:
            problems.append(f"{argv[2]}: intake at {e['ts']} us ended before its message was sent at {sent_us} us: "
                            "the files are not on one clock")
            break
        if any(b - 0.001 <= sent_us <= end + 0.001 for b, end in publishes):
            inside += 1
    if intakes and inside == 0:
        problems.append("no intake's sender stamp falls inside a controller publish slice: not one time base")

    for p in problems:
        print(p)
    if not problems:
        print(f"ok: {len(ctl)} controller and {len(view)} view events; {inside} of {len(intakes)} intakes "
              "carry a stamp inside a controller publish slice")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

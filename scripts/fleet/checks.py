"""The checks of one drive, on what it wrote: golden frames, signal expectations, commands.

Each returns a dict {kind, name, ok, message, ...}; `message` says what was expected and what was
found, so a failed drive's reason reads without opening the files.
"""
import csv
import math
import os
import re
import subprocess

# ImageMagick's compare: PSNR in dB ("inf" for equal images) and PAE, the peak absolute error of
# any channel of any pixel, printed as "<quantum> (<fraction>)"; fraction * 255 is the 8-bit
# difference. Both are Debian's imagemagick, which scripts/make-video already needs.
_NUMBER = re.compile(r"^\s*([0-9.eE+-]+|inf)(?:\s*\(([0-9.eE+-]+)\))?")


def _compare(metric, a, b):
    p = subprocess.run(["compare", "-metric", metric, a, b, "null:"], capture_output=True, text=True)
    m = _NUMBER.match(p.stderr)
    if p.returncode > 1 or not m:
        raise RuntimeError(f"compare -metric {metric} {a} {b}: {p.stderr.strip() or 'exit ' + str(p.returncode)}")
    return m


def golden(drive_dir, g):
    frame = g["frame"]
    png = os.path.join(drive_dir, "frames", f"frame_{frame:06d}.png")
    name = f"golden frame {frame}"
    base = {"kind": "golden", "name": name, "png": png, "golden": g["png"]}
    if not os.path.isfile(png):
        return dict(base, ok=False, message=f"{name}: the drive dumped no frame {frame} ({png} missing; "
                                           f"is it a multiple of dump_every?)")
    if not os.path.isfile(g["png"]):
        return dict(base, ok=False, message=f"{name}: no golden image {g['png']}")
    try:
        m = _compare("PSNR", png, g["png"])
        psnr = math.inf if m.group(1) == "inf" else float(m.group(1))
        m = _compare("PAE", png, g["png"])
        pae = round(float(m.group(2)) * 255) if m.group(2) else round(float(m.group(1)))
    except RuntimeError as e:
        return dict(base, ok=False, message=f"{name}: {e}")
    problems = []
    # min_psnr: dB over all pixels (drift everywhere); max_abs_diff: 0..255, the worst single
    # channel of the worst pixel (one needle drawn somewhere else).
    if "min_psnr" in g and psnr < g["min_psnr"]:
        problems.append(f"PSNR {psnr:.2f} dB < {g['min_psnr']} dB")
    if "max_abs_diff" in g and pae > g["max_abs_diff"]:
        problems.append(f"max abs diff {pae} > {g['max_abs_diff']}")
    ok = not problems
    msg = f"{name} vs {os.path.basename(g['png'])}: PSNR {'inf' if psnr == math.inf else f'{psnr:.2f}'} dB, max abs diff {pae}"
    if problems:
        msg = f"{name} vs {g['png']}: " + "; ".join(problems)
    return dict(base, ok=ok, message=msg, psnr=None if psnr == math.inf else psnr, max_abs_diff=pae)


def read_csv_rows(path, missing_ok=False):
    """The rows of a CSV with a header line (frames.csv, timing.csv) as dicts; [] for a missing
    file when missing_ok (a report shows what a failed drive left), else the OSError."""
    try:
        with open(path, newline="") as f:
            return list(csv.DictReader(f))
    except OSError:
        if missing_ok:
            return []
        raise


def signal(rows, s, frame_period):
    """The dumped row nearest to `at` (within half a dump interval), its drawn value vs the bound."""
    sig, at = s["signal"], float(s["at"])
    name = f"{sig} at {at:g} s"
    base = {"kind": "signal", "name": name, "signal": sig, "at": at}
    if not rows:
        return dict(base, ok=False, message=f"{name}: frames.csv has no rows (nothing dumped)")
    column = sig
    if column not in rows[0]:
        return dict(base, ok=False, message=f"{name}: frames.csv has no column {sig} (the scene binds "
                                            f"{', '.join(k for k in rows[0] if '.' in k and not k.endswith(('.status', '.failsafe')))})")
    row = min(rows, key=lambda r: abs(float(r["time_s"]) - at))
    t = float(row["time_s"])
    if abs(t - at) > frame_period / 2 + 1e-9:
        return dict(base, ok=False, message=f"{name}: no dumped frame within {frame_period / 2:g} s (nearest t={t:g} s); "
                                            "dump at that time (dump_at) or more often")
    problems, drawn = [], row[column]
    if "value" in s:
        want = s["value"]
        if isinstance(want, str):
            if drawn != want:
                problems.append(f"drew {drawn!r}, expected {want!r}")
        else:
            tol = float(s["tolerance"])
            if not (abs(float(drawn) - float(want)) <= tol):
                problems.append(f"drew {float(drawn):g}, expected {float(want):g} ± {tol:g}")
    if "status" in s and row.get(sig + ".status") != s["status"]:
        problems.append(f"status {row.get(sig + '.status')}, expected {s['status']}")
    where = f"{name} (frame {row['frame']}, t={t:g} s)"
    return dict(base, ok=not problems, frame=int(row["frame"]), drawn=drawn, expected=s.get("value"),
                tolerance=s.get("tolerance"), message=where + (": " + "; ".join(problems) if problems else f": drew {drawn}"))


def command(c, values, drive_dir):
    """Any program judging the run: exit 0 = pass. {run} {package} {junit} {frames} {recording}
    {bin} in argv are replaced; a JUnit file it writes at {junit} is kept for the drive's XML."""
    junit = os.path.join(drive_dir, "checks", f"{c['name']}.junit.xml")
    os.makedirs(os.path.dirname(junit), exist_ok=True)
    subs = dict(values, junit=junit)
    try:
        argv = [a.format(**subs) for a in c["argv"]]
    except KeyError as e:
        return {"kind": "command", "name": c["name"], "ok": False,
                "message": f"command {c['name']}: unknown placeholder {{{e.args[0]}}} (expected {', '.join(sorted(subs))})"}
    base = {"kind": "command", "name": c["name"], "argv": argv}
    log = os.path.join(drive_dir, "checks", f"{c['name']}.log")
    try:
        with open(log, "w") as out:
            p = subprocess.run(argv, stdout=out, stderr=subprocess.STDOUT, timeout=c.get("timeout", 600))
    except FileNotFoundError:
        return dict(base, ok=False, message=f"command {c['name']}: {argv[0]} not found")
    except subprocess.TimeoutExpired:
        return dict(base, ok=False, message=f"command {c['name']}: no exit within {c.get('timeout', 600)} s")
    with open(log, errors="replace") as f:
        tail = [line.rstrip() for line in f.readlines()[-3:]]
    result = dict(base, ok=p.returncode == 0, exit=p.returncode, log=log,
                  junit=junit if os.path.isfile(junit) else None)
    result["message"] = f"command {c['name']}: exit {p.returncode}" + (": " + " | ".join(tail) if tail and p.returncode else "")
    return result

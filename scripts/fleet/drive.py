"""One drive, as one CLI call: meter-controller replays the log(s) on its simulated clock (--replay
fast) and records what it publishes (--record); meter-view renders that recording on its own
simulated clock (--play), dumping frames, frames.csv and the timing CSV; then the checks run.
Writes <dir>/result.json (last, atomically: its presence means the drive finished) and junit.xml.
"""
import json
import os
import re
import resource
import shutil
import socket
import subprocess
import tempfile
import time

from . import checks, junit, logs

OUTPUTS = ("frames", "checks", "link.rec", "controller.log", "view.log", "timing.csv", "junit.xml",
           "result.json", "video.log")


def _cpu():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def _tail(path, n=2):
    return logs.tail(logs.read(path), n)


def _stage(name, argv, log, stages):
    t0, c0 = time.monotonic(), _cpu()
    with open(log, "w") as out:
        try:
            code = subprocess.run(argv, stdout=out, stderr=subprocess.STDOUT).returncode
        except FileNotFoundError:
            out.write(f"{argv[0]}: not found\n")
            code = 127
    stages.append({"name": name, "argv": argv, "exit": code, "wall_s": time.monotonic() - t0,
                   "cpu_s": _cpu() - c0, "log": log, "tail": _tail(log)})
    return code == 0


def _input_arg(spec):
    name, sep, path = spec.partition("=")
    return f"{name}=log:{path}" if sep else f"log:{spec}"


def controller_argv(drive, bin_dir, rec, sock):
    argv = [os.path.join(bin_dir, "meter-controller"), "run", "--map", drive["map"], "--replay", "fast",
            "--exit-at-end", "--record", rec, "--link", f"unix:{sock}", "--log", "json"]
    for spec in drive["logs"]:
        argv += ["--input", _input_arg(spec)]
    for spec in drive["dbcs"]:
        argv += ["--dbc", spec]
    if drive["catalog"]:
        argv += ["--catalog", drive["catalog"]]
    return argv


def view_argv(drive, bin_dir, rec, out):
    argv = [os.path.join(bin_dir, "meter-view"), "--scene", drive["scene"], "--backend", drive["backend"],
            "--play", rec, "--fps", f"{drive['fps']:g}", "--dump-every", str(drive["dump_every"]),
            "--msaa", str(drive["msaa"]), "--out", os.path.join(out, "frames"),
            "--timing-csv", os.path.join(out, "timing.csv"), "--log", "json"]
    if drive["size"]:
        argv += ["--size", drive["size"]]
    if drive["dump_at"]:
        argv += ["--dump-at", ",".join(f"{t:g}s" for t in drive["dump_at"])]
    if drive["dump_last"]:
        argv.append("--dump-last")
    if drive["duration"]:
        argv += ["--duration", f"{drive['duration']:g}"]
    if drive["catalog"]:
        argv += ["--catalog", drive["catalog"]]
    return argv


def run(drive, out, bin_dir, source_dir, attempt=1, extra=None):
    """Runs the drive into `out` (its old outputs removed first) and returns the result dict."""
    os.makedirs(out, exist_ok=True)
    for name in OUTPUTS:
        p = os.path.join(out, name)
        shutil.rmtree(p) if os.path.isdir(p) else (os.path.exists(p) and os.remove(p))
    t0, c0 = time.monotonic(), _cpu()
    started = time.time()
    stages, found, errors = [], [], []
    rec = os.path.join(out, "link.rec")
    sockdir = tempfile.mkdtemp(prefix="meter-fleet-")  # the link socket, private to this drive
    try:
        ok = _stage("meter-controller", controller_argv(drive, bin_dir, rec, os.path.join(sockdir, "c.sock")),
                    os.path.join(out, "controller.log"), stages)
        ok = ok and _stage("meter-view", view_argv(drive, bin_dir, rec, out), os.path.join(out, "view.log"), stages)
        render_cpu = time.monotonic() - t0, _cpu() - c0
        if ok:
            values = {"run": out, "package": drive["scene"], "frames": os.path.join(out, "frames"),
                      "recording": rec, "bin": bin_dir}
            rows = checks.read_csv_rows(os.path.join(out, "frames", "frames.csv"))
            period = max(drive["dump_every"], 1) / drive["fps"]
            for g in drive["golden"]:
                s = time.monotonic()
                found.append(dict(checks.golden(out, g), seconds=time.monotonic() - s))
            for sig in drive["signal"]:
                found.append(dict(checks.signal(rows, sig, period), seconds=0.0))
            for c in drive["command"]:
                s = time.monotonic()
                found.append(dict(checks.command(c, values, out), seconds=time.monotonic() - s))
            checked = time.monotonic() - t0, _cpu() - c0
            if drive["video"]:
                _stage("make-video", [os.path.join(source_dir, "scripts", "make-video"), os.path.join(out, "frames")],
                       os.path.join(out, "video.log"), stages)
        else:
            checked = render_cpu
    except Exception as e:  # a bug or an I/O failure here still leaves a result naming it
        errors.append(f"{type(e).__name__}: {e}")
        checked = time.monotonic() - t0, _cpu() - c0
    finally:
        shutil.rmtree(sockdir, ignore_errors=True)
    reasons = [f"{st['name']} exit {st['exit']}: {st['tail']}" for st in stages if st["exit"] != 0]
    reasons += [c["message"] for c in found if not c["ok"]] + errors
    failed_stage = any(st["exit"] != 0 and st["name"] != "make-video" for st in stages) or errors
    frames_dir = os.path.join(out, "frames")
    result = {
        "name": drive["name"], "attempt": attempt, "host": socket.gethostname(), "started": started,
        "verdict": "error" if failed_stage else ("fail" if reasons else "pass"), "reasons": reasons,
        "errors": errors, "wall_s": time.monotonic() - t0, "cpu_s": _cpu() - c0,
        # the part the speed goal counts: replay, render + dump, and every check (no video)
        "checked_wall_s": checked[0], "checked_cpu_s": checked[1],
        "stages": stages, "checks": found,
        "dumped": sorted(f for f in os.listdir(frames_dir) if re.fullmatch(r"frame_\d{6}\.png", f))
                  if os.path.isdir(frames_dir) else [],
        "controller_summary": _tail(os.path.join(out, "controller.log"), 1),
        "view_summary": _tail(os.path.join(out, "view.log"), 1),
        # the faults each process reported, from its structured records (a `fault` field)
        "faults": logs.faults(logs.read(os.path.join(out, "view.log")))
                  + logs.faults(logs.read(os.path.join(out, "controller.log"))),
        "drive": {k: drive[k] for k in ("logs", "dbcs", "map", "scene", "fps", "dump_every", "signal", "golden")},
    }
    result.update(extra or {})
    junit.write_drive(result, os.path.join(out, "junit.xml"))
    tmp = os.path.join(out, ".result.json.tmp")
    with open(tmp, "w") as f:
        json.dump(result, f, indent=1)
    os.replace(tmp, os.path.join(out, "result.json"))
    return result

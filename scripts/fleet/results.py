"""Results of a fleet run: each drive's result.json (or why there is none), the summary, exit status."""
import json
import os

from . import junit


def drive_dir(run_dir, name):
    return os.path.join(run_dir, "drives", name)


def read_result(run_dir, name):
    try:
        with open(os.path.join(drive_dir(run_dir, name), "result.json")) as f:
            return json.load(f)
    except (OSError, json.JSONDecodeError):
        return None


def missing(name, verdict, reason, **extra):
    """The entry of a drive that left no result (lost with its node, cancelled): never left out."""
    return dict({"name": name, "verdict": verdict, "reasons": [reason], "errors": [reason], "wall_s": 0.0,
                 "cpu_s": 0.0, "stages": [], "checks": [], "dumped": []}, **extra)


def write_summary(run_dir, manifest, outcomes, meta):
    """outcomes: name -> result dict (a real one or missing()). Writes summary.json and junit.xml."""
    drives = []
    for d in manifest["drives"]:
        r = outcomes.get(d["name"]) or missing(d["name"], "lost", "no outcome recorded for this drive")
        drives.append(r)
    counts = {v: sum(1 for r in drives if r["verdict"] == v) for v in ("pass", "fail", "error", "lost", "cancelled")}
    summary = dict(meta, total=len(drives), **counts,
                   cpu_s=sum(r.get("cpu_s", 0.0) for r in drives),
                   drives=[{k: r.get(k) for k in ("name", "verdict", "reasons", "wall_s", "cpu_s", "checked_cpu_s",
                                                  "attempt", "host", "slurm")} for r in drives])
    with open(os.path.join(run_dir, "summary.json"), "w") as f:
        json.dump(summary, f, indent=1)
    junit.write_fleet(drives, os.path.join(run_dir, "junit.xml"))
    return summary, drives


def print_summary(summary, out):
    out.write(f"meter-fleet: {summary['total']} drives: {summary['pass']} passed, {summary['fail']} failed, "
              f"{summary['error']} errors, {summary['lost']} lost, {summary['cancelled']} cancelled "
              f"({summary['executor']}, {summary['wall_s']:.1f} s wall, {summary['cpu_s']:.1f} CPU-s in drives)\n")
    for d in summary["drives"]:
        if d["verdict"] != "pass":
            out.write(f"  {d['verdict'].upper():9} {d['name']}: {'; '.join(d['reasons'] or ['?'])}\n")
    for key in ("retried", "requeued_by_slurm"):
        if summary.get(key):
            out.write(f"  {key.replace('_', ' ')}: {', '.join(summary[key])}\n")


def exit_status(summary):
    return 0 if summary["pass"] == summary["total"] else 1

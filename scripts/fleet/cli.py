"""meter-fleet: run a manifest of recorded drives, one CLI call per drive, on a local pool of
worker processes or a Slurm cluster (one sbatch --array), and write one summary and HTML report.

  meter-fleet run MANIFEST --out RUN [--executor local|slurm] [--workers N] [--retries N]
  meter-fleet drive --run RUN --index I     one drive (what every executor runs; docs/fleet.md)
  meter-fleet plan MANIFEST --out RUN       only the plan, for drives another scheduler runs
  meter-fleet collect RUN                   summary, JUnit and report of drives run elsewhere
  meter-fleet report RUN                    rewrite RUN/index.html from the results
Exit status of run: 0 when every drive passed, 1 when any failed, erred or was lost, 2 on a bad manifest.
"""
import argparse
import json
import os
import sys
import time

from . import drive, local_executor, manifest, report, results, slurm_executor
from .progress import Progress

SOURCE_DIR = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
FLEET = os.path.join(SOURCE_DIR, "scripts", "meter-fleet")


def default_bin():
    if os.environ.get("METER_BIN"):
        return os.environ["METER_BIN"]
    for sub in ("build/release/bin", "build/bin"):
        p = os.path.join(SOURCE_DIR, sub)
        if os.path.isfile(os.path.join(p, "meter-view")):
            return p
    return os.path.join(SOURCE_DIR, "build/release/bin")


def load_plan(run_dir):
    with open(os.path.join(run_dir, "plan.json")) as f:
        return json.load(f)


def make_plan(a):
    """The run folder's plan.json: the manifest with every path resolved, which each drive call
    reads. Returns (manifest, run_dir, bin_dir), or None after printing what is wrong."""
    try:
        m = manifest.load(a.manifest)
    except manifest.ManifestError as e:
        sys.stderr.write(f"meter-fleet: {e}\n")
        return None
    run_dir = os.path.abspath(a.out)
    os.makedirs(os.path.join(run_dir, "drives"), exist_ok=True)
    bin_dir = os.path.abspath(a.bin or default_bin())
    for tool in ("meter-controller", "meter-view"):
        if not os.access(os.path.join(bin_dir, tool), os.X_OK):
            sys.stderr.write(f"meter-fleet: {bin_dir}/{tool}: not found (build it, or give --bin DIR / METER_BIN)\n")
            return None
    plan = dict(m, bin=bin_dir, source_dir=SOURCE_DIR)
    with open(os.path.join(run_dir, "plan.json"), "w") as f:
        json.dump(plan, f, indent=1)
    return m, run_dir, bin_dir


def finish(run_dir, m, outcomes, meta, no_report):
    summary, drives = results.write_summary(run_dir, m, outcomes, meta)
    if not no_report:
        report.write(run_dir, summary, drives)
    results.print_summary(summary, sys.stdout)
    print(f"meter-fleet: summary {run_dir}/summary.json, JUnit {run_dir}/junit.xml"
          + ("" if no_report else f", report {run_dir}/index.html"))
    return summary


def cmd_plan(a):
    made = make_plan(a)
    if made is None:
        return 2
    m, run_dir, _ = made
    print(f"meter-fleet: {run_dir}/plan.json: {len(m['drives'])} drives, indices 0..{len(m['drives']) - 1}")
    return 0


def cmd_collect(a):
    """The summary of drives someone else ran (Kubernetes, Airflow): a drive without result.json is lost."""
    run_dir = os.path.abspath(a.run)
    plan = load_plan(run_dir)
    outcomes = {d["name"]: results.read_result(run_dir, d["name"])
                or results.missing(d["name"], "lost", f"no {results.drive_dir(run_dir, d['name'])}/result.json")
                for d in plan["drives"]}
    wall = max((r.get("started", 0) + r.get("wall_s", 0) for r in outcomes.values()), default=0) - \
        min((r["started"] for r in outcomes.values() if r.get("started")), default=0)
    summary = finish(run_dir, plan, outcomes, {"executor": "external", "wall_s": max(wall, 0.0)}, a.no_report)
    return results.exit_status(summary)


def cmd_run(a):
    made = make_plan(a)
    if made is None:
        return 2
    m, run_dir, bin_dir = made
    workers = a.workers or os.cpu_count() or 1

    def drive_cmd(index, attempt):
        return [sys.executable, FLEET, "drive", "--run", run_dir, "--index", str(index), "--attempt", str(attempt)]
    progress = Progress(len(m["drives"]))
    t0 = time.monotonic()
    if a.executor == "local":
        outcomes, meta = local_executor.run(run_dir, m, drive_cmd, workers, a.retries, progress)
    else:
        outcomes, meta = slurm_executor.run(run_dir, m, [sys.executable, FLEET], a, progress)
    meta.update(wall_s=time.monotonic() - t0, manifest=m["file"], bin=bin_dir)
    summary = finish(run_dir, m, outcomes, meta, a.no_report)
    return 130 if meta.get("interrupted") else results.exit_status(summary)


def cmd_drive(a):
    plan = load_plan(os.path.abspath(a.run))
    index = a.index
    if index is None:  # an array task: Slurm, a Kubernetes Indexed Job
        for var in ("SLURM_ARRAY_TASK_ID", "JOB_COMPLETION_INDEX"):
            if os.environ.get(var, "").isdigit():
                index = int(os.environ[var])
    if index is None or not 0 <= index < len(plan["drives"]):
        sys.stderr.write(f"meter-fleet drive: --index: expected 0..{len(plan['drives']) - 1}, got {index}\n")
        return 2
    d = plan["drives"][index]
    extra = {}
    if os.environ.get("SLURM_JOB_ID"):
        extra["slurm"] = {k: os.environ.get("SLURM_" + k.upper(), "") for k in ("job_id", "array_job_id",
                                                                               "array_task_id", "restart_count")}
    r = drive.run(d, results.drive_dir(os.path.abspath(a.run), d["name"]), plan["bin"], plan["source_dir"],
                  a.attempt, extra)
    print(f"meter-fleet drive {d['name']}: {r['verdict']} in {r['wall_s']:.2f} s ({r['cpu_s']:.2f} CPU-s)"
          + "".join(f"\n  {x}" for x in r["reasons"]))
    return 0 if r["verdict"] == "pass" else 1


def cmd_report(a):
    run_dir = os.path.abspath(a.run)
    with open(os.path.join(run_dir, "summary.json")) as f:
        summary = json.load(f)
    plan = load_plan(run_dir)
    drives = [results.read_result(run_dir, d["name"]) or results.missing(d["name"], s["verdict"], "; ".join(s["reasons"]))
              for d, s in zip(plan["drives"], summary["drives"])]
    report.write(run_dir, summary, drives)
    print(f"meter-fleet: {run_dir}/index.html")
    return 0


def main(argv):
    p = argparse.ArgumentParser(prog="meter-fleet", description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest="command", required=True)
    r = sub.add_parser("run", help="run every drive of a manifest")
    r.add_argument("manifest", help="TOML or JSON manifest (docs/fleet.md)")
    r.add_argument("--out", required=True, help="run folder (shared with the cluster for slurm)")
    r.add_argument("--executor", choices=("local", "slurm"), default="local")
    r.add_argument("--workers", type=int, default=0, help="local: worker processes (default: the core count)")
    r.add_argument("--retries", type=int, default=2,
                   help="times a drive that left no result (crashed, lost with its node) is run again (default 2)")
    r.add_argument("--bin", help="folder of meter-controller and meter-view (default: METER_BIN or build/release/bin)")
    r.add_argument("--no-report", action="store_true", help="do not write the HTML report")
    r.add_argument("--sbatch-arg", action="append", default=[], help="slurm: extra sbatch argument (repeatable)")
    r.add_argument("--drives-per-task", type=int, default=1,
                   help="slurm: drives each array task runs one after another (spreads Slurm's per-task start "
                        "over several short drives; retries run one drive per task)")
    r.add_argument("--poll", type=float, default=1.0, help="slurm: seconds between state polls")
    r.add_argument("--stall-timeout", type=float, default=600.0,
                   help="slurm: seconds without any task running or finishing after which the pending ones "
                        "are cancelled and reported lost (a cluster with no node up)")
    r.set_defaults(func=cmd_run)
    pl = sub.add_parser("plan", help="write RUN/plan.json only (for drives run by Kubernetes, Airflow, ...)")
    pl.add_argument("manifest")
    pl.add_argument("--out", required=True)
    pl.add_argument("--bin", help="folder of meter-controller and meter-view as the workers see it")
    pl.set_defaults(func=cmd_plan)
    co = sub.add_parser("collect", help="summary, JUnit and report of a run folder whose drives ran elsewhere")
    co.add_argument("run")
    co.add_argument("--no-report", action="store_true")
    co.set_defaults(func=cmd_collect)
    d = sub.add_parser("drive", help="run one drive of a run folder (what every executor calls)")
    d.add_argument("--run", required=True, help="run folder written by 'meter-fleet run' (its plan.json)")
    d.add_argument("--index", type=int, help="drive index (default: $SLURM_ARRAY_TASK_ID or $JOB_COMPLETION_INDEX)")
    d.add_argument("--attempt", type=int, default=1)
    d.set_defaults(func=cmd_drive)
    rep = sub.add_parser("report", help="rewrite the HTML report of a run folder")
    rep.add_argument("run")
    rep.set_defaults(func=cmd_report)
    a = p.parse_args(argv)
    if a.command == "run" and (a.workers < 0 or a.retries < 0):
        p.error("--workers and --retries must be >= 0")
    return a.func(a)

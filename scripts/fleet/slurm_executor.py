"""The Slurm executor: one `sbatch --array` for the drives, results collected from the shared run
folder, task states from `scontrol show job` and the jobcomp file (sacct needs slurmdbd, which a
small cluster may not run). A task that ended without a result (failed, lost with its node,
cancelled by the cluster) is submitted again, up to --retries times, as a new array of just those
drives; Slurm's own requeue of a task (after a node failure) is followed, not double counted.
Ctrl-C cancels every array submitted. Nothing is left out: each drive ends passed, failed, lost
(with the state and reason Slurm gave) or cancelled.
"""
import os
import re
import shlex
import subprocess
import time

from . import results
from .interrupt import CtrlC

TERMINAL = {"COMPLETED", "FAILED", "CANCELLED", "NODE_FAIL", "TIMEOUT", "PREEMPTED", "OUT_OF_MEMORY",
            "BOOT_FAIL", "DEADLINE"}
# A task whose array has left scontrol and the jobcomp file within this long after it finished
# without a result counts as lost: results on a shared folder may take a moment to appear.
RESULT_GRACE_S = 10.0


def _fields(line):
    return dict(tok.split("=", 1) for tok in line.split() if "=" in tok)


def _task_ids(text):
    """ArrayTaskId as scontrol prints it: 4, or a pending range "3-9,12%2"."""
    ids = []
    for part in text.split("%")[0].split(","):
        if re.fullmatch(r"\d+-\d+", part):
            a, b = map(int, part.split("-"))
            ids += range(a, b + 1)
        elif part.isdigit():
            ids.append(int(part))
    return ids


def scontrol_states(job_id):
    """{task index: {JobState, Reason, Restarts, ExitCode, NodeList}} of one array, {} once purged."""
    p = subprocess.run(["scontrol", "-o", "show", "job", str(job_id)], capture_output=True, text=True)
    states = {}
    if p.returncode != 0:
        return states
    for line in p.stdout.splitlines():
        f = _fields(line)
        for i in _task_ids(f.get("ArrayTaskId", "")):
            states[i] = f
    return states


def jobcomp_path():
    p = subprocess.run(["scontrol", "show", "config"], capture_output=True, text=True)
    for line in p.stdout.splitlines():
        key, _, value = line.partition("=")
        if key.strip() == "JobCompLoc" and value.strip().startswith("/"):
            return value.strip()
    return None


def jobcomp_states(path, job_ids):
    """Ended tasks in the jobcomp file: {(array job id, task): fields}; the last line of a task wins."""
    out = {}
    try:
        with open(path, errors="replace") as f:
            for line in f:
                fl = _fields(line)
                job = fl.get("ArrayJobId") or fl.get("JobId")
                if job in job_ids and fl.get("ArrayTaskId", "").isdigit():
                    out[(job, int(fl["ArrayTaskId"]))] = fl
    except OSError:
        pass
    return out


def submit(run_dir, chunks, attempt, fleet_cmd, sbatch_args):
    """One sbatch --array, task t running the drives chunks[t] one after another (several drives
    per task spread Slurm's per-task start over them). Returns the array job id."""
    slurm_dir = os.path.join(run_dir, "slurm")
    os.makedirs(slurm_dir, exist_ok=True)
    script = os.path.join(slurm_dir, "task.sh")
    with open(script, "w") as f:
        f.write("#!/bin/sh\n# One array task: line $SLURM_ARRAY_TASK_ID+1 of the submission's list holds its drive indices.\n"
                "set -- \"$1\" $(sed -n \"$((SLURM_ARRAY_TASK_ID + 1))p\" \"$2\")\nattempt=$1; shift\nstatus=0\n"
                f"for i in \"$@\"; do\n  {' '.join(shlex.quote(c) for c in fleet_cmd)} drive --run {shlex.quote(run_dir)} "
                "--index \"$i\" --attempt \"$attempt\" || status=1\ndone\nexit $status\n")
    os.chmod(script, 0o755)
    listing = os.path.join(slurm_dir, f"tasks-{len(os.listdir(slurm_dir))}.txt")
    with open(listing, "w") as f:
        f.write("".join(" ".join(map(str, c)) + "\n" for c in chunks))
    argv = ["sbatch", "--parsable", "--requeue", "-J", "meter-fleet", f"--array=0-{len(chunks) - 1}",
            "-o", os.path.join(slurm_dir, "%A_%a.out"), "-D", run_dir] + sbatch_args + [script, str(attempt), listing]
    p = subprocess.run(argv, capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError(f"sbatch failed (exit {p.returncode}): {p.stderr.strip()}")
    return p.stdout.strip().split(";")[0]


def run(run_dir, manifest, fleet_cmd, a, progress):
    drives = manifest["drives"]
    names = [d["name"] for d in drives]
    outcomes, retried, requeued, jobs = {}, [], set(), []
    attempt_of = {i: 1 for i in range(len(drives))}
    ended_at = {}  # index -> when Slurm said it ended without a result yet
    comp = jobcomp_path()
    ctrl_c = CtrlC()
    try:
        k = max(a.drives_per_task, 1)
        chunks = [list(range(c, min(c + k, len(drives)))) for c in range(0, len(drives), k)]
        job = submit(run_dir, chunks, 1, fleet_cmd, a.sbatch_arg)
        jobs.append(job)
        live = {i: (job, t) for t, c in enumerate(chunks) for i in c}  # drive index -> (array job, task)
        last_motion = time.monotonic()
        while live and not ctrl_c.hit:
            states = {}
            for j in {j for j, _ in live.values()}:
                states[j] = scontrol_states(j)
            done_comp = jobcomp_states(comp, {j for j, _ in live.values()}) if comp else {}
            running_tasks = set()
            for i in sorted(live):
                j, t = live[i]
                r = results.read_result(run_dir, names[i])
                if r is not None and r.get("attempt") == attempt_of[i]:
                    outcomes[names[i]] = r
                    del live[i]
                    last_motion = time.monotonic()
                    continue
                st = states[j].get(t) or done_comp.get((j, t))
                state = (st or {}).get("JobState", "")
                if st and int(st.get("Restarts", "0") or 0) > 0:
                    requeued.add(names[i])
                if state == "RUNNING":
                    running_tasks.add((j, t))
                if st and state == "PENDING" and "launch_failed_requeued_held" in st.get("Reason", ""):
                    # A task whose launch failed (its node went away as it started) is held by Slurm
                    # and would never run: cancel it and run the drive again like a failed one.
                    subprocess.run(["scancel", f"{j}_{t}"], capture_output=True)
                    state, ended_at[i] = "CANCELLED", time.monotonic() - RESULT_GRACE_S
                elif st and state not in TERMINAL:
                    ended_at.pop(i, None)
                    continue
                # Ended (or purged from the controller) with no result of this attempt.
                first = ended_at.setdefault(i, time.monotonic())
                if time.monotonic() - first < RESULT_GRACE_S:
                    continue
                why = (f"slurm task {j}_{t} {state or 'gone from scontrol and the jobcomp file'}"
                       + (f" ({st.get('Reason')})" if st and st.get("Reason") not in (None, "None") else "")
                       + (f", exit {st.get('ExitCode')}" if st and st.get("ExitCode") else ""))
                del live[i]
                ended_at.pop(i, None)
                last_motion = time.monotonic()
                if attempt_of[i] <= a.retries:
                    retried.append(f"{names[i]} ({why}, attempt {attempt_of[i]})")
                    attempt_of[i] += 1
                    live[i] = (submit(run_dir, [[i]], attempt_of[i], fleet_cmd, a.sbatch_arg), 0)
                    jobs.append(live[i][0])
                else:
                    outcomes[names[i]] = results.missing(names[i], "lost", f"{why}; no result after {attempt_of[i]} attempts")
            running = len(running_tasks)
            if running:
                last_motion = time.monotonic()
            failed = sum(1 for r in outcomes.values() if r["verdict"] != "pass")
            # (a drive resubmitted in this round is in a job this round's states do not have yet)
            pend = sum(1 for i in live if (states.get(live[i][0], {}).get(live[i][1]) or {}).get("JobState") == "PENDING")
            progress.show(len(outcomes), failed, running, f"{pend} pending" if pend else "")
            if live and time.monotonic() - last_motion > a.stall_timeout:
                nodes = subprocess.run(["sinfo", "-h", "-o", "%N %T"], capture_output=True, text=True).stdout.split()
                for i in sorted(live):
                    j, t = live[i]
                    st = states.get(j, {}).get(t) or {}
                    outcomes[names[i]] = results.missing(
                        names[i], "lost", f"slurm task {j}_{t} {st.get('JobState', '?')} (reason {st.get('Reason', '?')}, "
                                          f"nodes: {' '.join(nodes) or '?'}) with nothing running for {a.stall_timeout:g} s; "
                                          "cancelled")
                subprocess.run(["scancel"] + sorted({j for j, _ in live.values()}))
                live = {}
                break
            time.sleep(a.poll)
    finally:
        ctrl_c.restore()
        if ctrl_c.hit:
            subprocess.run(["scancel"] + jobs)
            for n in names:  # the drives that finished keep their result
                outcomes.setdefault(n, results.missing(n, "cancelled", "cancelled (Ctrl-C): scancel " + " ".join(jobs)))
        progress.finish()
    return outcomes, {"executor": "slurm", "jobs": jobs, "retried": retried, "requeued_by_slurm": sorted(requeued),
                      "interrupted": ctrl_c.hit}

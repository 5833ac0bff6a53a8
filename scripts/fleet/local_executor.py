"""The local executor: N worker processes, each drive one `meter-fleet drive` call."""
import os
import signal
import subprocess
import sys
import time

from . import results
from .interrupt import CtrlC


def run(run_dir, manifest, drive_cmd, workers, retries, progress):
    """drive_cmd(index, attempt) -> argv. Returns (outcomes, meta). A drive that leaves no result
    (the process crashed or was killed) is run again up to `retries` times, then reported lost."""
    drives = manifest["drives"]
    pending = [(i, 1) for i in range(len(drives))]
    running, outcomes, retried = {}, {}, []
    log_dir = os.path.join(run_dir, "logs")
    os.makedirs(log_dir, exist_ok=True)
    ctrl_c = CtrlC()
    try:
        while (pending or running) and not ctrl_c.hit:
            while pending and len(running) < workers:
                i, attempt = pending.pop(0)
                log = open(os.path.join(log_dir, f"{drives[i]['name']}.{attempt}.log"), "w")
                p = subprocess.Popen(drive_cmd(i, attempt), stdout=log, stderr=subprocess.STDOUT,
                                     start_new_session=True)  # Ctrl-C reaches the orchestrator only
                running[p] = (i, attempt, log)
            for p in [p for p in running if p.poll() is not None]:
                i, attempt, log = running.pop(p)
                log.close()
                name = drives[i]["name"]
                r = results.read_result(run_dir, name)
                if r is not None and r.get("attempt") == attempt:
                    outcomes[name] = r
                elif attempt <= retries:
                    retried.append(f"{name} (exit {p.returncode}, attempt {attempt})")
                    pending.append((i, attempt + 1))
                else:
                    outcomes[name] = results.missing(name, "lost", f"worker exit {p.returncode} without a result "
                                                                    f"after {attempt} attempts (log: {log.name})")
            failed = sum(1 for r in outcomes.values() if r["verdict"] != "pass")
            progress.show(len(outcomes), failed, len(running))
            time.sleep(0.05)
    finally:
        ctrl_c.restore()
        for p, (i, attempt, log) in running.items():  # Ctrl-C: stop what runs, report it cancelled
            os.killpg(p.pid, signal.SIGTERM)
            p.wait()
            log.close()
            outcomes[drives[i]["name"]] = results.missing(drives[i]["name"], "cancelled", "cancelled (Ctrl-C) while running")
        for i, attempt in pending:
            outcomes[drives[i]["name"]] = results.missing(drives[i]["name"], "cancelled", "cancelled (Ctrl-C) before it ran")
        progress.finish()
    if ctrl_c.hit:
        sys.stderr.write("meter-fleet: interrupted; running drives stopped\n")
    return outcomes, {"executor": f"local x{workers}", "retried": retried, "interrupted": ctrl_c.hit}

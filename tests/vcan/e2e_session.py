"""One VM boot for all end-to-end drives. Each end-to-end test is a drive (a guest scenario with its
own controller, and meter-view on the host) and a judgement. Booting the TCG guest costs 12-20 s,
so the CTest fixture vcan.e2e_drives runs every drive in one boot (tests/vcan/guest_session.sh runs
the scenarios one after another), in the order below, and saves what each test judges; each test
then judges its own drive. A test run on its own (no fixture), or whose drive the shared boot did
not finish, drives in a VM of its own: the verdict is the same either way.

Usage (the fixture): e2e_session.py"""
import json
import os
import pathlib
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(__file__))
import e2e  # noqa: E402
import vcanlib as v  # noqa: E402

GUEST_SESSION = os.path.join(v.SOURCE_DIR, "tests", "vcan", "guest_session.sh")
STATE = "drive-state.json"      # in a drive's folder: what its test needs to judge it
ROOT = v.out_dir("")


class Drive:
    """A scenario in the shared VM, with the part of Popen's interface e2e.Run uses."""

    def __init__(self, session, n):
        self.session, self.n, self.returncode = session, n, None

    def poll(self):
        done = os.path.join(self.session.dir, f"done-{self.n}")
        if os.path.exists(done):
            with open(done) as f:
                self.returncode = int(f.read().strip() or 125)
        elif self.session.vm.poll() is not None:
            self.returncode = 125     # the shared VM ended before this drive did
        return self.returncode

    def wait(self, timeout):
        deadline = time.monotonic() + timeout
        while self.poll() is None:
            if time.monotonic() > deadline:
                raise subprocess.TimeoutExpired(f"drive {self.n} in the shared VM", timeout)
            time.sleep(0.2)
        return self.returncode


class Session:
    """The shared VM: vcan0, the two forwarded ports every drive uses, the out folder writable."""

    def __init__(self, timeout):
        self.dir = v.fresh_dir("e2e_session")
        self.port, self.go_port = v.free_port(), v.free_port()
        self.n = 0
        self.vm = v.with_vcan([GUEST_SESSION, self.dir], ROOT, timeout=timeout, cpus=e2e.E2E_CPUS,
                              hostfwd=[f"{self.port}:{self.port}", f"{self.go_port}:{self.go_port}"])

    def submit(self, args):
        self.n += 1
        tmp = os.path.join(self.dir, f"next-{self.n}.tmp")
        with open(tmp, "w") as f:
            f.write("".join(a + "\n" for a in args))
        os.rename(tmp, os.path.join(self.dir, f"next-{self.n}"))
        return Drive(self, self.n)

    def close(self, timeout=30):
        open(os.path.join(self.dir, "end"), "w").close()
        try:
            return self.vm.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            self.vm.kill()
            return self.vm.wait()


def save(run, rcs):
    """What the judgement of a drive needs, next to its outputs."""
    with open(os.path.join(run.out, STATE), "w") as f:
        json.dump({"t_go": run.t_go, "views": run.views_state(), "rcs": list(rcs), "log": run.log}, f)


def shared_or_drive(name, drive):
    """(run, rcs) of drive `name`: the shared boot's when the fixture made it, else driven now."""
    state = os.path.join(v.out_dir(name), STATE)
    if os.environ.get("METER_E2E_SESSION") == "1" and os.path.exists(state):
        with open(state) as f:
            s = json.load(f)
        print(f"{name}: judging the drive of the shared boot (vcan.e2e_drives), {os.path.dirname(state)}")
        return e2e.Run.load(name, s), tuple(s["rcs"])
    if os.environ.get("METER_E2E_SESSION") == "1":
        print(f"{name}: the shared boot left no drive here; driving in a VM of its own")
    return drive(None)


def main():
    import test_e2e
    import test_latency
    drives = test_e2e.DRIVES + test_latency.DRIVES
    for name, _ in drives:      # no test may judge a drive of an earlier session
        pathlib.Path(v.out_dir(name), STATE).unlink(missing_ok=True)
    t0 = time.monotonic()
    # The whole session's bound: boot plus every drive's own bound.
    session = Session(timeout=90 + sum(e2e.Run.DEFAULT_TIMEOUT for _ in drives))
    failed = []
    for name, drive in drives:
        t = time.monotonic()
        try:
            run, rcs = drive(session)
            save(run, rcs)
            print(f"e2e_session: {name} driven in {time.monotonic() - t:.1f} s: vm {rcs[0]}, {rcs[2]}")
        except Exception as e:  # noqa: BLE001 - the drive's own test reports it, driving alone
            failed.append(name)
            print(f"e2e_session: {name} not driven in the shared boot: {e}")
            if session.vm.poll() is not None:
                break
    rc = session.close()
    print(f"e2e_session: {len(drives) - len(failed)} drives in one boot, {time.monotonic() - t0:.1f} s; VM exit {rc}; "
          f"timing {v.vm_timing(ROOT)}")
    # Not a verdict: every drive is judged by its own test, which drives alone what is missing here.
    return 0


if __name__ == "__main__":
    sys.exit(main())

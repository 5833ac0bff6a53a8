"""A single-node Slurm owned by a test: munged, slurmctld and slurmd with their configuration,
keys, state, logs and pid files in one folder; stopped by the pids in their pid files (never by
name), also when the test fails. Debian 12's slurm-wlm 22.05 and munge (scripts/install-deps)."""
import os
import signal
import socket
import subprocess
import time

CONF = """ClusterName=meterfleet
SlurmctldHost={host}
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket={d}/munge-run/munge.sock
CredType=cred/munge
StateSaveLocation={d}/state
SlurmdSpoolDir={d}/spool
SlurmctldPidFile={d}/run/slurmctld.pid
SlurmdPidFile={d}/run/slurmd.pid
SlurmctldLogFile={d}/log/slurmctld.log
SlurmdLogFile={d}/log/slurmd.log
SlurmctldPort={ctld_port}
SlurmdPort={slurmd_port}
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/filetxt
JobCompLoc={d}/log/jobcomp.txt
MpiDefault=none
ReturnToService=2
# A node silent for 10 s is down (pinged every third of it): the lost-node test waits this long.
SlurmdTimeout=10
MinJobAge=600
# The main scheduling pass every 2 s instead of 60: a node that returns gets work at once. Pending
# array tasks also start on job completion events; a busy site tunes this for its own load.
SchedulerParameters=sched_interval=2
NodeName={host} CPUs={cpus} RealMemory=2000 State=UNKNOWN
PartitionName=debug Nodes=ALL Default=YES MaxTime=INFINITE State=UP OverSubscribe=NO
"""


def _free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class SlurmCluster:
    def __init__(self, d, cpus=2):
        self.d = os.path.abspath(d)
        self.host = socket.gethostname().split(".")[0]
        self.conf = os.path.join(self.d, "slurm.conf")
        self.cpus = cpus
        self.env = dict(os.environ, SLURM_CONF=self.conf)

    def pidfile(self, name):
        return os.path.join(self.d, "munge-run" if name == "munged" else "run", f"{name}.pid")

    def start(self):
        # munged wants its key private and its socket's folder open to every user (0755).
        for sub in ("munge", "munge-run", "state", "spool", "log", "run", "jobs"):
            os.makedirs(os.path.join(self.d, sub), exist_ok=True)
        os.chmod(self.d, 0o755)
        os.chmod(os.path.join(self.d, "munge"), 0o700)
        key = os.path.join(self.d, "munge", "munge.key")
        with open(key, "wb") as f:
            f.write(os.urandom(1024))
        os.chmod(key, 0o400)
        m = os.path.join(self.d, "munge-run")
        os.chmod(m, 0o755)
        subprocess.run(["munged", f"--key-file={key}", f"--socket={m}/munge.sock", f"--pid-file={m}/munged.pid",
                        f"--log-file={self.d}/log/munged.log", f"--seed-file={self.d}/munge/munged.seed"], check=True)
        with open(self.conf, "w") as f:
            f.write(CONF.format(host=self.host, d=self.d, cpus=self.cpus, ctld_port=_free_port(), slurmd_port=_free_port()))
        subprocess.run(["slurmctld", "-f", self.conf], check=True, env=self.env)
        self.start_slurmd()
        self.wait_idle()

    def start_slurmd(self):
        subprocess.run(["slurmd", "-f", self.conf], check=True, env=self.env)

    def wait_idle(self, timeout=60):
        until = time.monotonic() + timeout
        while time.monotonic() < until:
            p = subprocess.run(["sinfo", "-h", "-o", "%T"], capture_output=True, text=True, env=self.env)
            if p.stdout.strip() in ("idle", "mixed", "allocated"):
                return
            time.sleep(0.5)
        raise RuntimeError(f"slurm node not up within {timeout} s: sinfo says {p.stdout.strip()!r} {p.stderr.strip()}; "
                           f"logs in {self.d}/log")

    def pid(self, name):
        try:
            with open(self.pidfile(name)) as f:
                return int(f.read().split()[0])
        except (OSError, ValueError, IndexError):
            return None

    def stop_daemon(self, name, sig=signal.SIGTERM, timeout=15):
        """Stops one daemon by the pid in its pid file; returns whether one was running."""
        pid = self.pid(name)
        if pid is None:
            return False
        try:
            os.kill(pid, sig)
        except ProcessLookupError:
            return False
        until = time.monotonic() + timeout
        while time.monotonic() < until:
            try:
                os.kill(pid, 0)
            except ProcessLookupError:
                return True
            time.sleep(0.1)
        os.kill(pid, signal.SIGKILL)
        return True

    def stop(self):
        for name in ("slurmd", "slurmctld", "munged"):
            self.stop_daemon(name)

    def __enter__(self):
        try:
            self.start()
        except BaseException:
            self.stop()
            raise
        return self

    def __exit__(self, *exc):
        self.stop()

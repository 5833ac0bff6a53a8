"""Helpers shared by the vcan integration tests: paths, candump -L parsing, running a command
where vcan exists (vcan/with-vcan picks the host or the qemu VM)."""
import os
import re
import subprocess
import time
from dataclasses import dataclass

SOURCE_DIR = os.environ.get("METER_SOURCE_DIR") or os.path.abspath(
    os.path.join(os.path.dirname(__file__), "..", ".."))
BINARY_DIR = os.environ.get("METER_BINARY_DIR") or os.path.join(SOURCE_DIR, "build", "vcan")
SHARED_DIR = os.environ.get("METER_SHARED_DIR") or os.path.abspath(os.path.join(SOURCE_DIR, "..", "shared"))
WITH_VCAN = os.path.join(SOURCE_DIR, "vcan", "with-vcan")
FT86_LOG = os.path.join(SHARED_DIR, "data", "can", "ft86_motec", "can_sample.log")
FT86_DBC = os.path.join(SHARED_DIR, "data", "can", "ft86_motec", "sample_can_spec.dbc")

_LINE = re.compile(r"^\((\d+)\.(\d{6})\)\s+(\S+)\s+([0-9A-Fa-f]+)#(\S*)$")


@dataclass(frozen=True)
class Frame:
    t_us: int        # timestamp in integer microseconds (exact; a float loses sub-us digits)
    iface: str
    can_id: str      # as written: 3 hex digits standard, 8 extended
    data: str        # payload hex (upper case), or R... for remote frames

    @property
    def key(self):
        return (self.can_id.upper(), self.data.upper())


def parse_candump(path, limit=None):
    """Parses a candump -L log; a line that does not parse is an error naming file and line."""
    frames = []
    with open(path, encoding="ascii") as f:
        for lineno, line in enumerate(f, 1):
            line = line.strip()
            if not line:
                continue
            m = _LINE.match(line)
            if not m:
                raise ValueError(f"{path}:{lineno}: expected '(sec.usec) iface id#data', got {line!r}")
            frames.append(Frame(int(m[1]) * 1_000_000 + int(m[2]), m[3], m[4], m[5].upper()))
            if limit is not None and len(frames) >= limit:
                break
    return frames


def out_dir(name):
    """A test's output folder under the build tree (the VM can write there through --share-out)."""
    return os.path.join(BINARY_DIR, "tests", "vcan", "out", name)


def fresh_dir(name):
    """out_dir(name), emptied."""
    d = out_dir(name)
    subprocess.run(["rm", "-rf", d], check=True)
    os.makedirs(d)
    return d


def with_vcan(args, share_out, timeout=110, hostfwd=(), env=(), cpus=None, boot_timeout=75, guest_clock=None,
              vm_args=(), **popen):
    """Starts `vcan/with-vcan` running args; returns the Popen. The timing file in share_out
    receives the VM's boot/command times (vm path only). guest_clock="instructions": the guest's
    clock counts its own instructions (vm path only; see vcan/vm/run-in-vm --help). vm_args: more
    run-in-vm options (--display, --qmp), passed on by with-vcan on the vm path."""
    cmd = [WITH_VCAN, "--share-out", share_out, "--timeout", str(timeout)]
    if guest_clock and os.environ.get("METER_VCAN_MODE_FORCE", "auto") != "direct":
        cmd += ["--guest-clock", guest_clock]
    for h in hostfwd:
        cmd += ["--hostfwd", h]
    for e in env:
        cmd += ["--env", e]
    if cpus:
        cmd += ["--cpus", str(cpus)]
    cmd += list(vm_args)
    # 12 s on an idle 2-core host; a host loaded by parallel builds has been seen at 59 s.
    cmd += ["--boot-timeout", str(boot_timeout)]
    if os.environ.get("METER_VCAN_MODE_FORCE", "auto") != "direct":
        cmd += ["--timing", os.path.join(share_out, "vm-timing.txt")]
    return subprocess.Popen(cmd + ["--"] + list(args), **popen)


def run_with_vcan(args, share_out, timeout=110, **kw):
    t0 = time.monotonic()
    p = with_vcan(args, share_out, timeout=timeout, **kw)
    p.wait(timeout=timeout + 30)
    return p.returncode, time.monotonic() - t0


def vm_timing(share_out):
    path = os.path.join(share_out, "vm-timing.txt")
    if not os.path.exists(path):
        return None
    with open(path) as f:
        return dict(kv.split("=") for kv in f.read().split())


def percentile(values, q):
    s = sorted(values)
    if not s:
        raise ValueError("percentile of nothing")
    i = min(len(s) - 1, max(0, int(round(q / 100.0 * (len(s) - 1)))))
    return s[i]


def free_port():
    """A TCP port free on the host right now; used for both sides of --hostfwd so the same test
    works on the direct path (where the ports must be equal)."""
    import socket
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def canmatrix_series(dbc_path, frames, wanted):
    """Independent reference: decodes frames with python3-canmatrix (not the project's decoder).
    wanted: iterable of (message_name, signal_name). Returns {(msg, sig): [(t_us, physical), ...]}."""
    import canmatrix.formats
    db = next(iter(canmatrix.formats.loadp(dbc_path).values()))
    by_id = {}
    for msg_name, sig_name in wanted:
        frame = db.frame_by_name(msg_name)
        if frame is None:
            raise KeyError(f"{dbc_path}: no message {msg_name}")
        by_id.setdefault(frame.arbitration_id.id, (frame, []))[1].append(sig_name)
    out = {w: [] for w in wanted}
    for fr in frames:
        hit = by_id.get(int(fr.can_id, 16))
        if hit is None or fr.data.startswith("R"):
            continue
        frame, sigs = hit
        decoded = frame.decode(bytes.fromhex(fr.data))
        for s in sigs:
            out[(frame.name, s)].append((fr.t_us, float(decoded[s].phys_value)))
    return out

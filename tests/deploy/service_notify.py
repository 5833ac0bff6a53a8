#!/usr/bin/env python3
"""The service-manager protocol of meter-controller and meter-view against a real listener.

A datagram socket stands where systemd's NOTIFY_SOCKET would; WATCHDOG_USEC is set as a unit's
WatchdogSec= sets it. For each process (the argument: controller or view):
  - READY=1 arrives once the controller's link listens (a connect to it succeeds then) / once the
    view has drawn its first frame (it is drawing: its STATUS says so);
  - WATCHDOG=1 keeps arriving, never silent for a whole WatchdogSec=, about twice a WatchdogSec=;
  - STOPPING=1 on SIGTERM, exit status 0;
  - with the test-only stall (METER_TEST_STALL_AFTER_KEEPALIVES=N) the keep-alives stop after N,
    as a hung loop's would, and the manager would restart it.
"""
import os
import signal
import socket
import subprocess
import sys
import tempfile
import time

BIN = os.path.join(os.environ["METER_BINARY_DIR"], "bin")
SRC = os.environ["METER_SOURCE_DIR"]
SCENE = os.path.join(os.environ["METER_BINARY_DIR"], "deploy", "scenes", "cluster.msp")
WATCHDOG_S = 0.4  # WatchdogSec=: keep-alives are due every 0.2 s
OBSERVE_S = 1.6   # four WatchdogSec= of keep-alives watched


def fail(msg):
    print("FAIL: " + msg)
    sys.exit(1)


class Listener:
    def __init__(self, path):
        self.path = path
        self.sock = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
        self.sock.bind(path)
        self.messages = []  # (monotonic time, {key: value})

    def receive_until(self, done, timeout):
        end = time.monotonic() + timeout
        while not done() and time.monotonic() < end:
            self.sock.settimeout(max(0.01, end - time.monotonic()))
            try:
                data = self.sock.recv(4096)
            except socket.timeout:
                break
            fields = dict(line.split("=", 1) for line in data.decode().splitlines() if "=" in line)
            self.messages.append((time.monotonic(), fields))

    def times(self, key):
        return [t for t, f in self.messages if key in f]


def controller_command(link, extra_env):
    demo = os.path.join(SRC, "controller", "vehicles", "demo")
    cmd = [os.path.join(BIN, "meter-controller"), "run", "--dbc", os.path.join(demo, "demo.dbc"),
           "--map", os.path.join(demo, "demo.map"), "--input",
           "log:" + os.path.join(SRC, "vcan", "logs", "demo-drive.log"), "--link", "unix:" + link]
    return cmd, extra_env


def start(cmd, tmp, name, notify, stall=None):
    env = dict(os.environ)
    env.pop("NOTIFY_SOCKET", None)
    env.pop("WATCHDOG_PID", None)
    if notify:
        env["NOTIFY_SOCKET"] = notify
        env["WATCHDOG_USEC"] = str(int(WATCHDOG_S * 1e6))
    if stall is not None:
        env["METER_TEST_STALL_AFTER_KEEPALIVES"] = str(stall)
    log = open(os.path.join(tmp, name + ".log"), "w")
    return subprocess.Popen(cmd, env=env, stdout=log, stderr=subprocess.STDOUT)


def link_accepts(path):
    s = socket.socket(socket.AF_UNIX, socket.SOCK_SEQPACKET)
    try:
        s.connect(path)
        return True
    except OSError:
        return False
    finally:
        s.close()


def stop(proc, name):
    proc.send_signal(signal.SIGTERM)
    try:
        return proc.wait(timeout=10)
    except subprocess.TimeoutExpired:
        proc.kill()
        fail(name + " did not end within 10 s of SIGTERM")


def check_keepalives(listener, name, ready_at):
    pings = [t for t in listener.times("WATCHDOG") if t >= ready_at]
    window = [ready_at] + pings
    gaps = [b - a for a, b in zip(window, window[1:])]
    if len(pings) < OBSERVE_S / WATCHDOG_S:
        fail(f"{name}: {len(pings)} keep-alives in {OBSERVE_S} s, expected about {2 * OBSERVE_S / WATCHDOG_S:.0f}")
    if max(gaps) >= WATCHDOG_S:
        fail(f"{name}: {max(gaps):.3f} s without a keep-alive, WatchdogSec= is {WATCHDOG_S} s")
    print(f"{name}: {len(pings)} keep-alives in {OBSERVE_S} s after READY=1, longest gap {max(gaps):.3f} s")


def check_stall(listener, name, stall):
    pings = listener.times("WATCHDOG")
    if len(pings) != stall:
        fail(f"{name}: {len(pings)} keep-alives with the stall after {stall}, expected exactly {stall}")
    silent = time.monotonic() - pings[-1]
    if silent < 2 * WATCHDOG_S:
        fail(f"{name}: only {silent:.2f} s silent after the stall")
    print(f"{name}: stalled after {stall} keep-alives, silent {silent:.2f} s (WatchdogSec= {WATCHDOG_S} s)")


def main():
    role = sys.argv[1]
    with tempfile.TemporaryDirectory(prefix="meter-notify-") as tmp:
        link = os.path.join(tmp, "link.sock")
        good = Listener(os.path.join(tmp, "notify.sock"))
        stalled = Listener(os.path.join(tmp, "notify-stall.sock"))
        ccmd, _ = controller_command(link, {})
        procs = []
        if role == "controller":
            proc = start(ccmd, tmp, "controller", good.path)
        else:
            procs.append(start(ccmd, tmp, "controller", None))
            vcmd = [os.path.join(BIN, "meter-view"), "--scene", SCENE, "--link", "unix:" + link, "--fps", "20",
                    "--backend", "egl", "--msaa", "1", "--out", tmp]
            proc = start(vcmd, tmp, "view", good.path)
        good.receive_until(lambda: good.times("READY"), 30)
        if not good.times("READY"):
            fail(f"{role}: no READY=1 within 30 s")
        ready_at = good.times("READY")[0]
        if role == "controller" and not link_accepts(link):
            fail("controller: READY=1 sent but the link does not accept a view")
        status = [f.get("STATUS", "") for _, f in good.messages if "READY" in f][0]
        print(f"{role}: READY=1, STATUS={status}")
        if role == "view" and "drawing" not in status:
            fail("view: READY=1 without saying it draws")
        if good.times("WATCHDOG") and good.times("WATCHDOG")[0] < ready_at:
            fail(f"{role}: a keep-alive before READY=1")
        good.receive_until(lambda: False, OBSERVE_S)
        check_keepalives(good, role, ready_at)
        rc = stop(proc, role)
        good.receive_until(lambda: good.times("STOPPING"), 5)
        if not good.times("STOPPING") or rc != 0:
            fail(f"{role}: exit {rc}, STOPPING=1 {'seen' if good.times('STOPPING') else 'missing'}")

        # The stalled loop: the same process with the test-only stall after 2 keep-alives.
        cmd = ccmd if role == "controller" else vcmd
        proc = start(cmd, tmp, role + "-stall", stalled.path, stall=2)
        stalled.receive_until(lambda: len(stalled.times("WATCHDOG")) >= 2, 30)
        stalled.receive_until(lambda: False, 3 * WATCHDOG_S)
        check_stall(stalled, role, 2)
        stop(proc, role + " (stalled)")
        for p in procs:
            stop(p, "controller")
    print("PASS")


if __name__ == "__main__":
    main()

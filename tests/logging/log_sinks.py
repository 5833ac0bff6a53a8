#!/usr/bin/env python3
"""meter-controller's log records through each sink, from one short replay (docs/logging.md).

The input is the first lines of the demo drive with two broken lines put in: the controller logs a
warning record when the replay meets the first skipped line (field file) and one per bad line (fields file, line), an info
record per connection line with -v, and its stats on stdout. The argument picks the sink:
  json     --log json: every stderr line is one JSON object with time, level, program, component,
           message and the fields; --log-level warning keeps the warnings and drops the info records;
  journal  no --log, JOURNAL_STREAM naming stderr: the records reach a datagram socket standing at
           /run/systemd/journal/socket (a private mount namespace, unshare -rm, so the host's /run
           is untouched) in the journal's native protocol, with PRIORITY, CODE_FILE/CODE_LINE and
           METER_* fields;
  dlt      --log dlt: first with no dlt-daemon (libdlt buffers, then drops at exit: the process must
           still end at once, stdout untouched); then a private dlt-daemon (-t DIR -p PORT, reached
           by DLT_PIPE_DIR / DLT_DAEMON_TCP_PORT) and dlt-receive show the records under app id MCTL
           and context ids INPT and RUN.
"""
import json
import os
import shutil
import socket
import struct
import subprocess
import sys
import tempfile
import threading
import time

BIN = os.path.join(os.environ["METER_BINARY_DIR"], "bin", "meter-controller")
SRC = os.environ["METER_SOURCE_DIR"]
DEMO = os.path.join(SRC, "controller", "vehicles", "demo")


def fail(msg):
    print("FAIL: " + msg)
    sys.exit(1)


def make_log(tmp):
    with open(os.path.join(SRC, "vcan", "logs", "demo-drive.log")) as f:
        lines = [next(f) for _ in range(400)]
    lines.insert(100, "this is no candump line\n")
    lines.insert(200, "(1767225600.5) vcan0 1A0#ZZ\n")
    path = os.path.join(tmp, "broken.log")
    with open(path, "w") as f:
        f.writelines(lines)
    return path


def argv(tmp, log, *extra):
    return [BIN, "run", "--map", os.path.join(DEMO, "demo.map"), "--dbc", os.path.join(DEMO, "demo.dbc"),
            "--input", "log:" + log, "--replay", "fast", "--exit-at-end", "--link", "unix:" + os.path.join(tmp, "c.sock"),
            "-v", *extra]


def run(cmd, env=None, timeout=20):
    t0 = time.monotonic()
    p = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=timeout)
    if p.returncode != 0:
        fail(f"{' '.join(cmd)}: exit {p.returncode}: {p.stderr[-2000:]}")
    return p, time.monotonic() - t0


def check_stdout(p):
    if not p.stdout.startswith("meter-controller: ") or "frames (" not in p.stdout:
        fail(f"stdout is not the stats lines alone: {p.stdout[:300]!r}")


def test_json(tmp, log):
    p, _ = run(argv(tmp, log, "--log", "json"))
    check_stdout(p)
    records = []
    for line in p.stderr.splitlines():
        try:
            records.append(json.loads(line))
        except ValueError:
            fail(f"a stderr line is no JSON object: {line!r}")
    for r in records:
        for key in ("time", "level", "program", "component", "message"):
            if key not in r:
                fail(f"record without {key}: {r}")
        if r["program"] != "meter-controller":
            fail(f"program: {r}")
    bad = [r for r in records if r.get("line") is not None]
    if sorted(r["line"] for r in bad) != [101, 201] or any(r["file"] != log or r["level"] != "warning" for r in bad):
        fail(f"expected two warning records with file {log} and lines 101, 201, got {bad}")
    # A streamed log says so when the replay meets its first bad line ("FILE: bad line(s) skipped:").
    if not any("bad line(s) skipped" in r["message"] and r["component"] == "input" and r.get("file") == log
               for r in records):
        fail("no record for the skipped lines")
    if not any(r["level"] == "info" and r["component"] == "run" and "input" in r for r in records):
        fail("no info record naming the input (-v)")
    p, _ = run(argv(tmp, log, "--log", "json", "--log-level", "warning"))
    levels = {json.loads(line)["level"] for line in p.stderr.splitlines()}
    if levels != {"warning"}:
        fail(f"--log-level warning: expected only warnings, got {levels}")
    print(f"json: {len(records)} records, {len(bad)} bad-line warnings with file and line; --log-level warning "
          "drops the rest")


def parse_native(datagram):
    """The journal's native protocol: KEY=VALUE\\n, or KEY\\n <u64 le size> VALUE \\n."""
    fields, i = {}, 0
    while i < len(datagram):
        nl = datagram.index(b"\n", i)
        entry = datagram[i:nl]
        if b"=" in entry:
            key, _, value = entry.partition(b"=")
            i = nl + 1
        else:
            key = entry
            (size,) = struct.unpack_from("<Q", datagram, nl + 1)
            value = datagram[nl + 9:nl + 9 + size]
            i = nl + 9 + size + 1
        fields[key.decode()] = value.decode()
    return fields


def test_journal_inside(tmp, log):
    subprocess.run(["mount", "-t", "tmpfs", "tmpfs", "/run/systemd"], check=True)
    os.makedirs("/run/systemd/journal")
    sock = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
    sock.bind("/run/systemd/journal/socket")
    sock.settimeout(0.2)
    # Read while the process runs, as journald does: a Unix datagram socket queues only a few
    # datagrams (net.unix.max_dgram_qlen) before the sender blocks.
    datagrams, stop = [], threading.Event()

    def receive():
        while not stop.is_set():
            try:
                datagrams.append(sock.recv(1 << 20))
            except socket.timeout:
                pass

    reader = threading.Thread(target=receive)
    reader.start()
    err_path = os.path.join(tmp, "stderr.txt")
    try:
        with open(err_path, "w") as err:
            st = os.fstat(err.fileno())
            env = dict(os.environ, JOURNAL_STREAM=f"{st.st_dev}:{st.st_ino}")
            p = subprocess.run(argv(tmp, log), stdout=subprocess.PIPE, stderr=err, text=True, env=env, timeout=20)
        time.sleep(0.3)
    finally:
        stop.set()
        reader.join()
    if p.returncode != 0:
        fail(f"exit {p.returncode}: {open(err_path).read()}")
    entries = [parse_native(d) for d in datagrams]
    if open(err_path).read():
        fail(f"records went to stderr instead of the journal: {open(err_path).read()[:300]}")
    bad = [e for e in entries if "METER_LINE" in e]
    if sorted(e["METER_LINE"] for e in bad) != ["101", "201"]:
        fail(f"expected two entries with METER_LINE 101 and 201, got {entries}")
    for e in bad:
        want = {"PRIORITY": "4", "SYSLOG_IDENTIFIER": "meter-controller", "METER_COMPONENT": "input", "METER_FILE": log}
        if any(e.get(k) != v for k, v in want.items()) or not e.get("CODE_FILE", "").endswith("command_output.cpp") \
                or not e.get("CODE_LINE", "").isdigit() or not e.get("MESSAGE", "").startswith("  " + log + ":"):
            fail(f"entry fields: {e}")
    info = [e for e in entries if e.get("PRIORITY") == "6" and e.get("METER_COMPONENT") == "run"]
    if not info:
        fail(f"no info entry from the run: {entries}")
    print(f"journal: {len(entries)} entries on the native socket, chosen by JOURNAL_STREAM; bad lines at "
          "PRIORITY 4 with METER_FILE/METER_LINE, CODE_FILE/CODE_LINE")


def test_journal(tmp, log):
    if not shutil.which("unshare"):
        fail("no unshare (util-linux): the journal check needs a private mount namespace")
    probe = subprocess.run(["unshare", "-rm", "true"], capture_output=True)
    if probe.returncode != 0:
        fail(f"unshare -rm refused here: {probe.stderr.decode().strip()} (the journal check needs a private mount namespace)")
    p = subprocess.run(["unshare", "-rm", sys.executable, __file__, "journal-inside", tmp, log], text=True,
                       capture_output=True, timeout=60)
    sys.stdout.write(p.stdout)
    if p.returncode != 0:
        fail(f"inside the namespace: exit {p.returncode}: {p.stderr[-2000:]}")


def free_port():
    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
    s.close()
    return port


def test_dlt(tmp, log):
    nodaemon = os.path.join(tmp, "no-daemon")
    os.makedirs(nodaemon)
    env = dict(os.environ, DLT_PIPE_DIR=nodaemon, DLT_DAEMON_TCP_PORT=str(free_port()))
    p, took = run(argv(tmp, log, "--log", "dlt"), env=env)
    check_stdout(p)
    if took > 3.0:
        fail(f"without a daemon the run took {took:.1f} s: libdlt blocked")
    print(f"dlt without a daemon: exit 0 in {took:.2f} s; libdlt said: "
          + " / ".join(line.split("~")[-1] for line in p.stderr.splitlines() if "~DLT~" in line))

    pipes, port = os.path.join(tmp, "dlt"), free_port()
    os.makedirs(pipes)
    daemon = subprocess.Popen(["dlt-daemon", "-t", pipes, "-p", str(port)], stdout=subprocess.DEVNULL,
                              stderr=subprocess.DEVNULL)
    recv_out = open(os.path.join(tmp, "received.txt"), "w+")
    receiver = None
    try:
        deadline = time.monotonic() + 5
        while not os.path.exists(os.path.join(pipes, "dlt")) and time.monotonic() < deadline:
            time.sleep(0.02)
        receiver = subprocess.Popen(["dlt-receive", "-a", "-p", str(port), "localhost"], stdout=recv_out,
                                    stderr=subprocess.DEVNULL)
        env = dict(os.environ, DLT_PIPE_DIR=pipes, DLT_DAEMON_TCP_PORT=str(port))
        p, _ = run(argv(tmp, log, "--log", "dlt"), env=env)
        check_stdout(p)
        want = ["MCTL INPT log warn", "MCTL RUN- log info"]
        deadline = time.monotonic() + 5
        while time.monotonic() < deadline:
            recv_out.seek(0)
            got = recv_out.read()
            if all(w in got for w in want) and "line=201" in got:
                break
            time.sleep(0.05)
    finally:
        for proc in (receiver, daemon):
            if proc:
                proc.terminate()
                proc.wait(5)
    lines = [line for line in got.splitlines() if " MCTL " in line]
    for w in want:
        if not any(w in line for line in lines):
            fail(f"no '{w}' record received through dlt-daemon: {lines[:10]}")
    bad = [line for line in lines if "MCTL INPT log warn" in line and f"file={log}" in line and "line=" in line]
    if len(bad) != 2:
        fail(f"expected 2 bad-line warnings with file= and line= arguments, got {bad}")
    print(f"dlt through dlt-daemon: {len(lines)} MCTL messages received, e.g. {bad[0][:160]}")


def main():
    if sys.argv[1] == "journal-inside":
        test_journal_inside(sys.argv[2], sys.argv[3])
        return
    with tempfile.TemporaryDirectory(prefix="meter-logging-") as tmp:
        log = make_log(tmp)
        {"json": test_json, "journal": test_journal, "dlt": test_dlt}[sys.argv[1]](tmp, log)
    print("PASS")


if __name__ == "__main__":
    main()

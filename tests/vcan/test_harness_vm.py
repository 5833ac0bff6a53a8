"""The VM harness's contract beyond CAN: a TCP port of the guest reachable from the host
(--hostfwd, how meter-view on the host talks to meter-controller in the VM), the command's exit
code propagated, bounded boot with the guest console printed on failure, the host's /tmp
visible to the guest (a checkout may live there) without the guest writing to it, a virtio-gpu
display with a QMP socket (--display, --qmp: meter-view --output drm checked by
tests/display/drm_check.py in the same boot), and the harness run from a git clone under /tmp with
its build folder and ../shared."""
import functools
import os
import shutil
import socket
import subprocess
import sys
import tempfile
import time
import unittest

sys.path.insert(0, os.path.dirname(__file__))
import vcanlib as v  # noqa: E402
sys.path.insert(0, os.path.join(v.SOURCE_DIR, "tests", "display"))
import drm_check  # noqa: E402


@functools.lru_cache(maxsize=None)
def on_vm_path():
    """with-vcan boots the VM here (this kernel has no CAN); asked of setup-vcan once."""
    return os.environ.get("METER_VCAN_MODE_FORCE") != "direct" and \
        subprocess.run([os.path.join(v.SOURCE_DIR, "vcan", "setup-vcan"), "probe"]).returncode != 0


def display_part(out):
    """The DRM display's guest command and the host's screendump watcher (tests/display); None in
    a build without meter-view and meter-convert (the display case then fails naming them, the
    others keep their boot)."""
    view, convert = (os.path.join(v.BINARY_DIR, "bin", name) for name in ("meter-view", "meter-convert"))
    if not (os.path.exists(view) and os.path.exists(convert)):
        return "true", [], None
    display_out = os.path.join(out, "display")
    os.makedirs(display_out)
    msp = drm_check.prepare(convert, v.SOURCE_DIR, out)
    qmp_dir = tempfile.mkdtemp(prefix="meter-qmp-", dir="/tmp")  # a socket path must stay short
    qmp = os.path.join(qmp_dir, "qmp.sock")
    watcher = drm_check.ScreenWatcher(qmp, display_out)
    watcher.start()
    vm_args = ["--display", drm_check.DISPLAY, "--qmp", qmp]
    return drm_check.guest_command(view, msp, display_out), vm_args, {"out": display_out, "watcher": watcher,
                                                                       "qmp_dir": qmp_dir}


class HarnessVm(unittest.TestCase):
    """Three of the cases need a whole boot each: the forwarded port with the exit code, the
    host's /tmp, and the display. On the VM path (this kernel has no CAN, so with-vcan boots the VM
    too) all run in one boot, the /tmp checks first, then the display's, and each case judges its
    own part of it; on a CAN kernel with-vcan runs directly and the /tmp and display cases boot
    run-in-vm of their own."""
    shared = None     # the combined boot's results, on the VM path

    @staticmethod
    def hostfwd_guest(out, port):
        # Inside the guest the kernel has CAN, so with-vcan's *direct* path runs there first: it
        # must create vcan1, run the command with METER_VCAN_MODE=direct, and delete vcan1 after.
        direct = os.path.join(out, "direct.txt")
        return (f"{v.WITH_VCAN} --vcan vcan1 -- bash -c 'echo mode=$METER_VCAN_MODE; "
                f"ip -details link show vcan1 | grep -c \" vcan \"' > {direct} 2>&1; "
                f"echo rc=$? >> {direct}; ip link show vcan1 >/dev/null 2>&1; echo after=$? >> {direct}; "
                f"exec /usr/bin/python3 {os.path.join(v.SOURCE_DIR, 'tests', 'vcan', 'guest_echo_server.py')} "
                f"{port} vcan0")

    @staticmethod
    def host_tmp_guest(out, host):
        # A checkout (and ../shared beside it) may live under /tmp: the guest must run what is
        # there, while its own writes to /tmp never reach the host.
        script = os.path.join(host, "hello.sh")
        with open(script, "w") as f:
            f.write("#!/bin/sh\necho \"hello from the host's /tmp\"\n")
        os.chmod(script, 0o755)
        return (f"{script} > {out}/seen.txt 2>&1; "
                f"echo guest > {host}/written-by-guest && echo written > {out}/wrote.txt; "
                f"cat {host}/written-by-guest >> {out}/wrote.txt; "
                f"touch /tmp/meter-guest-scratch && echo scratch-ok >> {out}/wrote.txt")

    @staticmethod
    def talk(p, port, wait_s=80):
        """Sends "exit 7" to the guest's echo server through the forwarded port; its reply."""
        deadline = time.monotonic() + wait_s
        # qemu accepts on the host side at once and drops the connection while nothing listens in
        # the guest, so connect-and-retry until the guest server answers.
        while time.monotonic() < deadline and p.poll() is None:
            try:
                with socket.create_connection(("127.0.0.1", port), timeout=2) as s:
                    s.sendall(b"exit 7\n")
                    data = s.makefile().readline()
                    if data:
                        s.sendall(b"ack\n")   # the server exits only on this (guest_echo_server.py)
                        return data.strip()
            except OSError:
                pass
            time.sleep(0.3)
        return None

    @classmethod
    def setUpClass(cls):
        if not on_vm_path():
            return
        out = v.fresh_dir("harness_vm_shared")
        host = tempfile.mkdtemp(prefix="meter-vm-host-tmp-", dir="/tmp")
        port = v.free_port()
        display, vm_args, shown = display_part(out)
        guest = cls.host_tmp_guest(out, host) + "; " + display + "; " + cls.hostfwd_guest(out, port)
        # 200 s: the boot, the /tmp and port checks, and the display's four views.
        p = v.with_vcan(["bash", "-c", guest], out, timeout=200, hostfwd=[f"{port}:{port}"], vm_args=vm_args)
        reply = cls.talk(p, port, wait_s=170)
        cls.shared = {"out": out, "host": host, "reply": reply, "rc": p.wait(timeout=60), "display": shown}

    @classmethod
    def tearDownClass(cls):
        if cls.shared:
            shutil.rmtree(cls.shared["host"], ignore_errors=True)
            if cls.shared["display"]:
                shutil.rmtree(cls.shared["display"]["qmp_dir"], ignore_errors=True)

    def test_drm_display_in_the_vm(self):
        if self.shared and self.shared["display"] is None:
            self.fail(f"meter-view and meter-convert are not built in {v.BINARY_DIR}/bin: nothing to show")
        # meter-view --output drm on the guest's virtio-gpu: the QMP screendump equals its offscreen
        # render byte for byte (centred, black around), a second view on the card is refused, a
        # view killed with SIGKILL leaves the card free for the next (tests/display/drm_guest.sh).
        if self.shared:
            shown = self.shared["display"]
        else:
            out = v.fresh_dir("harness_display")
            display, vm_args, shown = display_part(out)
            if shown is None:
                self.fail(f"meter-view and meter-convert are not built in {v.BINARY_DIR}/bin: nothing to show")
            p = subprocess.run([os.path.join(v.SOURCE_DIR, "vcan", "vm", "run-in-vm"), "--share-out", out, *vm_args,
                                "--timeout", "150", "--", "bash", "-c", display],
                               capture_output=True, text=True, timeout=180)
            shutil.rmtree(shown["qmp_dir"], ignore_errors=True)
            self.assertEqual(p.returncode, 0, p.stderr[-3000:])
        shown["watcher"].join(timeout=30)
        notes = []
        errors = drm_check.judge(shown["out"], shown["watcher"], notes)
        print("\n".join(notes))
        self.assertEqual(errors, [], "\n".join(errors))

    def test_hostfwd_and_exit_code(self):
        if self.shared:
            out, reply, rc = self.shared["out"], self.shared["reply"], self.shared["rc"]
        else:
            out = v.fresh_dir("harness_hostfwd")
            port = v.free_port()
            p = v.with_vcan(["bash", "-c", self.hostfwd_guest(out, port)], out, timeout=90, hostfwd=[f"{port}:{port}"])
            reply = self.talk(p, port)
            rc = p.wait(timeout=60)
        self.assertEqual(reply, "vcan0 exit 7", "no answer through the forwarded port")
        self.assertEqual(rc, 7, "the guest command's exit code did not reach the host")
        with open(os.path.join(out, "direct.txt")) as f:
            lines = f.read().split()
        if on_vm_path():
            # with-vcan's direct path inside the guest: vcan1 created (a vcan device), mode reported,
            # exit 0, and vcan1 gone afterwards (ip link show fails).
            self.assertIn("mode=direct", lines, f"direct.txt: {lines}")
            self.assertIn("rc=0", lines, f"direct.txt: {lines}")
            self.assertIn("after=1", lines, f"direct.txt: {lines}")

    def test_boot_timeout_prints_console(self):
        # run-in-vm directly (not with-vcan): the VM harness works on any kernel, so this runs on
        # the direct path too.
        out = v.fresh_dir("harness_boot_timeout")
        p = subprocess.run([os.path.join(v.SOURCE_DIR, "vcan", "vm", "run-in-vm"), "--share-out", out,
                            "--boot-timeout", "1", "--", "true"], capture_output=True, text=True, timeout=60)
        self.assertEqual(p.returncode, 125)
        self.assertIn("boot did not finish within 1s", p.stderr)
        self.assertIn("---- guest console ----", p.stderr)
        self.assertIn("---- end of guest console ----", p.stderr)

    def test_host_tmp_readable_but_guest_writes_stay_in_the_guest(self):
        if self.shared:
            out, host = self.shared["out"], self.shared["host"]
            self.check_host_tmp(out, host)
            return
        out = v.fresh_dir("harness_host_tmp")
        host = tempfile.mkdtemp(prefix="meter-vm-host-tmp-", dir="/tmp")
        try:
            p = subprocess.run([os.path.join(v.SOURCE_DIR, "vcan", "vm", "run-in-vm"), "--share-out", out,
                                "--", "bash", "-c", self.host_tmp_guest(out, host)],
                               capture_output=True, text=True, timeout=110)
            self.assertEqual(p.returncode, 0, p.stderr)
            self.check_host_tmp(out, host)
        finally:
            shutil.rmtree(host, ignore_errors=True)

    def check_host_tmp(self, out, host):
        with open(os.path.join(out, "seen.txt")) as f:
            self.assertEqual(f.read().strip(), "hello from the host's /tmp")
        with open(os.path.join(out, "wrote.txt")) as f:
            self.assertEqual(f.read().split(), ["written", "guest", "scratch-ok"])
        self.assertFalse(os.path.exists(os.path.join(host, "written-by-guest")),
                         "a write to /tmp in the guest reached the host")
        self.assertFalse(os.path.exists("/tmp/meter-guest-scratch"))


class HarnessFromClone(unittest.TestCase):
    def test_harness_from_a_clone_under_tmp(self):
        # The whole chain from a checkout under /tmp: a git clone of this tree with ../shared beside
        # it (a symlink, as a checkout next to the data would have) and a build folder inside it.
        # The clone's own with-vcan boots the VM, which runs the clone's setup-vcan and guest script,
        # the clone's build of meter-controller reading the clone's vehicle files, and reads
        # ../shared through the clone: nothing of it may be hidden in the guest.
        clone_root = tempfile.mkdtemp(prefix="meter-clone-", dir="/tmp")
        try:
            clone = os.path.join(clone_root, "meter")
            subprocess.run(["git", "clone", "-q", v.SOURCE_DIR, clone], check=True, timeout=60)
            os.symlink(os.path.realpath(v.SHARED_DIR), os.path.join(clone_root, "shared"))
            os.makedirs(os.path.join(clone, "build", "bin"))
            shutil.copy2(os.path.join(v.BINARY_DIR, "bin", "meter-controller"), os.path.join(clone, "build", "bin"))
            out = os.path.join(clone, "build", "vcan-out")   # the writable share lives under /tmp too
            os.makedirs(out)
            subprocess.run(f"head -n 2500 {clone}/vcan/logs/demo-drive.log > {out}/head.log", shell=True, check=True)
            shared_log = os.path.join(clone, "..", "shared", "data", "can", "ft86_motec", "can_sample.log")
            guest = (f"head -n 3 {shared_log} > {out}/shared.txt && "
                     f"exec /bin/sh {clone}/controller/tests/socketcan_guest.sh")
            env = dict(os.environ, METER_VM_CACHE=os.environ.get("METER_VM_CACHE", os.path.join(
                v.SOURCE_DIR, "build", "vcan-vm-cache")))
            # The guest's instruction-counted clock, as the controller's own vcan tests use for this
            # guest script (nothing on the host meets it in real time).
            p = subprocess.run([os.path.join(clone, "vcan", "with-vcan"), "--guest-clock", "instructions",
                                "--share-out", out, "--timeout", "110",
                                "--env", f"METER_BIN={clone}/build/bin/meter-controller", "--env",
                                f"METER_SRC={clone}", "--env", f"OUT={out}", "--", "bash", "-c", guest],
                               capture_output=True, text=True, timeout=170, env=env, cwd=clone)
            self.assertEqual(p.returncode, 0, p.stderr[-3000:])
            with open(shared_log) as f:
                first = [next(f) for _ in range(3)]
            with open(os.path.join(out, "shared.txt")) as f:
                self.assertEqual(f.readlines(), first, "../shared of the clone, read in the guest")
            with open(os.path.join(out, "ctl.out")) as f:
                self.assertIn(" 2500 frames (2500 mapped, 0 unknown id", f.read())
            with open(os.path.join(out, "ctl.err")) as f:
                self.assertIn("exit=0", f.read())
        finally:
            shutil.rmtree(clone_root, ignore_errors=True)


if __name__ == "__main__":
    unittest.main(verbosity=2)

#!/usr/bin/env python3
"""The Debian packages, built from this build tree (no rebuild: the tree is built before the tests),
checked, unpacked into a fresh root and run from there alone.

  1. cpack writes meter-controller, meter-view, meter-tools and meter-dev; lintian finds no error.
  2. Each package's Depends is satisfied on this machine (what dpkg -i would check); each is unpacked
     (dpkg -x) into a root under a temporary folder, outside the source and build trees. The font
     travels in the scene package: meter-tools (which converts) depends on fonts-dejavu-core, meter-view
     does not.
  3. The packages' users made in the root by systemd-sysusers; the units in the root pass
     systemd-analyze verify (their programs are the root's).
  4. The demo's path from the root only, as the units run it: the controller replays the bundled
     drive log with the shipped vehicle files and configuration, the view draws the shipped scene
     from its link and dumps frames. Both run under strace: no path into the source or build tree is
     opened, stat'ed or executed, and the view opens no font file (its texts' font is the package's).
  5. The development kit: a program built with pkg-config's flags for meter-protocol, and a CMake
     project's find_package(meter), against the root, link the protocol library and run.
"""
import glob
import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile
import time

BUILD = os.path.realpath(os.environ["METER_BINARY_DIR"])
SRC = os.path.realpath(os.environ["METER_SOURCE_DIR"])
PREFIX = os.environ.get("METER_INSTALL_PREFIX", "/usr")
ROLES = ["controller", "view", "tools", "dev"]


def fail(msg):
    print("FAIL: " + msg)
    sys.exit(1)


def run(cmd, **kw):
    t = time.monotonic()
    p = subprocess.run(cmd, capture_output=True, text=True, **kw)
    print(f"$ {' '.join(cmd[:4])}{' ...' if len(cmd) > 4 else ''}  ({time.monotonic() - t:.1f} s, exit {p.returncode})")
    return p


def build_packages(out):
    p = run(["cpack", "--config", os.path.join(BUILD, "CPackConfig.cmake"), "-B", out])
    if p.returncode != 0:
        fail("cpack failed:\n" + p.stdout + p.stderr)
    debs = {}
    for role in ROLES:
        found = glob.glob(os.path.join(out, f"meter-{role}_*.deb"))
        if len(found) != 1:
            fail(f"cpack wrote {found} for meter-{role}, expected one .deb")
        debs[role] = found[0]
    return debs


def lintian(debs):
    p = run(["lintian", "--fail-on", "error", "--tag-display-limit", "0", *debs.values()])
    print(p.stdout + p.stderr)
    if p.returncode != 0 or re.search(r"^E: ", p.stdout, re.M):
        fail("lintian reports errors")


def satisfied(relation):
    """One alternative 'pkg (op version)' installed on this machine at a fitting version."""
    m = re.fullmatch(r"\s*([a-z0-9.+-]+)(?::any)?\s*(?:\((<<|<=|=|>=|>>)\s*([^)]+)\))?\s*", relation)
    if not m:
        fail(f"cannot read the relation '{relation}'")
    # One line per installed architecture (a foreign one, arm64 for the cross build, lists libc6
    # twice): the package of this machine's architecture, or of all, is the one dpkg -i checks.
    q = subprocess.run(["dpkg-query", "-W", "-f", "${Status}\t${Version}\t${Architecture}\n", m.group(1)],
                       capture_output=True, text=True)
    native = subprocess.run(["dpkg", "--print-architecture"], capture_output=True, text=True).stdout.strip()
    versions = [f[1] for f in (line.split("\t") for line in q.stdout.splitlines())
                if f[0] == "install ok installed" and f[2] in (native, "all")]
    if q.returncode != 0 or not versions:
        return False
    if not m.group(2):
        return True
    ops = {"<<": "lt", "<=": "le", "=": "eq", ">=": "ge", ">>": "gt"}
    return subprocess.run(["dpkg", "--compare-versions", versions[0], ops[m.group(2)], m.group(3)]).returncode == 0


def check_depends_and_unpack(debs, root):
    for role, deb in debs.items():
        depends = subprocess.run(["dpkg-deb", "-f", deb, "Depends"], capture_output=True, text=True).stdout.strip()
        if role != "dev" and not depends:
            fail(f"meter-{role} states no Depends")
        for clause in filter(None, (c.strip() for c in depends.split(","))):
            if not any(satisfied(alt) for alt in clause.split("|")):
                fail(f"meter-{role}: Depends '{clause}' is not satisfied here: dpkg -i would refuse it")
        print(f"meter-{role}: Depends: {depends or '(none)'}")
        names = {re.split(r"[\s(:]", alt.strip())[0] for alt in re.split(r"[,|]", depends)}
        if ("fonts-dejavu-core" in names) != (role == "tools"):
            fail(f"meter-{role}: Depends {'lacks' if role == 'tools' else 'names'} fonts-dejavu-core (the converter "
                 "embeds the font in the scene package; the view reads it from there)")
        if subprocess.run(["dpkg", "-x", deb, root]).returncode != 0:
            fail(f"dpkg -x {deb} failed")


def make_users(root):
    """The packages' sysusers.d files applied to the root, as their postinst applies them."""
    files = sorted(glob.glob(os.path.join(root, "usr/lib/sysusers.d/meter-*.conf")))
    p = run(["systemd-sysusers", f"--root={root}", *files])
    if p.returncode != 0 or len(files) != 2:
        fail(f"systemd-sysusers on {files}:\n" + p.stdout + p.stderr)
    passwd = open(os.path.join(root, "etc/passwd")).read()
    group = open(os.path.join(root, "etc/group")).read()
    for user in ("meter-controller", "meter-view"):
        if not re.search(rf"^{user}:x:\d+:\d+:.*:/usr/sbin/nologin$", passwd, re.M):
            fail(f"no system user {user} in the root's /etc/passwd:\n{passwd}")
    if not re.search(r"^meter:x:\d+:meter-view$", group, re.M):
        fail(f"the view's user is not in the group meter (the socket's):\n{group}")
    print("users: meter-controller, meter-view (in the group meter)")


def verify_units(root):
    units = sorted(glob.glob(os.path.join(root, "lib/systemd/system/meter-*.service")))
    if len(units) != 2:
        fail(f"expected the controller's and the view's unit in the root, found {units}")
    # The units they need (sysinit.target, multi-user.target, ...) from this machine's systemd, as
    # the system the packages install into would have them.
    shutil.copytree("/lib/systemd/system", os.path.join(root, "usr/lib/systemd/system"), symlinks=True)
    p = run(["systemd-analyze", "verify", "--man=no", f"--root={root}", *units])
    print(p.stdout + p.stderr)
    if p.returncode != 0 or p.stderr.strip():
        fail("systemd-analyze verify reports problems with the units")


def unit_command(root, role, tmp, overrides):
    """The unit's ExecStart with its configuration file's arguments, every path in the root."""
    unit = open(os.path.join(root, f"lib/systemd/system/meter-{role}.service")).read()
    conf = open(os.path.join(root, f"etc/meter/{role}.conf")).read()
    var, args = re.search(r"^(METER_\w+_ARGS)=(.*)$", conf, re.M).groups()
    exec_start = re.search(r"^ExecStart=(.*)$", unit, re.M).group(1).replace("$" + var, args)
    words = []
    for w in shlex.split(exec_start):
        w = w.replace("/run/meter/", tmp + "/run/").replace(f"/var/lib/meter-{role}", f"{tmp}/state-{role}")
        w = re.sub(r"(^|:)(" + re.escape(PREFIX) + r"/)", lambda m: m.group(1) + root + m.group(2), w)
        words.append(w)
    for option, value in overrides.items():
        if option in words:
            words[words.index(option) + 1] = value
        else:
            words += [option, value]
    return words


def traced(cmd, trace, log):
    # Only what a process asks of the file system by name; the seccomp filter keeps strace's cost low.
    env = {"PATH": "/usr/bin:/bin", "HOME": os.path.dirname(trace), "LANG": "C.UTF-8"}
    return subprocess.Popen(["strace", "-f", "-qq", "--seccomp-bpf", "-e", "trace=%file", "-o", trace, *cmd],
                            env=env, cwd=os.path.dirname(trace), stdout=log, stderr=subprocess.STDOUT)


def run_demo(root, tmp):
    os.makedirs(tmp + "/run")
    frames = tmp + "/state-view"
    os.makedirs(frames)
    controller = unit_command(root, "controller", tmp, {"--replay": "scale:30"}) + ["--exit-at-end", "--linger", "1"]
    view = unit_command(root, "view", tmp, {"--fps": "10", "--dump-every": "5", "--duration": "4", "--msaa": "1"})
    print("controller: " + " ".join(controller))
    print("view: " + " ".join(view))
    vlog, clog = open(tmp + "/view.log", "w"), open(tmp + "/controller.log", "w")
    v = traced(view, tmp + "/view.strace", vlog)
    time.sleep(0.3)
    c = traced(controller, tmp + "/controller.strace", clog)
    crc, vrc = c.wait(timeout=60), v.wait(timeout=60)
    for name, rc in (("controller", crc), ("view", vrc)):
        print(f"--- {name} (exit {rc}), its last lines:\n" + "\n".join(open(f"{tmp}/{name}.log").read().splitlines()[-3:]))
        if rc != 0:
            fail(f"the installed {name} failed")
    stats = open(tmp + "/controller.log").read()
    m = re.search(r"(\d+) frames \((\d+) mapped", stats)
    if not m or int(m.group(2)) == 0:
        fail("the installed controller mapped no frame of the demo log")
    pngs = glob.glob(frames + "/*.png")
    if len(pngs) < 3 or not os.path.exists(frames + "/frames.csv"):
        fail(f"the installed view dumped {len(pngs)} frames into {frames}")
    print(f"demo from the root: {m.group(2)} frames mapped, {len(pngs)} frames dumped")
    for name in ("controller", "view"):
        text = open(f"{tmp}/{name}.strace").read()
        if root not in text:
            fail(f"the {name}'s trace names no file of the root: the trace is not of the installed program")
        for tree in (SRC, BUILD):
            for line in text.splitlines():
                if tree in line:
                    fail(f"the installed {name} reached into {tree}:\n{line}")
        print(f"{name}: {len(text.splitlines())} file-system calls traced, none into the source or build tree")
    # The texts are drawn (the speed readout, live) from the font in the scene package.
    fonts = [line for line in open(tmp + "/view.strace").read().splitlines()
             if re.search(r"\.(ttf|otf|pfb|pfa|woff2?)\b|/fonts/|fontconfig", line, re.I)]
    if fonts:
        fail("the installed view looked for a font file:\n" + "\n".join(fonts[:5]))
    print("view: no font file opened (the scene package carries it)")


def check_dev_kit(root, tmp):
    probe = tmp + "/probe.cpp"
    with open(probe, "w") as f:
        f.write('#include <meter/protocol/endpoint.hpp>\n#include <cstdio>\n'
                'int main() { std::puts(meter::protocol::Endpoint::parse("tcp:localhost:7000").to_string().c_str()); }\n')
    libdir = glob.glob(root + PREFIX + "/lib/*/pkgconfig") + glob.glob(root + PREFIX + "/lib/pkgconfig")
    # The root's pkg-config files first, then this machine's: the kit's own dependencies (libsodium)
    # are Debian packages its Depends names, installed here (checked above), not in the root.
    host = run(["pkg-config", "--variable", "pc_path", "pkg-config"]).stdout.strip().split(":")
    env = dict(os.environ, PKG_CONFIG_SYSROOT_DIR=root, PKG_CONFIG_LIBDIR=":".join(libdir + host))
    flags = run(["pkg-config", "--cflags", "--libs", "meter-protocol"], env=env)
    if flags.returncode != 0:
        fail("pkg-config does not find meter-protocol in the root:\n" + flags.stderr)
    p = run(["g++", probe, *shlex.split(flags.stdout), "-o", tmp + "/probe"])
    if p.returncode != 0:
        fail("a program does not build with pkg-config's flags:\n" + p.stderr)
    out = run([tmp + "/probe"]).stdout.strip()
    if out != "tcp:localhost:7000":
        fail(f"the probe built against the root printed '{out}'")
    consumer = tmp + "/consumer"
    os.makedirs(consumer)
    with open(consumer + "/CMakeLists.txt", "w") as f:
        f.write("cmake_minimum_required(VERSION 3.25)\nproject(consumer CXX)\nfind_package(meter 0.1 REQUIRED)\n"
                f"add_executable(probe {probe})\ntarget_link_libraries(probe PRIVATE meter::protocol)\n")
    p = run(["cmake", "-S", consumer, "-B", consumer + "/build", "-G", "Ninja", "-DCMAKE_PREFIX_PATH=" + root + PREFIX])
    if p.returncode != 0:
        fail("find_package(meter) fails against the root:\n" + p.stdout + p.stderr)
    p = run(["cmake", "--build", consumer + "/build"])
    if p.returncode != 0:
        fail("a program does not build against meter::protocol:\n" + p.stdout)
    if run([consumer + "/build/probe"]).stdout.strip() != "tcp:localhost:7000":
        fail("the find_package(meter) probe printed the wrong endpoint")
    print("dev kit: pkg-config meter-protocol and find_package(meter) build and run a program against the root")


def main():
    with tempfile.TemporaryDirectory(prefix="meter-deploy-") as tmp:
        tmp = os.path.realpath(tmp)
        if tmp.startswith(SRC) or tmp.startswith(BUILD):
            fail(f"the temporary root {tmp} lies inside the source or build tree")
        debs = build_packages(tmp + "/packages")
        lintian(debs)
        root = tmp + "/root"
        check_depends_and_unpack(debs, root)
        make_users(root)
        verify_units(root)
        run_demo(root, tmp)
        check_dev_kit(root, tmp)
    print("PASS")


if __name__ == "__main__":
    main()

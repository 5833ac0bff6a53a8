#!/usr/bin/env python3
"""Runs a build's ctest tests of one label, one process per test program instead of one per test:
    run_unit_groups.py BUILD_DIR LABEL_REGEX EXCLUDE_REGEX JOBS
Under qemu-user a process start costs about half a second, so ctest's one process per GoogleTest
case spends most of the emulated run starting programs. Here the tests ctest would run (the same
label and exclusion, read from `ctest --show-only=json-v1`) are grouped by program, working folder
and environment, and each group runs once with a --gtest_filter naming exactly its tests; a test
without a gtest filter runs alone as ctest would. A test that fails in its group runs again alone, one
process as ctest runs it (emulated, one test's child process has been seen to fail beside the others
of its program and pass alone: both outcomes are printed). Exit 1 naming every test that also fails
alone, or a group that failed without naming a test."""
import concurrent.futures
import json
import os
import re
import subprocess
import sys
import time


def groups(build, label, exclude):
    listing = subprocess.run(["ctest", "--test-dir", build, "-L", label, "-E", exclude, "-N", "--show-only=json-v1"],
                             capture_output=True, text=True, check=True)
    out = {}
    for test in json.loads(listing.stdout)["tests"]:
        props = {p["name"]: p["value"] for p in test.get("properties", [])}
        cmd = test["command"]
        names = [a[len("--gtest_filter="):] for a in cmd if a.startswith("--gtest_filter=")]
        base = tuple(a for a in cmd if not a.startswith("--gtest_filter="))
        key = (base, props.get("WORKING_DIRECTORY", build), tuple(props.get("ENVIRONMENT", [])))
        if names:
            out.setdefault(key, []).extend(names)
        else:
            out[key + (test["name"],)] = None  # not a GoogleTest case: alone
    return out


def run(key, names):
    base, cwd, env = key[0], key[1], key[2]
    cmd = list(base) + (["--gtest_filter=" + ":".join(names)] if names else [])
    environ = dict(os.environ)
    environ.update(e.split("=", 1) for e in env)
    start = time.monotonic()
    p = subprocess.run(cmd, cwd=cwd, env=environ, capture_output=True, text=True)
    return p.returncode, time.monotonic() - start, p.stdout + p.stderr, names


def failed_names(output):
    """The GoogleTest summary's failed tests ("[  FAILED  ] Suite.Name", after "listed below")."""
    below = output.split("listed below:", 1)
    if len(below) != 2:
        return []
    return re.findall(r"^\[  FAILED  \] (\S+)", below[1], flags=re.M)


def main():
    if len(sys.argv) != 5:
        sys.exit(__doc__)
    build, label, exclude, jobs = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4])
    work = groups(build, label, exclude)
    if not work:
        sys.exit(f"run_unit_groups: no test labelled '{label}' in {build}")
    failed, tests = [], 0
    with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
        futures = {pool.submit(run, k, n): k for k, n in work.items()}
        for f in concurrent.futures.as_completed(futures):
            rc, seconds, output, names = f.result()
            program = next((a for a in futures[f][0] if "/bin/" in a and not a.startswith("/usr/")), futures[f][0][-1])
            count = len(names) if names else 1
            tests += count
            print(f"{'ok  ' if rc == 0 else 'FAIL'} {count:4d} test(s) {seconds:7.1f} s  {program}", flush=True)
            if rc == 0:
                continue
            print(output[-20000:], flush=True)
            again = failed_names(output) if names else []
            if not again:
                failed.append(program)
                continue
            for name in again:
                rc1, s1, out1, _ = run(futures[f], [name])
                print(f"{'ok  ' if rc1 == 0 else 'FAIL'}    alone {s1:7.1f} s  {name}", flush=True)
                if rc1 != 0:
                    failed.append(name)
                    print(out1[-20000:], flush=True)
    print(f"run_unit_groups: {tests} tests in {len(work)} processes, {len(failed)} failed")
    if failed:
        sys.exit("run_unit_groups: failed: " + ", ".join(failed))


if __name__ == "__main__":
    main()

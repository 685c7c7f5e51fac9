"""What the Python script tests share (tests/cluster_test.py, tests/study_cluster_test.py): named
steps and checks that print as they go and collect the failures, a logged subprocess runner, and
a wrapper program that fails for one value of one option, to exercise the drivers' retries."""

import os
import subprocess
import sys
import time

failures = []


def step(text):
    print(f"== {text}", flush=True)


def check(condition, what, detail=""):
    if condition:
        print(f"   ok: {what}", flush=True)
    else:
        print(f"   FAILED: {what}" + (f"\n{detail}" if detail else ""), flush=True)
        failures.append(what)
    return condition


def run(cmd, env=None, timeout=400):
    start = time.monotonic()
    proc = subprocess.run(cmd, env=env, stdin=subprocess.DEVNULL, capture_output=True, text=True, timeout=timeout)
    print(f"   $ {' '.join(cmd)}\n     exit {proc.returncode} in {time.monotonic() - start:.1f} s", flush=True)
    return proc


def finish():
    """Exit 1 naming the failed checks, or print that all passed."""
    if failures:
        print(f"FAILED: {len(failures)} check(s): " + "; ".join(failures))
        sys.exit(1)
    print("all checks passed")


FLAKY_WRAPPER = """#!/bin/sh
# A test wrapper: when the argument after {option} is $OAS_TEST_FAIL_VALUE, fail the first time (or
# every time with OAS_TEST_FAIL_MODE=always), appending a line to $OAS_TEST_MARKER; otherwise, and
# after that, run $OAS_TEST_REAL with the same arguments.
prev=
for arg in "$@"; do
  if [ "$prev" = {option} ] && [ "$arg" = "$OAS_TEST_FAIL_VALUE" ]; then
    if [ "$OAS_TEST_FAIL_MODE" = always ] || [ ! -e "$OAS_TEST_MARKER" ]; then
      echo "$arg" >> "$OAS_TEST_MARKER"
      echo "test wrapper: injected failure for {option} $arg" >&2
      exit 1
    fi
  fi
  prev=$arg
done
exec "$OAS_TEST_REAL" "$@"
"""


def write_flaky_wrapper(path, option):
    """Writes the wrapper (FLAKY_WRAPPER) for `option` at path. Its environment: OAS_TEST_REAL (the
    program), OAS_TEST_MARKER (a file), OAS_TEST_FAIL_VALUE and optionally OAS_TEST_FAIL_MODE."""
    with open(path, "w") as f:
        f.write(FLAKY_WRAPPER.replace("{option}", option))
    os.chmod(path, 0o755)

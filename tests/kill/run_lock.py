#!/usr/bin/env python3
"""One run at a time on a case, and what a killed run leaves behind cleared at the next start.

  * A second run on a case that a run is using stops at once with status 6, names the
    first run's PID, and touches nothing: the first run finishes and its output equals an
    uninterrupted run's byte for byte (CPU, one thread).
  * A lock left by a run that no longer exists (a lock file naming a dead PID) is no lock:
    the next run takes it over.
  * The hidden temporaries a killed run left (".<file>.tmp<pid>_<n>", as the atomic writes
    name them) in VTK/, postProcessing/<function>/ and checkpoints/ are removed by the next
    run's start (--restart included), and none is left at its end.

Exit status 0 when every check holds; 1 with the failed checks listed.
"""
import argparse
import os
import subprocess
import sys
import tempfile
import time
import shutil

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "support"))
from case_copy import copy_case  # noqa: E402

LOCK = ".scree.lock"


def output_files(case):
    out = {}
    for sub in ("VTK", "postProcessing"):
        for root, _, files in os.walk(os.path.join(case, sub)):
            for f in files:
                p = os.path.join(root, f)
                with open(p, "rb") as h:
                    out[os.path.relpath(p, case)] = h.read()
    return out


def hidden(case):
    return sorted(os.path.relpath(os.path.join(root, f), case) for root, _, files in os.walk(case) for f in files
                  if f.startswith(".") and f != LOCK)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scree", required=True)
    ap.add_argument("--case", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "case"))
    a = ap.parse_args()
    env = dict(os.environ, OMP_NUM_THREADS="1")
    base = [a.scree, "--device", "cpu", "--threads", "1"]
    failures = []
    tmp = tempfile.mkdtemp(prefix="scree_lock_")
    try:
        ref, work = os.path.join(tmp, "reference"), os.path.join(tmp, "work")
        copy_case(a.case, ref)
        copy_case(a.case, work)
        r = subprocess.run(base + ["--case", ref], env=env, capture_output=True, text=True)
        if r.returncode != 0:
            print(r.stdout, r.stderr)
            print(f"FAIL: the reference run exited {r.returncode}")
            return 1

        # 1. A second run while the first holds the case.
        first = subprocess.Popen(base + ["--case", work], env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                 text=True)
        lock = os.path.join(work, LOCK)
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline and first.poll() is None:
            if os.path.exists(lock) and f"PID {first.pid} " in open(lock).read():
                break
            time.sleep(0.01)
        if first.poll() is not None:
            failures.append("the first run ended before a second one could be started beside it")
        else:
            t0 = time.monotonic()
            second = subprocess.run(base + ["--case", work, "--overwrite"], env=env, capture_output=True, text=True)
            took = time.monotonic() - t0
            if second.returncode != 6:
                failures.append(f"a second run on a case in use exited {second.returncode}, not 6:\n{second.stderr}")
            if f"PID {first.pid}" not in second.stderr or "in use by another run" not in second.stderr:
                failures.append(f"the second run's message does not name the first run (PID {first.pid}):\n"
                                f"{second.stderr}")
            print(f"second run: status {second.returncode} after {took:.2f} s: {second.stderr.strip()}")
        out, _ = first.communicate()
        if first.returncode != 0:
            failures.append(f"the first run exited {first.returncode} with a second run beside it:\n{out[-2000:]}")
        ref_files, work_files = output_files(ref), output_files(work)
        if ref_files != work_files:
            differ = sorted(k for k in set(ref_files) | set(work_files) if ref_files.get(k) != work_files.get(k))
            failures.append(f"the first run's output differs from an uninterrupted run's: {differ[:5]}")

        # 2. A stale lock and a killed run's temporaries, then --restart from the older checkpoint.
        with open(lock, "w") as f:
            f.write("PID 999999999 on host nowhere, started 2000-01-01 00:00:00 UTC\n")
        planted = []
        for sub, name in (("VTK", ".particles_7.vtp.tmp12345_0"), ("postProcessing/front", ".runOut.csv.tmp12345_3"),
                          ("postProcessing/energy", ".energies.csv.tmp12345_1"),
                          ("checkpoints", ".1.4.ckpt.tmp12345_2")):
            p = os.path.join(work, sub, name)
            with open(p, "w") as f:
                f.write("half a file")
            planted.append(p)
        ckpts = sorted((f for f in os.listdir(os.path.join(work, "checkpoints")) if f.endswith(".ckpt")),
                       key=lambda f: float(f[:-5]))
        older = ckpts[-2][:-5] if len(ckpts) > 1 else None
        if older is None:
            failures.append(f"the case kept fewer than two checkpoints: {ckpts}")
            older = "0"
        r = subprocess.run(base + ["--case", work, f"--restart={older}"], env=env, capture_output=True, text=True)
        if r.returncode != 0:
            failures.append(f"a restart after a stale lock and a killed run's temporaries exited {r.returncode}:\n"
                            f"{r.stderr[-2000:]}")
        left = [p for p in planted if os.path.exists(p)]
        if left:
            failures.append(f"temporaries a killed run left were not removed: {left}")
        if hidden(work):
            failures.append(f"hidden files left after the run: {hidden(work)}")
        if output_files(work) != ref_files:
            failures.append("the run after the clean-up does not reproduce the uninterrupted run")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    for f in failures:
        print("FAIL:", f)
    if not failures:
        print("run lock and start-up clean-up: every check holds")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())

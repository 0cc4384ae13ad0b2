#!/usr/bin/env python3
"""A shipped case is a case you can copy: copied without results to a temporary directory
outside the repository (as a user copies a tutorial), it and each of its variants (run from
within the copy, as they include their parent case's files) pass `scree --check`.

    check_case_copy.py --scree BUILD/bin/scree cases/NAME

A file that includes another outside its case, an STL or table that lives elsewhere, fails
here with scree's own message. The free memory the check compares the case with is fixed
(SCREE_TEST_FREE_MEMORY) so that the result does not depend on the machine.

Exit status 0 when every check passes; 1 with scree's output for each that failed.
"""
import argparse
import os
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "support"))
from case_copy import copy_case  # noqa: E402


def is_case(d):
    return os.path.isfile(os.path.join(d, "system", "controlDict"))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scree", required=True)
    ap.add_argument("case")
    a = ap.parse_args()
    tmp = tempfile.mkdtemp(prefix="scree_case_copy_")
    failures = 0
    try:
        copy = os.path.join(tmp, os.path.basename(os.path.normpath(a.case)))
        copy_case(a.case, copy)
        checks = [copy]
        variants = os.path.join(copy, "variants")
        if os.path.isdir(variants):
            checks += [os.path.join(variants, v) for v in sorted(os.listdir(variants))
                       if is_case(os.path.join(variants, v))]
        env = dict(os.environ, SCREE_TEST_FREE_MEMORY="1e12")
        for case in checks:
            r = subprocess.run([a.scree, "--case", case, "--check", "--device", "cpu"], env=env, stdout=subprocess.PIPE,
                               stderr=subprocess.STDOUT, text=True, timeout=300)
            rel = os.path.relpath(case, tmp)
            if r.returncode != 0:
                failures += 1
                print(f"FAIL: scree --check on a copy of {rel} exited {r.returncode}:\n{r.stdout}")
            else:
                print(f"ok: {rel}")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    print(f"{len(checks) - failures} of {len(checks)} copies pass --check")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())

"""Copying a shipped case as a user starts from it, for the Python tests.

The same rule as copy_case() in tests/support/scree_test.hpp (the C++ tests): a case
directory (cases/<name>, one of its variants, or a test's own case) is copied without
what a run of it or of one of its variants left there: no VTK/, postProcessing/ or
checkpoints/ directory, hidden temporary or lock file, at any depth. The setup script's default run leaves results in
cases/elasticColumn; a test that copied them along failed on a fresh machine.
"""
import os
import shutil

RESULTS = ("VTK", "postProcessing", "checkpoints")


def _left_by_a_run(name):
    return name in RESULTS or name.startswith(".") or name.endswith(".lock")


def copy_case(src, dst):
    """Copy the case directory src to dst (created; it must not exist) without results."""
    shutil.copytree(src, dst, ignore=lambda directory, names: [n for n in names if _left_by_a_run(n)])

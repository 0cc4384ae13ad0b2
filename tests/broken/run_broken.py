#!/usr/bin/env python3
"""Broken cases: each variant breaks the valid case base/ in one way and asserts what
`scree` does about it.

    run_broken.py --scree BUILD/bin/scree VARIANT_DIR [VARIANT_DIR ...]

A variant is a directory under variants/ holding
  variant.json   what to run and what to expect (below);
  prepare.sh     optional: run with bash -e in the copied case directory (mkfifo, sed, ...;
                 $SCREE is the scree under test, to run the case first);
  any other file copied over the case at its relative path (e.g. constant/bodies).

variant.json:
  "doc":        the defect it guards against (one line)
  "base":       optional: the valid case to break, relative to the repository root
                (default: tests/broken/base), e.g. "cases/elasticColumn"; a copy of it
                without its results (tests/support/case_copy.py)
  "args":       scree's arguments besides --case (e.g. ["--check"])
  "env":        optional: environment variables set for scree, e.g.
                {"SCREE_TEST_FREE_MEMORY": "2e9"} (the free memory its check assumes)
  "exit":       the expected exit status
  "stderr", "stdout":          regular expressions that must each match (re.MULTILINE)
  "not_stderr", "not_stdout":  regular expressions that must not match
  "errors":     optional: the exact number of error lines on stderr (lines not starting
                with "scree:" or "    ")
  "results":    "planted" (default): results of an "earlier run" are put where the
                case's writer and function object write (VTK/particles.pvd,
                VTK/particles_0.vtp, postProcessing/front/runOut.csv) before scree runs;
                "none": the case starts without results
  "outputs":    "untouched" (default when exit != 0): afterwards every file of the case
                is as it was, and no file or directory was added; "replaced": the
                planted VTK/particles.pvd was replaced; "any": not checked
  "timeout":    seconds before the run counts as hung (default 20)
  "written":    paths (glob patterns) that must exist after the run, e.g. the last
                frame a failed run writes
  "not_written": paths (glob patterns) that must not exist after the run, e.g. a
                checkpoint of the state a failed run stopped in
  "signal_when_stdout": {"pattern": regex, "signal": "SIGTERM"}: once stdout matches,
                scree is sent that signal and must then exit with "exit" by itself
  "pvd_last_time": {"file": a .pvd, "stderr": a regex with one group}: the newest frame
                listed in the .pvd has the time the group captures (relative 1e-6)
  "kill_when_stdout": a regular expression: once stdout (a file, as when a log is
                redirected) matches it within "timeout" seconds, scree is killed (SIGKILL)
                and the variant passes; if it never does, it fails. For output that must
                reach the log before a run ends.
In patterns, {case} stands for the case directory (regex-escaped).

Exit status 0 when every variant behaves as expected; otherwise each difference is
printed with scree's output.
"""
import argparse
import glob
import hashlib
import json
import os
import re
import shutil
import signal
import stat
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "tests", "support"))
from case_copy import copy_case  # noqa: E402
PLANTED = {
    "VTK/particles.pvd": "<?xml version=\"1.0\"?>\n<!-- results of an earlier run -->\n",
    "VTK/particles_0.vtp": "earlier run, t = 0\n",
    "postProcessing/front/runOut.csv": "time [s],runout [m]\n0,0.2\n",
}


def snapshot(root):
    """relative path -> sha256 of a regular file, or the file type of anything else."""
    files = {}
    for dirpath, dirnames, filenames in os.walk(root):
        for name in dirnames + filenames:
            path = os.path.join(dirpath, name)
            rel = os.path.relpath(path, root)
            st = os.lstat(path)
            if stat.S_ISREG(st.st_mode):
                with open(path, "rb") as f:
                    files[rel] = hashlib.sha256(f.read()).hexdigest()
            elif stat.S_ISDIR(st.st_mode):
                files[rel] = "directory"
            else:
                files[rel] = "special %o" % stat.S_IFMT(st.st_mode)
    return files


def prepare_case(variant_dir, case, base=None, scree=None):
    src = os.path.join(ROOT, base) if base else os.path.join(HERE, "base")
    copy_case(src, case)
    for dirpath, _, filenames in os.walk(variant_dir):
        for name in filenames:
            src = os.path.join(dirpath, name)
            rel = os.path.relpath(src, variant_dir)
            if rel in ("variant.json", "prepare.sh"):
                continue
            dst = os.path.join(case, rel)
            os.makedirs(os.path.dirname(dst), exist_ok=True)
            shutil.copyfile(src, dst)
    script = os.path.join(variant_dir, "prepare.sh")
    if os.path.exists(script):
        env = dict(os.environ)
        if scree:
            env["SCREE"] = scree  # a prepare.sh may run the case first (a restart's checkpoint)
        subprocess.run(["bash", "-e", script], cwd=case, check=True, env=env)


def run_scree(scree, case, spec, out_path, err_path):
    """Runs scree; returns (exit status or None when hung, seconds, note)."""
    cmd = [scree, "--case", case] + spec.get("args", [])
    timeout = spec.get("timeout", 20)
    kill_pattern = spec.get("kill_when_stdout")
    sig = spec.get("signal_when_stdout")
    signalled = False
    start = time.monotonic()
    with open(out_path, "wb") as out, open(err_path, "wb") as err:
        env = dict(os.environ, **spec.get("env", {}))
        proc = subprocess.Popen(cmd, stdout=out, stderr=err, start_new_session=True, env=env)
        while True:
            rc = proc.poll()
            elapsed = time.monotonic() - start
            if kill_pattern:
                with open(out_path, "r", errors="replace") as f:
                    if re.search(kill_pattern, f.read(), re.MULTILINE):
                        os.killpg(proc.pid, signal.SIGKILL)
                        proc.wait()
                        return "killed", elapsed, "stdout matched %r after %.1f s" % (kill_pattern, elapsed)
            if sig and not signalled and rc is None:
                with open(out_path, "r", errors="replace") as f:
                    if re.search(sig["pattern"], f.read(), re.MULTILINE):
                        proc.send_signal(getattr(signal, sig["signal"]))
                        signalled = True
            if rc is not None:
                if sig and not signalled:
                    return rc, elapsed, "exited before stdout matched %r" % sig["pattern"]
                return rc, elapsed, ""
            if elapsed > timeout:
                os.killpg(proc.pid, signal.SIGKILL)
                proc.wait()
                return None, elapsed, "no exit within %g s (hung?)" % timeout
            time.sleep(0.05)


def check_variant(scree, variant_dir):
    variant_dir = os.path.abspath(variant_dir)
    name = os.path.basename(os.path.normpath(variant_dir))
    with open(os.path.join(variant_dir, "variant.json")) as f:
        spec = json.load(f)
    problems = []
    work = tempfile.mkdtemp(prefix="scree-broken-%s-" % name)
    try:
        case = os.path.join(work, "case")
        prepare_case(variant_dir, case, spec.get("base"), os.path.abspath(scree))
        if spec.get("results", "planted") == "planted":
            for rel, text in PLANTED.items():
                path = os.path.join(case, rel)
                os.makedirs(os.path.dirname(path), exist_ok=True)
                with open(path, "w") as f:
                    f.write(text)
        before = snapshot(case)
        out_path, err_path = os.path.join(work, "stdout"), os.path.join(work, "stderr")
        rc, seconds, note = run_scree(scree, case, spec, out_path, err_path)
        with open(out_path, errors="replace") as f:
            out = f.read()
        with open(err_path, errors="replace") as f:
            err = f.read()
        after = snapshot(case)

        def pattern(p):
            return p.replace("{case}", re.escape(case))

        if spec.get("kill_when_stdout"):
            if rc != "killed":
                problems.append("stdout never matched %r (%s)" % (spec["kill_when_stdout"], note or "exit %s" % rc))
        elif rc is None:
            problems.append(note)
        elif rc != spec["exit"]:
            problems.append("exit status %s, expected %s" % (rc, spec["exit"]))
        for stream, text in (("stderr", err), ("stdout", out)):
            for p in spec.get(stream, []):
                if not re.search(pattern(p), text, re.MULTILINE):
                    problems.append("%s does not match %r" % (stream, p))
            for p in spec.get("not_" + stream, []):
                if re.search(pattern(p), text, re.MULTILINE):
                    problems.append("%s matches %r, which it must not" % (stream, p))
        if "pvd_last_time" in spec:
            want = re.search(spec["pvd_last_time"]["stderr"], err, re.MULTILINE)
            pvd = os.path.join(case, spec["pvd_last_time"]["file"])
            times = []
            if os.path.exists(pvd):
                with open(pvd) as f:
                    times = [float(t) for t in re.findall(r'timestep="([^"]+)"', f.read())]
            if not want:
                problems.append("stderr does not match %r" % spec["pvd_last_time"]["stderr"])
            elif not times or abs(times[-1] - float(want.group(1))) > 1e-6 * max(1.0, abs(times[-1])):
                problems.append("the newest frame of %s is at %s, expected %s" % (
                    spec["pvd_last_time"]["file"], times[-1] if times else "(none)", want.group(1)))
        for p in spec.get("written", []):
            if not glob.glob(os.path.join(case, p)):
                problems.append("nothing written at %s" % p)
        for p in spec.get("not_written", []):
            found = glob.glob(os.path.join(case, p))
            if found:
                problems.append("written, and must not be: %s" % ", ".join(os.path.relpath(f, case) for f in found))
        if "errors" in spec:
            lines = [l for l in err.splitlines() if l and not l.startswith("scree:") and not l.startswith("    ")]
            if len(lines) != spec["errors"]:
                problems.append("%d error line(s) on stderr, expected %d" % (len(lines), spec["errors"]))
        outputs = spec.get("outputs", "untouched" if spec.get("exit", 0) != 0 else "any")
        if outputs == "untouched" and rc != "killed":
            changed = sorted(k for k in set(before) | set(after) if before.get(k) != after.get(k))
            if changed:
                problems.append("the case changed: " + ", ".join(
                    "%s %s" % (k, "added" if k not in before else "removed" if k not in after else "modified")
                    for k in changed))
        elif outputs == "replaced":
            if before.get("VTK/particles.pvd") == after.get("VTK/particles.pvd"):
                problems.append("VTK/particles.pvd of the earlier run was not replaced")
        if problems:
            print("FAIL %s: %s" % (name, spec.get("doc", "")))
            for p in problems:
                print("    " + p)
            print("    command: %s --case %s %s" % (scree, case, " ".join(spec.get("args", []))))
            print("    --- stdout ---\n" + "".join("    " + l + "\n" for l in out.splitlines()[-20:]), end="")
            print("    --- stderr ---\n" + "".join("    " + l + "\n" for l in err.splitlines()[-20:]), end="")
        else:
            print("ok   %s (%.1f s): %s" % (name, seconds, spec.get("doc", "")))
    finally:
        if os.environ.get("SCREE_KEEP_TEST_CASES"):
            print("    kept in " + work)
        else:
            # A case made unreadable or holding a FIFO is still removable by its owner.
            shutil.rmtree(work, ignore_errors=True)
    return not problems


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scree", required=True, help="the scree executable")
    ap.add_argument("variants", nargs="+", help="variant directories")
    a = ap.parse_args()
    scree = os.path.abspath(a.scree)
    ok = [check_variant(scree, v) for v in a.variants]
    return 0 if all(ok) else 1


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""Ensembles of a case, run by `scree` as users run them (CPU, one thread a member).

The case: an elastic block sliding on a Coulomb floor (tests/kill/case), whose front stops
after v0^2 / (2 mu g), the rigid block's stopping distance (the block's own compression
under the floor's traction, mu rho g H L / E, is 1e-4 of it).

1. Eight members (a truncated normal friction coefficient, two initial speeds): each
   member's stopping distance within 1% of v0^2 / (2 mu g) for its own mu and v0 (the
   discretised contact and the front's measure, the furthest point, take it no further
   than a few 1e-4); the summary's statistics equal Python's own over members.csv.
2. A member's results (every VTK and CSV file) equal, byte for byte, those of the base case
   with that member's values written in by hand and run alone.
3. An ensemble stopped by SIGTERM and continued with --restart ends with the uninterrupted
   ensemble's members' results and summary, byte for byte; started again without
   --restart or --overwrite it is refused (exit 4) and nothing changes. Killed outright
   (SIGKILL), its running members end too, and --restart finishes it the same.
4. A member that blows up stops alone with its diagnosis; the others finish (exit 5).
5. A member whose drawn value its case refuses: --check and the run name it and exit 1
   before anything runs.
6. Members that each fit in the free memory but not membersAtOnce of them together: refused
   (exit 1) before anything runs, with the number that fits.
"""
import argparse
import csv
import math
import os
import re
import shutil
import signal
import statistics
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "support"))
from case_copy import copy_case  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
BLOCK = os.path.join(os.path.dirname(HERE), "kill", "case")
G = 9.81

ENSEMBLE = """FoamFile { version 2.0; format ascii; class dictionary; object ensembleDict; }
seed 20261129;
samples 4;
parameters
{
    friction { file constant/boundaryConditions; entry floor/coefficient;
               distribution { type normal; mean 0.4; standardDeviation 0.05; lower 0.3; upper 0.5; } }
    speed    { file constant/bodies; entry block/velocity; values ((1.5 0) (2 0)); }
}
summary
{
    front { file postProcessing/front/runOut.csv; column runout; at end; }
    start { file postProcessing/front/runOut.csv; column runout; at 0; }
}
"""


def percentile(sorted_x, p):
    """numpy's default percentile: linear between the order statistics around (n - 1) p / 100."""
    h = (len(sorted_x) - 1) * p / 100
    lo = math.floor(h)
    hi = min(lo + 1, len(sorted_x) - 1)
    return sorted_x[lo] + (h - lo) * (sorted_x[hi] - sorted_x[lo])


def read(path):
    with open(path, "rb") as f:
        return f.read()


def results(case):
    """Every file a run writes (VTK/, postProcessing/), relative to the case."""
    out = []
    for sub in ("VTK", "postProcessing"):
        for root, _, files in os.walk(os.path.join(case, sub)):
            out += [os.path.relpath(os.path.join(root, f), case) for f in files]
    return sorted(out)


def edit(path, pattern, repl):
    with open(path) as f:
        text = f.read()
    new, n = re.subn(pattern, repl, text)
    assert n == 1, f"{path}: {pattern} not found once"
    with open(path, "w") as f:
        f.write(new)


def base_case(dst, end=0.8):
    copy_case(BLOCK, dst)
    c = os.path.join(dst, "system", "controlDict")
    edit(c, r"endTime\s+1\.5;", f"endTime {end};")
    edit(c, r"writeInterval\s+0\.025;", "writeInterval 0.1;")
    edit(c, r"\n\s*probe\s+\{[^\n]*\}", "")
    edit(c, r"\n\s*energy\s+\{[^\n]*\}", "")


def members(case):
    with open(os.path.join(case, "ensemble", "members.csv")) as f:
        return list(csv.DictReader(f))


def wait_for_two_done(p, case, limit=60):
    """Until two members of the running ensemble `case` are done (or it ends, or `limit` s)."""
    deadline = time.monotonic() + limit
    mc = os.path.join(case, "ensemble", "members.csv")
    while time.monotonic() < deadline and p.poll() is None:
        if os.path.exists(mc) and sum(m["status"] == "done" for m in members(case)) >= 2:
            return
        time.sleep(0.05)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scree", required=True)
    ap.add_argument("--keep", action="store_true")
    a = ap.parse_args()
    failures = []
    tmp = tempfile.mkdtemp(prefix="scree_ensemble_")
    env = dict(os.environ, OMP_NUM_THREADS="1")
    base = [a.scree, "--device", "cpu", "--threads", "2"]

    def run(case, *args):
        return subprocess.run(base + ["--case", case, *args], env=env, stdout=subprocess.PIPE,
                              stderr=subprocess.STDOUT, text=True)

    def expect(cond, what):
        if not cond:
            failures.append(what)
        return cond

    try:
        # 1. The stopping distances and the summary.
        ens = os.path.join(tmp, "ensemble")
        base_case(ens)
        with open(os.path.join(ens, "system", "ensembleDict"), "w") as f:
            f.write(ENSEMBLE)
        r = run(ens)
        print(r.stdout[-3000:])
        if not expect(r.returncode == 0, f"the ensemble exited {r.returncode}"):
            raise SystemExit
        rows = members(ens)
        expect(len(rows) == 8, f"{len(rows)} members, not 8")
        worst = 0.0
        for m in rows:
            mu = float(m["friction"])
            v0 = float(re.match(r"\(([^ ]+) ", m["speed"]).group(1))
            expect(0.3 <= mu <= 0.5, f"member {m['member']}: friction {mu} outside [0.3, 0.5]")
            got = float(m["front"]) - float(m["start"])
            want = v0 * v0 / (2 * mu * G)
            worst = max(worst, abs(got / want - 1))
            expect(m["status"] == "done", f"member {m['member']}: {m['status']}")
            expect(abs(got / want - 1) < 0.01,
                   f"member {m['member']} (mu {mu}, v0 {v0}): stopped after {got:.5f} m, v0^2/(2 mu g) = {want:.5f} m")
        print(f"stopping distances: worst relative error {worst:.2e} against v0^2/(2 mu g) over {len(rows)} members")
        x = sorted(float(m["front"]) for m in rows)
        with open(os.path.join(ens, "ensemble", "summary.csv")) as f:
            summary = {s["quantity"]: s for s in csv.DictReader(f)}
        want = {"mean": statistics.fmean(x), "standard deviation": statistics.stdev(x), "min": x[0], "max": x[-1],
                "p5": percentile(x, 5), "p50": statistics.median(x), "p95": percentile(x, 95)}
        for k, v in want.items():
            expect(abs(float(summary["front"][k]) - v) <= 1e-10 * max(1.0, abs(v)),
                   f"summary front {k}: {summary['front'][k]}, numpy {v}")
        with open(os.path.join(ens, "ensemble", "exceedance.csv")) as f:
            exc = [e for e in csv.DictReader(f) if e["quantity"] == "front"]
        expect([float(e["value"]) for e in exc] == x, "exceedance values are not the sorted fronts")
        expect(all(abs(float(e["exceedance probability"]) - sum(v > float(e["value"]) for v in x) / len(x)) < 1e-12
                   for e in exc),
               "exceedance probabilities are not the fractions above")

        # 2. Member 5 against its case run alone.
        m5 = rows[5]
        alone = os.path.join(tmp, "alone")
        base_case(alone)
        edit(os.path.join(alone, "constant", "boundaryConditions"), r"coefficient 0\.4;", f"coefficient {m5['friction']};")
        edit(os.path.join(alone, "constant", "bodies"), r"velocity \(1\.5 0\);", f"velocity {m5['speed']};")
        r = subprocess.run([a.scree, "--device", "cpu", "--threads", "1", "--case", alone], env=env,
                           stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        expect(r.returncode == 0, f"member 5's case alone exited {r.returncode}: {r.stdout[-500:]}")
        member5 = os.path.join(ens, "ensemble", "member_0005")
        files = results(alone)
        expect(files == results(member5), f"member 5 wrote {results(member5)}, its case alone {files}")
        differ = [f for f in files if read(os.path.join(alone, f)) != read(os.path.join(member5, f))]
        expect(not differ and len(files) > 3, f"member 5's results differ from its case run alone: {differ}")
        print(f"member 5 against its case run alone: {len(files)} files, {len(differ)} differ")

        # 3. Stopped and continued; refused without --restart.
        again = os.path.join(tmp, "again")
        base_case(again)
        with open(os.path.join(again, "system", "ensembleDict"), "w") as f:
            f.write(ENSEMBLE)
        p = subprocess.Popen(base + ["--case", again], env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        wait_for_two_done(p, again)
        p.send_signal(signal.SIGTERM)
        out, _ = p.communicate()
        expect(p.returncode == 143, f"the ensemble stopped by SIGTERM exited {p.returncode}: {out[-800:]}")
        states = [m["status"] for m in members(again)]
        print(f"stopped by SIGTERM: members {states}")
        expect("done" in states and states.count("done") < 8, f"the stop did not fall mid-ensemble: {states}")
        snapshot = {f: read(os.path.join(again, "ensemble", f)) for f in ("members.csv",)}
        r = run(again)
        expect(r.returncode == 4, f"started again without --restart: exit {r.returncode}, not 4")
        expect(read(os.path.join(again, "ensemble", "members.csv")) == snapshot["members.csv"],
               "a refused start changed members.csv")
        r = run(again, "--restart")
        expect(r.returncode == 0, f"--restart exited {r.returncode}: {r.stdout[-800:]}")
        expect(read(os.path.join(again, "ensemble", "summary.csv")) == read(os.path.join(ens, "ensemble", "summary.csv")),
               "the continued ensemble's summary.csv differs from the uninterrupted one's")
        for k in range(8):
            d1 = os.path.join(ens, "ensemble", f"member_{k:04d}")
            d2 = os.path.join(again, "ensemble", f"member_{k:04d}")
            f1, f2 = results(d1), results(d2)
            bad = [f for f in f1 if f not in f2 or read(os.path.join(d1, f)) != read(os.path.join(d2, f))]
            expect(f1 == f2 and not bad, f"member {k} after the stop and --restart: files differ {bad[:3]}")

        # 3b. The ensemble killed outright (SIGKILL): its running members are told (SIGTERM),
        # write the state they reached and end; --restart finishes it as uninterrupted.
        killed = os.path.join(tmp, "killed")
        base_case(killed)
        with open(os.path.join(killed, "system", "ensembleDict"), "w") as f:
            f.write(ENSEMBLE)
        p = subprocess.Popen(base + ["--case", killed], env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        wait_for_two_done(p, killed)
        time.sleep(0.5)  # the next members past their start-up, running steps
        p.kill()
        p.wait()

        def members_running():
            n = 0
            for pid in filter(str.isdigit, os.listdir("/proc")):
                try:
                    with open(f"/proc/{pid}/cmdline", "rb") as f:
                        n += os.path.join(killed, "ensemble", "member_").encode() in f.read()
                except OSError:
                    pass
            return n

        deadline = time.monotonic() + 30
        while members_running() and time.monotonic() < deadline:
            time.sleep(0.1)
        expect(members_running() == 0, "members still run 30 s after their ensemble was killed")
        told = 0
        for k in range(8):
            log = os.path.join(killed, "ensemble", f"member_{k:04d}", "log.scree")
            if os.path.exists(log):
                with open(log) as f:
                    told += "stopped by signal 15" in f.read()
        expect(told >= 1, "no member was stopped by SIGTERM when its ensemble was killed (they ran on alone)")
        print(f"ensemble killed: {told} running member(s) stopped by SIGTERM")
        r = run(killed, "--restart")
        expect(r.returncode == 0, f"--restart after SIGKILL exited {r.returncode}: {r.stdout[-800:]}")
        expect(read(os.path.join(killed, "ensemble", "summary.csv")) == read(os.path.join(ens, "ensemble", "summary.csv")),
               "the ensemble killed and continued: summary.csv differs from the uninterrupted one's")

        # 4. A member that blows up.
        blow = os.path.join(tmp, "blow")
        base_case(blow, end=0.2)
        c = os.path.join(blow, "system", "controlDict")
        edit(c, r"adjustTimeStep\s+yes;", "adjustTimeStep no;")
        edit(c, r"deltaT\s+1e-3;", "deltaT 1e-4;")
        with open(os.path.join(blow, "system", "ensembleDict"), "w") as f:
            f.write("parameters { E { file constant/materialProperties; entry block/E; values (1e6 1e10 2e6); } }\n"
                    "summary { front { file postProcessing/front/runOut.csv; column runout; } }\n")
        r = run(blow)
        expect(r.returncode == 5, f"the ensemble with an unstable member exited {r.returncode}, not 5")
        st = [m["status"] for m in members(blow)]
        expect(st == ["done", "failed", "done"], f"member statuses {st}, not done, failed, done")
        expect("member 1 (E 1e10) went wrong" in r.stdout, "the ensemble's log does not name the member that went wrong")
        with open(os.path.join(blow, "ensemble", "member_0001", "log.scree")) as f:
            expect("exceeds the stable step" in f.read(), "member 1's log has no diagnosis")
        with open(os.path.join(blow, "ensemble", "summary.csv")) as f:
            expect(next(csv.DictReader(f))["members"] == "2", "the summary is not over the two members that finished")

        # 5. A drawn value the case refuses: named, nothing run.
        bad = os.path.join(tmp, "bad")
        base_case(bad)
        with open(os.path.join(bad, "system", "ensembleDict"), "w") as f:
            f.write("seed 1; samples 6;\nparameters { mu { file constant/boundaryConditions; entry floor/coefficient;\n"
                    "  distribution { type normal; mean 0.05; standardDeviation 0.2; } } }\n")
        for args in (["--check"], []):
            r = run(bad, *args)
            expect(r.returncode == 1, f"{args}: a member with a negative friction coefficient: exit {r.returncode}, not 1")
            expect(re.search(r"ensemble member \d+ \(mu -[0-9.e-]+\)", r.stdout) and "constant/boundaryConditions:" in r.stdout,
                   f"{args}: the member and its file:line are not named: {r.stdout[-600:]}")
            expect(not os.path.exists(os.path.join(bad, "ensemble")), f"{args}: something was written before the refusal")
        print(r.stdout[-600:])

        # 6. Members that fit one at a time but not two at once: refused before anything runs.
        mem = os.path.join(tmp, "memory")
        base_case(mem)
        r = run(mem, "--check")
        need = re.search(r"a run needs about ([0-9.]+) (kB|MB) of host memory", r.stdout)
        expect(need, f"--check of the base case says nothing of its memory: {r.stdout[-300:]}")
        with open(os.path.join(mem, "system", "ensembleDict"), "w") as f:
            f.write("membersAtOnce 2;\nparameters { E { file constant/materialProperties; entry block/E; values (1e6 2e6); } }\n")
        free = 1.5 * float(need.group(1)) * (1e3 if need.group(2) == "kB" else 1e6)
        r = subprocess.run(base + ["--case", mem], env=dict(env, SCREE_TEST_FREE_MEMORY=str(free)), stdout=subprocess.PIPE,
                           stderr=subprocess.STDOUT, text=True)
        expect(r.returncode == 1 and "membersAtOnce 1 fits" in r.stdout,
               f"two members at once in 1.5 members' memory: exit {r.returncode}, {r.stdout[-400:]}")
        expect(not os.path.exists(os.path.join(mem, "ensemble")), "the refused ensemble wrote ensemble/")
    finally:
        if a.keep:
            print("kept", tmp)
        else:
            shutil.rmtree(tmp, ignore_errors=True)
    for f in failures:
        print("FAIL:", f)
    print("ensemble trials:", "passed" if not failures else f"{len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())

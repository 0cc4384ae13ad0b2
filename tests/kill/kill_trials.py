#!/usr/bin/env python3
"""Kill and signal trials: a run killed (SIGKILL) or stopped (SIGTERM, SIGINT) at random moments
loses no finished result, and its restarts reach the uninterrupted run's results bit for bit.

--signal KILL (the default) kills; TERM or INT stop the run as a batch system or Ctrl-C
does (it finishes its chunk of steps, writes the state it reached with a checkpoint and
exits 128 + the signal); `mixed` draws one of the three for each trial.

The case (tests/kill/case) runs once uninterrupted (the reference). A copy is then started,
killed with SIGKILL at a random moment, and continued with `scree --restart` (or started
again with --overwrite while no checkpoint exists yet), killed again, and so on for
--trials kills; a last restart runs it to the end. After every kill:

  * every file the .pvd lists exists and equals the reference's file of that name byte for
    byte (a frame is complete, and the same numbers as the uninterrupted run's);
  * every CSV row of postProcessing/ is a row of the reference's file (complete rows only).

A restart never lists fewer frames than the killed run had listed (it lists a frame the
killed run wrote but did not list, and keeps later frames listed until it writes them
again). Each time a chain of kills and restarts reaches endTime, and at the end, the whole
output (series, frames, CSVs) equals the reference's byte for byte (CPU, one thread), and no
hidden temporary is left. A run that reaches endTime between kills does not count as a kill:
the case then starts again from its beginning.

Exit status 0 when every check holds; 1 with the failed checks listed.
"""
import argparse
import os
import random
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "support"))
from case_copy import copy_case  # noqa: E402


def listed(pvd):
    """The files a .pvd lists (relative to its directory), or [] when there is none."""
    if not os.path.exists(pvd):
        return []
    with open(pvd) as f:
        text = f.read()
    if "</VTKFile>" not in text:
        raise AssertionError(f"{pvd}: incomplete collection")
    return re.findall(r'file="([^"]*)"', text)


def frames_on_disk(vtk_dir):
    """Frame indices of particles_<i>.vtp files on disk (hidden temporaries aside)."""
    out = []
    if os.path.isdir(vtk_dir):
        for f in os.listdir(vtk_dir):
            m = re.fullmatch(r"particles_(\d+)\.vtp", f)
            if m:
                out.append(int(m.group(1)))
    return sorted(out)


def output_files(case):
    """Every regular file the run writes (checkpoints aside), relative to the case."""
    out = []
    for sub in ("VTK", "postProcessing"):
        for root, _, files in os.walk(os.path.join(case, sub)):
            for f in files:
                out.append(os.path.relpath(os.path.join(root, f), case))
    return sorted(out)


def read(path):
    with open(path, "rb") as f:
        return f.read()


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scree", required=True)
    ap.add_argument("--case", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "case"))
    ap.add_argument("--trials", type=int, default=20)
    ap.add_argument("--seed", type=int, default=20261125)
    ap.add_argument("--keep", action="store_true", help="keep the temporary directory")
    ap.add_argument("--signal", choices=["KILL", "TERM", "INT", "mixed"], default="KILL",
                    help="how each trial stops the run (mixed: one of the three at random)")
    a = ap.parse_args()
    rng = random.Random(a.seed)
    failures = []
    tmp = tempfile.mkdtemp(prefix="scree_kill_")
    env = dict(os.environ, OMP_NUM_THREADS="1")
    base = [a.scree, "--device", "cpu", "--threads", "1"]

    def run(case, *args, **kw):
        return subprocess.run(base + ["--case", case, *args], env=env, stdout=subprocess.PIPE,
                              stderr=subprocess.STDOUT, text=True, **kw)

    try:
        ref = os.path.join(tmp, "reference")
        work = os.path.join(tmp, "work")
        copy_case(a.case, ref)
        copy_case(a.case, work)
        t0 = time.monotonic()
        r = run(ref)
        t_ref = time.monotonic() - t0
        if r.returncode != 0:
            print(r.stdout)
            print(f"FAIL: the reference run exited {r.returncode}")
            return 1
        ref_files = output_files(ref)
        print(f"reference: {len(ref_files)} files in {t_ref:.2f} s")

        def compare(what):
            """The whole output equals the reference's, byte for byte; no temporaries left."""
            hidden = [os.path.join(root, f) for root, _, files in os.walk(work) for f in files if f.startswith(".") and f != ".scree.lock"]
            if hidden:
                failures.append(f"{what}: temporaries left: {hidden[:5]}")
            work_files = output_files(work)
            if work_files != ref_files:
                failures.append(f"{what}: the files differ from the uninterrupted run's: only here "
                                f"{sorted(set(work_files) - set(ref_files))[:5]}, only there "
                                f"{sorted(set(ref_files) - set(work_files))[:5]}")
            differing = [f for f in ref_files if f in work_files and read(os.path.join(ref, f)) !=
                         read(os.path.join(work, f))]
            if differing:
                failures.append(f"{what}: {len(differing)} file(s) differ from the uninterrupted run's, "
                                f"e.g. {differing[:5]}")

        def stop_time():
            """The time of the newest checkpoint (a signal's stop writes its state there), or None."""
            d = os.path.join(work, "checkpoints")
            times = [float(c[:-5]) for c in os.listdir(d) if c.endswith(".ckpt")] if os.path.isdir(d) else []
            return max(times) if times else None

        def at_stop(t, t_stop):
            """t is the stop's time (checkpoint names carry 8 digits, CSV rows 12)."""
            return t_stop is not None and abs(t - t_stop) <= 1e-7 * max(1.0, abs(t_stop))

        def check_after_kill(trial, how):
            pvd = os.path.join(work, "VTK", "particles.pvd")
            try:
                files = listed(pvd)
            except AssertionError as e:
                failures.append(f"trial {trial}: {e}")
                return
            # A run stopped by a signal also wrote the state it reached (a frame and a row of
            # every CSV at its stop time): the uninterrupted run's outputs plus that state.
            # (until a restart writes past it, also after later kills that wrote nothing)
            nonlocal signal_stop
            if how != "KILL":
                signal_stop = stop_time()
            t_stop = signal_stop
            times = dict(zip(re.findall(r'file="([^"]*)"', open(pvd).read()),
                             map(float, re.findall(r'timestep="([^"]*)"', open(pvd).read())))) if files else {}
            for f in files:
                p = os.path.join(work, "VTK", f)
                q = os.path.join(ref, "VTK", f)
                stop_frame = f == files[-1] and at_stop(times.get(f, -1.0), t_stop)
                if not os.path.exists(p):
                    failures.append(f"trial {trial}: {f} is listed but missing")
                elif stop_frame:
                    continue
                elif not os.path.exists(q) or read(p) != read(q):
                    failures.append(f"trial {trial}: {f} is listed but differs from the uninterrupted run's")
            for rel in output_files(work):
                if not rel.startswith("postProcessing") or not rel.endswith(".csv"):
                    continue
                ref_rows = set(read(os.path.join(ref, rel)).decode().splitlines())
                text = read(os.path.join(work, rel)).decode()
                rows = text.splitlines()
                if text and not text.endswith("\n"):
                    rows = rows[:-1]  # a row being written when the process died: not finished
                bad = [x for x in rows if x not in ref_rows and not at_stop(float(x.split(",")[0]), t_stop)]
                if bad:
                    failures.append(f"trial {trial}: {rel}: {len(bad)} row(s) not in the uninterrupted run's, "
                                    f"e.g. {bad[0]!r}")
            return len(files)

        signal_stop = None  # the time of the last stop by a signal (its state was written there)
        newest_left = None  # the newest frame a killed run left on disk
        restarts = 0
        unlisted_kills = 0  # kills that left the newest frame on disk unlisted (to be repaired)
        kills = 0
        chains = 0  # runs that reached endTime through kills and restarts (then started again)
        attempt = 0
        fresh = True
        listed_before = 0  # frames the .pvd listed after the previous run
        while kills < a.trials:
            attempt += 1
            ckpt_dir = os.path.join(work, "checkpoints")
            has_ckpt = os.path.isdir(ckpt_dir) and any(c.endswith(".ckpt") for c in os.listdir(ckpt_dir))
            mode = "--restart" if has_ckpt and not fresh else "--overwrite"
            fresh = False
            restarts += mode == "--restart"
            delay = rng.uniform(0.05, min(1.0, 0.3 * t_ref))
            p = subprocess.Popen(base + ["--case", work, mode], env=env, stdout=subprocess.DEVNULL,
                                 stderr=subprocess.DEVNULL)
            deadline = time.monotonic() + delay
            while time.monotonic() < deadline and p.poll() is None:
                time.sleep(0.005)
            finished = p.poll() is not None
            how = rng.choice(["KILL", "TERM", "INT"]) if a.signal == "mixed" else a.signal
            if not finished:
                sig = getattr(signal, "SIG" + how)
                p.send_signal(sig)
                kills += 1
                p.wait()
                # -sig: the signal came before the handler was installed (the case was being read)
                if how != "KILL" and p.returncode not in (128 + sig, 0, -sig):
                    failures.append(f"run {attempt}: stopped by SIG{how}, it exited {p.returncode}, not "
                                    f"{128 + sig} (or 0 had it just reached endTime)")
                finished = how != "KILL" and p.returncode == 0  # it reached endTime before the signal
            p.wait()
            n = check_after_kill(attempt, how if not finished else "KILL")
            if mode == "--restart" and n is not None and n < listed_before:
                failures.append(f"run {attempt}: the restart unlisted finished frames ({listed_before} -> {n})")
            listed_before = n or 0
            if newest_left is not None and mode == "--restart":
                frames = listed(os.path.join(work, "VTK", "particles.pvd"))
                indices = [int(m.group(1)) for m in (re.fullmatch(r"particles_(\d+)\.vtp", f) for f in frames) if m]
                if indices and max(indices) >= newest_left and f"particles_{newest_left}.vtp" not in frames:
                    failures.append(f"run {attempt}: frame {newest_left}, left by the killed run, is not listed "
                                    f"after the restart wrote past it")
            on_disk = frames_on_disk(os.path.join(work, "VTK"))
            newest_left = on_disk[-1] if on_disk else None
            unlisted = newest_left is not None and f"particles_{newest_left}.vtp" not in listed(
                os.path.join(work, "VTK", "particles.pvd"))
            unlisted_kills += unlisted
            stopped = "killed" if how == "KILL" else f"stopped by SIG{how} (exit {p.returncode})"
            print(f"run {attempt:2d}: {mode:11s} {'finished (exit %d)' % p.returncode if finished else stopped} "
                  f"after {delay:.2f} s; {n} frames listed, newest on disk {newest_left}"
                  f"{' (not listed)' if unlisted else ''}")
            if finished:
                # The chain of kills and restarts reached endTime: its output is the reference's.
                if p.returncode != 0:
                    failures.append(f"run {attempt} exited {p.returncode}")
                compare(f"chain {chains + 1} (run {attempt})")
                chains += 1
                fresh = True  # the next kill trials start the case again
                signal_stop = None

        ckpt_dir = os.path.join(work, "checkpoints")
        has_ckpt = os.path.isdir(ckpt_dir) and any(c.endswith(".ckpt") for c in os.listdir(ckpt_dir))
        r = run(work, "--restart" if has_ckpt and not fresh else "--overwrite")
        if r.returncode != 0:
            failures.append(f"the last run exited {r.returncode}: {r.stdout[-2000:]}")
        compare("the last chain")
        print(f"{kills} kills ({unlisted_kills} left a frame on disk that the .pvd did not list), {restarts} "
              f"restarts, {chains + 1} chains of runs to endTime, each ending with the uninterrupted run's "
              f"{len(ref_files)} files byte for byte" + (" (but see the failures)" if failures else ""))
    finally:
        if a.keep:
            print(f"kept {tmp}")
        else:
            shutil.rmtree(tmp, ignore_errors=True)
    for f in failures:
        print("FAIL:", f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/python3
"""Read the series' function-object CSVs and write the run-out table and figure.

    cd cases/columnCollapse/series
    /usr/bin/python3 analyse.py RUNS [RUNS ...] [--out results] [--label "device, date"]

RUNS: folders holding case folders (as run-series.sh leaves them, or unpacked from its
results.tar.gz). A case holds one column (function objects massFront, front999, deposit,
surface) or several (the same names prefixed by the column's body name, e.g.
a8_massFront). A column's name gives its aspect ratio (a8, a0p5 or a0.5), the case's
name its cell size (h5mm, h2.5mm) and, after the aspect ratio, the factor.

Measures, for each column, from its own left wall:
  d99, d999, d100   the 0.99 and 0.999 quantiles and the furthest point of the mass
  dconn             the front of the connected mass: the far edge of the last surface
                    bin reached from the wall through bins holding points, no gap wider
                    than one cell (from the last surface profile, when it is at the end)
  runout            (d - d0)/L0, d0 the same measure before release: the experiments'
                    (d_inf - L0)/L0
  H/L0              the highest point (the deposit's height at the wall)
  points lost       the fraction of the points that left the domain by the end; beyond
                    0.1 % the fronts are those of a smaller mass and the column is not fitted
  near rest         as at rest, but the 0.99 front still moved up to 1 % over the last
                    0.25 tau_c (fitted too, and marked)
  t_rest            the time after release, in tau_c = sqrt(h0/g), after which the 0.99
                    front stays within 0.5 % of its last value; a column is "at rest" when
                    its run reached 3.5 tau_c, its kinetic energy has fallen below 2 % of
                    its peak and its 0.99 front moved less than 0.2 % over the last
                    0.25 tau_c. The 0.999, furthest and connected fronts are given for
                    columns at rest only (they are sampled less often), the furthest and
                    connected ones only where no point left the domain.
  factors           each column that is not a base column of 5 mm cells against the base
                    column of the same a and 5 mm cells (the longest run of it), both at
                    the last time the shorter of the two reached: the change of the 0.99
                    front (d - d0)/L0 there
Writes OUT/summary.json, OUT/summary.md and OUT/series.png.
"""
import argparse
import glob
import json
import math
import os
import re
import sys

L0 = 0.2
RELEASE = 0.1
G = 9.81
T_COMPARE = 0.34   # [s] a time every run reached: the factors are compared there mid-flow


def law_lube(a):
    return 1.2 * a if a < 2.3 else 1.9 * a ** (2.0 / 3.0)


def read_csv(path):
    """The columns of a function object's CSV by name (units dropped), as lists of floats."""
    with open(path) as f:
        head = [h.split(" [")[0] for h in f.readline().strip().split(",")]
        rows = [[float(v) for v in line.split(",")] for line in f if line.strip()]
    return {h: [r[i] for r in rows] for i, h in enumerate(head)}


def interp(x0, x, y):
    """y at x0, linear between the samples (x increasing), held beyond them."""
    if x0 <= x[0]:
        return y[0]
    for i in range(1, len(x)):
        if x0 <= x[i]:
            w = (x0 - x[i - 1]) / (x[i] - x[i - 1]) if x[i] > x[i - 1] else 1.0
            return y[i - 1] + w * (y[i] - y[i - 1])
    return y[-1]


def parse(case, column):
    """Aspect ratio, cell size [mm] and factor of a column."""
    name = column or case
    m = re.match(r"a(\d+(?:[p.]\d+)?)", name)
    a = float(m.group(1).replace("p", "."))
    hm = re.search(r"h(\d+(?:\.\d+)?)mm", case)
    h = float(hm.group(1))
    rest = name[m.end():]
    rest = re.sub(r"_h\d+(?:\.\d+)?mm", "", rest).strip("_")
    case_factor = re.sub(r"^h\d+(?:\.\d+)?mm_?", "", case) if column else ""
    case_factor = "" if case_factor.startswith("a") else case_factor
    factor = "_".join(x for x in (case_factor, rest) if x)
    return a, h, factor or "base"


def connected_front(path, h):
    d = read_csv(path)
    x = sorted(x for x, n in zip(d["distance"], d["particles"]) if n > 0)
    if len(x) == 0:
        return None
    i = 0
    while i + 1 < len(x) and x[i + 1] - x[i] <= 2.0 * h + 1e-9:
        i += 1
    return float(x[i] + 0.5 * h)


def at_time(t, y, t0):
    if t[-1] < t0 - 1e-9:
        return None
    return float(interp(t0, t, y))


def column_record(casedir, prefix):
    case = os.path.basename(casedir.rstrip("/"))
    pp = os.path.join(casedir, "postProcessing")
    col = prefix[:-1] if prefix else ""
    a, h_mm, factor = parse(case, col)
    tc = math.sqrt(a * L0 / G)
    mf = read_csv(os.path.join(pp, prefix + "massFront", "runOut.csv"))
    t, d99, ke = mf["time"], mf["runout"], mf["kinetic_energy"]
    rec = {"case": case, "column": col or case, "a": a, "cell_mm": h_mm, "factor": factor,
           "tau_c_s": tc, "t_last_s": float(t[-1]), "t_last_tau": float((t[-1] - RELEASE) / tc)}
    status = os.path.join(casedir, "status.txt")
    rec["status"] = open(status).read().split()[0] if os.path.exists(status) else "?"
    fronts = {"d99": (t, d99)}
    for key, fo in (("d999", "front999"), ("d100", "deposit")):
        p = os.path.join(pp, prefix + fo, "runOut.csv")
        if os.path.exists(p):
            r = read_csv(p)
            fronts[key] = (r["time"], r["runout"])
            if key == "d100":
                rec["H_over_L0"] = float(r["height"][-1] / L0)
                rec["H0_over_L0"] = float(r["height"][0] / L0)
    for key, (tt, dd) in fronts.items():
        rec[key + "_m"] = float(dd[-1])
        rec[key.replace("d", "runout") if False else "runout_" + key[1:]] = float((dd[-1] - dd[0]) / L0)
        v = at_time(tt, dd, T_COMPARE)
        rec[f"runout_{key[1:]}_at_{T_COMPARE:g}s"] = None if v is None else float((v - dd[0]) / L0)
    n = mf.get("particles")
    rec["lost_fraction"] = float(1.0 - n[-1] / n[0]) if n is not None and n[0] > 0 else None
    surf = sorted((q for q in glob.glob(os.path.join(pp, prefix + "surface", "*.csv"))
                   if re.match(r"^[0-9.eE+-]+\.csv$", os.path.basename(q))),
                  key=lambda p: float(os.path.basename(p)[:-4]))
    rec["dconn_m"] = None
    if surf:
        ts = float(os.path.basename(surf[-1])[:-4])
        if abs(ts - t[-1]) < 0.03:
            dc, dc0 = connected_front(surf[-1], h_mm * 1e-3), connected_front(surf[0], h_mm * 1e-3)
            rec["dconn_m"] = dc
            rec["runout_conn"] = None if dc is None else float((dc - dc0) / L0)
    kmax = float(max(ke)) if len(ke) else 0.0
    rec["ke_last_over_max"] = float(ke[-1] / kmax) if kmax > 0 else None
    fin = d99[-1]
    moving = [i for i, d in enumerate(d99) if abs(d - fin) > 0.005 * (fin - d99[0] + L0)]
    t_rest = float(t[moving[-1] + 1]) if moving and moving[-1] + 1 < len(t) else float(t[0])
    rec["t_rest_tau"] = float((t_rest - RELEASE) / tc)
    recent = next(i for i, ti in enumerate(t) if ti >= t[-1] - 0.25 * tc)
    rec["last_quarter_tau_change"] = float(abs(d99[recent] - fin) / (fin - d99[0] + L0))
    calm = bool(rec["t_last_tau"] >= 3.5 and kmax > 0 and ke[-1] < 0.02 * kmax)
    rec["at_rest"] = calm and rec["last_quarter_tau_change"] < 0.002
    # "near rest": the same but the front still creeps by up to 1 % per 0.25 tau_c
    rec["near_rest"] = calm and rec["last_quarter_tau_change"] < 0.01
    # Points that left the domain are missing from the quantiles: beyond 0.1 % of them
    # the 0.99 front is that of a smaller mass, so the column does not count.
    rec["valid"] = bool(rec["lost_fraction"] is None or rec["lost_fraction"] <= 1e-3)
    rec["_history"] = ([(ti - RELEASE) / tc for ti in t], [(d - d99[0]) / L0 for d in d99])
    rec["_lost"] = (t, [1.0 - ni / n[0] for ni in n]) if n is not None and n[0] > 0 else None
    return rec


def collect(folders):
    recs = []
    for folder in folders:
        for casedir in sorted(glob.glob(os.path.join(folder, "*/"))):
            pp = os.path.join(casedir, "postProcessing")
            if not os.path.isdir(pp):
                continue
            for fo in sorted(os.listdir(pp)):
                if fo.endswith("massFront"):
                    prefix = fo[: -len("massFront")]
                    recs.append(column_record(casedir, prefix))
    return recs


def longest_runs(recs):
    """(a, cell size) -> the column that ran longest among recs (a column run in two cases)."""
    out = {}
    for r in recs:
        k = (r["a"], r["cell_mm"])
        if k not in out or r["t_last_s"] > out[k]["t_last_s"]:
            out[k] = r
    return out


def fit(points):
    """Exponent and prefactor of runout = lam a^alpha through the points (a, runout)."""
    import numpy as np
    if len(points) < 2:
        return None
    a, r = np.log([p[0] for p in points]), np.log([p[1] for p in points])
    alpha, loglam = np.polyfit(a, r, 1)
    return {"alpha": float(alpha), "lambda": float(math.exp(loglam)), "a": [p[0] for p in points]}


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("runs", nargs="+")
    p.add_argument("--out", default="results")
    p.add_argument("--label", default="", help="device and date of the runs, for the figure")
    args = p.parse_args()
    recs = collect(args.runs)
    if not recs:
        sys.exit("no postProcessing/*massFront/runOut.csv found")
    os.makedirs(args.out, exist_ok=True)

    # The series: base columns; where a column ran in two cases, the longer run counts.
    series = longest_runs(r for r in recs if r["factor"] == "base")
    # Families of one-column cases that change one case-wide setting at every a (a factor
    # named after the setting and the column, e.g. phic30_a4): fitted as a series too.
    family = {id(r): m.group(1) for r in recs if (m := re.match(r"^(.+)_a\d+(?:p\d+)?$", r["factor"]))}
    families = {name: longest_runs(r for r in recs if family.get(id(r)) == name) for name in set(family.values())}
    fits = {}
    for name, cols in [("", series)] + sorted(families.items()):
        for h in sorted({k[1] for k in cols}, reverse=True):
            for lo, hi, tag in ((0, 2.3, "below"), (2.3, 1e9, "above")):
                pts = [(a, cols[(a, h)]["runout_99"]) for a in sorted(a for a, hh in cols if hh == h)
                       if lo <= a < hi and cols[(a, h)]["near_rest"] and cols[(a, h)]["valid"]]
                if name and len(pts) < 2:
                    continue
                fits[f"{h:g}mm_{tag}" + (f"_{name}" if name else "")] = fit(pts)

    factor_rows = []
    for r in recs:
        if r["factor"] == "base" and r["cell_mm"] == 5.0:
            continue
        base = series.get((r["a"], 5.0))
        if base is None:
            continue
        t_star = min(r["t_last_s"], base["t_last_s"])
        tb, db = base["_history"]
        tf, df = r["_history"]
        ts = (t_star - RELEASE) / r["tau_c_s"]
        vb, vf = float(interp(ts, tb, db)), float(interp(ts, tf, df))
        lost = max(float(interp(t_star, *x["_lost"])) if x["_lost"] else 0.0 for x in (r, base))
        factor_rows.append({"a": r["a"], "factor": r["factor"] if r["factor"] != "base" else f"cells {r['cell_mm']:g} mm",
                            "case": r["case"], "column": r["column"], "compared_at_s": t_star,
                            "compared_at_tau": ts, "base_case": base["case"],
                            "base_runout_99": vb, "factor_runout_99": vf,
                            "change": vf / vb - 1.0 if vb > 0 else None,
                            "lost_fraction_then": lost,
                            "base_at_rest": base["near_rest"] and t_star >= base["t_last_s"] - 1e-9,
                            "factor_at_rest": r["near_rest"] and t_star >= r["t_last_s"] - 1e-9})

    out = {"L0_m": L0, "factors": factor_rows, "compare_time_s": T_COMPARE, "label": args.label, "fits_runout_99": fits,
           "columns": [{k: v for k, v in r.items() if not k.startswith("_")} for r in recs]}
    with open(os.path.join(args.out, "summary.json"), "w") as f:
        json.dump(out, f, indent=1)

    def fmt(v, spec=".3f"):
        return "-" if v is None else format(v, spec)

    lines = ["| case | column | a | cells | factor | reached (tau_c) | at rest | front change, last 0.25 tau_c | t_rest (tau_c) | "
             "(d-d0)/L0: 0.99 | 0.999 | furthest | connected | Lube 2005 | H/L0 | KE/KE_max | "
             f"0.99 front at t = {T_COMPARE:g} s | points lost |",
             "|" + "---|" * 18]
    for r in sorted(recs, key=lambda r: (r["factor"] != "base", r["a"], -r["cell_mm"], r["factor"], r["case"])):
        lines.append(
            f"| {r['case']} | {r['column']} | {r['a']:g} | {r['cell_mm']:g} mm | {r['factor']} | "
            f"{r['t_last_tau']:.2f} | {'yes' if r['at_rest'] else 'near' if r['near_rest'] else 'no'} | "
            f"{r['last_quarter_tau_change']:.2%} | "
            f"{fmt(r['t_rest_tau'], '.2f') if r['near_rest'] else '-'} | {fmt(r.get('runout_99'))} | "
            f"{fmt(r.get('runout_999') if r['near_rest'] and r['valid'] else None)} | "
            f"{fmt(r.get('runout_100') if r['near_rest'] and not r['lost_fraction'] else None)} | "
            f"{fmt(r.get('runout_conn') if r['near_rest'] and not r['lost_fraction'] else None)} | "
            f"{float(law_lube(r['a'])):.2f} | {fmt(r.get('H_over_L0'))} | {fmt(r['ke_last_over_max'], '.2g')} | "
            f"{fmt(r.get(f'runout_99_at_{T_COMPARE:g}s'))} | {fmt(r['lost_fraction'], '.2%')} |")
    lines.append("")
    lines.append("One factor at a time: the 0.99 front (d - d0)/L0 of each column against the 5 mm base "
                 "column of the same a, both at the last time the shorter run reached:")
    lines.append("")
    lines.append("| a | factor | run | compared at t - t_release (tau_c) | base | with the factor | change | "
                 "both at (near) rest | points lost by then (the larger) |")
    lines.append("|---|---|---|---|---|---|---|---|---|")
    for f in sorted(factor_rows, key=lambda f: (-f["a"], f["factor"], f["compared_at_tau"])):
        lines.append(f"| {f['a']:g} | {f['factor']} | {f['case']}/{f['column']} | {f['compared_at_tau']:.2f} | "
                     f"{f['base_runout_99']:.3f} | {f['factor_runout_99']:.3f} | {fmt(f['change'], '+.1%')} | "
                     f"{'yes' if f['base_at_rest'] and f['factor_at_rest'] else 'no'} | "
                     f"{fmt(f['lost_fraction_then'], '.2%')} |")
    lines.append("")
    lines.append("Fits of (d - d0)/L0 (0.99 front) = lambda a^alpha over the base columns at or near rest "
                 "that lost no more than 0.1 % of their points (below: a < 2.3; above: a >= 2.3), and over "
                 "the columns of each family that changes one setting (its name after the cell size):")
    for k, v in fits.items():
        lines.append(f"- {k}: " + ("too few columns at rest" if v is None else
                                    f"alpha = {v['alpha']:.3f}, lambda = {v['lambda']:.3f} (a = {v['a']})"))
    with open(os.path.join(args.out, "summary.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))

    import matplotlib
    import numpy as np
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 3, figsize=(16, 5))
    aa = np.logspace(np.log10(0.3), np.log10(20), 100)
    ax[0].loglog(aa, [law_lube(x) for x in aa], "k-", lw=1, label="Lube 2005: 1.2 a; 1.9 a^(2/3)")
    for key, ls in (("5mm_below", ":"), ("2.5mm_below", "-."), ("5mm_above", "--")):
        fz = fits.get(key)
        if fz:
            ab = np.array([min(fz["a"]), max(fz["a"])])
            ax[0].loglog(ab, fz["lambda"] * ab ** fz["alpha"], ls, color="0.3",
                         label=f"fit {key.split('_')[0]}: {fz['lambda']:.2f} a^{fz['alpha']:.2f}")
    ax[1].axhline(0, color="0.8")
    colors = {5.0: "C0", 2.5: "C3"}
    for (a, h), r in sorted(series.items()):
        c = colors.get(h, "C2")
        mk = "o" if r["near_rest"] else "^"
        fill = c if r["near_rest"] else "none"
        ax[0].loglog([a], [r["runout_99"]], mk, color=c, mfc=fill, ms=8)
        if r.get("runout_conn") is not None and r["near_rest"] and not r["lost_fraction"]:
            ax[0].loglog([a * 1.03], [r["runout_conn"]], "s", color=c, mfc="none", ms=5)
        tt, dd = r["_history"]
        ax[1].plot(tt, dd, "-" if h == 5.0 else "--", color=plt.cm.viridis(np.log2(a * 2) / 5.0),
                   label=f"a = {a:g}, {h:g} mm" + ("" if r["near_rest"] else " (stopped early)"))
        if "H_over_L0" in r and r["near_rest"]:
            ax[2].loglog([a], [r["H_over_L0"]], "o", color=c, ms=8)
    for (name, cols), c in zip(sorted(families.items()), ("C2", "C4", "C5", "C6")):
        pts = sorted((a, r["runout_99"]) for (a, h), r in cols.items() if r["near_rest"] and r["valid"])
        if len(pts) < 2:
            continue
        ax[0].loglog([p[0] for p in pts], [p[1] for p in pts], "D", color=c, ms=6,
                     label=f"{name} (one setting changed), at rest")
        for (a, h), r in cols.items():
            if r["near_rest"] and "H_over_L0" in r:
                ax[2].loglog([a], [r["H_over_L0"]], "D", color=c, ms=6)
    for h, c in colors.items():
        ax[0].plot([], [], "o", color=c, label=f"{h:g} mm cells, 0.99 front, at (near) rest")
        ax[0].plot([], [], "^", color=c, mfc="none", label=f"{h:g} mm: stopped before rest (a lower bound)")
    ax[0].plot([], [], "s", color="0.3", mfc="none", label="connected-mass front")
    ax[0].set_xlabel("a = h0 / L0")
    ax[0].set_ylabel("(d - L0) / L0")
    ax[0].legend(fontsize=7)
    ax[0].set_title("run-out")
    ax[1].axvline(3.0, color="0.6", ls=":", lw=1)
    ax[1].text(3.05, 5.6, "3 tau_c", fontsize=7, color="0.4")
    ax[1].set_ylim(-0.2, None)
    ax[1].set_xlabel("t / sqrt(h0/g) after release")
    ax[1].set_ylabel("0.99 front: (d(t) - d0) / L0")
    ax[1].legend(fontsize=6, ncol=2)
    ax[1].set_title("front against time (solid 5 mm, dashed 2.5 mm)")
    ax[2].loglog(aa, np.where(aa < 0.7, aa, 0.7 ** (2 / 3) * aa ** (1 / 3)), "k-", lw=1,
                 label="Lajeunesse 2005 (2D): a; a^(1/3) (prefactor matched at 0.7)")
    ax[2].set_xlabel("a")
    ax[2].set_ylabel("H_inf / L0")
    ax[2].legend(fontsize=7)
    ax[2].set_title("final height (columns at rest)")
    fig.suptitle("Scree 2D column collapse series" + (f" - {args.label}" if args.label else ""), fontsize=10)
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "series.png"), dpi=110)


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/python3
"""Contact statistics of dense active Brownian hard disks against the time step, both pair rules
(docs/active.md, "Contact statistics against dt").

Usage: active_step_scan.py HSBD OUT [--parts phi04,phi05[,phi04x16,phi05x4]] [--rules exact,mirror]
       active_step_scan.py HSBD OUT --tables   (the table of the runs already in OUT, nothing run)

phi04: 2D, N 400, packing fraction 0.4, Pe = v0 sigma / D = 20 (D_r = 3 D / sigma^2), seeds
       1 to 4, dt 8e-4, 4e-4, 2e-4, 1e-4, 5e-5.
phi05: 2D, N 1000, packing fraction 0.5, Pe 30, seed 1, dt 4e-4, 2e-4, 1e-4, 5e-5.
phi04x16: phi04 with seeds 1 to 16 at dt 8e-4, 2e-4 and 5e-5 (do the rules' limits agree?).
phi05x4: phi05 with seeds 1 to 4.
Every run: `hsbd run` from random insertion, 0.5 time units unsampled (run.t_equil), 5 sampled
in 5 blocks of 1 time unit, one thread (the results are the same on any number). Read from each
summary.json: swim_speed_ratio, pressure_collisional (+- its block error),
pair_corrections_per_particle_step (the exact rule's quantile-map corrections; 0 under the
mirror rule) and collisions_per_particle_step. Several seeds: the mean and the standard error
of the mean over the seeds; one seed: the value and the collisional pressure's block error.
Writes OUT/runs.tsv (one line per case, rule and dt: the means over its seeds) and prints a markdown table, one row per (case, dt), the
exact rule's columns then the mirror's. Units sigma = D = kT = 1. Runs already complete in OUT
are kept. About 10 minutes of CPU for phi04 and phi05, 6 more for phi04x16 and 8 for phi05x4;
one run at a time.
"""
import argparse
import json
import math
import os
import subprocess

CASES = {
    "phi04": dict(n=400, phi=0.4, pe=20, seeds=(1, 2, 3, 4), dts=(8e-4, 4e-4, 2e-4, 1e-4, 5e-5)),
    "phi05": dict(n=1000, phi=0.5, pe=30, seeds=(1,), dts=(4e-4, 2e-4, 1e-4, 5e-5)),
}
# more seeds of the same runs (the first seeds' runs shared)
CASES["phi04x16"] = dict(CASES["phi04"], seeds=tuple(range(1, 17)), dts=(8e-4, 2e-4, 5e-5), runs="phi04")
CASES["phi05x4"] = dict(CASES["phi05"], seeds=(1, 2, 3, 4), runs="phi05")
KEYS = ("swim_speed_ratio", "pressure_collisional", "pressure_collisional_err",
        "pair_corrections_per_particle_step", "collisions_per_particle_step", "cpu_seconds")

INI = """[system]
model = spheres
dimension = 2
N = {n}
packing_fraction = {phi}
seed = {seed}
[active]
v0 = {pe}
[run]
dt = {dt:g}
t_equil = 0.5
t_total = 5
pair_rule = {rule}
[sample]
blocks = 5
"""


def run_dir(out, case, rule, dt, seed):
    return os.path.join(out, f"{CASES[case].get('runs', case)}-{rule}-dt{dt:g}-s{seed}")


def summary(path):
    try:
        with open(os.path.join(path, "summary.json")) as f:
            s = json.load(f)
    except (OSError, ValueError):
        return None
    return s if s.get("completed") else None


def run(hsbd, out, case, rule, dt, seed):
    path = run_dir(out, case, rule, dt, seed)
    s = summary(path)
    if s is None:
        c = CASES[case]
        ini = path + ".ini"
        with open(ini, "w") as f:
            f.write(INI.format(n=c["n"], phi=c["phi"], pe=c["pe"], seed=seed, dt=dt, rule=rule))
        subprocess.run([hsbd, "run", ini, "--out", path, "--force", "--quiet", "--threads", "1"],
                       check=True)
        s = summary(path)
    print(f"{case} {rule} dt {dt:g} seed {seed}: " +
          ", ".join(f"{k} {s[k]:.5g}" for k in KEYS), flush=True)
    return s


def mean_sem(values):
    m = sum(values) / len(values)
    if len(values) < 2:
        return m, math.nan
    var = sum((v - m) ** 2 for v in values) / (len(values) - 1)
    return m, math.sqrt(var / len(values))


def cells(runs):
    """the swim speed ratio, the collisional pressure, corrections and collisions of one
    (case, rule, dt) over its seeds"""
    ratio = mean_sem([s["swim_speed_ratio"] for s in runs])
    pc = mean_sem([s["pressure_collisional"] for s in runs])
    corr = sum(s["pair_corrections_per_particle_step"] for s in runs) / len(runs)
    coll = sum(s["collisions_per_particle_step"] for s in runs) / len(runs)
    if len(runs) > 1:
        return (f"{ratio[0]:.4f} +- {ratio[1]:.4f}", f"{pc[0]:.3f} +- {pc[1]:.3f}", corr, coll)
    return (f"{ratio[0]:.4f}", f"{pc[0]:.2f} +- {runs[0]['pressure_collisional_err']:.2f}",
            corr, coll)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("hsbd")
    ap.add_argument("out")
    ap.add_argument("--parts", default="phi04,phi05")
    ap.add_argument("--rules", default="exact,mirror")
    ap.add_argument("--tables", action="store_true", help="only tabulate the runs in OUT")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    parts, rules = a.parts.split(","), a.rules.split(",")
    results = {}
    for case in parts:
        c = CASES[case]
        for dt in c["dts"]:
            for seed in c["seeds"]:
                for rule in rules:  # the rules in turns
                    if a.tables:
                        s = summary(run_dir(a.out, case, rule, dt, seed))
                        if s is None:
                            continue
                    else:
                        s = run(a.hsbd, a.out, case, rule, dt, seed)
                    results.setdefault((case, rule, dt), []).append(s)
    with open(os.path.join(a.out, "runs.tsv"), "w") as f:
        f.write("# case rule dt runs " + " ".join(KEYS) + " (means over the seeds)\n")
        for (case, rule, dt), runs in results.items():
            f.write(f"{case}\t{rule}\t{dt:g}\t{len(runs)}\t" + "\t".join(
                f"{sum(s[k] for s in runs) / len(runs):.6g}" for k in KEYS) + "\n")
    print("| phi, Pe | dt | exact: swim speed ratio | collisional pressure | corrections, "
          "collisions per particle-step | mirror: swim speed ratio | collisional pressure | "
          "collisions per particle-step |")
    print("|---|---|---|---|---|---|---|---|")
    for case in parts:
        c = CASES[case]
        for i, dt in enumerate(c["dts"]):
            label = f"{c['phi']}, {c['pe']} ({len(c['seeds'])} seed{'s' * (len(c['seeds']) > 1)})"
            row = [label if i == 0 else "", f"{dt:g}"]
            for rule in ("exact", "mirror"):
                runs = results.get((case, rule, dt))
                if not runs:
                    row += ["", "", ""]
                    continue
                ratio, pc, corr, coll = cells(runs)
                row += [ratio, pc, f"{corr:.3f}, {coll:.3f}" if rule == "exact" else f"{coll:.3f}"]
            print("| " + " | ".join(row) + " |")


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""The long-time self-diffusion D_L of hard spheres (and disks) against the time step.

Usage: dl_step_scan.py HSBD OUT [--parts equil,shell,scan,dilute,disks,short,tracers,multi
                       [,long]]
                       [--jobs 2] [--figure docs/figures/spheres-dl-dt.png]
       dl_step_scan.py HSBD OUT --parts tables [--figure ...]   (the tables and
                       fits of the runs already in OUT, nothing run)

equil:  one equilibrated start per packing fraction: N 1000 from the default initial state
        (random insertion, or compression above phi 0.30), 20 time units at dt 1e-2 (the
        step samples the equilibrium distribution exactly at any dt), the last frame kept
        as OUT/start-<d>d-phi<phi>.xyz. Every other run starts from it, unequilibrated.
shell:  the neighbour scheme's share: 500 steps at phi 0.3, dt 1e-2 from the same start with
        shell radii 0.05, 0.15 and the default, and both event orders; the end positions
        compared bit for bit.
scan:   3D, phi 0.1 .. 0.5, dt 3e-4 .. 1e-2 (and 1e-4 at phi 0.3), N 1000, 100 time units
        per seed (seed 1; also seed 2 at phi 0.3 and 0.45); D_L is hsbd's own estimate (summary.json D_long: the MSD's slope between
        lags 0.4 and 4), its error from 20 time blocks. One model for all phi:
        D_L(dt) = D_L(0, phi) (1 - c(phi) dt), c(phi) = a phi^p, fitted to every run at
        once (scipy least squares, errors scaled by sqrt(chi^2/dof)); the dt at which the
        deficit reaches 1 % and 0.1 %. Per phi also a straight line through dt <= 2.1e-3.
dilute: phi 0.05, 1000 time units per dt (seeds 1 and 2): the pair level (three spheres
        meet within a step at a rate of order phi^2 of the pairs').
disks:  2D, phi 0.4 and 0.6, dt 3e-4 .. 1e-2, 80 time units.
short:  the MSD at lags 0.05 .. 0.5 (5 time units, sampled every 0.01) at phi 0.3 and 0.45
        down to dt 3e-5 against the smallest dt: the order of the error in dt.
tracers: point-like tracers (diameter 0.001, D 1) among the phi 0.3 start's spheres
        frozen in place (D 0), 4000 of them, 20 time units, dt 1e-4 .. 1e-2: binary
        encounters with a curved surface and nothing else.
multi:  from each start, N(0, 2 D dt) displacements drawn here (numpy, fixed seed) and, for
        every pair, whether its straight relative path within the step reaches contact (the
        binary prediction a step begins with): the mean number of such contacts per
        particle (against the engine's measured 2 x collisions per particle-step) and the
        fraction of particles with two or more (a three-body encounter inside a step).
long:   phi 0.1, 0.3, 0.5 at dt 1e-3 over 400 units with the MSD to lag 20: the slope
        between lags 2 and 20 against the scan's lags 0.4 and 4.
Each part writes OUT/<part>.tsv (fits: OUT/<part>-fit.tsv); the figure shows the deficit
against dt with the model, the dt each accuracy needs, and the short-lag order check.
Units sigma = D = kT = 1. Fixed seeds; runs already complete in OUT are kept. Run it with
nice on a shared machine: about 2 hours of CPU in all (nice -n 10 ... --jobs 2).
"""
import argparse
import hashlib
import json
import math
import os
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "tools"))
from hsbd_tools import read_table  # noqa: E402

PHIS = (0.3, 0.45, 0.1, 0.2, 0.4, 0.5)  # the run order
DTS = (1e-2, 5e-3, 2e-3, 1e-3, 3e-4)
SMALLEST = (0.3, 1e-4)  # one run at the smallest dt
SECOND_SEED_PHIS = (0.45, 0.3)  # a second seed at every dt
DILUTE_DTS = (1e-2, 5e-3, 2e-3, 1e-3, 5e-4)
DILUTE_SEEDS = (1, 2)
DISK_PHIS = (0.4, 0.6)
DISK_DTS = (1e-2, 3e-3, 1e-3, 3e-4)
N = 1000


def run(hsbd, out, args):
    """One hsbd run into out (kept when it completed before)."""
    if os.path.exists(os.path.join(out, "summary.json")):
        return out
    cmd = [hsbd, "run", "--defaults", "--quiet", "--force", "--threads", "1", "--out", out] + args
    subprocess.run(cmd, check=True, stderr=subprocess.DEVNULL)
    return out


def run_all(hsbd, jobs, runs):
    """runs: (directory, arguments) pairs, the longest expected first."""
    with ThreadPoolExecutor(jobs) as pool:
        list(pool.map(lambda r: run(hsbd, r[0], r[1]), runs))


def summary(d):
    with open(os.path.join(d, "summary.json")) as f:
        return json.load(f)


def base(dim, phi):
    return ["--set", "system.model=spheres", "--set", f"system.dimension={dim}",
            "--set", f"system.N={N}", "--set", f"system.packing_fraction={phi:g}"]


def start_path(out, dim, phi):
    return os.path.join(out, f"start-{dim}d-phi{phi:g}.xyz")


def equil_part(hsbd, out, jobs, dim, phis):
    runs = []
    for phi in phis:
        d = os.path.join(out, f"equil-{dim}d-phi{phi:g}")
        runs.append((d, base(dim, phi) + [
            "--set", "run.dt=1e-2", "--set", "run.t_equil=0", "--set", "run.t_total=20",
            "--set", "sample.every=10", "--set", "system.seed=101",
            "--set", "output.trajectory=xyz", "--set", "output.trajectory_every=20"]))
    run_all(hsbd, jobs, runs)
    for phi, (d, _) in zip(phis, runs):
        with open(os.path.join(d, "trajectory.xyz")) as f:
            lines = f.read().splitlines()
        n = int(lines[0])
        with open(start_path(out, dim, phi), "w") as f:  # the last frame alone
            f.write("\n".join(lines[-(n + 2):]) + "\n")


def dl_args(out, dim, phi, dt, seed, t_total, lag):
    blocks = 20
    every = max(1, round(0.02 / dt))
    return base(dim, phi) + [
        "--set", f"init.positions={start_path(out, dim, phi)}",
        "--set", f"run.dt={dt:g}", "--set", "run.t_equil=0", "--set", f"run.t_total={t_total:g}",
        "--set", f"sample.every={every}", "--set", f"sample.blocks={blocks}",
        "--set", f"sample.msd_max_lag={lag:g}", "--set", f"system.seed={seed}"]


def dl_runs(out, name, dim, phis, dts, seeds, t_total, lag=4, extra=()):
    """(phi, dt, seed, directory, arguments) in the order of phis, the largest dt first;
    extra: more (phi, dt) pairs."""
    pairs = [(phi, dt) for phi in phis for dt in sorted(dts, reverse=True)] + list(extra)
    runs = []
    for phi, dt in pairs:
        for seed in seeds:
            d = os.path.join(out, f"{name}-{dim}d-phi{phi:g}-dt{dt:g}-seed{seed}")
            runs.append((phi, dt, seed, d, dl_args(out, dim, phi, dt, seed, t_total, lag)))
    return runs


LAG_D2 = 2.0  # the lag of the apparent diffusion coefficient MSD / (2 d t)


def msd_over_6t(d, lag, dim):
    """MSD(lag) / (2 d lag) of run d and its error (log-log interpolation in msd.tsv)."""
    t = read_table(os.path.join(d, "msd.tsv")).data
    return tuple(float(np.exp(np.interp(math.log(lag), np.log(t[:, 0]), np.log(t[:, c]))))
                 / (2 * dim * lag) for c in (1, 2))


def write_dl_table(path, runs, dim=3):
    with open(path, "w") as f:
        f.write("phi\tdt\tseed\tD_L\tD_L_err\tD_2\tD_2_err\tcollisions_per_particle_step\t"
                "Z_virial\tZ_theory\tcpu_seconds\ttime\n")
        for phi, dt, seed, d, _ in runs:
            if not os.path.exists(os.path.join(d, "summary.json")):
                continue  # not run (yet): --parts tables
            s = summary(d)
            z_theory = s.get("Z_theory_klm", s.get("Z_theory", float("nan")))
            d2, d2_err = msd_over_6t(d, LAG_D2, dim)
            f.write(f"{phi:g}\t{dt:g}\t{seed}\t{s['D_long']:.8g}\t{s['D_long_err']:.4g}\t"
                    f"{d2:.8g}\t{d2_err:.4g}\t{s['collisions_per_particle_step']:.6g}\t{s.get('Z_virial', 0):.7g}\t"
                    f"{z_theory:.7g}\t{s['cpu_seconds_production']:.4g}\t"
                    f"{s['time_simulated']:.6g}\n")
    print(f"table: {path}")


def run_sets(out):
    """Every D_L run of the parts scan, dilute and disks: name -> (dimension, runs)."""
    return {
        "scan": (3, dl_runs(out, "scan", 3, PHIS, DTS, (1,), 100, extra=(SMALLEST,)) +
                 dl_runs(out, "scan", 3, SECOND_SEED_PHIS, DTS, (2,), 100)),
        "dilute": (3, dl_runs(out, "dilute", 3, (0.05,), DILUTE_DTS, DILUTE_SEEDS, 1000)),
        "disks": (2, dl_runs(out, "disks", 2, DISK_PHIS, DISK_DTS, (1,), 80)),
    }


def scan_part(hsbd, out, jobs, name, dry=False):
    """The runs of one set (unless dry) and its table of those complete."""
    dim, runs = run_sets(out)[name]
    if not dry:
        run_all(hsbd, jobs, [(r[3], r[4]) for r in runs])
    write_dl_table(os.path.join(out, f"{name}.tsv"), runs, dim)


def shell_part(hsbd, out):
    """Bit-identical end positions whatever the shell radius and the event order?"""
    variants = [("default", []), ("shell0.05", ["--set", "system.shell=0.05"]),
                ("shell0.15", ["--set", "system.shell=0.15"]),
                ("global", ["--set", "run.events=global"]),
                ("groups", ["--set", "run.events=groups"])]
    rows = []
    for name, extra in variants:
        d = os.path.join(out, f"shell-{name}")
        run(hsbd, d, base(3, 0.3) + [
            "--set", f"init.positions={start_path(out, 3, 0.3)}", "--set", "run.dt=1e-2",
            "--set", "run.t_equil=0", "--set", "run.t_total=5", "--set", "sample.every=10",
            "--set", "output.trajectory=xyz", "--set", "output.trajectory_every=5"] + extra)
        with open(os.path.join(d, "trajectory.xyz"), "rb") as f:
            frame = f.read().split(b"\n", 2)[2]  # the particles' lines
        s = summary(d)
        rows.append((name, s["shell"], hashlib.sha256(frame).hexdigest()[:16],
                     s["collisions_per_particle_step"]))
    with open(os.path.join(out, "shell.tsv"), "w") as f:
        f.write("variant\tshell\tpositions_sha256\tcollisions_per_particle_step\n")
        for r in rows:
            f.write(f"{r[0]}\t{r[1]:g}\t{r[2]}\t{r[3]:.6g}\n")
    same = len({r[2] for r in rows}) == 1
    print(f"shell: end positions {'identical' if same else 'DIFFER'} across "
          f"{', '.join(r[0] for r in rows)}")


def read_xyz(path):
    with open(path) as f:
        lines = f.read().splitlines()
    n = int(lines[0])
    lattice = lines[1].split('Lattice="')[1].split('"')[0].split()
    box = np.array([float(lattice[0]), float(lattice[4]), float(lattice[8])])
    x = np.array([[float(v) for v in ln.split()[1:4]] for ln in lines[2:2 + n]])
    return x, box


def predicted_contacts(x, box, dim, dt, rng, sigma=1.0):
    """Per particle: the pairs whose straight relative path reaches contact within the step
    (relative displacement N(0, 4 D dt) per axis, approaching, closest approach < sigma)."""
    x = x[:, :dim]
    box = box[:dim]
    n = len(x)
    dx = rng.normal(0.0, math.sqrt(2 * dt), size=(n, dim))
    reach = sigma + 8 * math.sqrt(4 * dt)
    counts = np.zeros(n, dtype=int)
    for i in range(n - 1):
        r = x[i + 1:] - x[i]
        r -= box * np.round(r / box)
        near = np.einsum("ij,ij->i", r, r) < reach * reach
        j = np.nonzero(near)[0] + i + 1
        r = r[near]
        u = dx[j] - dx[i]  # relative displacement of j from i over the step
        ru, uu, rr = np.einsum("ij,ij->i", r, u), np.einsum("ij,ij->i", u, u), np.einsum(
            "ij,ij->i", r, r)
        s = np.clip(-ru / np.maximum(uu, 1e-300), 0.0, 1.0)  # closest approach in [0, 1]
        closest = rr + 2 * s * ru + s * s * uu
        hit = (ru < 0) & (closest < sigma * sigma)
        counts[i] += hit.sum()
        np.add.at(counts, j[hit], 1)
    return counts


def multi_part(out, dim=3, phis=PHIS, dts=DTS, scan_name="scan"):
    rng = np.random.default_rng(2024)
    measured = {}
    path = os.path.join(out, f"{scan_name}.tsv")
    if os.path.exists(path):
        t = load(path)
        for phi, dt, cpp in zip(t["phi"], t["dt"], t["collisions_per_particle_step"]):
            measured[(round(phi, 6), round(dt, 12))] = cpp
    with open(os.path.join(out, f"multi-{dim}d.tsv"), "w") as f:
        f.write("phi\tdt\tcontacts_per_particle\tmeasured_2cpp\tfraction_ge1\tfraction_ge2\t"
                "fraction_ge3\n")
        for phi in phis:
            x, box = read_xyz(start_path(out, dim, phi))
            for dt in dts:
                c = np.concatenate([predicted_contacts(x, box, dim, dt, rng) for _ in range(4)])
                m = 2 * measured.get((round(phi, 6), round(dt, 12)), float("nan"))
                f.write(f"{phi:g}\t{dt:g}\t{c.mean():.5g}\t{m:.5g}\t{(c >= 1).mean():.5g}\t"
                        f"{(c >= 2).mean():.5g}\t{(c >= 3).mean():.5g}\n")
    print(f"multi: {os.path.join(out, f'multi-{dim}d.tsv')}")


def long_part(hsbd, out, jobs, phis=(0.1, 0.3, 0.5), dt=1e-3):
    """The MSD to lag 20: its slope between 2 and 20 (hsbd's D_long of these runs) against
    the slope between 0.4 and 4 of the same MSD (the scan's estimator), both over 6."""
    runs = []
    for phi in phis:
        d = os.path.join(out, f"long-3d-phi{phi:g}-dt{dt:g}")
        runs.append((phi, dt, 7, d, dl_args(out, 3, phi, dt, 7, 400, 20)))
    run_all(hsbd, jobs, [(r[3], r[4]) for r in runs])
    with open(os.path.join(out, "long.tsv"), "w") as f:
        f.write("phi\tdt\tslope_2_20\terr_2_20\tslope_0.4_4\tratio\n")
        for phi, dt, _, d, _ in runs:
            s = summary(d)
            t = read_table(os.path.join(d, "msd.tsv")).data
            msd = lambda lag: np.interp(math.log(lag), np.log(t[:, 0]), t[:, 1])  # noqa: E731
            short, longer = (msd(4) - msd(0.4)) / (6 * 3.6), s["D_long"]
            f.write(f"{phi:g}\t{dt:g}\t{longer:.6g}\t{s['D_long_err']:.3g}\t{short:.6g}\t"
                    f"{longer / short:.5f}\n")
    print(f"long: {os.path.join(out, 'long.tsv')}")


TRACER_DTS = (1e-2, 3e-3, 1e-3, 3e-4, 1e-4)


def tracers_part(hsbd, out, jobs, dts=TRACER_DTS, count=4000, tracer_sigma=0.001):
    """Point-like tracers among immobile obstacles: the phi 0.3 start's 1000 spheres frozen
    (D = 0), 4000 tracers of diameter 0.001 and D 1 placed at random outside them. Each
    tracer meets fixed spheres of contact radius 0.5 and nothing else (tracer-tracer contacts
    are of measure zero): binary encounters with a curved surface, no momentum passed on."""
    x, box = read_xyz(start_path(out, 3, 0.3))
    rng = np.random.default_rng(5)
    tracers = []
    while len(tracers) < count:
        p = rng.uniform(0, box[0], 3)
        r = x - p
        r -= box * np.round(r / box)
        if (np.sqrt((r * r).sum(axis=1)) > 0.5 + tracer_sigma / 2 + 1e-4).all():
            tracers.append(p)
    start = os.path.join(out, "start-tracers.xyz")
    with open(start, "w") as f:
        f.write(f"{count + len(x)}\nLattice=\"{box[0]:.17g} 0 0 0 {box[1]:.17g} 0 0 0 "
                f"{box[2]:.17g}\" pbc=\"T T T\" Properties=species:S:1:pos:R:3\n")
        for p in tracers:
            f.write("tracer %.12g %.12g %.12g\n" % tuple(p))
        for p in x:
            f.write("obstacle %.12g %.12g %.12g\n" % tuple(p))
    phi = (len(x) + count * tracer_sigma ** 3) * math.pi / 6 / float(np.prod(box))
    runs = []
    for dt in dts:
        d = os.path.join(out, f"tracers-dt{dt:g}")
        runs.append((dt, d, [
            "--set", "system.model=spheres", "--set", "system.dimension=3",
            "--set", f"system.N={count + len(x)}", "--set", f"system.packing_fraction={phi!r}",
            "--set", "system.seed=3", "--set", "species.names=tracer,obstacle",
            "--set", f"species.count={count},{len(x)}",
            "--set", f"species.sigma={tracer_sigma:g},1", "--set", "species.D=1,0",
            "--set", f"init.positions={start}", "--set", f"run.dt={dt:g}",
            "--set", "run.t_equil=0", "--set", "run.t_total=20",
            "--set", f"sample.every={max(1, round(0.01 / dt))}",
            "--set", "sample.msd_max_lag=2", "--set", "sample.blocks=10"]))
    run_all(hsbd, jobs, [(r[1], r[2]) for r in runs])
    with open(os.path.join(out, "tracers.tsv"), "w") as f:
        f.write("dt\tD_L\tD_L_err\tcollisions_per_particle_step\n")
        for dt, d, _ in runs:
            s = summary(d)
            dl, err = s["D_long_species"]["tracer"]
            f.write(f"{dt:g}\t{dl:.6g}\t{err:.3g}\t{s['collisions_per_particle_step']:.5g}\n")
    print(f"tracers: {os.path.join(out, 'tracers.tsv')}")


SHORT_PHIS = (0.3, 0.45)
SHORT_DTS = (1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 3e-5)
SHORT_LAGS = (0.05, 0.1, 0.2, 0.5)


def short_part(hsbd, out, jobs, phis=SHORT_PHIS, dts=SHORT_DTS, t_total=5):
    """The MSD at short lags (sampled every 0.01, the same lags in every run) down to
    dt 3e-5: the relative deficit against the smallest dt, the error's order in dt."""
    runs = []
    for phi in phis:
        for dt in sorted(dts, reverse=True):
            d = os.path.join(out, f"short-3d-phi{phi:g}-dt{dt:g}")
            args = dl_args(out, 3, phi, dt, 1, t_total, 0.5)
            args[args.index(f"sample.every={max(1, round(0.02 / dt))}")] = \
                f"sample.every={max(1, round(0.01 / dt))}"
            args[args.index("sample.blocks=20")] = "sample.blocks=10"
            runs.append((phi, dt, d, args))
    run_all(hsbd, jobs, [(r[2], r[3]) for r in runs])
    with open(os.path.join(out, "short.tsv"), "w") as f:
        f.write("phi\tdt\tlag\tmsd\tmsd_err\tratio_to_smallest_dt\tratio_err\n")
        for phi in phis:
            tables = {}
            for p, dt, d, _ in runs:
                if p == phi:  # the MSD and its error at each lag (log-log interpolation:
                    # the sampling interval is the multiple of dt nearest to 0.01)
                    t = read_table(os.path.join(d, "msd.tsv")).data
                    tables[dt] = [tuple(np.exp(np.interp(math.log(lag), np.log(t[:, 0]),
                                                         np.log(t[:, c]))) for c in (1, 2))
                                  for lag in SHORT_LAGS]
            ref = tables[min(dts)]
            for dt in sorted(dts, reverse=True):
                for k, lag in enumerate(SHORT_LAGS):
                    (m, e), (m0, e0) = tables[dt][k], ref[k]
                    f.write(f"{phi:g}\t{dt:g}\t{lag:g}\t{m:.7g}\t{e:.3g}\t{m / m0:.6f}\t"
                            f"{m / m0 * math.hypot(e / m, e0 / m0):.2g}\n")
    print(f"short: {os.path.join(out, 'short.tsv')}")


# ---- analysis ----

def load(path):
    t = read_table(path)
    return {n: t.data[:, k] for k, n in enumerate(t.names)} if t.data.size else None


SMALL_DT = 2.1e-3  # the linear regime of the deficit: its slope c from dt <= this


def deficit(dt, c, s):
    """The fitted form of 1 - D_L(dt) / D_L(0): c dt at small dt, saturating at s."""
    return c * dt / (1 + c * dt / s)


def fit_linear(dt, y, e):
    """Weighted least squares y = D0 (1 - c dt): D0, c, their errors (scaled by
    sqrt(chi^2/dof) when that exceeds 1) and chi^2/dof."""
    m = np.array([np.ones_like(dt), dt]).T / e[:, None]
    p, *_ = np.linalg.lstsq(m, y / e, rcond=None)
    cov = np.linalg.inv(m.T @ m)
    chi2 = float(np.sum((m @ p - y / e) ** 2)) / max(1, len(y) - 2)
    cov *= max(1.0, chi2)
    d0, c = p[0], -p[1] / p[0]
    c_err = c * math.hypot(math.sqrt(cov[1, 1]) / p[1], math.sqrt(cov[0, 0]) / p[0])
    return d0, math.sqrt(cov[0, 0]), c, abs(c_err), chi2


def dt_at(level, c, s):
    """The dt at which deficit(dt, c, s) reaches level (inf when it never does)."""
    return level / (c * (1 - level / s)) if c > 0 and 0 < level < s else float("inf")


def seed_means(d, sel, value, error):
    """Per dt (sorted): the seeds' weighted mean of a column and its error."""
    dts, y, e = [], [], []
    for dt in sorted(set(d["dt"][sel])):
        s = sel & (d["dt"] == dt)
        w = 1 / d[error][s] ** 2
        dts.append(dt)
        y.append(np.sum(w * d[value][s]) / np.sum(w))
        e.append(1 / math.sqrt(np.sum(w)))
    return map(np.array, (dts, y, e))


def global_fit(data, fixed_s=None):
    """One model for every phi: D_L(dt) = D_L(0, phi) (1 - deficit(dt, c(phi), s)) with
    c(phi) = a phi^p; data: (phi, dts, y, e) per phi. The parameters (a, p, s, then each
    D_L(0)), their errors (scaled by sqrt(chi^2/dof) when that exceeds 1) and chi^2/dof."""
    from scipy.optimize import least_squares

    def residuals(q):
        a, pw = q[0], q[1]
        sat = fixed_s if fixed_s else q[2]
        off = 2 if fixed_s else 3
        return np.concatenate([(q[off + k] * (1 - deficit(dts, a * phi ** pw, sat)) - y) / e
                               for k, (phi, dts, y, e) in enumerate(data)])
    q0 = [30.0, 1.5] + ([] if fixed_s else [0.3]) + [y[np.argmin(dts)] for _, dts, y, _ in data]
    r = least_squares(residuals, q0)
    dof = max(1, len(r.fun) - len(q0))
    chi2 = float(np.sum(r.fun ** 2)) / dof
    cov = np.linalg.pinv(r.jac.T @ r.jac) * max(1.0, chi2)
    err = np.sqrt(np.diag(cov))
    q = list(r.x)
    if fixed_s:
        q.insert(2, fixed_s)
        err = np.insert(err, 2, 0.0)
    return q, err, chi2, cov[:2, :2]


def analyse(out, name="scan", fixed_s=math.inf):
    """The global model over every phi of the table (global_fit), and per phi the slope of
    a straight line through dt <= SMALL_DT as a check."""
    path = os.path.join(out, f"{name}.tsv")
    d = load(path) if os.path.exists(path) else None
    if d is None:
        return None
    data = []
    for phi in sorted(set(d["phi"])):
        dts, y, e = seed_means(d, d["phi"] == phi, "D_L", "D_L_err")
        if len(dts) >= 3:
            data.append((phi, dts, y, e))
    if not data:
        return None
    if len(data) < 2:  # too few phi for c(phi): a straight line through every dt
        q, err, chi2, cov = [float("nan")] * 3 + [0.0] * len(data), [0.0] * 3, 0.0, None
    else:
        q, err, chi2, cov = global_fit(data, fixed_s)
    a, pw, sat = q[:3]
    rows = []
    for k, (phi, dts, y, e) in enumerate(data):
        small = dts <= SMALL_DT
        c_local, c_local_err = (fit_linear(dts[small], y[small], e[small])[2:4]
                                if small.sum() >= 2 else (float("nan"), float("nan")))
        if cov is None:
            d0, d0_err, c, c_err, _ = fit_linear(dts, y, e)
            sat = float("inf")
        else:
            d0, d0_err, c = q[3 + k], err[3 + k], a * phi ** pw
            grad = np.array([c / a, c * math.log(phi)])  # c's error from (a, p)
            c_err = math.sqrt(float(grad @ cov @ grad))
        rows.append(dict(phi=phi, d0=d0, d0_err=d0_err, c=c, c_err=c_err, c_local=c_local,
                         c_local_err=c_local_err, s=sat, dts=dts, y=y, e=e,
                         dt1=dt_at(0.01, c, sat), dt01=dt_at(0.001, c, sat)))
    with open(os.path.join(out, f"{name}-fit.tsv"), "w") as f:
        f.write(f"# D_L(dt) = D_L(0) (1 - c dt / (1 + c dt / s)), c = a phi^p: a = {a:.4g} +- "
                f"{err[0]:.2g}, p = {pw:.4g} +- {err[1]:.2g}, s = {sat:.3g} +- {err[2]:.2g} "
                f"(inf: fixed, a straight line), chi^2/dof = {chi2:.3g}\n")
        f.write("phi\tD_L0\tD_L0_err\tc\tc_err\tc_local\tc_local_err\tdt_1pc\tdt_0.1pc\n")
        for r in rows:
            f.write(f"{r['phi']:g}\t{r['d0']:.5f}\t{r['d0_err']:.5f}\t{r['c']:.4g}\t"
                    f"{r['c_err']:.2g}\t"
                    f"{r['c_local']:.3g}\t{r['c_local_err']:.2g}\t{r['dt1']:.3g}\t"
                    f"{r['dt01']:.3g}\n")
    print(f"fit: {os.path.join(out, f'{name}-fit.tsv')}")
    return rows


def figure(out, path, rows, dilute=None, disks=None):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from hsbd_tools import save_figure
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.6))
    colours = plt.cm.viridis(np.linspace(0, 0.9, len(rows)))
    fine = np.logspace(-4.2, -1.9, 100)
    for r, col in zip(rows, colours):
        ax[0].errorbar(r["dts"], 100 * (r["y"] / r["d0"] - 1), 100 * r["e"] / r["d0"], fmt="o",
                       color=col, ms=4, capsize=2,
                       label=f"phi {r['phi']:g}: D_L(0) = {r['d0']:.3f}, c = {r['c']:.3g}")
        ax[0].plot(fine, -100 * deficit(fine, r["c"], r["s"]), "-", color=col, lw=1)
    for extra, mark, colour in ((dilute, "s", "grey"), (disks, "^", "tab:red")):
        for r in extra or []:
            ax[0].errorbar(r["dts"], 100 * (r["y"] / r["d0"] - 1), 100 * r["e"] / r["d0"],
                           fmt=mark, ms=4, color=colour, capsize=2,
                           label=f"{'disks' if mark == '^' else 'spheres'} phi {r['phi']:g}")
    for level in (-1, -0.1):
        ax[0].axhline(level, color="k", lw=0.6, ls=":")
    ax[0].set_xscale("log")
    ax[0].set_xlabel("dt (sigma^2 / D)")
    ax[0].set_ylabel("D_L(dt) / D_L(0) - 1  (%)")
    ax[0].set_title("D_L (MSD slope, lags 0.4-4) against dt, N 1000")
    ax[0].legend(fontsize=6.5)
    phis = np.array([r["phi"] for r in rows])
    ax[1].semilogy(phis, [r["dt1"] for r in rows], "o-", label="1 %")
    ax[1].semilogy(phis, [r["dt01"] for r in rows], "s-", label="0.1 %")
    ax[1].set_xlabel("phi")
    ax[1].set_ylabel("largest dt (sigma^2 / D)")
    ax[1].set_title("the time step for a given accuracy of D_L (3D)")
    ax[1].legend()
    short = os.path.join(out, "short.tsv")
    if os.path.exists(short):
        t = load(short)
        ref = min(t["dt"])
        for phi, col in zip(sorted(set(t["phi"])), ("tab:blue", "tab:orange")):
            sel = (t["phi"] == phi) & (t["lag"] == SHORT_LAGS[0]) & (t["dt"] > ref)
            x, y, e = t["dt"][sel], 1 - t["ratio_to_smallest_dt"][sel], t["ratio_err"][sel]
            ax[2].errorbar(x, 100 * y, 100 * e, fmt="o", color=col, capsize=2,
                           label=f"phi {phi:g}")
            small = x <= 3.1e-3  # order 1: y = c (dt - ref) through the small steps
            w = (x[small] - ref) / e[small] ** 2
            c = np.sum(w * y[small]) / np.sum(w * (x[small] - ref))
            ax[2].plot(fine, 100 * c * (fine - ref), "-", color=col, lw=1,
                       label=f"{c:.3g} (dt - 3e-5), order 1")
            big = np.argmax(x)  # order 1/2 through the largest step
            a = y[big] / (math.sqrt(x[big]) - math.sqrt(ref))
            ax[2].plot(fine, 100 * a * (np.sqrt(fine) - math.sqrt(ref)), "--", color=col, lw=1,
                       label=f"{a:.2g} (sqrt(dt) - sqrt(3e-5)), order 1/2")
        ax[2].axhline(0, color="k", lw=0.5)
        ax[2].set_xscale("log")
        ax[2].set_ylim(-1, 8)
        ax[2].set_xlabel("dt (sigma^2 / D)")
        ax[2].set_ylabel("MSD deficit at lag 0.05 against dt 3e-5 (%)")
        ax[2].set_title("the order of the error: the MSD at a short lag")
        ax[2].legend(fontsize=6.5)
    fig.tight_layout()
    save_figure(fig, path)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("hsbd")
    ap.add_argument("out")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--parts", default="equil,shell,scan,dilute,disks,short,tracers,multi")
    ap.add_argument("--figure", default="")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    hsbd = os.path.abspath(args.hsbd)
    out = os.path.abspath(args.out)
    parts = args.parts.split(",")
    if "equil" in parts:
        equil_part(hsbd, out, args.jobs, 3, PHIS + (0.05,))
        if "disks" in parts:
            equil_part(hsbd, out, args.jobs, 2, DISK_PHIS)
    if "shell" in parts:
        shell_part(hsbd, out)
    dry = "tables" in parts  # the tables of the runs done so far, nothing run
    for name in ("scan", "dilute", "disks"):
        if name in parts or dry:
            scan_part(hsbd, out, args.jobs, name, dry)
    if "short" in parts:
        short_part(hsbd, out, args.jobs)
    if "tracers" in parts:
        tracers_part(hsbd, out, args.jobs)
    if "multi" in parts:
        multi_part(out, phis=PHIS + (0.05,))
    if "long" in parts:
        long_part(hsbd, out, args.jobs)
    rows, dilute, disks = (analyse(out, name) for name in ("scan", "dilute", "disks"))
    if args.figure and rows:
        figure(out, args.figure, rows, dilute, disks)


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""The long-time self-diffusion D_L of hard spheres (and disks) against the time step.

Usage: dl_step_scan.py HSBD OUT [--parts equil,scan,dilute,shell,multi,disks,long]
                       [--jobs 2] [--seeds 1,2] [--figure docs/figures/spheres-dl-dt.png]

equil:  one equilibrated start per packing fraction: N 1000 from the default initial state
        (random insertion, or compression above phi 0.30), 20 time units at dt 1e-2 (the
        scheme samples the equilibrium distribution exactly at any dt), the last frame kept
        as OUT/start-<d>d-phi<phi>.xyz. Every other run starts from it with no equilibration.
scan:   3D, phi 0.1 .. 0.5, dt 1e-4 .. 1e-2, N 1000, 80 time units per seed; D_L is hsbd's
        own estimate (summary.json D_long: the MSD's slope between lags 0.4 and 4), its error
        from 20 time blocks. Per phi a fit D_L(dt) = D_0 (1 - c dt - c2 dt^2), weighted by the
        errors; the dt at which the fit's deficit reaches 1 % and 0.1 %.
dilute: phi 0.05, 1000 time units per dt: the pair level (two-body encounters alone; three
        spheres meet within a step at a rate of order phi^2 of the pairs').
shell:  the neighbour scheme's share: 500 steps at phi 0.3, dt 1e-2 from the same start with
        shell radii 0.05, 0.15 and the default, and both event orders; the end positions
        compared bit for bit.
multi:  from each start, N(0, 2 D dt) displacements drawn here (numpy, fixed seed) and, for
        every pair, whether its straight relative path within the step reaches contact (the
        binary prediction the step begins with): the mean number of such contacts per
        particle (against the engine's measured 2 x collisions per particle-step) and the
        fraction of particles with two or more (a three-body encounter inside a step).
disks:  2D, phi 0.4 and 0.6, a shorter dt scan.
long:   per phi one run at dt 5e-4 over 400 units with the MSD to lag 20: the slope between
        lags 2 and 20 against the scan's lags 0.4 and 4 (how long "long time" must be).
Each part writes OUT/<part>.tsv; the figure shows D_L / D_0 - 1 against dt with the fits.
Units sigma = D = kT = 1. Fixed seeds; runs already complete in OUT are kept.
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
DILUTE_DTS = (1e-2, 5e-3, 2e-3, 1e-3, 5e-4)
DILUTE_SEEDS = (1, 2, 3, 4)
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


def write_dl_table(path, runs):
    with open(path, "w") as f:
        f.write("phi\tdt\tseed\tD_L\tD_L_err\tcollisions_per_particle_step\tZ_virial\t"
                "Z_theory\tcpu_seconds\ttime\n")
        for phi, dt, seed, d, _ in runs:
            s = summary(d)
            z_theory = s.get("Z_theory_klm", s.get("Z_theory", float("nan")))
            f.write(f"{phi:g}\t{dt:g}\t{seed}\t{s['D_long']:.8g}\t{s['D_long_err']:.4g}\t"
                    f"{s['collisions_per_particle_step']:.6g}\t{s.get('Z_virial', 0):.7g}\t"
                    f"{z_theory:.7g}\t{s['cpu_seconds_production']:.4g}\t"
                    f"{s['time_simulated']:.6g}\n")
    print(f"table: {path}")


def scan_part(hsbd, out, jobs, seeds, name="scan", dim=3, phis=PHIS, dts=DTS, t_total=100,
              extra=()):
    runs = dl_runs(out, name, dim, phis, dts, seeds, t_total, extra=extra)
    run_all(hsbd, jobs, [(r[3], r[4]) for r in runs])
    write_dl_table(os.path.join(out, f"{name}.tsv"), runs)


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
        t = read_table(path)
        for row in t.data:
            measured[(round(row[0], 6), round(row[1], 12))] = row[5]
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


# ---- analysis ----

def load(path):
    t = read_table(path)
    return {n: t.data[:, k] for k, n in enumerate(t.names)}


def fit(dt, y, e, quadratic):
    """Weighted least squares y = D0 (1 - c dt - c2 dt^2): D0, c, c2, their covariance, chi2/dof."""
    cols = [np.ones_like(dt), dt] + ([dt * dt] if quadratic else [])
    a = np.array(cols).T / e[:, None]
    b = y / e
    p, *_ = np.linalg.lstsq(a, b, rcond=None)
    cov = np.linalg.inv(a.T @ a)
    dof = max(1, len(y) - len(p))
    chi2 = float(np.sum((a @ p - b) ** 2)) / dof
    d0 = p[0]
    c = -p[1] / d0
    c2 = -p[2] / d0 if quadratic else 0.0
    return d0, c, c2, cov, chi2


def dt_at(level, c, c2):
    """The dt at which c dt + c2 dt^2 reaches level."""
    if c2 == 0:
        return level / c if c > 0 else float("inf")
    disc = c * c + 4 * c2 * level
    return (-c + math.sqrt(disc)) / (2 * c2) if disc >= 0 else float("inf")


def analyse(out, name="scan"):
    d = load(os.path.join(out, f"{name}.tsv"))
    rows = []
    for phi in sorted(set(d["phi"])):
        sel = d["phi"] == phi
        dts = sorted(set(d["dt"][sel]))
        dt_m, y, e = [], [], []
        for dt in dts:  # the seeds' mean, its error from the blocks (and the seeds' scatter)
            s = sel & (d["dt"] == dt)
            w = 1 / d["D_L_err"][s] ** 2
            dt_m.append(dt)
            y.append(np.sum(w * d["D_L"][s]) / np.sum(w))
            e.append(1 / math.sqrt(np.sum(w)))
        dt_m, y, e = map(np.array, (dt_m, y, e))
        lin = fit(dt_m, y, e, False)
        quad = fit(dt_m, y, e, True)
        use = quad if lin[4] > 2 and len(dt_m) > 3 else lin
        d0, c, c2, cov, chi2 = use
        d0_err = math.sqrt(cov[0, 0])
        c_err = math.sqrt(cov[1, 1]) / d0
        rows.append(dict(phi=phi, d0=d0, d0_err=d0_err, c=c, c_err=c_err, c2=c2, chi2=chi2,
                         model="quadratic" if use is quad else "linear", lin_chi2=lin[4],
                         dt1=dt_at(0.01, c, c2), dt01=dt_at(0.001, c, c2),
                         dts=dt_m, y=y, e=e))
    with open(os.path.join(out, f"{name}-fit.tsv"), "w") as f:
        f.write("phi\tD_0\tD_0_err\tc\tc_err\tc2\tchi2_dof\tmodel\tlinear_chi2_dof\t"
                "dt_1pc\tdt_0.1pc\n")
        for r in rows:
            f.write(f"{r['phi']:g}\t{r['d0']:.5f}\t{r['d0_err']:.5f}\t{r['c']:.4g}\t"
                    f"{r['c_err']:.2g}\t{r['c2']:.4g}\t{r['chi2']:.3g}\t{r['model']}\t"
                    f"{r['lin_chi2']:.3g}\t{r['dt1']:.3g}\t{r['dt01']:.3g}\n")
    print(f"fit: {os.path.join(out, f'{name}-fit.tsv')}")
    return rows


def figure(out, path, rows, dilute=None, disks=None):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from hsbd_tools import save_figure
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.4))
    colours = plt.cm.viridis(np.linspace(0, 0.9, len(rows)))
    fine = np.logspace(-4.2, -1.9, 100)
    for r, col in zip(rows, colours):
        rel = r["y"] / r["d0"] - 1
        ax[0].errorbar(r["dts"], 100 * rel, 100 * r["e"] / r["d0"], fmt="o", color=col, ms=4,
                       capsize=2, label=f"phi {r['phi']:g}: D_0 = {r['d0']:.4f}")
        ax[0].plot(fine, -100 * (r["c"] * fine + r["c2"] * fine ** 2), "-", color=col, lw=1)
    for extra, mark, lab in ((dilute, "s", "phi 0.05"), (disks, "^", "disks")):
        for r in extra or []:
            rel = r["y"] / r["d0"] - 1
            ax[0].errorbar(r["dts"], 100 * rel, 100 * r["e"] / r["d0"], fmt=mark, ms=4,
                           color="grey" if mark == "s" else "tab:red", capsize=2,
                           label=f"{lab} {r['phi']:g}" if mark == "^" else lab)
    ax[0].axhline(-1, color="k", lw=0.6, ls=":")
    ax[0].axhline(-0.1, color="k", lw=0.6, ls=":")
    ax[0].set_xscale("log")
    ax[0].set_xlabel("dt (sigma^2 / D)")
    ax[0].set_ylabel("D_L(dt) / D_L(0) - 1  (%)")
    ax[0].set_title("D_L against the time step (N 1000, 3D unless marked)")
    ax[0].legend(fontsize=7)
    phis = np.array([r["phi"] for r in rows])
    ax[1].semilogy(phis, [r["dt1"] for r in rows], "o-", label="1 %")
    ax[1].semilogy(phis, [r["dt01"] for r in rows], "s-", label="0.1 %")
    ax[1].set_xlabel("phi")
    ax[1].set_ylabel("largest dt for the D_L error")
    ax[1].set_title("time step for a given accuracy of D_L")
    ax[1].legend()
    fig.tight_layout()
    save_figure(fig, path)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("hsbd")
    ap.add_argument("out")
    ap.add_argument("--seeds", default="1")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--parts", default="equil,scan,dilute,shell,multi,disks,long")
    ap.add_argument("--figure", default="")
    args = ap.parse_args()
    seeds = [int(s) for s in args.seeds.split(",")]
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
    if "scan" in parts:
        scan_part(hsbd, out, args.jobs, seeds, extra=(SMALLEST,))
    if "dilute" in parts:
        scan_part(hsbd, out, args.jobs, DILUTE_SEEDS, "dilute", 3, (0.05,), DILUTE_DTS, 1000)
    if "disks" in parts:
        scan_part(hsbd, out, args.jobs, seeds[:1], "disks", 2, DISK_PHIS, DISK_DTS, 80)
    if "multi" in parts:
        multi_part(out)
    if "long" in parts:
        long_part(hsbd, out, args.jobs)
    rows = analyse(out) if os.path.exists(os.path.join(out, "scan.tsv")) else []
    dilute = analyse(out, "dilute") if os.path.exists(os.path.join(out, "dilute.tsv")) else None
    disks = analyse(out, "disks") if os.path.exists(os.path.join(out, "disks.tsv")) else None
    if args.figure and rows:
        figure(out, args.figure, rows, dilute, disks)


if __name__ == "__main__":
    main()

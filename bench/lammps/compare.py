#!/usr/bin/python3
"""hsbd against LAMMPS' pseudo-hard-sphere Brownian dynamics: CPU time per Brownian time
(sigma^2 / D) at matched error in Z and in D_L, both codes run in turns on one thread.

Usage: bench/lammps/compare.py HSBD [--lammps LMP | --build DIR] [--out DIR]
           [--phis 0.3,0.45] [--n 4000] [--lammps-dt 1e-5] [--lammps-time 10]
           [--hsbd-dt 1e-2,1e-3] [--hsbd-time 40] [--rounds 1] [--seed 1]

Per packing fraction: an hsbd hard-sphere fluid (N particles, the default initial state,
20 time units at dt 1e-2) is the common start; LAMMPS reads it scaled to the
Barker-Henderson diameter of the pseudo-hard spheres (0.99981 sigma_LJ), so both codes
simulate the same phi. Then, in turns, LAMMPS (in.phs: Mie 50-49, fix brownian, D = 1;
0.05 time units unsampled, then --lammps-time sampled) and hsbd at each --hsbd-dt (from the
start, --hsbd-time sampled). Measured for each: Z against Kolafa-Labik-Malijevsky (LAMMPS:
Z = 1 + P_virial / (rho kT) from the thermo output, errors from 10 blocks; hsbd: Z_virial),
D_L as the MSD's slope between lags 0.4 and 4 (LAMMPS: from frames of unwrapped positions
every 0.02, all origins, errors from 10 groups of particles; hsbd: D_long with
sample.msd_max_lag 4 and time blocks of at least that lag), and the production's CPU time per sigma^2 / D (LAMMPS: loop time x
its CPU use; hsbd: cpu_seconds_production). Times and lengths of LAMMPS are converted to the
Barker-Henderson diameter. --rounds repeats the turns (the machine's speed drifts).

--build DIR runs build-lammps.sh DIR first (LAMMPS from Debian's source package with the
BROWNIAN and EXTRA-PAIR packages; about an hour of CPU) unless DIR/build/lmp exists.
Without --lammps or --build only hsbd is run (its rows of the table).
"""
import argparse
import json
import math
import os
import re
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
D_BH = 0.99981  # Barker-Henderson diameter of the Mie 50-49 potential at kT/eps = 1.5
LAGS = (0.4, 4.0)  # the MSD slope of both codes


def klm(phi):
    """Kolafa-Labik-Malijevsky equation of state of hard spheres."""
    return (1 + phi + phi ** 2 - 2.0 / 3.0 * phi ** 3 * (1 + phi)) / (1 - phi) ** 3


def blocks_mean(values, nb=10):
    """Mean of values and its error from nb consecutive blocks."""
    v = np.asarray(values, dtype=float)
    m = len(v) // nb * nb
    b = v[:m].reshape(nb, -1).mean(axis=1)
    return float(v.mean()), float(b.std(ddof=1) / math.sqrt(nb))


def hsbd_args(phi, n, seed):
    return ["--set", "system.model=spheres", "--set", "system.dimension=3", "--set",
            f"system.N={n}", "--set", f"system.packing_fraction={phi:g}", "--set",
            f"system.seed={seed}"]


def make_start(hsbd, out, phi, n, seed):
    """An equilibrated hard-sphere fluid: XYZ for hsbd, a data file for LAMMPS."""
    d = os.path.join(out, f"start-phi{phi:g}-n{n}-seed{seed}")  # reused only as made
    xyz, data = d + ".xyz", d + ".data"
    if os.path.exists(data):
        return xyz, data
    subprocess.run([hsbd, "run", "--defaults", "--quiet", "--force", "--threads", "1", "--out", d]
                   + hsbd_args(phi, n, seed) +
                   ["--set", "run.dt=1e-2", "--set", "run.t_equil=0", "--set", "run.t_total=20",
                    "--set", "output.trajectory=xyz", "--set", "output.trajectory_every=20"],
                   check=True, stderr=subprocess.DEVNULL)
    with open(os.path.join(d, "trajectory.xyz")) as f:
        lines = f.read().splitlines()
    count = int(lines[0])
    frame = lines[-(count + 2):]
    with open(xyz, "w") as f:
        f.write("\n".join(frame) + "\n")
    box = float(frame[1].split('Lattice="')[1].split()[0])
    with open(data, "w") as f:  # lengths in sigma_LJ: the hard-sphere diameter is D_BH
        f.write(f"hsbd hard-sphere fluid, phi {phi:g}, scaled to the Barker-Henderson "
                f"diameter\n\n{count} atoms\n1 atom types\n\n")
        for a in "xyz":
            f.write(f"0 {box * D_BH:.12g} {a}lo {a}hi\n")
        f.write("\nAtoms # atomic\n\n")
        for k, line in enumerate(frame[2:]):
            p = [float(v) % box * D_BH for v in line.split()[1:4]]
            f.write(f"{k + 1} 1 {p[0]:.12g} {p[1]:.12g} {p[2]:.12g}\n")
    return xyz, data


def run_hsbd(hsbd, out, phi, n, seed, dt, t_total, xyz, tag):
    d = os.path.join(out, f"hsbd-phi{phi:g}-n{n}-dt{dt:g}-{tag}")
    if not os.path.exists(os.path.join(d, "summary.json")):
        subprocess.run([hsbd, "run", "--defaults", "--quiet", "--force", "--threads", "1",
                        "--out", d] + hsbd_args(phi, n, seed) +
                       ["--set", f"init.positions={xyz}", "--set", "run.t_equil=0",
                        "--set", f"run.dt={dt:g}", "--set", f"run.t_total={t_total:g}",
                        "--set", f"sample.every={max(1, round(0.02 / dt))}",
                        "--set", f"sample.msd_max_lag={LAGS[1]:g}",
                        "--set", f"sample.blocks={min(20, int(t_total // LAGS[1]))}"],
                       check=True, stderr=subprocess.DEVNULL)
    with open(os.path.join(d, "summary.json")) as f:
        s = json.load(f)
    return dict(code="hsbd", dt=dt, z=s["Z_virial"], z_err=s["Z_virial_err"], dl=s["D_long"],
                dl_err=s["D_long_err"],
                cpu=s["cpu_seconds_production"] / s["time_simulated"])


def read_dump(path, n):
    """Frames of unwrapped positions, sorted by id: times (steps) and an array (F, n, 3)."""
    steps, frames = [], []
    with open(path) as f:
        while True:
            line = f.readline()
            if not line:
                break
            if line.startswith("ITEM: TIMESTEP"):
                steps.append(int(f.readline()))
            elif line.startswith("ITEM: ATOMS"):
                rows = [f.readline().split() for _ in range(n)]
                frames.append(np.array([[float(v) for v in r[1:4]] for r in rows]))
    return np.array(steps), np.array(frames)


def msd_slope(t, x, nb=10):
    """The MSD's slope between LAGS over 6, from all time origins; its error from nb groups
    of particles (time blocks shorter than the lag would be correlated); t in units of
    D_BH^2 / D, x in D_BH."""
    dt = t[1] - t[0]
    k0, k1 = (int(round(lag / dt)) for lag in LAGS)
    groups = np.array_split(np.arange(x.shape[1]), nb)
    per_group = []
    for g in groups:
        m0 = np.mean(np.sum((x[k0:, g] - x[:-k0, g]) ** 2, axis=2))
        m1 = np.mean(np.sum((x[k1:, g] - x[:-k1, g]) ** 2, axis=2))
        per_group.append((m1 - m0) / (6 * (t[k1] - t[k0])))
    return float(np.mean(per_group)), float(np.std(per_group, ddof=1) / math.sqrt(nb))


def run_lammps(lmp, out, phi, n, seed, dt, t_total, data, tag):
    d = os.path.join(out, f"lammps-phi{phi:g}-n{n}-dt{dt:g}-{tag}")
    os.makedirs(d, exist_ok=True)
    log, dump = os.path.join(d, "log.lammps"), os.path.join(d, "positions.dump")
    sample_every = max(1, round(0.001 / dt))  # Z every 0.001, frames every 0.02
    frame_every = max(1, round(0.02 / dt))
    if not (os.path.exists(log) and "Total wall time" in open(log).read()):
        subprocess.run([lmp, "-in", os.path.join(HERE, "in.phs"), "-log", log, "-screen", "none",
                        "-var", "data", data, "-var", "dt", f"{dt:g}", "-var", "seed", str(seed),
                        "-var", "equil_steps", str(round(0.05 / dt)),
                        "-var", "steps", str(round(t_total / dt)),
                        "-var", "thermo_every", str(sample_every),
                        "-var", "dump_every", str(frame_every), "-var", "dump", dump],
                       check=True, cwd=d)
    text = open(log).read()
    runs = text.split("Loop time of ")
    loop = float(runs[-1].split()[0])
    cpu_use = float(re.search(r"([\d.]+)% CPU use", runs[-1]).group(1)) / 100
    # the production run's thermo rows: step time c_pvir
    table = runs[-2].split("Step")[-1].splitlines()[1:]
    pvir = [float(r.split()[2]) for r in table if re.match(r"^\s*\d+\s", r)]
    box = float(re.search(r"^0 (\S+) xlo xhi", open(data).read(), re.M).group(1))
    rho = n / box ** 3
    z, z_err = blocks_mean(1 + np.array(pvir[1:]) / rho)  # kT = 1
    steps, x = read_dump(dump, n)
    t = steps * dt / D_BH ** 2
    dl, dl_err = msd_slope(t, x / D_BH)
    bt = t_total / D_BH ** 2  # the run's length in D_BH^2 / D
    return dict(code="LAMMPS", dt=dt / D_BH ** 2, z=z, z_err=z_err, dl=dl, dl_err=dl_err,
                cpu=loop * cpu_use / bt)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("hsbd")
    ap.add_argument("--lammps", default="")
    ap.add_argument("--build", default="")
    ap.add_argument("--out", default="runs/bench-lammps")
    ap.add_argument("--phis", default="0.3,0.45")
    ap.add_argument("--n", type=int, default=4000)
    ap.add_argument("--lammps-dt", type=float, default=1e-5)
    ap.add_argument("--lammps-time", type=float, default=10.0)
    ap.add_argument("--hsbd-dt", default="1e-2,1e-3")
    ap.add_argument("--hsbd-time", type=float, default=40.0)
    ap.add_argument("--rounds", type=int, default=1)
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args()
    if min(a.hsbd_time, a.lammps_time) < 2 * LAGS[1]:
        ap.error(f"--hsbd-time and --lammps-time must be at least {2 * LAGS[1]:g} (the MSD's "
                 f"slope is taken up to lag {LAGS[1]:g})")
    hsbd = os.path.abspath(a.hsbd)
    lmp = os.path.abspath(a.lammps) if a.lammps else ""
    if a.build and not lmp:
        lmp = os.path.join(os.path.abspath(a.build), "build", "lmp")
        if not os.path.exists(lmp):
            subprocess.run([os.path.join(HERE, "build-lammps.sh"), a.build, "2"], check=True)
    os.makedirs(a.out, exist_ok=True)
    out = os.path.abspath(a.out)
    cpu = subprocess.run(["grep", "-m1", "model name", "/proc/cpuinfo"], capture_output=True,
                         text=True).stdout.split(":")[-1].strip()
    print(f"# {time.strftime('%Y-%m-%d')}, {cpu}, one thread each, CPU time, N {a.n}, 3D")
    print("# Z against Kolafa-Labik-Malijevsky; D_L = MSD slope between lags 0.4 and 4 / 6;"
          " CPU s per sigma^2/D")
    print("| phi | code | dt | Z vs KLM | D_L / D_0 | CPU s per sigma^2/D |")
    print("|---|---|---|---|---|---|")
    for phi in (float(p) for p in a.phis.split(",")):
        xyz, data = make_start(hsbd, out, phi, a.n, a.seed)
        for r in range(a.rounds):
            rows = []
            if lmp:
                rows.append(run_lammps(lmp, out, phi, a.n, a.seed + r, a.lammps_dt,
                                       a.lammps_time, data, f"r{r}"))
            for dt in (float(x) for x in a.hsbd_dt.split(",")):
                rows.append(run_hsbd(hsbd, out, phi, a.n, a.seed + r, dt, a.hsbd_time, xyz,
                                     f"r{r}"))
            for row in rows:
                ref = klm(phi)
                print(f"| {phi:.2f} | {row['code']} | {row['dt']:.3g} | "
                      f"{100 * (row['z'] / ref - 1):+.2f} +- {100 * row['z_err'] / ref:.2f} % | "
                      f"{row['dl']:.4f} +- {row['dl_err']:.4f} | {row['cpu']:.3g} |",
                      flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())

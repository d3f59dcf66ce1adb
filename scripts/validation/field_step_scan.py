#!/usr/bin/python3
"""Euler's and Heun's field steps (run.field_step) against exact theory as dt shrinks.

Usage: field_step_scan.py HSBD OUT [--seeds 1,2,3] [--jobs 2] [--parts percus,points,msd]
                          [--figure docs/figures/field-step.png]

percus: hard rods in the flagship case (sigma 0.5, mean density 0.5, cosine U0 6 kT,
  wavelength 1, D = kT = 1), N 500 on a ring of 1000 periods, 20 time units of
  equilibration and 100 of sampling at each dt, errors from 50 segments of the ring
  (sample.blocking = space). Against Percus' exact profile (hsbd theory percus) averaged
  over each bin of 0.02: the density's chi^2/dof over 50 bins, the peak error (the mean
  relative error of the bins between 0.46 and 0.54, with its error from the segments), and
  the contact density's chi^2/dof and the error of its mean over the period.
sticky: the same with contact_rule = sticky.
points: point particles (sigma 0) with the hard core in the same field, N 500 on 1000
  periods: the density against Boltzmann's and the contact density rho2(x, x) against the
  ideal gas' (1 - 1/N) rho(x)^2, each averaged over the bin.
msd: the tagged-particle MSD of the flagship case sampled every 1e-3 time units, for each
  dt against the smallest dt's.
Each part writes OUT/<part>.tsv; the figure shows the peak errors, chi^2/dof and the
contact errors against dt. Fixed seeds; each run's error bars come from its own blocks.
"""
import argparse
import math
import os
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "tools"))
from hsbd_tools import read_table  # noqa: E402

STEPS = ("euler", "heun")
DTS = (1e-5, 2e-5, 3e-5, 5e-5, 1e-4, 2e-4, 3e-4, 5e-4, 7e-4, 1e-3, 2e-3)
PEAK = (0.46, 0.54)
BASE = [
    "--set", "system.N=500", "--set", "system.L=1000", "--set", "system.sigma=0.5",
    "--set", "field.type=cosine", "--set", "field.amplitude=6", "--set", "field.wavelength=1",
    "--set", "sample.bin_width=0.02", "--set", "sample.contact_width=0.02",
    "--set", "sample.blocking=space", "--set", "sample.blocks=50",
    "--set", "run.t_equil=20", "--set", "run.t_total=100",
]


def run(hsbd, out, args):
    """One hsbd run into out (kept when it completed before)."""
    if os.path.exists(os.path.join(out, "summary.json")):
        return out
    cmd = [hsbd, "run", "--defaults", "--quiet", "--threads", "1", "--out", out] + args
    subprocess.run(cmd, check=True, stderr=subprocess.DEVNULL)
    return out


def sampling(dt, interval=5e-4):
    """sample.every for a sampling interval of about `interval` (at least every step)."""
    return max(1, round(interval / dt))


def bin_average(theory_x, theory_y, centres, width, period=1.0):
    """The theory averaged over each bin of the given centres and width (periodic)."""
    fine = np.linspace(0, period, 20001)[:-1]
    ref = np.interp(fine, theory_x, theory_y, period=period)
    return np.array([ref[((fine - (c - width / 2)) % period) < width].mean() for c in centres])


def chi2_dof(sim, err, ref):
    return float(np.mean(((sim - ref) / err) ** 2))


def block_columns(path):
    t = read_table(path)
    return t.data[:, 0], t.data[:, 1:]


def peak_error(blocks_path, ref, x):
    """Mean relative error over the peak's bins: its mean over the blocks and error."""
    _, blocks = block_columns(blocks_path)
    sel = (x > PEAK[0]) & (x < PEAK[1])
    per_block = (blocks[sel] / ref[sel, None]).mean(axis=0) - 1
    nb = per_block.size
    return per_block.mean(), per_block.std(ddof=1) / math.sqrt(nb)


def mean_error(blocks_path, ref):
    """Relative error of the profile's mean over the period, and its error over the blocks."""
    _, blocks = block_columns(blocks_path)
    per_block = blocks.mean(axis=0) / ref.mean() - 1
    return per_block.mean(), per_block.std(ddof=1) / math.sqrt(per_block.size)


def analyse_rods(d, theory):
    """chi^2/dof and peak error of the density, chi^2/dof and mean error of the contacts."""
    dens = read_table(os.path.join(d, "density.tsv"))
    x, width = dens.data[:, 0], dens.data[1, 0] - dens.data[0, 0]
    ref = bin_average(theory[:, 0], theory[:, 1], x, width)
    rho, err = dens.data[:, 1], dens.data[:, 2]
    peak, peak_err = peak_error(os.path.join(d, "density_blocks.tsv"), ref, x)
    con = read_table(os.path.join(d, "contact.tsv"))
    k = con.names.index("rho2")
    ref2 = bin_average(theory[:, 0], theory[:, 2], con.data[:, 0], width)
    cmean, cmean_err = mean_error(os.path.join(d, "contact_blocks.tsv"), ref2)
    return dict(chi2=chi2_dof(rho, err, ref), peak=peak, peak_err=peak_err,
                contact_chi2=chi2_dof(con.data[:, k], con.data[:, k + 1], ref2),
                contact=cmean, contact_err=cmean_err)


def run_grid(hsbd, out, prefix, dts, seeds, jobs, settings):
    """Runs every field step x dt x seed with run.field_step, run.dt, system.seed and the
    `settings(dt)` (key=value strings) into out/PREFIX-STEP-dtDT-seedSEED; the list of
    (step, dt, seed, directory)."""
    runs = [(step, dt, seed, os.path.join(out, f"{prefix}-{step}-dt{dt:g}-seed{seed}"))
            for step in STEPS for dt in dts for seed in seeds]

    def one(r):
        step, dt, seed, d = r
        sets = [f"run.field_step={step}", f"run.dt={dt:g}", f"system.seed={seed}"] + settings(dt)
        run(hsbd, d, BASE + [a for kv in sets for a in ("--set", kv)])

    with ThreadPoolExecutor(jobs) as pool:
        list(pool.map(one, runs))
    return runs


def percus_part(hsbd, out, seeds, jobs, rule="reflect", dts=DTS):
    theory_path = os.path.join(out, "theory-percus.tsv")
    subprocess.run([hsbd, "theory", "percus", "--sigma", "0.5", "--rho", "0.5", "--amplitude",
                    "6", "--out", theory_path], check=True, stdout=subprocess.DEVNULL)
    theory = read_table(theory_path).data
    runs = run_grid(hsbd, out, rule, dts, seeds, jobs,
                    lambda dt: [f"run.dt_equil={max(dt, 1e-4):g}", f"sample.every={sampling(dt)}",
                                f"system.contact_rule={rule}"])
    name = "percus" if rule == "reflect" else rule
    with open(os.path.join(out, f"{name}.tsv"), "w") as f:
        f.write("step\tdt\tseed\tchi2\tpeak\tpeak_err\tcontact_chi2\tcontact\tcontact_err\n")
        for step, dt, seed, d in runs:
            a = analyse_rods(d, theory)
            f.write(f"{step}\t{dt:g}\t{seed}\t{a['chi2']:.4g}\t{a['peak']:.6g}\t"
                    f"{a['peak_err']:.3g}\t{a['contact_chi2']:.4g}\t{a['contact']:.5g}\t"
                    f"{a['contact_err']:.3g}\n")
    print(f"{name}: {os.path.join(out, name + '.tsv')}")


def points_part(hsbd, out, seeds, jobs, dts=(1e-4, 3e-4, 1e-3, 3e-3)):
    """Point particles with the hard core: Boltzmann's density and the ideal contacts."""
    runs = run_grid(hsbd, out, "points", dts, seeds, jobs,
                    lambda dt: ["system.sigma=0", f"run.dt_equil={dt:g}",
                                f"sample.every={sampling(dt)}"])
    fine = np.linspace(0, 1, 20001)[:-1]
    boltz = np.exp(-3.0 * np.cos(2 * np.pi * fine))
    boltz *= 0.5 / boltz.mean()
    n = 500
    with open(os.path.join(out, "points.tsv"), "w") as f:
        f.write("step\tdt\tseed\tchi2\tpeak\tpeak_err\tcontact_chi2\tcontact\tcontact_err\n")
        for step, dt, seed, d in runs:
            dens = read_table(os.path.join(d, "density.tsv"))
            x, width = dens.data[:, 0], dens.data[1, 0] - dens.data[0, 0]
            ref = bin_average(fine, boltz, x, width)
            peak, peak_err = peak_error(os.path.join(d, "density_blocks.tsv"), ref, x)
            con = read_table(os.path.join(d, "contact.tsv"))
            k = con.names.index("rho2")
            ref2 = bin_average(fine, (1 - 1 / n) * boltz ** 2, con.data[:, 0], width)
            cmean, cmean_err = mean_error(os.path.join(d, "contact_blocks.tsv"), ref2)
            f.write(f"{step}\t{dt:g}\t{seed}\t{chi2_dof(dens.data[:, 1], dens.data[:, 2], ref):.4g}"
                    f"\t{peak:.6g}\t{peak_err:.3g}\t"
                    f"{chi2_dof(con.data[:, k], con.data[:, k + 1], ref2):.4g}\t{cmean:.5g}\t"
                    f"{cmean_err:.3g}\n")
    print(f"points: {os.path.join(out, 'points.tsv')}")


def msd_part(hsbd, out, seeds, jobs, dts=(1e-5, 1e-4, 3e-4, 1e-3)):
    """The MSD at common lags (sampled every 1e-3) against the smallest dt's."""
    runs = run_grid(hsbd, out, "msd", dts, seeds, jobs,
                    lambda dt: [f"run.dt_equil={max(dt, 1e-4):g}", "run.t_total=20",
                                "sample.blocking=time", "sample.blocks=20",
                                "sample.msd_max_lag=1", f"sample.every={sampling(dt, 1e-3)}"])
    with open(os.path.join(out, "msd.tsv"), "w") as f:
        f.write("step\tdt\tseed\tlag\tmsd\tmsd_err\n")
        for step, dt, seed, d in runs:
            t = read_table(os.path.join(d, "msd.tsv")).data
            for row in t:
                f.write(f"{step}\t{dt:g}\t{seed}\t{row[0]:.6g}\t{row[1]:.8g}\t{row[2]:.3g}\n")
    print(f"msd: {os.path.join(out, 'msd.tsv')}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("hsbd")
    ap.add_argument("out")
    ap.add_argument("--seeds", default="1")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--parts", default="percus,points,msd")
    ap.add_argument("--dts", default="")
    args = ap.parse_args()
    seeds = [int(s) for s in args.seeds.split(",")]
    dts = tuple(float(x) for x in args.dts.split(",")) if args.dts else DTS
    os.makedirs(args.out, exist_ok=True)
    hsbd = os.path.abspath(args.hsbd)
    parts = args.parts.split(",")
    if "percus" in parts:
        percus_part(hsbd, args.out, seeds, args.jobs, dts=dts)
    if "sticky" in parts:
        percus_part(hsbd, args.out, seeds, args.jobs, rule="sticky",
                    dts=tuple(d for d in dts if d >= 3e-5))
    if "points" in parts:
        points_part(hsbd, args.out, seeds, args.jobs)
    if "msd" in parts:
        msd_part(hsbd, args.out, seeds, args.jobs)


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Driven rods against exact theory, one figure per family (docs/validation.md section 17).

    tools/plot_driven.py build/hsbd OUTDIR [--quick] [--only washboard|trap|rocking]

Runs hsbd (fixed seeds) and writes OUTDIR/driven-washboard.png (one particle and rods of
one wavelength in a tilted cosine: mean velocity and D_eff against the tilt, with
`hsbd theory washboard`), OUTDIR/driven-trap.png (the centre of mass of rods in a dragged
trap: lag against the drag speed, exact v / (mu k)) and OUTDIR/driven-rocking.png (the
rocked particle against the adiabatic drift), each with its table OUTDIR/*.tsv.
Debian's python3-numpy and python3-matplotlib only."""
import json
import os
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

U0 = 4.0
FC = np.pi * U0


def run(hsbd, out, sets):
    args = [hsbd, "run", "--defaults", "--quiet", "--force", "--out", out]
    for k, v in sets.items():
        args += ["--set", f"{k}={v}"]
    subprocess.run(args, check=True)
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f)


def theory(hsbd, *flags):
    txt = subprocess.run([hsbd, "theory", "washboard", *flags, "--out", "-"], check=True,
                         capture_output=True, text=True).stdout
    rows = [ln.split() for ln in txt.splitlines() if ln and ln[0] not in "#f"]
    return np.array(rows, dtype=float)


def free_particles(extra):
    base = {"system.N": 500, "system.L": 500, "system.hard_core": "off", "system.sigma": 0,
            "field.type": "cosine+tilt", "field.amplitude": U0, "run.dt": 2e-4,
            "run.t_equil": 2, "sample.every": 10, "sample.bin_width": 0.05}
    base.update(extra)
    return base


def washboard(hsbd, out, scale):
    th = theory(hsbd, "--amplitude", str(U0), "--force-min", "0", "--force-max", "25",
                "--forces", "126")
    rows = []
    for k, ratio in enumerate([0.25, 0.5, 0.75, 1.0, 1.25, 1.5, 1.75]):
        s = run(hsbd, os.path.join(out, "runs", f"wb{k}"),
                free_particles({"field.force": ratio * FC, "system.seed": 10 + k,
                                "run.t_total": 20 * scale, "sample.blocks": 20}))
        rows.append(("particle", ratio * FC, s["mean_velocity"], s["mean_velocity_err"],
                     s["d_eff_tagged"], s["d_eff_tagged_err"]))
    for k, ratio in enumerate([0.5, 1.0, 1.5]):
        n = 20
        s = run(hsbd, os.path.join(out, "runs", f"rods{k}"),
                {"system.N": n, "system.L": 40, "system.sigma": 1, "system.seed": 20 + k,
                 "field.type": "cosine+tilt", "field.amplitude": U0, "field.force": ratio * FC,
                 "run.dt": 2e-4, "run.t_equil": 2, "run.t_total": 200 * scale,
                 "sample.blocks": 100, "sample.every": 10, "sample.bin_width": 0.05})
        rows.append(("rods", ratio * FC, s["mean_velocity"], s["mean_velocity_err"],
                     n * s["d_eff_cm"], n * s["d_eff_cm_err"]))
    with open(os.path.join(out, "driven-washboard.tsv"), "w") as f:
        f.write("kind\tforce\tvelocity\tvelocity_err\td_eff\td_eff_err\n")
        for r in rows:
            f.write("\t".join(str(x) for x in r) + "\n")
    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    ax[0].plot(th[:, 0] / FC, th[:, 1], "k-", label="exact (Stratonovich)")
    ax[1].plot(th[:, 0] / FC, th[:, 2], "k-", label="exact (Reimann et al.)")
    for kind, mark in (("particle", "o"), ("rods", "s")):
        r = np.array([x[1:] for x in rows if x[0] == kind])
        lab = "one particle" if kind == "particle" else "rods sigma = lambda, packing 0.5 (N D_cm)"
        ax[0].errorbar(r[:, 0] / FC, r[:, 1], r[:, 2], fmt=mark, mfc="none", label=lab)
        ax[1].errorbar(r[:, 0] / FC, r[:, 3], r[:, 4], fmt=mark, mfc="none", label=lab)
    ax[0].set(xlabel="tilt F / F_c", ylabel="mean velocity", title=f"U0 = {U0:g} kT")
    ax[1].set(xlabel="tilt F / F_c", ylabel="D_eff / D", title="effective diffusion")
    for a in ax:
        a.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "driven-washboard.png"), dpi=110)


def trap(hsbd, out, scale):
    k, n, mu = 2.0, 20, 1.0
    rows = []
    for j, v in enumerate([0.5, 1.0, 2.0, 4.0]):
        for sticky in (0, 1):
            sets = {"system.N": n, "system.L": 200, "system.sigma": 0.5, "system.seed": 30 + j,
                    "field.type": "harmonic", "field.stiffness": k, "field.center": 100,
                    "drive.parameter": "center", "drive.velocity": v, "run.dt": 1e-3,
                    "run.t_equil": 5, "run.t_total": 100 * scale, "sample.blocks": 20,
                    "sample.bin_width": 0.5, "sample.period": 200}
            if sticky:  # the small step of Antonov Eq. (33): mu max|f| dt / eps = 0.086
                sets.update({"contact.gamma": 2, "system.contact_rule": "sticky",
                             "run.dt": 2.5e-5, "run.t_total": 25 * scale})
            s = run(hsbd, os.path.join(out, "runs", f"trap{j}{sticky}"), sets)
            dt = sets["run.dt"]
            rows.append((sticky, v, s["trap_offset"], s["trap_offset_err"],
                         s["trap_variance"] * n * k, s["trap_variance_err"] * n * k,
                         1 / (1 - mu * k * dt / 2)))
    with open(os.path.join(out, "driven-trap.tsv"), "w") as f:
        f.write("sticky\tv\ttrap_offset\ttrap_offset_err\tNk_var\tNk_var_err\texact_Nk_var\n")
        for r in rows:
            f.write("\t".join(str(x) for x in r) + "\n")
    r = np.array(rows)
    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    vv = np.linspace(0, 4.2, 50)
    ax[0].plot(vv, -vv / (mu * k), "k-", label="exact: -v / (mu k)")
    ax[1].axhline(1, color="k", label="exact: kT / (N k) (times 1/(1 - mu k dt/2))")
    for sticky, mark in ((0, "o"), (1, "s")):
        q = r[r[:, 0] == sticky]
        lab = "sticky rods (gamma 2)" if sticky else "hard rods"
        ax[0].errorbar(q[:, 1], q[:, 2], q[:, 3], fmt=mark, mfc="none", label=lab)
        ax[1].errorbar(q[:, 1], q[:, 4] / q[:, 6], q[:, 5] / q[:, 6], fmt=mark, mfc="none",
                       label=lab)
    ax[0].set(xlabel="drag speed v", ylabel="<X - c(t)>",
              title=f"dragged trap, N = {n}, k = {k:g}, mu = {mu:g}: lag")
    ax[1].set(xlabel="drag speed v", ylabel="var X / exact",
              title="centre-of-mass variance")
    for a in ax:
        a.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "driven-trap.png"), dpi=110)


def rocking(hsbd, out, scale):
    f1, period = 9.0, 20.0
    rows = []
    for j, f0 in enumerate([0.0, 1.5, 3.0, 4.5, 6.0]):
        s = run(hsbd, os.path.join(out, "runs", f"rock{j}"),
                free_particles({"field.force": f0, "drive.parameter": "force",
                                "drive.wave": "cosine", "drive.amplitude": f1,
                                "drive.period": period, "system.seed": 40 + j,
                                "system.N": int(400 * scale), "system.L": int(400 * scale),
                                "run.dt": 5e-4, "run.t_equil": 0, "run.t_total": 10 * period,
                                "sample.blocks": 10, "sample.every": 20}))
        th = theory(hsbd, "--amplitude", str(U0), "--force", str(f0), "--rocking", str(f1))
        rows.append((f0, s["mean_velocity"], s["mean_velocity_err"], th[0, 4], th[0, 1]))
    with open(os.path.join(out, "driven-rocking.tsv"), "w") as f:
        f.write("f0\tvelocity\tvelocity_err\tadiabatic\tstatic\n")
        for r in rows:
            f.write("\t".join(str(x) for x in r) + "\n")
    r = np.array(rows)
    fig, ax = plt.subplots(figsize=(5, 4))
    ax.plot(r[:, 0], r[:, 3], "k-", label="exact adiabatic limit")
    ax.plot(r[:, 0], r[:, 4], "k:", label="static tilt F0")
    ax.errorbar(r[:, 0], r[:, 1], r[:, 2], fmt="o", mfc="none", label=f"period {period:g}")
    ax.set(xlabel="F0", ylabel="mean velocity",
           title=f"rocked particle, F = F0 + {f1:g} cos(2 pi t / {period:g})")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "driven-rocking.png"), dpi=110)


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    hsbd, out = sys.argv[1], sys.argv[2]
    scale = 0.25 if "--quick" in sys.argv[3:] else 1.0
    only = sys.argv[sys.argv.index("--only") + 1] if "--only" in sys.argv else None
    os.makedirs(os.path.join(out, "runs"), exist_ok=True)
    for family in (washboard, trap, rocking):
        if only in (None, family.__name__):
            family(hsbd, out, scale)


if __name__ == "__main__":
    main()

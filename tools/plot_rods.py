#!/usr/bin/python3
"""Plot a hard-rod run: density profile, contact density and MSD (PNG).

usage: tools/plot_rods.py RUN_DIR [--theory PERCUS.tsv] [--out FILE.png]

Uses only Debian's python3-numpy and python3-matplotlib. The ideal-gas (Boltzmann)
profile of the same field is drawn as a reference for what the hard core changes.
"""
import argparse
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def read_table(path):
    """Return (parameters dict from '# key = value' lines, data array)."""
    params, rows = {}, []
    with open(path) as f:
        for line in f:
            if line.startswith("#"):
                if " = " in line:
                    k, v = line[1:].split(" = ", 1)
                    params[k.strip()] = v.strip()
                continue
            if line[0].isalpha():
                continue  # column names
            rows.append([float(x) for x in line.split()])
    return params, np.array(rows)


def cosine_potential(p, x):
    kind = p.get("field.type", "none")
    if "cosine" not in kind:
        return np.zeros_like(x)
    u0, lam = float(p["field.amplitude"]), float(p["field.wavelength"])
    return 0.5 * u0 * np.cos(2 * math.pi * x / lam)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run_dir")
    ap.add_argument("--out", help="PNG file (default RUN_DIR/plot.png)")
    ap.add_argument("--theory", help="exact profile from 'hsbd theory percus' (x rho rho2)")
    a = ap.parse_args()
    dens_path = os.path.join(a.run_dir, "density.tsv")
    if not os.path.exists(dens_path):
        sys.exit(f"plot_rods: no density.tsv in {a.run_dir}")
    p, dens = read_table(dens_path)
    n, length = float(p["system.N"]), float(p["system.L"])
    contact_path = os.path.join(a.run_dir, "contact.tsv")
    panels = 3 if os.path.exists(contact_path) else 2
    fig, ax = plt.subplots(1, panels, figsize=(5 * panels, 4))

    x = dens[:, 0]
    ax[0].errorbar(x, dens[:, 1], yerr=dens[:, 2], fmt="o", ms=2.5, lw=0.8, label="hsbd (BCD)")
    fine = np.linspace(0, float(p["sample.period"]), 500)
    boltz = np.exp(-cosine_potential(p, fine))
    boltz *= (n / length) / boltz.mean()
    ax[0].plot(fine, boltz, "--", color="0.6", lw=1, label="ideal gas (no hard core)")
    theory = read_table(a.theory)[1] if a.theory else None
    if theory is not None:
        ax[0].plot(theory[:, 0], theory[:, 1], "k-", lw=1, label="Percus (exact)")
    ax[0].set_xlabel("x")
    ax[0].set_ylabel(r"$\rho(x)$")
    ax[0].set_title(rf"$\sigma$ = {p['system.sigma']}, $\bar\rho$ = {n / length:g}, "
                    rf"$U_0$ = {p['field.amplitude']}")
    ax[0].legend(fontsize=8)

    if panels == 3:
        cp, con = read_table(contact_path)
        # columns: x, rho2 (default estimator), theorem, window, extrapolated (value, error)
        default = ("extrapolated" if cp.get("system.contact_rule") == "reflect"
                   else "contact theorem")
        ax[1].errorbar(con[:, 0], con[:, 5], yerr=con[:, 6], fmt="s", ms=2, lw=0.5,
                       color="0.65", label="window (biased)")
        ax[1].errorbar(con[:, 0], con[:, 1], yerr=con[:, 2], fmt="o", ms=2.5, lw=0.8,
                       label=f"{default} (default)")
        if theory is not None:
            ax[1].plot(theory[:, 0], theory[:, 2], "k-", lw=1, label="Percus (exact)")
        ax[1].legend(fontsize=8)
        ax[1].set_xlabel("x (left rod)")
        ax[1].set_ylabel(r"$\rho_2(x, x+\sigma)$")
        ax[1].set_title(rf"contact density, $\Delta'$ = {p['sample.contact_width']}")

    _, msd = read_table(os.path.join(a.run_dir, "msd.tsv"))
    d = float(p["system.D"])
    m = ax[-1]
    m.errorbar(msd[:, 0], msd[:, 1], yerr=msd[:, 2], fmt="o", ms=3, lw=0.8, label="tagged MSD")
    m.plot(msd[:, 0], 2 * d * msd[:, 0], "k--", lw=1, label="2 D t")
    m.set_xscale("log")
    m.set_yscale("log")
    m.set_xlabel("t")
    m.set_ylabel("MSD")
    m.legend(fontsize=8)
    fig.tight_layout()
    out = a.out or os.path.join(a.run_dir, "plot.png")
    tmp = out + ".part.png"
    fig.savefig(tmp, dpi=120)
    os.replace(tmp, out)
    print(f"plot: {out}")


if __name__ == "__main__":
    main()

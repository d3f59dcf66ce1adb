#!/usr/bin/python3
"""Plot a hard-rod run: density profile, contact density and MSD (PNG).

usage: tools/plot_rods.py RUN_DIR [--theory PERCUS.tsv] [--out FILE.png]

Uses only Debian's python3-numpy and python3-matplotlib (and, for the exact single-file
MSD, the hsbd module of build/python when it is built). The ideal-gas (Boltzmann) profile
of the same field, exp(-U/kT) for any of its terms, is drawn as a reference for what the
hard core changes (not for a tilted ring, which is out of equilibrium, or a table).
"""
import argparse
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from hsbd_tools import read_table, save_figure  # noqa: E402


def floats(v):
    return [float(x) for x in v.replace(",", " ").split()]


def field_terms(p):
    return [t for t in p.get("field.type", "none").split("+") if t and t != "none"]


def describe_field(p):
    """The external field in words, with its parameters (kT units)."""
    words = []
    for t in field_terms(p):
        if t == "cosine":
            words.append(f"cosine U0 = {float(p['field.amplitude']):g} kT, "
                         f"wavelength {float(p['field.wavelength']):g}")
        elif t == "tilt":
            words.append(f"tilt force {float(p['field.force']):g} kT/length")
        elif t == "harmonic":
            words.append(f"harmonic k = {float(p['field.stiffness']):g} about "
                         f"{float(p['field.center']):g}")
        elif t == "table":
            words.append(f"tabulated {p.get('field.table_kind', 'potential')} "
                         f"({os.path.basename(p.get('field.table', ''))})")
    return " + ".join(words) if words else "no field"


def ideal_gas_profile(p, period, n, length):
    """The ideal-gas (Boltzmann, no hard core) profile exp(-U/kT) folded into the
    profile's period, or None with the reason when there is none to draw: a tilted ring
    is out of equilibrium, a tabulated field's file is not at hand."""
    terms = field_terms(p)
    walls = p.get("system.boundary") == "walls"
    if "tilt" in terms and not walls:
        return None, "tilted ring: a driven steady state, no Boltzmann reference"
    if "table" in terms:
        return None, "tabulated field: no ideal-gas line drawn"
    bins = 400
    xf = (np.arange(bins) + 0.5) * period / bins  # the folded coordinate
    x = xf[None, :] + period * np.arange(math.ceil(length / period - 1e-9))[:, None]
    u = np.zeros_like(x)
    if "cosine" in terms:
        u += 0.5 * float(p["field.amplitude"]) * np.cos(2 * math.pi * x / float(p["field.wavelength"]))
    if "tilt" in terms:
        u -= float(p["field.force"]) * x
    if "harmonic" in terms:
        u += 0.5 * float(p["field.stiffness"]) * (x - float(p["field.center"])) ** 2
    w = np.where(x < length, np.exp(-(u - u.min()) / float(p.get("system.kT", 1))), 0.0)
    prof = w.sum(axis=0)
    prof *= (n / length) / prof.mean()
    return (xf, prof), None


def single_file_law(t, rho, sigma, d):
    """The exact field-free single-file MSD from the hsbd Python module (build/python),
    or None when the module is not built."""
    here = os.path.dirname(os.path.abspath(__file__))
    sys.path.insert(0, os.path.join(here, "..", "build", "python"))
    try:
        import hsbd  # noqa: F401
    except ImportError:
        return None
    return hsbd.single_file_msd(t, rho, sigma, d)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run_dir")
    ap.add_argument("--out", help="PNG file (default RUN_DIR/plot.png)")
    ap.add_argument("--theory", help="exact profile from 'hsbd theory percus' (x rho rho2)")
    a = ap.parse_args()
    dens_path = os.path.join(a.run_dir, "density.tsv")
    if not os.path.exists(dens_path):
        sys.exit(f"plot_rods: no density.tsv in {a.run_dir}")
    p, _, dens = read_table(dens_path)
    n, length = float(p["system.N"]), float(p["system.L"])
    names = p.get("species.names", "").split()
    sigmas = floats(p["species.sigma"]) if names else [float(p["system.sigma"])]
    diffs = floats(p["species.D"]) if names else [float(p["system.D"])]
    counts = floats(p["species.count"]) if names else [n]
    contact_path = os.path.join(a.run_dir, "contact.tsv")
    panels = 3 if os.path.exists(contact_path) else 2
    fig, ax = plt.subplots(1, panels, figsize=(5.5 * panels, 4.6))
    rods = (", ".join(f"{c:g} {nm} (sigma {s:g}, D {d:g})"
                      for nm, c, s, d in zip(names, counts, sigmas, diffs))
            if names else f"sigma = {sigmas[0]:g}, D = {diffs[0]:g}")
    walls = p.get("system.boundary") == "walls"
    fig.suptitle(f"hard rods: N = {n:g} on {'a line between walls' if walls else 'a ring'} of "
                 f"L = {length:g} (mean density {n / length:g}), {rods}\n"
                 f"field: {describe_field(p)}; kT = {float(p.get('system.kT', 1)):g}",
                 fontsize=10)

    x = dens[:, 0]
    period = float(p.get("sample.period") or length)
    theory = read_table(a.theory).data if a.theory else None
    if theory is not None:
        ax[0].plot(theory[:, 0], theory[:, 1], "k-", lw=1.2, label="Percus (exact)", zorder=2)
    ax[0].errorbar(x, dens[:, 1], yerr=dens[:, 2], fmt="o-" if len(x) > 100 else "o",
                   ms=2 if len(x) > 100 else 2.5, lw=0.6,
                   label="hsbd (BCD), error bars 1 s.e.", zorder=3)
    ideal, why = ideal_gas_profile(p, period, n, length)
    if ideal is not None:
        ax[0].plot(ideal[0], ideal[1], "-.", color="tab:red", lw=1.2, zorder=4,
                   label="ideal gas exp(-U/kT) (no hard core)")
    else:
        ax[0].plot([], [], " ", label=why)  # the reason, in the legend
    ax[0].set_xlabel("x" + (f" folded into one period {period:g}" if period < length else ""))
    ax[0].set_ylabel(r"density $\rho(x)$  [rods per unit length]")
    ax[0].set_title("density profile", fontsize=10)
    ax[0].legend(fontsize=8)

    if panels == 3:
        cp, _, con = read_table(contact_path)
        # columns: x, rho2 (default estimator), theorem, window, extrapolated (value, error)
        default = ("extrapolated" if cp.get("system.contact_rule") == "reflect"
                   else "contact theorem")
        window = float(p["sample.contact_width"])
        ax[1].errorbar(con[:, 0], con[:, 5], yerr=con[:, 6], fmt="s", ms=2, lw=0.5,
                       color="0.65", label=f"gaps < {window:.3g} (window, biased)")
        ax[1].errorbar(con[:, 0], con[:, 1], yerr=con[:, 2], fmt="o-" if len(con) > 100 else "o",
                       ms=2 if len(con) > 100 else 2.5, lw=0.6,
                       label=f"{default} to zero gap (default)")
        if theory is not None:
            ax[1].plot(theory[:, 0], theory[:, 2], "k-", lw=1, label="Percus (exact)")
        ax[1].legend(fontsize=8)
        ax[1].set_xlabel("x of the left rod")
        ax[1].set_ylabel(r"$\rho_2(x, x+\sigma)$  [per length$^2$]")
        ax[1].set_title(f"contact density (window {window:.3g})", fontsize=10)

    _, cols, msd = read_table(os.path.join(a.run_dir, "msd.tsv"))
    m = ax[-1]
    t = msd[:, 0]
    for k in range(len(names) or 1):
        col = cols.index(f"msd_{names[k]}") if names else 1
        lab = names[k] if names else "tagged rod"
        line = m.errorbar(t, msd[:, col], yerr=msd[:, col + 1], fmt="o", ms=3, lw=0.8,
                          label=f"MSD {lab}")
        m.plot(t, 2 * diffs[k] * t, ":", color=line[0].get_color(), lw=1,
               label=f"free 2 D t, D = {diffs[k]:g}")
    if not names and not walls and "tilt" not in field_terms(p):
        law = single_file_law(t, n / length, sigmas[0], diffs[0])
        if law is not None:
            m.plot(t, law, "k-", lw=1,
                   label="exact single-file law" + (" (field-free)" if field_terms(p) else ""))
    m.set_xscale("log")
    m.set_yscale("log")
    m.set_xlabel("lag time t  [sigma^2/D]")
    m.set_ylabel("mean-squared displacement  [length$^2$]")
    m.set_title("tagged-rod MSD", fontsize=10)
    m.legend(fontsize=8)
    fig.tight_layout()
    save_figure(fig, a.out or os.path.join(a.run_dir, "plot.png"))


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Plot a run of hard disks or spheres: g(r), MSD and F_s(k, t) per species (PNG).

usage: tools/plot_spheres.py RUN_DIR [--out FILE.png]

Reads gr.tsv, msd.tsv, fs.tsv and summary.json of RUN_DIR and writes RUN_DIR/plot.png:
- g(r) for every species pair, its contact value g(sigma_ab+) measured (dot with error
  bar) and from the equation of state (star: Carnahan-Starling / BMCSL in 3D, Henderson
  in 2D, as summary.json names it);
- the MSD per particle of each species with the free-diffusion line 2 d D t (dotted) and
  the long-time line 2 d D_L t fitted by hsbd (dashed);
- the self-intermediate scattering function F_s(k, t) of each species.
Uses only Debian's python3-numpy and python3-matplotlib. Lengths in units of the
configuration (sigma = 1 by default), times in units of sigma^2 / D.
"""
import argparse
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from hsbd_tools import read_table, save_figure  # noqa: E402


def as_list(v):
    return v.replace(",", " ").split() if isinstance(v, str) else list(v) if isinstance(v, list) else [v]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run_dir")
    ap.add_argument("--out", help="PNG file (default RUN_DIR/plot.png)")
    a = ap.parse_args()
    try:
        with open(os.path.join(a.run_dir, "summary.json")) as f:
            s = json.load(f)
    except OSError as e:
        sys.exit(f"plot_spheres: {e}")
    if s.get("model") != "spheres":
        sys.exit(f"plot_spheres: {a.run_dir} is a run of {s.get('model')}, not spheres")
    par = s["parameters"]
    dim = int(s["dimension"])
    names = as_list(par["species"]["names"]) if par["species"].get("names") else []
    ns = max(1, len(names))
    diff = [float(v) for v in as_list(par["species"]["D"])] if names else [float(par["system"]["D"])]
    sigmas = [float(v) for v in as_list(par["species"]["sigma"])] if names else [float(par["system"]["sigma"])]
    fig, ax = plt.subplots(1, 3, figsize=(16, 4.8))
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    body = "disks" if dim == 2 else "spheres"
    poly = float(par["species"].get("polydispersity", 0) or 0)
    title = (f"hard {body} ({dim}D), N = {par['system']['N']}, packing fraction "
             f"{float(s['packing_fraction']):.3g}"
             + (f", species {', '.join(names)}" if names else "")
             + (f", polydispersity {poly:g}" if poly > 0 else "")
             + f"; run of t = {float(s['time_simulated']):g} sigma^2/D")
    fig.suptitle(title)

    # g(r) per pair with the contact values
    gr_path = os.path.join(a.run_dir, "gr.tsv")
    g = ax[0]
    if os.path.exists(gr_path):
        _, cols, gr = read_table(gr_path)
        contacts = s.get("contacts", [])
        for p in range(len(contacts) or 1):
            c = colours[p % len(colours)]
            label = (f" {contacts[p]['a']}-{contacts[p]['b']}" if names and contacts else "")
            g.plot(gr[:, 0], gr[:, 1 + 2 * p], "-", color=c, lw=1, label=f"g(r){label}")
            if p < len(contacts):
                ct = contacts[p]
                ia = names.index(ct["a"]) if names else 0
                ib = names.index(ct["b"]) if names else 0
                sab = 0.5 * (sigmas[ia] + sigmas[ib]) if not poly else 1.0
                frozen = diff[ia] == 0 and diff[ib] == 0
                g.errorbar([sab], [ct["g_contact"]], [ct["g_contact_err"]], fmt="o", color=c,
                           ms=5, capsize=3,
                           label=f"contact {ct['g_contact']:.3f}"
                           + (" (frozen pair)" if frozen else f" ± {ct['g_contact_err']:.3f}"))
                if ct.get("theory") is not None:
                    g.plot([sab], [ct["theory"]], "*", color=c, ms=13, mec="k",
                           label=f"{ct.get('theory_eos', 'EOS')} {ct['theory']:.3f}")
        g.axhline(1.0, color="0.6", lw=0.6)
        g.set_xlabel("r  [sigma]")
        g.set_ylabel("g(r)")
        z = (f"Z = {s['Z_virial']:.3f} ± {s['Z_virial_err']:.3f} (virial)"
             + (f", {s['Z_theory']:.3f} ({s['Z_theory_eos']})" if s.get("Z_theory") else ""))
        g.set_title("pair distribution; " + z, fontsize=9)
        if poly > 0:
            g.text(0.98, 0.55, "polydisperse: g(r) over centre distances is\n"
                   "smeared over the contact distances sigma_ij;\n"
                   "contact values are those of each pair at\n"
                   "r = sigma_ij (mean weighted by sigma_ij^d)",
                   transform=g.transAxes, ha="right", fontsize=7)
        g.legend(fontsize=7, ncol=1 if ns == 1 else 2)
    else:
        g.text(0.5, 0.5, "no g(r) (sample.gr_every = 0)", ha="center", transform=g.transAxes)

    # MSD per species with 2 d D t and 2 d D_L t
    _, cols, msd = read_table(os.path.join(a.run_dir, "msd.tsv"))
    m = ax[1]
    t = msd[:, 0]
    dl_species = s.get("D_long_species", {})
    for k in range(ns):
        c = colours[k % len(colours)]
        name = names[k] if names else "all"
        col = cols.index(f"msd_{name}") if names else 1
        if diff[k] == 0:  # immobile: nothing to draw on log axes
            m.plot([], [], " ", label=f"{name}: immobile (D = 0, MSD = 0)")
            continue
        m.errorbar(t, msd[:, col], msd[:, col + 1], fmt="o", ms=3, color=c,
                   label=f"MSD {name}" if names else "MSD")
        m.plot(t, 2 * dim * diff[k] * t, ":", color=c, lw=1,
               label=f"2dDt, D = {diff[k]:g}" + (f" ({name})" if names else ""))
        dl = dl_species.get(name, [s.get("D_long"), s.get("D_long_err")]) if names else \
            [s.get("D_long"), s.get("D_long_err")]
        if dl and dl[0]:
            m.plot(t, 2 * dim * dl[0] * t, "--", color=c, lw=1,
                   label=f"2dD_L t, D_L = {dl[0]:.3f} ± {dl[1]:.3f}")
    m.set_xscale("log")
    m.set_yscale("log")
    m.set_xlabel("lag time t  [sigma^2/D]")
    m.set_ylabel("MSD per particle  [sigma^2]")
    m.set_title("mean-squared displacement", fontsize=9)
    m.legend(fontsize=7)

    # F_s(k, t)
    f = ax[2]
    fs_path = os.path.join(a.run_dir, "fs.tsv")
    if os.path.exists(fs_path):
        _, cols, fs = read_table(fs_path)
        for k in range(ns):
            c = colours[k % len(colours)]
            name = names[k] if names else "all"
            col = cols.index(f"fs_{name}") if names else 1
            f.errorbar(fs[:, 0], fs[:, col], fs[:, col + 1], fmt="o-", ms=3, lw=0.8, color=c,
                       label=name if names else "F_s")
            # free diffusion: exp(-k^2 D t)
            kk = float(par["sample"]["fs_k"])
            f.plot(fs[:, 0], np.exp(-kk * kk * diff[k] * fs[:, 0]), ":", color=c, lw=1,
                   label=f"free diffusion exp(-k²Dt)" + (f" ({name})" if names else ""))
        f.set_xscale("log")
        f.set_xlabel("lag time t  [sigma^2/D]")
        f.set_ylabel("F_s(k, t)")
        f.set_title(f"self-intermediate scattering, k = {float(par['sample']['fs_k']):.3g} / sigma",
                    fontsize=9)
        f.legend(fontsize=7)
    fig.tight_layout()
    save_figure(fig, a.out or os.path.join(a.run_dir, "plot.png"))


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Figures of a validation run (hsbd validate): paper Figs. 3 and 4 style grids.

usage: tools/plot_validation.py VALIDATE_DIR [--out FIG_DIR]

For every percus-s<sigma>-rho<rho> case: simulated density (Fig. 3) and contact density
(Fig. 4; the default estimator of the run's contact rule, and the windowed one in grey) as symbols over
the exact Percus theory (line). For the sticky-g<gamma>-rho<rho> cases: the density (Fig. 6) over the
exact theory of the delta_eps model. For the spheres-* cases at finite density: g(r) of every
species pair with the contact value the equation of state gives (KLM / BMCSL) marked at
contact. Debian's python3-matplotlib only.
"""
import json
import argparse
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_rows(path):
    rows = []
    with open(path) as f:
        for line in f:
            if line.startswith("#") or line[0].isalpha():
                continue
            rows.append([float(v) for v in line.split()])
    return rows


def column(rows, k):
    return [r[k] for r in rows]


def grid_figure(cases, base, kind, out, row_label=r"$\sigma$", theory_label="Percus (exact)"):
    sigmas = sorted({s for s, _ in cases})
    rhos = sorted({r for _, r in cases})
    fig, axes = plt.subplots(len(sigmas), len(rhos), figsize=(3.4 * len(rhos), 2.6 * len(sigmas)),
                             squeeze=False)
    for i, s in enumerate(sigmas):
        for j, r in enumerate(rhos):
            ax = axes[i][j]
            d = os.path.join(base, cases[(s, r)])
            th = read_rows(os.path.join(d, "theory.tsv"))
            if kind == "density":
                sim = read_rows(os.path.join(d, "density.tsv"))
                ax.errorbar(column(sim, 0), column(sim, 1), yerr=column(sim, 2), fmt="o", ms=2.5,
                            lw=0.7, label="hsbd")
                ax.plot(column(th, 0), column(th, 1), "k-", lw=0.9, label=theory_label)
                ax.set_ylabel(r"$\rho(x)$")
            else:
                sim = read_rows(os.path.join(d, "contact.tsv"))
                # columns: x, rho2 (default), theorem, window, extrapolated (value, error)
                ax.errorbar(column(sim, 0), column(sim, 5), yerr=column(sim, 6), fmt="s", ms=2,
                            lw=0.5, color="0.65", label="window estimator")
                ax.errorbar(column(sim, 0), column(sim, 1), yerr=column(sim, 2), fmt="o", ms=2.5,
                            lw=0.7, label="default estimator")
                ax.plot(column(th, 0), column(th, 2), "k-", lw=0.9, label="Percus (exact)")
                ax.set_ylabel(r"$\rho_2(x, x+\sigma)$")
            ax.set_title(rf"{row_label} = {s:g}, $\bar\rho$ = {r:g}", fontsize=9)
            ax.set_xlabel("x")
    axes[0][0].legend(fontsize=7)
    fig.tight_layout()
    tmp = out + ".part.png"
    fig.savefig(tmp, dpi=110)
    os.replace(tmp, out)
    print(f"plot: {out}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("dir")
    ap.add_argument("--out", help="folder for the PNG files (default: DIR)")
    a = ap.parse_args()
    out = a.out or a.dir
    os.makedirs(out, exist_ok=True)
    def find(pattern):
        found = {}
        for name in sorted(os.listdir(a.dir)):
            m = re.fullmatch(pattern, name)
            if m and os.path.exists(os.path.join(a.dir, name, "theory.tsv")):
                found[(float(m.group(1)), float(m.group(2)))] = name
        return found

    cases = find(r"percus-s([0-9.]+)-rho([0-9.]+)")
    sticky = find(r"sticky-g([0-9.]+)-rho([0-9.]+)")
    spheres = [n for n in sorted(os.listdir(a.dir)) if re.fullmatch(r"spheres-(3d|binary|poly).*", n)
               and os.path.exists(os.path.join(a.dir, n, "gr.tsv"))]
    if not cases and not sticky and not spheres:
        sys.exit(f"plot_validation: no percus-*, sticky-* or spheres-* cases in {a.dir}")
    if spheres:
        spheres_figure(a.dir, spheres, os.path.join(out, "validation-spheres.png"))
    if cases:
        grid_figure(cases, a.dir, "density", os.path.join(out, "validation-density.png"))
        grid_figure(cases, a.dir, "contact", os.path.join(out, "validation-contact.png"))
    if sticky:
        grid_figure(sticky, a.dir, "density", os.path.join(out, "validation-sticky.png"),
                    row_label=r"$\gamma$", theory_label=r"exact ($\delta_\epsilon$, p = 3, $\epsilon$ = 0.05)")


def spheres_figure(base, names, out):
    """g(r) per species pair of the spheres cases, the theory's contact value as a cross."""
    fig, axes = plt.subplots(1, len(names), figsize=(4.2 * len(names), 3.4), squeeze=False)
    for ax, name in zip(axes[0], names):
        rows = read_rows(os.path.join(base, name, "gr.tsv"))
        with open(os.path.join(base, name, "summary.json")) as f:
            summary = json.load(f)
        contacts = summary.get("contacts", [])
        for p, c in enumerate(contacts):
            r, g = column(rows, 0), column(rows, 1 + 2 * p)
            line, = ax.plot(r, g, lw=1, label=f"{c['a']}-{c['b']}")
            # the theory's contact value, drawn at the first bin the pair reaches; with a
            # size spread (g(r) smeared) at the mean diameter: it is the sigma_ij^3-weighted
            # mean of the pairs' contact values there
            first = next((x for x, y in zip(r, g) if y > 0), None)
            sizes = summary.get("sizes", {})
            if sizes.get("polydispersity", 0) > 0:
                first = sizes["mean"]
            elif first is not None:
                first -= 0.5 * (r[1] - r[0])
            if c["theory"] > 0 and first is not None:
                ax.plot([first], [c["theory"]], "x", color=line.get_color(), ms=8)
        ax.set_title(f"{name} (x: {contacts[0]['theory_eos'] if contacts else ''} at contact)",
                     fontsize=8)
        ax.set_xlabel(r"$r / \sigma$")
        ax.set_ylabel(r"$g(r)$")
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    plt.close(fig)
    print(out)


if __name__ == "__main__":
    main()

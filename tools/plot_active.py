#!/usr/bin/python3
"""Plot a run of active Brownian disks or spheres (PNG).

usage: tools/plot_active.py RUN_DIR [--out FILE.png] [--dpi N]

Reads summary.json, the last frame of trajectory.xyz (or trajectory.gsd), msd.tsv,
orientation.tsv and local_density.tsv of RUN_DIR (whichever it has) and writes
RUN_DIR/plot.png:
- a snapshot of the last frame, each particle coloured by the angle of its orientation
  in the x-y plane (spheres: those of a slab of thickness 2 sigma through the middle);
- the distribution of the local packing fraction (two peaks: motility-induced phase
  separation), with the run's mean packing fraction;
- the MSD per particle against the exact law of free active Brownian particles,
  2 d D t + 2 v0^2 / k^2 (k t - 1 + exp(-k t)) with k = (d-1) D_r, and the orientation
  correlation <e(0).e(t)> against exp(-k t).
Prints the peaks of the local density and the MSD at the largest lag with the free law's.
Uses only Debian's python3-numpy and python3-matplotlib (and python3-gsd for a GSD file).
"""
import argparse
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import PatchCollection  # noqa: E402
from matplotlib.patches import Circle  # noqa: E402


def table(path):
    """The columns of an hsbd table: {name: array}, or None when the file is missing."""
    if not os.path.exists(path):
        return None
    with open(path) as f:
        lines = f.read().splitlines()
    # the column names: the last '#' line before the data (older tables: the first line
    # without '#')
    body = [ln for ln in lines if ln.strip() and not ln.startswith("#")]
    if body and not body[0].split()[0].replace(".", "").replace("-", "").replace("e", "").isdigit():
        names, body = body[0].split(), body[1:]
    else:
        names = [ln for ln in lines if ln.startswith("#")][-1].lstrip("#").split()
    data = np.array([[float(v) for v in ln.split()] for ln in body])
    return {n: data[:, k] for k, n in enumerate(names)} if len(data) else None


def last_frame(run_dir):
    """Positions (n x 3), radii, orientations (n x 3) and box of the last frame."""
    xyz = os.path.join(run_dir, "trajectory.xyz")
    if os.path.exists(xyz):
        with open(xyz) as f:
            lines = f.read().split("\n")
        start, i = None, 0
        while i < len(lines) and lines[i].strip():
            start = i
            i += 2 + int(lines[i])
        n = int(lines[start])
        head = lines[start + 1]
        box = [float(v) for v in head.split('Lattice="')[1].split('"')[0].split()[0::4]]
        props = head.split("Properties=")[1].split()[0].split(":")
        col, cols = 0, {}
        for k in range(0, len(props), 3):
            cols[props[k]] = col
            col += int(props[k + 2])
        rows = np.array([[float(v) for v in ln.split()[1:]] for ln in lines[start + 2:start + 2 + n]])
        at = lambda name: cols[name] - 1  # noqa: E731 (the species' name is not in rows)
        e = rows[:, at("dipoles"):at("dipoles") + 3] if "dipoles" in cols else None
        return rows[:, at("pos"):at("pos") + 3], rows[:, at("radius")], e, box
    gsd_path = os.path.join(run_dir, "trajectory.gsd")
    if os.path.exists(gsd_path):
        import gsd.hoomd
        f = gsd.hoomd.open(gsd_path, "rb")[-1]
        box = list(f.configuration.box[:3])
        q = f.particles.orientation.astype(float) if f.particles.orientation is not None else None
        e = None
        if q is not None:
            w, x, y, z = q.T
            e = np.stack([w * w + x * x - y * y - z * z, 2 * (x * y + w * z), 2 * (x * z - w * y)], 1)
        return f.particles.position + np.array(box) / 2, f.particles.diameter / 2, e, box
    return None


def local_density_peaks(phi, p, width=0.02):
    """The maxima of P(phi) smoothed over a Gaussian of `width`, above a fifth of the largest
    and at least 0.1 apart (the dilute and the dense phase of a separated fluid)."""
    kernel = np.exp(-0.5 * ((phi[:, None] - phi[None, :]) / width) ** 2)
    smooth = kernel @ p / kernel.sum(axis=1)
    peaks = []
    for i in np.argsort(-smooth):
        if smooth[i] < 0.2 * smooth.max():
            break
        is_max = (i == 0 or smooth[i] >= smooth[i - 1]) and (i == len(p) - 1 or smooth[i] >= smooth[i + 1])
        if is_max and all(abs(phi[i] - q) >= 0.1 for q in peaks):
            peaks.append(phi[i])
    return sorted(peaks)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run_dir")
    ap.add_argument("--out", help="PNG file (default RUN_DIR/plot.png)")
    ap.add_argument("--dpi", type=int, default=110, help="resolution (default 110)")
    a = ap.parse_args()
    try:
        with open(os.path.join(a.run_dir, "summary.json")) as f:
            s = json.load(f)
    except OSError as e:
        sys.exit(f"plot_active: {e}")
    act = s.get("parameters", {}).get("active", {})
    if s.get("model") != "spheres" or not act.get("v0"):
        sys.exit(f"plot_active: {a.run_dir} is not a run of active disks or spheres")
    par = s["parameters"]
    dim = int(s["dimension"])
    v0 = float(str(act["v0"]).replace(",", " ").split()[0])
    diff = float(par["system"]["D"])
    sigma = float(par["system"]["sigma"])
    dr = float(str(act["rotational_D"]).replace(",", " ").split()[0]) if act.get("rotational_D") else 3 * diff / sigma ** 2
    k = (dim - 1) * dr
    fig, ax = plt.subplots(1, 3, figsize=(17, 5.2))
    fig.suptitle(f"active Brownian {'disks' if dim == 2 else 'spheres'}, N = {par['system']['N']}, "
                 f"packing fraction {float(s['packing_fraction']):.3g}, Pe = v0 sigma / D = {v0 * sigma / diff:g}, "
                 f"D_r = {dr:g}; t = {float(s['time_simulated']):g} sigma^2/D")

    frame = last_frame(a.run_dir)
    if frame is not None:
        x, r, e, box = frame
        if dim == 3:  # a slab through the middle, 2 sigma thick
            keep = np.abs(x[:, 2] - box[2] / 2) < sigma
            x, r, e = x[keep], r[keep], e[keep] if e is not None else None
        angle = np.arctan2(e[:, 1], e[:, 0]) if e is not None else np.zeros(len(r))
        patches = [Circle((xi[0], xi[1]), ri) for xi, ri in zip(x, r)]
        pc = PatchCollection(patches, cmap="hsv", linewidths=0)
        pc.set_array(angle)
        pc.set_clim(-math.pi, math.pi)
        ax[0].add_collection(pc)
        ax[0].set_xlim(0, box[0])
        ax[0].set_ylim(0, box[1])
        ax[0].set_aspect("equal")
        fig.colorbar(pc, ax=ax[0], label="orientation angle in the x-y plane")
        ax[0].set_title("last frame" + (" (the slab |z - L/2| < sigma)" if dim == 3 else ""))
    else:
        ax[0].text(0.5, 0.5, "no trajectory (output.trajectory)", ha="center", transform=ax[0].transAxes)

    loc = table(os.path.join(a.run_dir, "local_density.tsv"))
    if loc is not None:
        phi = loc["phi"]
        ax[1].errorbar(phi, loc["P"], yerr=loc["P_err"], fmt="-", lw=1, drawstyle="steps-mid")
        ax[1].axvline(float(s["packing_fraction"]), ls=":", c="k", label="mean packing fraction")
        used = np.nonzero(loc["P"] > 0)[0]
        if len(used):
            ax[1].set_xlim(max(0, phi[used[0]] - 0.05), min(1, phi[used[-1]] + 0.05))
        peaks = local_density_peaks(phi, loc["P"])
        for x in peaks:
            ax[1].axvline(x, c="C1", lw=1)
        print("local density peaks at phi =", ", ".join(f"{x:.3f}" for x in peaks))
        ax[1].set_xlabel("local packing fraction")
        ax[1].set_ylabel("P(phi)")
        ax[1].legend()
        ax[1].set_title("local density (sample.local_density_every)")
    else:
        ax[1].text(0.5, 0.5, "no local_density.tsv", ha="center", transform=ax[1].transAxes)

    msd = table(os.path.join(a.run_dir, "msd.tsv"))
    if msd is not None:
        t = msd["t"]
        law = 2 * dim * diff * t + 2 * v0 ** 2 / k ** 2 * (k * t - 1 + np.exp(-k * t)) if k > 0 else 2 * dim * diff * t + (v0 * t) ** 2
        ax[2].errorbar(t, msd["msd"], yerr=msd["msd_err"], fmt="o", ms=3, label="MSD")
        ax[2].plot(t, law, "k--", label="free ABP: 2dDt + 2v0²/k²(kt-1+e^-kt)")
        ax[2].plot(t, 2 * dim * diff * t, "k:", label="2dDt")
        ax[2].set_xscale("log")
        ax[2].set_yscale("log")
        ax[2].set_xlabel("t (sigma²/D)")
        ax[2].set_ylabel("MSD")
        print(f"MSD at t = {t[-1]:g}: {msd['msd'][-1]:.4g} +- {msd['msd_err'][-1]:.2g}, the free ABP law {law[-1]:.4g}")
        rot = table(os.path.join(a.run_dir, "orientation.tsv"))
        if rot is not None:
            twin = ax[2].twinx()
            twin.errorbar(rot["t"], rot["C"], yerr=rot["C_err"], fmt="s", ms=2, c="C3", label="<e(0).e(t)>")
            twin.plot(rot["t"], np.exp(-k * rot["t"]), c="C3", lw=1, label="exp(-(d-1) D_r t)")
            twin.set_ylabel("orientation correlation", color="C3")
            twin.set_ylim(0, 1.05)
            twin.legend(loc="lower right")
        ax[2].legend(loc="upper left")
        ax[2].set_title("MSD and orientation correlation")
    out = a.out or os.path.join(a.run_dir, "plot.png")
    fig.tight_layout()
    fig.savefig(out, dpi=a.dpi)
    print(f"plot_active: {out}")


if __name__ == "__main__":
    main()

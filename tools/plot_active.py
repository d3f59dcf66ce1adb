#!/usr/bin/python3
"""Plot a run of active Brownian disks or spheres (PNG); hsbd.plot draws it.

usage: tools/plot_active.py RUN_DIR [--out FILE.png]

The same figure as `python3 -m hsbd.plot RUN_DIR` (the package hsbd, installed or built in
build/python; docs/python.md): the last frame coloured by each particle's orientation
(spheres: a slab through the middle), the distribution of the local packing fraction with
its peaks, the MSD against the exact law of free active Brownian particles and the
orientation correlation against exp(-(d-1) D_r t). Prints the local density's peaks (what
tools/validate_mips.sh judges) and the MSD at the largest lag.
"""
import argparse

from hsbd_tools import load_run


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run_dir")
    ap.add_argument("--out", help="PNG file (default RUN_DIR/plot.png)")
    a = ap.parse_args()
    hsbd, run = load_run("plot_active", a.run_dir, lambda hsbd, run: None if hsbd.plot._is_active(
        run) else "is not a run of active disks or spheres")
    if "local_density" in run.tables:
        loc = run["local_density"]
        peaks = hsbd.plot.local_density_peaks(loc["phi"], loc["P"])
        print("local density peaks at phi =", ", ".join(f"{x:.3f}" for x in peaks))
    if "msd" in run.tables:
        msd = run["msd"]
        print(f"MSD at t = {msd['t'][-1]:g}: {msd['msd'][-1]:.4g} +- {msd['msd_err'][-1]:.2g}")
    print(f"plot_active: {hsbd.plot(run, out=a.out)}")


if __name__ == "__main__":
    main()

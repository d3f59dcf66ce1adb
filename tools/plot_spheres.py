#!/usr/bin/python3
"""Plot a run of hard disks or spheres: g(r), density profiles, MSD, F_s (PNG); hsbd.plot
draws it.

usage: tools/plot_spheres.py RUN_DIR [--out FILE.png]

The same figure as `python3 -m hsbd.plot RUN_DIR` (the package hsbd, installed or built in
build/python; docs/python.md): g(r) per species pair with the measured contact values and
the equation of state's, the density profile per species along each axis with walls or
the field with the density at contact with each wall, the MSD per species with 2dDt and
2dD_L t, and F_s(k, t).
"""
import argparse

from hsbd_tools import load_run


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run_dir")
    ap.add_argument("--out", help="PNG file (default RUN_DIR/plot.png)")
    a = ap.parse_args()
    hsbd, run = load_run("plot_spheres", a.run_dir, lambda hsbd, run: None if run.model == "spheres"
                         else f"is a run of {run.model}, not spheres")
    print(f"plot: {hsbd.plot(run, out=a.out)}")


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Plot a hard-rod run: density profile, contact density, MSD (PNG); hsbd.plot draws it.

usage: tools/plot_rods.py RUN_DIR [--theory PERCUS.tsv] [--out FILE.png]

The same figure as `python3 -m hsbd.plot RUN_DIR` (the package hsbd, installed or built in
build/python; docs/python.md): the density profile with the ideal-gas reference exp(-U/kT)
and Percus' exact profile where it applies (or the table --theory of `hsbd theory
percus`), the contact density, the MSD per species with the single-file law.
"""
import argparse

from hsbd_tools import load_run


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run_dir")
    ap.add_argument("--out", help="PNG file (default RUN_DIR/plot.png)")
    ap.add_argument("--theory", help="exact profile from 'hsbd theory percus' (x rho rho2)")
    a = ap.parse_args()
    hsbd, run = load_run("plot_rods", a.run_dir, lambda hsbd, run: None if run.model == "rods"
                         else f"is a run of {run.model}, not rods")
    print(f"plot: {hsbd.plot(run, out=a.out, theory=a.theory)}")


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Every table hsbd writes is read by numpy.loadtxt with its defaults: the header lines, the
column names last, start with '#', and every row has one number per name.

Short runs with every table on: rods on a ring (profiles, contacts, blocks, MSD, clusters,
current, phases of a drive), rods of two species between walls, spheres (g(r), MSD, F_s,
S(k)), disks between walls in a field along the other axis (a profile per axis), an ensemble of two replicas and its merged
tables, and the tables of `hsbd theory`. Usage: test_tables.py path/to/hsbd
"""
import glob
import os
import subprocess
import sys
import tempfile

import numpy as np

HSBD = os.path.abspath(sys.argv[1])
SHORT = ["--quiet", "--set", "run.t_equil=0.05", "--set", "sample.blocks=4"]
RODS = "[system]\nN = 50\nL = 40\nseed = 3\n[run]\ndt = 2e-4\n"  # the flagship's field
SPHERES = "[system]\nmodel = spheres\nN = 200\npacking_fraction = 0.3\n[run]\ndt = 1e-3\n"
RUNS = {
    "rods": ["--set", "run.t_total=1", "--set", "sample.current_every=0.25",
             "--set", "drive.parameter=amplitude", "--set", "drive.wave=square",
             "--set", "drive.amplitude=2", "--set", "drive.period=0.5",
             "--set", "sample.phases=2", "--set", "sample.blocking=space"],
    "rods-walls": ["--set", "run.t_total=1", "--set", "system.boundary=walls",
                   "--set", "species.names=a,b", "--set", "species.count=30,20",
                   "--set", "species.sigma=0.5,0.8", "--set", "species.D=1,0.5"],
    "rods-ensemble": ["--set", "run.t_total=1", "--set", "run.replicas=2"],
    "spheres": ["--set", "run.t_total=0.2", "--set", "sample.gr_every=10",
                "--set", "sample.sk_every=10"],
    "disks-walls": ["--set", "system.dimension=2", "--set", "system.boundary=walls,periodic",
                    "--set", "field.type=tilt", "--set", "field.force=-1",
                    "--set", "run.t_total=0.2", "--set", "sample.gr_every=10"],
}
THEORIES = [
    ["percus", "--sigma", "0.5", "--rho", "0.5", "--amplitude", "6", "--points", "200"],
    ["box", "--N", "10", "--L", "10", "--sigma", "0.5", "--force", "-1", "--bin", "0.5"],
    ["washboard", "--amplitude", "2", "--force-min", "0", "--force-max", "4", "--forces", "3"],
]

failures = []


def check(cond, what):
    if not cond:
        failures.append(what)
        print("FAIL:", what, file=sys.stderr)


def column_names(path):
    """The names of the header's last line ('# ' and names between tabs)."""
    last = None
    with open(path) as f:
        for line in f:
            if not line.startswith("#"):
                break
            last = line
    return last[1:].split() if last else []


with tempfile.TemporaryDirectory() as tmp:
    os.chdir(tmp)
    for config, text in (("rods.ini", RODS), ("spheres.ini", SPHERES)):
        with open(config, "w") as f:
            f.write(text)
    for name, sets in RUNS.items():
        config = "rods.ini" if name.startswith("rods") else "spheres.ini"
        subprocess.run([HSBD, "run", config, "--out", name] + SHORT + sets, check=True)
    for t in THEORIES:
        subprocess.run([HSBD, "theory"] + t + ["--out", f"theory-{t[0]}.tsv"], check=True)
    tables = sorted(glob.glob("**/*.tsv", recursive=True))
    kinds = {os.path.basename(t) for t in tables}
    for want in ("density.tsv", "contact.tsv", "density_blocks.tsv", "contact_blocks.tsv",
                 "msd.tsv", "clusters.tsv", "current.tsv", "density_phases.tsv", "gr.tsv",
                 "fs.tsv", "sk.tsv", "density_x.tsv", "theory-percus.tsv", "theory-box.tsv",
                 "theory-washboard.tsv"):
        check(want in kinds, f"the runs wrote no {want}")
    check(os.path.exists("rods-ensemble/replica-1/msd.tsv"), "no replica tables")
    for path in tables:
        try:
            data = np.loadtxt(path, ndmin=2)
        except ValueError as e:
            check(False, f"numpy.loadtxt({path}): {e}")
            continue
        names = column_names(path)
        check(data.shape[0] > 0, f"{path}: no rows")
        check(data.shape[1] == len(names) > 1,
              f"{path}: {data.shape[1]} columns under {len(names)} names {names}")
    print(f"test_tables: numpy.loadtxt read {len(tables)} tables of {len(kinds)} kinds")

if failures:
    print(f"test_tables: {len(failures)} failures", file=sys.stderr)
    sys.exit(1)

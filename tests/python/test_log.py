#!/usr/bin/python3
"""log.tsv and the progress lines of a batch job.

log.tsv's lines split the production into intervals of output.log_every, so the mean of
each column over the lines is the whole run's mean that summary.json gives, exactly (to
the tables' 10 digits): the particle current (rods; on a ring, also with
sample.blocking = replicas, whose replica changes fall inside intervals), the walls'
contact densities (rods between walls, sampled as the contacts observer samples them),
collisions per particle-step and the virial Z (spheres; P_virial = (N/V) kT Z, at
kT = 2), each wall's pressure kT x its contact density (disks in a slit). The t column
steps by log_every; the same seed gives the same bytes; log_every = 0 writes no log.tsv,
one shorter than run.dt or negative is refused (exit 2). Without a terminal the progress
comes as whole lines: one as the run starts and one at its end (stage, percent, simulated
time, rate, ETA); --quiet prints nothing. Usage: test_log.py path/to/hsbd
"""
import filecmp
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

HSBD = os.path.abspath(sys.argv[1])
SRC = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
failures = []


def check(cond, what):
    if not cond:
        failures.append(what)
        print("FAIL:", what, file=sys.stderr)


def near(a, b, what):
    check(abs(a - b) <= 1e-8 * max(abs(b), 1e-12), f"{what}: log.tsv's mean {a!r}, summary {b!r}")


def run(example, out, *sets, quiet=True):
    args = [HSBD, "run", os.path.join(SRC, "examples", example), "--out", out]
    args += ["--quiet"] if quiet else []
    for s in ("run.t_equil=0.05",) + sets:
        args += ["--set", s]
    p = subprocess.run(args, capture_output=True, text=True)  # stderr: a pipe, no terminal
    return p.returncode, p.stderr


def load(out):
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    with open(os.path.join(out, "log.tsv")) as f:
        names = [ln for ln in f if ln.startswith("#")][-1][1:].split()
    table = np.loadtxt(os.path.join(out, "log.tsv"), ndmin=2)
    return summary, dict(zip(names, table.T))


with tempfile.TemporaryDirectory() as tmp:
    os.chdir(tmp)
    # rods between walls, and on a ring with replicas
    for name, example, sets in (
            ("walls", "rods-sediment.ini", ("run.t_total=2", "output.log_every=0.01")),
            ("ring", "rods-cosine.ini", ("run.t_total=1", "system.N=100", "system.L=200",
                                         "sample.blocking=replicas", "sample.blocks=4",
                                         "output.log_every=0.01"))):
        rc, err = run(example, name, *sets)
        check(rc == 0, f"rods {name}: {err}")
        if rc:
            continue
        s, log = load(name)
        check(len(log["t"]) == 100 * float(sets[0].split("=")[1]) and
              np.allclose(np.diff(log["t"]), 0.01), f"rods {name}: the t column {log['t'][:3]}")
        near(log["J"].mean(), s["particle_current"], f"rods {name}: J")
        check(np.all(log["mean_cluster_size"] >= 1), f"rods {name}: mean cluster sizes")
        if name == "walls":
            near(log["wall_left"].mean(), s["contacts"]["wall_left"], "rods: wall_left")
            near(log["wall_right"].mean(), s["contacts"]["wall_right"], "rods: wall_right")
    # spheres in a periodic box at kT = 2, and disks in a slit
    rc, err = run("spheres-fluid.ini", "fluid", "system.N=300", "system.kT=2", "run.t_total=0.4")
    check(rc == 0, f"spheres: {err}")
    if rc == 0:
        s, log = load("fluid")
        check(len(log["t"]) == 400, f"spheres: {len(log['t'])} lines, default t_total/1000")
        near(log["collisions_per_particle_step"].mean(), s["collisions_per_particle_step"],
             "spheres: collisions")
        density = 300 / np.prod(s["box"])
        near(log["P_virial"].mean() / (2 * density), s["Z_virial"], "spheres: Z from P_virial")
    rc, err = run("spheres-slit.ini", "slit", "system.kT=2", "run.t_total=0.4",
                  "output.log_every=0.004")
    check(rc == 0, f"slit: {err}")
    if rc == 0:
        s, log = load("slit")
        for wall in s["walls"]:
            column = f"P_wall_{wall['axis']}_{wall['side']}"
            near(log[column].mean() / 2, wall["contact_density"], f"slit: {column}")
    # same seed, same bytes; no log; refused intervals
    rc, err = run("spheres-fluid.ini", "fluid-again", "system.N=300", "system.kT=2",
                  "run.t_total=0.4")
    check(rc == 0 and filecmp.cmp("fluid/log.tsv", "fluid-again/log.tsv", shallow=False),
          "the same seed gave another log.tsv")
    rc, err = run("rods-cosine.ini", "nolog", "run.t_total=0.5", "output.log_every=0")
    check(rc == 0 and not os.path.exists("nolog/log.tsv"), "output.log_every = 0 wrote log.tsv")
    for value, text in (("1e-5", "output.log_every = 1e-05 is shorter than run.dt"),
                        ("-1", "output.log_every")):
        rc, err = run("rods-cosine.ini", "badlog", f"output.log_every={value}")
        check(rc == 2 and text in err and not os.path.exists("badlog"),
              f"output.log_every = {value}: exit {rc}, {err.strip()}")
    # progress without a terminal: whole lines
    rc, err = run("rods-cosine.ini", "progress", "run.t_total=0.5", quiet=False)
    lines = err.splitlines()
    check(rc == 0 and lines and lines[0].startswith("hsbd: equilibrating   0.0%  t = 0 of 0.05")
          and "steps to go" in lines[0], f"the first progress line: {err}")
    done = [ln for ln in lines if ln.startswith("hsbd: done 100.0%  t = 0.5 of 0.5  ")]
    check(len(done) == 1 and "M particle-steps/s  ETA 0:00:00  (after " in done[0],
          f"the last progress line: {err}")
    check(lines[-1] == "hsbd: results in progress/", f"the results line: {err}")
    rc, err = run("rods-cosine.ini", "quiet", "run.t_total=0.5")
    check(rc == 0 and err == "", f"--quiet printed: {err}")

if failures:
    print(f"test_log: {len(failures)} failures", file=sys.stderr)
    sys.exit(1)
print("test_log: log.tsv's means are the summary's; progress lines in a batch log")

#!/usr/bin/python3
"""The Python module `hsbd` (build/python) against the CLI and its own promises.

- hsbd.run() of a configuration file with keys set from Python writes tables
  byte-identical to `hsbd run FILE --set ...` (rods and spheres).
- Bad input raises hsbd.InputError with exactly the message `hsbd run` prints (after
  its "hsbd: " prefix), for files; keys from Python name the key and the range.
- positions, images, diameters, species are read-only views without copies: two
  accesses share memory, an array taken before a step shows the state after it
  (spheres: the engine's own arrays), writes raise ValueError.
- A Simulation advanced to its end holds the density profile and MSD that the run's
  tables print (10 digits), and two simulations stepped alternately in one process
  give the same states as each one alone.
Usage: test_module.py path/to/hsbd path/to/build/python
"""
import os
import subprocess
import sys
import tempfile

import numpy as np

HSBD = os.path.abspath(sys.argv[1])
sys.path.insert(0, os.path.abspath(sys.argv[2]))
import hsbd  # noqa: E402

SRC = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
failures = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what, file=sys.stderr if not cond else sys.stdout)
    if not cond:
        failures.append(what)


def tables(d):
    return sorted(f for f in os.listdir(d) if f.endswith(".tsv"))


def table_of(path):
    """The numbers of a table (every header line, the column names too, starts with '#')."""
    return np.loadtxt(path, ndmin=2)


def same_tables(a, b):
    names = tables(a)
    if not names or names != tables(b):
        return False
    return all(open(os.path.join(a, f), "rb").read() == open(os.path.join(b, f), "rb").read()
               for f in names)


RODS = os.path.join(SRC, "examples", "rods-mixture.ini")
RODS_SETS = {"run": {"t_total": 2.0, "t_equil": 0.2}, "sample": {"blocks": 4}}
SPHERES = {"system": {"model": "spheres", "N": 400, "packing_fraction": 0.3, "seed": 3},
           "species": {"names": ["A", "B"], "fraction": [0.5, 0.5], "sigma": [1, 1.2],
                       "D": [1, 0.8]},
           "run": {"dt": 1e-3, "t_total": 0.6, "t_equil": 0.05},
           "sample": {"gr_every": 10, "blocks": 4}}


def cli_sets(sections):
    out = []
    for sec, keys in sections.items():
        for k, v in keys.items():
            v = ",".join(str(x) for x in v) if isinstance(v, list) else v
            out += ["--set", f"{sec}.{k}={v}"]
    return out


with tempfile.TemporaryDirectory() as d:
    os.chdir(d)
    # 1. runs written by the module and by the CLI: the same bytes
    subprocess.run([HSBD, "run", RODS, "--quiet", "--out", "cli-rods", *cli_sets(RODS_SETS)],
                   check=True)
    out = hsbd.run(RODS, out="py-rods", **RODS_SETS)
    check(out == "py-rods" and same_tables("cli-rods", "py-rods"),
          f"rods: hsbd.run tables = hsbd run tables ({len(tables('cli-rods'))} files)")
    with open("spheres.ini", "w") as f:
        f.write("[system]\nmodel = spheres\n")
    rest = {k: v for k, v in SPHERES.items()}
    subprocess.run([HSBD, "run", "--defaults", "--quiet", "--out", "cli-spheres",
                    *cli_sets(rest)], check=True)
    hsbd.run(SPHERES, out="py-spheres")
    check(same_tables("cli-spheres", "py-spheres"),
          f"spheres: hsbd.run tables = hsbd run tables ({len(tables('cli-spheres'))} files)")
    check('"completed": true' in open("py-spheres/summary.json").read(), "summary.json written")

    # 2. errors: the same message as the CLI
    bad = {"fit.ini": "[system]\nN = 10\nL = 3\nsigma = 0.5\n",
           "word.ini": "[system]\nN = abc\n",
           "key.ini": "[system]\nsigmaa = 1\n",
           "spheres-dense.ini": "[system]\nmodel = spheres\nN = 100\npacking_fraction = 0.9\n"}
    for name, text in bad.items():
        with open(name, "w") as f:
            f.write(text)
        cli = subprocess.run([HSBD, "run", name, "--quiet", "--out", "x-" + name],
                             capture_output=True, text=True)
        try:
            hsbd.Simulation(name)
            msg = None
        except hsbd.InputError as e:
            msg = str(e)
        expect = cli.stderr.strip().removeprefix("hsbd: ")
        check(cli.returncode == 2 and msg == expect, f"{name}: InputError '{msg}'")
    try:
        hsbd.Simulation(system={"N": -3})
        msg = ""
    except hsbd.InputError as e:
        msg = str(e)
    check("system.N" in msg and "1 <= N" in msg, f"keyword error names the key: '{msg}'")
    check(issubclass(hsbd.InputError, ValueError), "InputError is a ValueError")

    # 3. views without copies, read-only
    sim = hsbd.Simulation(SPHERES)
    sim.step(10)
    before = sim.positions
    copy = before.copy()
    check(np.shares_memory(before, sim.positions) and np.shares_memory(sim.images, sim.images)
          and np.shares_memory(sim.diameters, sim.diameters)
          and np.shares_memory(sim.species, sim.species), "spheres: arrays share memory")
    sim.step(10)
    check(np.array_equal(before, sim.positions) and not np.array_equal(before, copy),
          "spheres: an array taken before a step shows the state after it (a view)")
    for name in ("positions", "images", "diameters", "species"):
        a = getattr(sim, name)
        try:
            a[0] = 0
            refused = False
        except ValueError:
            refused = True
        check(refused and not a.flags.writeable, f"{name}: writes refused")
    check(sim.positions.shape == (400, 3) and sim.species.tolist().count(1) == 200
          and set(sim.diameters.tolist()) == {1.0, 1.2}, "spheres: shapes, species, diameters")
    rods = hsbd.Simulation(RODS, **RODS_SETS)
    p = rods.positions
    check(np.shares_memory(p, rods.positions) and not p.flags.writeable, "rods: views")

    # 4. a simulation to its end holds what the tables print; side by side = alone
    while rods.stage != "done":
        rods.step(5000)
    x, rho, err = rods.density()
    table = table_of("py-rods/density.tsv")
    check(np.allclose(table[:, 0], x, rtol=1e-9) and np.allclose(table[:, 1], rho, rtol=1e-9),
          "rods: Simulation.density() = density.tsv")
    t, msd, _ = rods.msd()
    table = table_of("py-rods/msd.tsv")
    check(np.allclose(table[:, 1], msd, rtol=1e-9, atol=0), "rods: Simulation.msd() = msd.tsv")
    sph = hsbd.Simulation(SPHERES)
    while sph.stage != "done":
        sph.step(100)
    pairs = sph.gr_pairs()
    _, g01, _ = sph.gr(1)
    table = table_of("py-spheres/gr.tsv")
    check(len(pairs) == 3 and np.allclose(table[:, 3], g01, rtol=1e-9),
          "spheres: Simulation.gr(1) = gr.tsv column of pair A-B")
    a_alone = hsbd.Simulation(SPHERES)
    a_alone.step(300)
    alone = a_alone.positions.copy()
    a = hsbd.Simulation(SPHERES)
    b = hsbd.Simulation(SPHERES, system={"seed": 9})
    for _ in range(30):
        a.step(10)
        b.step(10)
    check(np.array_equal(a.positions, alone) and not np.array_equal(a.positions, b.positions),
          "two simulations side by side: each as if alone")

print(f"test_module: {len(failures)} failures")
sys.exit(1 if failures else 0)

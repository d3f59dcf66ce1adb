#!/usr/bin/python3
"""The package hsbd (build/python/hsbd): what a user of the Python API is promised.

- Findings of a first use, each fixed: gr(pair=0) by keyword; step(-1) refused (and
  nothing done); msd(species=0) of one species is everyone's, a wrong species named in
  the message; the equations of state refuse packing fractions outside [0, close packing)
  and Tonks rho sigma >= 1; `time` counts from the start, equilibration included, as its
  docstring says; help() and inspect.signature show every function's parameters;
  __version__ is the library's (and the CLI's).
- A Simulation run to its end holds what the run's files say (same configuration, same
  seed, so the same numbers to the tables' 10 digits): F_s (fs.tsv), D_L and Z (summary's
  D_long, Z_virial), the walls' contact densities and the density profiles per species
  of spheres between walls in a field (summary's walls, density.tsv); summary() is the
  summary's dict, and run(t) advances the simulated time by t across both stages.
- positions can be set before the first step: the run then goes exactly as one started
  from the same positions by init.positions (rods) or as given back from another
  simulation (spheres); overlaps, a wrong shape, and setting after a step are refused.
- hsbd.load reads run directories of the CLI and of the module alike: summary as a dict,
  each table as named columns equal to numpy.loadtxt's numbers, the blocks, an
  ensemble's replicas; tables whose column names are on a '#' line (what numpy.loadtxt
  skips) read the same as with the names on a line of their own.
Usage: test_package.py path/to/hsbd path/to/build/python
"""
import inspect
import json
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np

HSBD = os.path.abspath(sys.argv[1])
sys.path.insert(0, os.path.abspath(sys.argv[2]))
import hsbd  # noqa: E402

failures = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what, file=sys.stdout if cond else sys.stderr)
    if not cond:
        failures.append(what)


def raises(exc, fn, *args, **kw):
    """The message of exc raised by fn(*args, **kw), or None when it raised nothing."""
    try:
        fn(*args, **kw)
    except exc as e:
        return str(e)
    return None


def close(a, b, rtol=1e-9):
    a, b = np.asarray(a, float), np.asarray(b, float)
    return a.shape == b.shape and np.allclose(a, b, rtol=rtol, atol=1e-300, equal_nan=True)


SPHERES = {"system": {"model": "spheres", "N": 300, "packing_fraction": 0.3, "seed": 4},
           "run": {"dt": 1e-3, "t_equil": 0.05, "t_total": 0.4},
           "sample": {"gr_every": 10, "blocks": 4}}
WALLS = {"system": {"model": "spheres", "N": 300, "box": "8 8 10", "seed": 5,
                    "boundary": "periodic periodic walls"},
         "species": {"names": "A B", "fraction": "0.5 0.5", "sigma": "1 1.2", "D": "1 0.8"},
         "field": {"type": "tilt", "axis": "z", "force": -0.5},
         "run": {"dt": 1e-3, "t_equil": 0.05, "t_total": 0.4}, "sample": {"blocks": 4}}

# ---- findings of a first use --------------------------------------------------------------
sim = hsbd.Simulation(SPHERES)
sim.run()
check(close(sim.gr(pair=0)[1], sim.gr(0)[1]) and sim.gr(pair=0)[1].max() > 1,
      "gr(pair=0) by keyword")
steps = sim.steps
msg = raises(hsbd.InputError, sim.step, -1)
check(msg is not None and "n >= 0" in msg and sim.steps == steps, f"step(-1) refused: {msg}")
check(close(sim.msd(species=0)[1], sim.msd()[1]), "msd(species=0) of one species: everyone's")
msg = raises(hsbd.InputError, sim.msd, species=1)
check(msg is not None and "-1" not in msg and "one species" in msg, f"msd(species=1): {msg}")
for f, phi in ((hsbd.hs_z_cs, 1.5), (hsbd.hs_z_cs, -0.1), (hsbd.hs_contact_cs, 0.75),
               (hsbd.hd_z_henderson, 0.95), (hsbd.hd_contact_henderson, 1.0)):
    msg = raises(hsbd.InputError, f, phi)
    check(msg is not None and "close packing" in msg, f"{f.__name__}({phi}) refused: {msg}")
phi = 0.3
check(abs(hsbd.hs_z_cs(phi) - (1 + phi + phi**2 - phi**3) / (1 - phi)**3) < 1e-14,
      "hs_z_cs(0.3) is Carnahan-Starling's")
msg = raises(hsbd.InputError, hsbd.tonks_pressure, 2.0, 0.5)
check(msg is not None and "rho sigma < 1" in msg, f"tonks_pressure(2, 0.5) refused: {msg}")
rods = hsbd.Simulation(system={"N": 20, "L": 40}, run={"dt": 1e-3, "dt_equil": 4e-3,
                                                       "t_equil": 1, "t_total": 2})
rods.step(250)
check(rods.stage == "producing" and abs(rods.time - 1.0) < 1e-9 and "equilibration included"
      in type(rods).time.__doc__, f"time counts from the start: {rods.time} after t_equil")
rods.run(0.5)
check(rods.steps == (250, 500) and abs(rods.time - 1.5) < 1e-9,
      f"run(0.5) in production: {rods.steps}, t = {rods.time}")
fresh = hsbd.Simulation(system={"N": 20, "L": 40}, run={"dt": 1e-3, "dt_equil": 4e-3,
                                                        "t_equil": 1, "t_total": 2})
fresh.run(1.2)
check(fresh.steps == (250, 200) and abs(fresh.time - 1.2) < 1e-9,
      f"run(1.2) across the stages (dt_equil, then dt): {fresh.steps}")
fresh.run()
check(fresh.stage == "done" and fresh.steps == (250, 2000), "run() goes to the end")
sigs = {f: str(inspect.signature(f)) for f in (
    hsbd.Simulation, hsbd.Simulation.step, hsbd.Simulation.gr, hsbd.Simulation.msd,
    hsbd.Simulation.density, hsbd.run, hsbd.percus, hsbd.hs_z_cs, hsbd.single_file_msd,
    hsbd.load, hsbd.plot)}
check(all("(" in s for s in sigs.values()) and "pair=0" in sigs[hsbd.Simulation.gr]
      and "axis=None, species=None" in sigs[hsbd.Simulation.density]
      and "out=None" in sigs[hsbd.run], f"signatures: {list(sigs.values())}")
check(all(f.__doc__ and len(f.__doc__) > 40 for f in sigs), "docstrings")
cli = subprocess.run([HSBD, "--version"], capture_output=True, text=True).stdout
check(hsbd.__version__ and hsbd.__version__ in cli and hsbd.version().startswith(
    hsbd.__version__), f"__version__ {hsbd.__version__} = the CLI's ({cli.strip()})")

with tempfile.TemporaryDirectory() as d:
    os.chdir(d)
    # ---- a Simulation holds what the run's files say --------------------------------------
    hsbd.run(SPHERES, out="sph")
    hsbd.run(WALLS, out="walls")
    sph, walls = hsbd.load("sph"), hsbd.load("walls")
    t, fs, fs_err = sim.fs()
    table = sph["fs"]
    check(close(table["t"], t) and close(table["fs"], fs, 1e-9)
          and close(table["fs_err"], fs_err, 1e-3), "fs() = fs.tsv")
    dl, dl_err = sim.d_long()
    check(abs(dl - sph.summary["D_long"]) < 1e-9 * dl and abs(
        dl_err - sph.summary["D_long_err"]) < 1e-6 * dl_err, f"d_long() = D_long ({dl:.4f})")
    z, z_err = sim.z()
    check(abs(z - sph.summary["Z_virial"]) < 1e-9 * z, f"z() = Z_virial ({z:.4f} +- {z_err:.4f})")
    def results(s):  # all but the timings and where the files went
        s = {k: v for k, v in s.items() if not (k.startswith(("cpu_", "wall_")) or k in (
            "particle_steps_per_second", "collisions_per_second", "time_per_cpu_second"))}
        s["parameters"] = {k: v for k, v in s["parameters"].items() if k != "output"}
        return s
    summary = sim.summary()
    check(summary["completed"] and results(summary) == results(sph.summary),
          f"summary() = summary.json but for timings and outputs ({len(summary)} keys)")
    msg = raises(hsbd.Error, hsbd.Simulation(WALLS).z)
    check(msg is not None and "walls" in msg, f"z() between walls refused: {msg}")
    w = hsbd.Simulation(WALLS)
    w.run()
    check(w.walls() == walls.summary["walls"] and len(w.walls()) == 2,
          "walls() = summary's walls (both walls, per species)")
    dens = walls["density"]
    for species, col in ((None, "rho"), ("A", "rho_A"), (1, "rho_B")):
        x, rho, err = w.density(species=species)
        check(close(dens["x"], x) and close(dens[col], rho) and close(dens[col + "_err"], err, 1e-3),
              f"density(species={species!r}) = density.tsv {col}")
    check(close(w.density(axis="z")[1], w.density(axis=2)[1]), "density(axis='z') = axis=2")
    msg = raises(hsbd.InputError, w.density, axis="x")
    check(msg is not None and "'z'" in msg, f"density(axis='x') refused: {msg}")
    msg = raises(hsbd.InputError, w.density, species="C")
    check(msg is not None and "A .. B" in msg, f"density(species='C') refused: {msg}")

    # ---- positions set before the first step -----------------------------------------------
    x0 = np.sort(np.random.default_rng(1).uniform(0, 40, 20))
    x0 = np.cumsum(np.full(20, 1.5)) + 0.3 * np.random.default_rng(1).uniform(size=20)
    with open("start.txt", "w") as f:
        f.write("".join(f"{v!r}\n" for v in x0))
    conf = {"system": {"N": 20, "L": 40, "seed": 3}, "run": {"dt": 1e-3, "t_total": 1}}
    from_file = hsbd.Simulation(conf, init={"positions": "start.txt"})
    given = hsbd.Simulation(conf)
    given.positions = x0
    check(close(given.positions[:, 0], x0, 1e-15), "rods: positions set")
    from_file.step(400)
    given.step(400)
    check(np.array_equal(from_file.positions, given.positions),
          "rods: positions set = init.positions: the same run")
    msg = raises(hsbd.InputError, setattr, given, "positions", x0)
    check(msg is not None and "before the first step" in msg, f"set after a step: {msg}")
    bad = x0.copy()
    bad[3] = bad[2] + 0.1
    msg = raises(hsbd.InputError, setattr, hsbd.Simulation(conf), "positions", bad)
    check(msg is not None and "overlap" in msg, f"overlapping rods refused: {msg}")
    s1 = hsbd.Simulation(WALLS)
    start = s1.positions.copy()
    s2 = hsbd.Simulation(WALLS, system={"seed": 9})
    s2.positions = start
    check(np.array_equal(s2.positions, start) and np.array_equal(s2.species, s1.species),
          "spheres: positions set, species kept")
    msg = raises(hsbd.InputError, setattr, s2, "positions", start[:10])
    check(msg is not None and "shape" in msg, f"a wrong shape refused: {msg}")
    start[5, 2] = 0.2
    msg = raises(hsbd.InputError, setattr, s2, "positions", start)
    check(msg is not None and "outside the walls" in msg, f"outside the walls refused: {msg}")

    # ---- hsbd.load -------------------------------------------------------------------------
    subprocess.run([HSBD, "run", "--defaults", "--quiet", "--out", "cli", "--set", "system.N=30",
                    "--set", "run.t_total=1", "--set", "run.replicas=2"], check=True)
    run = hsbd.load("cli")
    with open("cli/summary.json") as f:
        check(run.summary == json.load(f) and run.model == "rods", "load: summary.json as a dict")
    check({"clusters", "contact", "density", "msd"} <= set(run.tables)
          and sorted(run.blocks) == ["contact", "density"] and len(run.replicas) == 2
          and run.replicas[1].summary["parameters"]["run"]["replica"] == 1,
          f"load: tables {sorted(run.tables)}, blocks {sorted(run.blocks)}, 2 replicas")

    def numbers(path):  # the rows of numbers, read without hsbd
        rows = [ln for ln in open(path) if ln.strip() and not ln.startswith("#")
                and not ln[0].isalpha()]
        return np.loadtxt(rows, ndmin=2) if rows else np.empty((0, 0))

    for name, table in list(run.tables.items()) + list(run.blocks.items()):
        check((np.array_equal(table.data, numbers(table.path)) or not len(table.data))
              and table.names[0] in ("x", "t", "size") and table.params["system.N"] == "30",
              f"load: {name} = its numbers, named")
    check(close(run["density"]["rho"], run["density"].data[:, 1]), "columns by name")

    # the column names on a line of their own, or on the last '#' line (what numpy.loadtxt
    # reads as it is): the tables of the other form than the CLI's read the same
    shutil.copytree("cli", "other")
    for name in os.listdir("other"):
        if name.endswith(".tsv"):
            lines = open(os.path.join("other", name)).read().splitlines(True)
            k = sum(1 for ln in lines if ln.startswith("#"))
            if k < len(lines) and lines[k][:1].isalpha():
                lines[k] = "# " + lines[k]  # names on a line of their own -> '#' line
            else:
                lines[k - 1] = lines[k - 1][1:].lstrip()  # '#' line -> a line of their own
            open(os.path.join("other", name), "w").write("".join(lines))
    other = hsbd.load("other")
    check(all(other[n].names == run[n].names and np.array_equal(other[n].data, run[n].data)
              for n in run.tables), "load: both forms of the column names read the same")
    hashed = run if open(run["density"].path).read().count("# x\t") else other
    check(np.array_equal(np.loadtxt(hashed["density"].path, ndmin=2), run["density"].data),
          "numpy.loadtxt reads the '#' form as it is")
    msg = raises(OSError, hsbd.load, "cli/replica-0/density.tsv")
    check(msg is not None and "a file" in msg, f"load of a file refused: {msg}")
    os.mkdir("empty")
    msg = raises(ValueError, hsbd.load, "empty")
    check(msg is not None and "not a run directory" in msg, f"load of an empty directory: {msg}")

print(f"test_package: {len(failures)} failures")
sys.exit(1 if failures else 0)

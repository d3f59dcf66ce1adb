#!/usr/bin/python3
"""init.positions in GSD: files written by Debian's gsd (2.7, HOOMD's own writer) and by
hsbd start runs whose N, box, species and diameters come from the file.

- A 3D binary mixture (types A, B and an unused C; diameters 1 and 1.4; two frames; with
  orientations) starts a run that restates nothing: its parameters are the file's, and
  its first trajectory frame (D = 1e-12: the particles barely move) holds the file's
  particles, types and radii, moved from HOOMD's centred box into hsbd's [0, L).
  init.frame = 0 picks the other frame. The same file in GSD 1's layout (HOOMD-blue 2's:
  a name in each 64 bytes of the name list) reads the same.
- A polydisperse 2D frame (one type, diameters 0.8 .. 1.2, Lz = 1 as HOOMD writes 2D
  boxes) keeps each particle's diameter; its packing fraction is theirs.
- hsbd's own GSD output (a rods mixture on a ring, disks between walls) restarts a run
  at its last frame with the exact float64 positions (log/hsbd/position).
- A restated value that disagrees, and files that cannot be read, exit 2 with a message
  naming both values (or what is wrong) and leave no run directory.
Usage: test_gsd_input.py path/to/hsbd
"""
import json
import os
import struct
import subprocess
import sys
import tempfile
import warnings

import numpy as np

warnings.simplefilter("ignore", DeprecationWarning)
import gsd.fl  # noqa: E402
import gsd.hoomd  # noqa: E402

HSBD = os.path.abspath(sys.argv[1])
QUIET = ["--quiet", "--set", "run.t_equil=0", "--set", "run.dt=1e-3", "--set", "run.t_total=0.02",
         "--set", "sample.blocks=2", "--set", "output.trajectory=xyz",
         "--set", "output.trajectory_every=0.001"]
failures = []


def check(cond, what):
    if not cond:
        failures.append(what)
        print("FAIL:", what, file=sys.stderr)


def run(config, out, *sets):
    args = [HSBD, "run", config, "--out", out] + QUIET
    for s in sets:
        args += ["--set", s]
    p = subprocess.run(args, capture_output=True, text=True)
    return p.returncode, p.stderr


def parameters(out):
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f)["parameters"]


def first_frame(out):
    """names, positions (n x 3) and radii of the first frame of out/trajectory.xyz"""
    with open(os.path.join(out, "trajectory.xyz")) as f:
        n = int(f.readline())
        f.readline()
        rows = [f.readline().split() for _ in range(n)]
    return ([r[0] for r in rows], np.array([[float(v) for v in r[1:4]] for r in rows]),
            np.array([float(r[4]) for r in rows]))


def write(path, frames):
    with gsd.hoomd.open(path, "wb") as f:
        for s in frames:
            f.append(s)


def frame(box, pos, types, typeid, diameter, dim=3, orientation=None):
    s = gsd.hoomd.Snapshot()
    s.configuration.box = box
    s.configuration.dimensions = dim
    s.particles.N = len(pos)
    s.particles.types = types
    s.particles.typeid = np.asarray(typeid, dtype=np.uint32)
    s.particles.diameter = np.asarray(diameter, dtype=np.float32)
    s.particles.position = np.asarray(pos, dtype=np.float32)
    if orientation is not None:
        s.particles.orientation = orientation
    return s


def refused(name, config, texts, *sets):
    rc, err = run(config, name, *sets)
    check(rc == 2, f"{name}: exit {rc}, expected 2 ({err.strip()})")
    for t in texts:
        check(t in err, f"{name}: the message lacks '{t}': {err.strip()}")
    check(not os.path.exists(name), f"{name}: a run directory was made")


with tempfile.TemporaryDirectory() as tmp:
    os.chdir(tmp)
    with open("spheres.ini", "w") as f:
        f.write("[system]\nmodel = spheres\n[init]\npositions = mix.gsd\n")

    # a binary mixture on a simple cubic lattice (spacing 2 in a box of 12), two frames
    grid = np.array([[i, j, k] for i in range(6) for j in range(6) for k in range(6)]) * 2.0 - 5
    typeid = np.arange(len(grid)) % 2
    diameter = np.where(typeid == 0, 1.0, 1.4)
    quaternions = np.tile([1.0, 0, 0, 0], (len(grid), 1))
    shifted = grid + [0.3, -0.2, 0.1]
    write("mix.gsd", [frame([12, 12, 12, 0, 0, 0], grid, ["A", "B", "C"], typeid, diameter,
                            orientation=quaternions),
                      frame([12, 12, 12, 0, 0, 0], shifted, ["A", "B", "C"], typeid, diameter,
                            orientation=quaternions)])
    rc, err = run("spheres.ini", "mix", "system.D=1e-12")
    check(rc == 0, f"the mixture from gsd did not run: {err}")
    if rc == 0:
        p = parameters("mix")
        check(p["system"]["N"] == 216 and p["system"]["box"] == "12 12 12" and
              p["system"]["dimension"] == 3, f"N, box, dimension: {p['system']}")
        check(p["species"]["names"] == "A B" and p["species"]["count"] == "108 108",
              f"species: {p['species']}")
        check(abs(float(p["species"]["sigma"].split()[1]) - 1.4) < 1e-6,
              f"diameters: {p['species']['sigma']}")
        names, x, radius = first_frame("mix")
        check(names == ["AB"[t] for t in typeid], "the particles' types")
        check(np.abs(x - (shifted + 6)).max() < 1e-5,
              f"positions of the last frame: off by {np.abs(x - (shifted + 6)).max():.3g}")
        check(np.abs(radius - diameter / 2).max() < 1e-6, "radii")
    rc, err = run("spheres.ini", "mix0", "init.frame=0", "system.D=1e-12")
    check(rc == 0 and np.abs(first_frame("mix0")[1] - (grid + 6)).max() < 1e-5,
          f"init.frame = 0: {err}")
    with open("mix.gsd", "rb") as f:  # GSD 1.0: version 1.0, the names in 64-byte slots
        data = bytearray(f.read())
    names_at, slots = struct.unpack("<QQ", data[24:40])
    names = [n for n in bytes(data[names_at:names_at + 64 * slots]).split(b"\0") if n]
    data[names_at:names_at + 64 * slots] = b"".join(n.ljust(64, b"\0") for n in names).ljust(
        64 * slots, b"\0")
    data[44:48] = struct.pack("<I", 1 << 16)
    with open("mix1.gsd", "wb") as f:
        f.write(data)
    rc, err = run("spheres.ini", "mix1", "init.positions=mix1.gsd", "system.D=1e-12")
    check(rc == 0 and np.abs(first_frame("mix1")[1] - (shifted + 6)).max() < 1e-5,
          f"the GSD 1 layout: {err}")
    # restated values: the same (to float32) runs, with the configuration's exact value
    rc, err = run("spheres.ini", "mix-restated", "system.N=216", "system.box=12",
                  "species.names=A,B", "species.count=108,108", "species.sigma=1,1.4",
                  "species.D=1e-12,1e-12")
    check(rc == 0 and parameters("mix-restated")["species"]["sigma"] == "1,1.4",
          f"restated agreeing values: {err}")

    # polydisperse disks: each particle's diameter
    rng = np.random.default_rng(5)
    square = np.array([[i, j, 0] for i in range(10) for j in range(10)]) * 2.0 - [9, 9, 0]
    poly = rng.uniform(0.8, 1.2, len(square)).astype(np.float32)
    write("poly.gsd", [frame([20, 20, 1, 0, 0, 0], square, ["P"], np.zeros(100), poly, dim=2)])
    rc, err = run("spheres.ini", "poly", "init.positions=poly.gsd", "system.D=1e-12")
    check(rc == 0, f"polydisperse disks did not run: {err}")
    if rc == 0:
        with open("poly/summary.json") as f:
            s = json.load(f)
        phi = np.sum(np.pi * poly.astype(float) ** 2 / 4) / 400
        check(s["parameters"]["system"]["dimension"] == 2 and abs(s["packing_fraction"] - phi) <
              1e-6 * phi, f"2D, packing fraction {s['packing_fraction']} (the file's: {phi})")
        check(np.abs(first_frame("poly")[2] - poly / 2).max() < 1e-6, "polydisperse radii")

    # hsbd's own output restarts: rods of two species on a ring, disks between walls
    with open("rods.ini", "w") as f:
        f.write("[system]\nN = 30\nL = 30\n[species]\nnames = long short\n"
                "count = 10 20\nsigma = 0.9 0.4\nD = 1 1\n[field]\ntype = none\n")
    with open("disks.ini", "w") as f:
        f.write("[system]\nmodel = spheres\ndimension = 2\nN = 50\nbox = 10 8\nD = 1\n"
                "boundary = periodic walls\n")
    for model, config in (("rods", "rods.ini"), ("disks", "disks.ini")):
        rc, err = run(config, f"{model}-gsd", "output.trajectory=gsd", "run.t_total=0.05")
        check(rc == 0, f"{model}: no GSD output: {err}")
        with gsd.hoomd.open(f"{model}-gsd/trajectory.gsd", "rb") as f:
            last = f[-1]
            box = last.configuration.box
        with gsd.fl.open(f"{model}-gsd/trajectory.gsd", "rb") as f:
            exact = f.read_chunk(frame=f.nframes - 1, name="log/hsbd/position")
        with open("restart.ini", "w") as f:  # the walls are not in a GSD file
            f.write(f"[system]\nmodel = {'rods' if model == 'rods' else 'spheres'}\n"
                    f"D = 1e-12\n{'boundary = periodic walls' if model == 'disks' else ''}\n"
                    f"[init]\npositions = {model}-gsd/trajectory.gsd\n")
        rc, err = run("restart.ini", f"{model}-restart")
        check(rc == 0, f"{model}: hsbd's GSD output did not restart a run: {err}")
        if rc != 0:
            continue
        p = parameters(f"{model}-restart")
        names, x, _ = first_frame(f"{model}-restart")
        dim = 1 if model == "rods" else 2
        want = exact[:, :dim] + 0.5 * np.asarray(box[:dim])
        if model == "rods":  # the ring's order may start elsewhere: compare sorted by x
            want = np.sort(want % box[0], axis=0)
            x = np.sort(x, axis=0)
            check(p["system"]["N"] == 30 and p["system"]["L"] == 30 and
                  p["species"]["names"] == "long short" and p["species"]["count"] == "10 20",
                  f"rods restarted: {p['system']}, {p['species']}")
        else:
            check(p["system"]["N"] == 50 and p["system"]["box"] == "10 8", f"disks: {p['system']}")
        check(np.abs(x[:, :dim] - want).max() < 1e-6,
              f"{model}: restarted off the file's float64 positions by "
              f"{np.abs(x[:, :dim] - want).max():.3g}")

    # restated values that disagree: both values and where each came from
    where = "command line (--set)"
    refused("bad-n", "spheres.ini", [where, "system.N = 200", "N = 216"], "system.N=200")
    refused("bad-box", "spheres.ini", [where, "system.box = '10'", "the box 12 x 12 x 12"],
            "system.box=10")
    refused("bad-names", "spheres.ini", [where, "species.names = 'B,A'", "the types 'A B'"],
            "species.names=B,A", "species.D=1,1")
    refused("bad-sigma", "spheres.ini", [where, "species.sigma = '1,1.5'", "1.39999998"],
            "species.sigma=1,1.5")
    refused("bad-dimension", "spheres.ini", [where, "system.dimension = 2", "3 dimensions"],
            "system.dimension=2")
    write("plane.gsd", [frame([10, 10, 0, 0, 0, 0], [[0, 0, 0], [2, 1, 0]], ["R"], [0, 0],
                              [0.5, 0.5], dim=2)])
    refused("bad-rods", "rods.ini", ["plane.gsd", "particle 1 has y = 1", "rods lie on the x axis"],
            "system.N=2", "system.L=10", "species.names=R", "species.count=2",
            "species.sigma=0.5", "species.D=1", "init.positions=plane.gsd")

    # files that cannot be read
    with gsd.fl.open("nopos.gsd", "wb", application="test", schema="hoomd",
                     schema_version=[1, 4]) as f:
        f.write_chunk(name="particles/N", data=np.array([3], dtype=np.uint32))
        f.end_frame()
    refused("bad-nopos", "spheres.ini", ["nopos.gsd", "no particles/position"],
            "init.positions=nopos.gsd")
    write("tilted.gsd", [frame([12, 12, 12, 0.5, 0, 0], grid, ["A"], np.zeros(216), np.ones(216))])
    refused("bad-tilted", "spheres.ini", ["tilted.gsd", "tilted (triclinic) box"],
            "init.positions=tilted.gsd")
    with open("mix.gsd", "rb") as f:
        data = f.read()
    with open("cut.gsd", "wb") as f:
        f.write(data[:len(data) - 200])
    refused("bad-cut", "spheres.ini", ["cut.gsd", "cut short"], "init.positions=cut.gsd")
    refused("bad-frame", "spheres.ini", ["mix.gsd", "init.frame = 2 is not a frame"],
            "init.frame=2")

if failures:
    print(f"test_gsd_input: {len(failures)} failures", file=sys.stderr)
    sys.exit(1)
print("test_gsd_input: gsd's and hsbd's files start runs; disagreements and bad files refused")

#!/usr/bin/python3
"""GSD trajectories read back by Debian's gsd (2.7, the HOOMD reader) and MDAnalysis.

Each case runs twice with the same seed, once writing extended XYZ and once GSD (the
dynamics do not depend on the format). Every frame of the GSD file must carry the XYZ
frame's step and time, the box (rods: L x 1, 2D; spheres: their box, Lz = 0 in 2D),
N, the types, typeid and diameter of every particle, the float32 positions equal to the
float64 log/hsbd/position rounded to float32, those equal to the XYZ positions shifted
by half the box (within the XYZ's 10 digits), and the images (spheres: the XYZ's image
columns; rods: (x_unwrapped - x) / L); active particles' orientation quaternions equal
the XYZ's (OVITO's x y z w order there) and turn the body's x axis into the XYZ's unit
vector e. MDAnalysis must see the same frames, positions
and boxes. Usage: test_gsd.py path/to/hsbd
"""
import os
import subprocess
import sys
import tempfile
import warnings

import numpy as np

warnings.simplefilter("ignore", DeprecationWarning)
import gsd.hoomd  # noqa: E402
import MDAnalysis  # noqa: E402

HSBD = os.path.abspath(sys.argv[1])
failures = []


def check(cond, what):
    if not cond:
        failures.append(what)
        print("FAIL:", what, file=sys.stderr)


CASES = {
    "rods-mixture-ring": [
        "--set", "system.N=60", "--set", "system.L=60", "--set", "field.type=cosine",
        "--set", "field.amplitude=3", "--set", "species.names=long,short",
        "--set", "species.count=20,40", "--set", "species.sigma=0.9,0.4",
        "--set", "species.D=0.5,1"],
    "rods-walls": [
        "--set", "system.N=30", "--set", "system.L=40", "--set", "system.sigma=0.5",
        "--set", "system.boundary=walls", "--set", "field.type=tilt",
        "--set", "field.force=0.5"],
    "spheres-3d-mixture": [
        "--set", "system.model=spheres", "--set", "system.N=300",
        "--set", "system.packing_fraction=0.3", "--set", "species.names=A,B",
        "--set", "species.fraction=0.5,0.5", "--set", "species.sigma=1,1.3",
        "--set", "species.D=1,0.7", "--set", "run.dt=1e-3"],
    "disks-active": [
        "--set", "system.model=spheres", "--set", "system.dimension=2", "--set", "system.N=200",
        "--set", "system.packing_fraction=0.4", "--set", "active.v0=5", "--set", "run.dt=1e-3"],
    "spheres-3d-active": [
        "--set", "system.model=spheres", "--set", "system.N=200",
        "--set", "system.packing_fraction=0.3", "--set", "active.v0=5", "--set", "run.dt=1e-3"],
    "disks-polydisperse": [
        "--set", "system.model=spheres", "--set", "system.dimension=2", "--set", "system.N=200",
        "--set", "system.packing_fraction=0.4", "--set", "species.polydispersity=0.1",
        "--set", "run.dt=1e-3"],
}
COMMON = ["--set", "run.t_equil=0.05", "--set", "run.t_total=0.5", "--set", "system.seed=5",
          "--set", "output.trajectory_every=0.02", "--quiet"]


def read_xyz(path):
    """Frames of an extended XYZ file: header dict and rows of words."""
    frames = []
    with open(path) as f:
        lines = f.read().split("\n")
    i = 0
    while i < len(lines) and lines[i].strip():
        n = int(lines[i])
        head = {}
        for word in lines[i + 1].replace('"', "").split():
            if "=" in word:
                k, v = word.split("=", 1)
                head[k] = v
        lat = lines[i + 1].split('Lattice="')[1].split('"')[0].split()
        head["box"] = [float(lat[0]), float(lat[4]), float(lat[8])]
        rows = [ln.split() for ln in lines[i + 2:i + 2 + n]]
        frames.append((head, rows))
        i += 2 + n
    return frames


def run(name, settings, fmt, d):
    out = os.path.join(d, f"{name}-{fmt}")
    cmd = [HSBD, "run", "--defaults", "--out", out, *COMMON, *settings, "--set", f"output.trajectory={fmt}"]
    subprocess.run(cmd, check=True)
    return os.path.join(out, f"trajectory.{fmt}")


def compare(name, xyz_path, gsd_path):
    rods = "rods" in name
    xyz = read_xyz(xyz_path)
    traj = gsd.hoomd.open(gsd_path, "rb")
    check(len(traj) == len(xyz) and len(xyz) == 25, f"{name}: {len(traj)} GSD frames, {len(xyz)} XYZ")
    worst_pos, worst_32 = 0.0, 0.0
    for k, (frame, (head, rows)) in enumerate(zip(traj, xyz)):
        n = len(rows)
        names = [r[0] for r in rows]
        xw = np.array([[float(v) for v in r[1:4]] for r in rows])
        radius = np.array([float(r[4]) for r in rows])
        box = head["box"]
        dim = 3 if "3d" in name else 2
        lx, ly, lz = (box[0], 1.0, 0.0) if rods else (box[0], box[1], box[2] if dim == 3 else 0.0)
        check(frame.configuration.step == int(head["Step"]), f"{name} frame {k}: step")
        check(frame.log["hsbd/time"][0] == float(head["Time"]), f"{name} frame {k}: time")
        check(frame.configuration.dimensions == dim, f"{name} frame {k}: dimensions")
        check(np.array_equal(frame.configuration.box, np.float32([lx, ly, lz, 0, 0, 0])),
              f"{name} frame {k}: box {frame.configuration.box}")
        check(frame.particles.N == n, f"{name} frame {k}: N")
        types = list(frame.particles.types)
        check([types[t] for t in frame.particles.typeid] == names, f"{name} frame {k}: types")
        # float32 of the diameter; the XYZ radius has 10 digits
        d32 = frame.particles.diameter
        check(np.all(np.abs(d32 - 2 * radius) <= 0.5 * np.spacing(d32) + 1e-9 * 2 * radius),
              f"{name} frame {k}: diameters")
        exact = frame.log["hsbd/position"]
        pos = frame.particles.position
        check(pos.dtype == np.float32 and exact.dtype == np.float64, f"{name}: dtypes")
        check(np.array_equal(pos, exact.astype(np.float32)), f"{name} frame {k}: float32 rounding")
        ulp = np.spacing(np.abs(exact).astype(np.float32))
        worst_32 = max(worst_32, float(np.max(np.abs(pos - exact) / np.where(ulp > 0, ulp, 1))))
        half = np.array([lx, 0.0 if rods else ly, lz]) / 2  # rods lie at y = 0
        diff = np.max(np.abs(exact + half - xw))
        worst_pos = max(worst_pos, diff)
        check(diff <= 1e-9 * max(lx, ly, lz), f"{name} frame {k}: positions differ by {diff}")
        check(np.all(np.abs(exact) <= np.array([lx, ly, lz]) / 2 + 1e-12), f"{name} frame {k}: not centred")
        if rods:
            xu = np.array([float(r[5]) for r in rows])
            image = np.rint((xu - xw[:, 0]) / lx)
            check(np.array_equal(frame.particles.image[:, 0], image) and
                  not frame.particles.image[:, 1:].any(), f"{name} frame {k}: images")
        else:
            image = np.array([[int(v) for v in r[5:8]] for r in rows])
            check(np.array_equal(frame.particles.image, image), f"{name} frame {k}: images")
        if "active" in name:  # quaternions (w, x, y, z) that take the body's x axis to e
            check("orientation:R:4:dipoles:R:3" in head["Properties"], f"{name}: XYZ columns")
            q_xyz = np.array([[float(v) for v in r[9:13]] for r in rows])  # x y z w (OVITO)
            e = np.array([[float(v) for v in r[13:16]] for r in rows])
            q = frame.particles.orientation.astype(np.float64)
            check(np.allclose(q, q_xyz[:, [3, 0, 1, 2]], atol=1e-7), f"{name} frame {k}: GSD and XYZ quaternions")
            w, x, y, z = q.T
            rotated = np.stack([w * w + x * x - y * y - z * z, 2 * (x * y + w * z), 2 * (x * z - w * y)], 1)
            check(np.allclose(rotated, e, atol=1e-6), f"{name} frame {k}: q x q* is not e")
            check(np.allclose(np.linalg.norm(e, axis=1), 1, atol=1e-9) and (dim == 3 or not e[:, 2].any()),
                  f"{name} frame {k}: e is not a unit vector (in the plane)")
        else:
            check(frame.particles.orientation is None or np.all(frame.particles.orientation == [1, 0, 0, 0]),
                  f"{name} frame {k}: an orientation chunk of passive particles")
    # MDAnalysis: the same frames, positions and boxes
    u = MDAnalysis.Universe(gsd_path)
    check(u.trajectory.n_frames == len(traj) and u.atoms.n_atoms == traj[0].particles.N,
          f"{name}: MDAnalysis sees {u.trajectory.n_frames} frames of {u.atoms.n_atoms}")
    for k, ts in enumerate(u.trajectory):
        f = traj[k]
        check(np.array_equal(ts.positions, f.particles.position), f"{name} MDAnalysis frame {k}: positions")
        check(np.allclose(ts.dimensions[:3], f.configuration.box[:3]), f"{name} MDAnalysis frame {k}: box")
    check(list(u.atoms.types) == [f.particles.types[t] for t in traj[0].particles.typeid],
          f"{name}: MDAnalysis types")
    print(f"  {name}: {len(traj)} frames of {traj[0].particles.N}, positions within {worst_pos:.2g} "
          f"of the XYZ, float32 within {worst_32:.2g} ulp of the doubles")


with tempfile.TemporaryDirectory() as d:
    for name, settings in CASES.items():
        xyz = run(name, settings, "xyz", d)
        g = run(name, settings, "gsd", d)
        compare(name, xyz, g)

print(f"test_gsd: {len(failures)} failures")
sys.exit(1 if failures else 0)

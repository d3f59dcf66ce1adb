"""Brownian dynamics of hard rods, disks and spheres with an exact hard core.

hsbd simulates hard rods on a line (Brownian cluster dynamics) and hard disks and spheres
(event-driven Brownian dynamics), in fields, between walls, as mixtures. This package is
its Python interface (docs/python.md):

- ``Simulation(config, **sections)``: a run held in memory and stepped from Python, its
  state as numpy views and its observers' results so far;
- ``run(config, out=DIR, **sections)``: a whole run written to a directory exactly as the
  command ``hsbd run`` writes it; ``load(DIR)`` reads such a directory back (summary,
  tables as named columns, the blocks behind the error bars); ``plot(DIR)`` (or
  ``python3 -m hsbd.plot DIR``) draws it;
- exact theory: ``percus``, ``tonks_pressure``, ``tonks_contact``, ``single_file_msd``,
  ``hs_z_cs``, ``hs_contact_cs``, ``hd_z_henderson``, ``hd_contact_henderson``.

Configurations use the keys of docs/config.md: a file, a dict (``{"system.N": 50}`` or
``{"system": {"N": 50}}``) and sections as keywords (``system={"N": 50}``). Bad input
raises ``InputError`` (a ``ValueError``) with the message ``hsbd run`` prints.
"""
import json as _json
import math as _math

from . import _hsbd
from ._hsbd import (Error, InputError, hd_contact_henderson, hd_z_henderson, hs_contact_cs,
                    hs_z_cs, percus, run, single_file_msd, tonks_contact, tonks_pressure,
                    version)
from ._load import Run, Table, load

#: The package's version: that of the C library it is built with (CMakeLists.txt's
#: project version, the one ``hsbd --version`` prints).
__version__ = version().split()[0]

__all__ = ["Simulation", "Run", "Table", "load", "plot", "run", "Error", "InputError",
           "percus", "tonks_pressure", "tonks_contact", "single_file_msd", "hs_z_cs",
           "hs_contact_cs", "hd_z_henderson", "hd_contact_henderson", "version",
           "__version__"]


class Simulation(_hsbd.Simulation):
    """A run held in memory and advanced from Python.

    ``Simulation(config=None, /, **sections)`` builds the model, its initial state and its
    observers exactly as ``hsbd run`` does, from a configuration file (a path), a dict of
    keys (``{"system.N": 50}`` or ``{"system": {"N": 50}}``) and/or sections as keywords
    (``system={"N": 50}``, applied after the file). It writes no files (no trajectory,
    currents or checkpoints; ``hsbd.run`` writes a run directory).

    The run goes through equilibration (``run.t_equil``, no sampling), then production
    (``run.t_total``, the observers sampling on their schedule): ``step(n)`` and ``run(t)``
    advance it, ``stage`` says where it is. The state (``positions``, ``images``,
    ``diameters``, ``species``) is read-only numpy views that follow the steps; copy them
    to keep them. The observers' results so far: ``density``, ``contact`` (rods),
    ``msd``, ``fs``, ``d_long``, ``gr``, ``gr_pairs``, ``z``, ``walls`` and ``summary``
    (everything summary.json would hold now). Errors come from block averages, as in the
    tables of ``hsbd run``.

    Several simulations live side by side in one process; stepping releases the GIL.
    """

    def __init__(self, config=None, /, **sections):
        """config: a configuration file's path, a dict of keys, or None (the defaults);
        sections: dicts of keys by section, applied after config (run={"t_total": 5})."""
        super().__init__(config, **sections)

    def run(self, t=None):
        """Advance the simulated time by t (None: to the end of the run).

        Equilibration steps are of ``run.dt_equil`` (rods; ``run.dt`` when unset), the
        production's of ``run.dt``: the steps are counted in each stage so that ``time``
        grows by t (to the nearest step), stopping early when the run ends.
        """
        if t is None:
            while self.stage != "done":
                self.step(1 << 30)
            return
        t = float(t)
        if not (t >= 0 and _math.isfinite(t)):
            raise InputError(f"run(t): t = {t!r}; allowed: finite and >= 0 (None: to the end)")
        plan = self.schedule
        target = self.time + t
        while self.stage != "done":
            equilibrating = self.stage == "equilibrating"
            dt = plan["dt_equil"] if equilibrating else plan["dt"]
            n = round((target - self.time) / dt)
            if n < 1:
                break
            if equilibrating and plan["equilibration_steps"]:
                left = plan["equilibration_steps"] - self.steps[0] % plan["equilibration_steps"]
                n = min(n, left)
            self.step(n)

    def summary(self):
        """The results so far as the dict that summary.json would hold now (the model's
        and every observer's lines: e.g. Z_virial, D_long, walls, contacts, clusters,
        drift; and the parameters); ``completed`` once the run is done."""
        return _json.loads(self.summary_json())

    def z(self):
        """Disks and spheres in a periodic box without a field: the compressibility factor
        Z = beta P / rho from the collisional virial so far, as (Z, err) (summary.json's
        Z_virial). Between walls see ``walls()``; rods: ``tonks_pressure``."""
        s = self.summary()
        if "Z_virial" not in s:
            raise Error("z(): the virial pressure is measured for disks and spheres in a "
                        "periodic box without a field (walls: see walls())")
        return s["Z_virial"], s["Z_virial_err"]

    def walls(self):
        """The walls' results so far. Disks and spheres: a list with one dict per wall
        ({'axis', 'side', 'contact_density', 'contact_density_err',
        'contact_density_profile', ..., 'species': [...]}: the density at contact from the
        wall's impulses (contact theorem: the pressure on it is kT times this) and from the
        profile). Rods: {'left': (value, err), 'right': (value, err)}, the density at
        contact with each wall (kT times it is the force on the wall)."""
        s = self.summary()
        if self.model == "rods":
            c = s.get("contacts", {})
            if s["parameters"]["system"]["boundary"] != "walls":
                raise Error("walls(): this run has no walls (system.boundary)")
            return {"left": (c["wall_left"], c["wall_left_err"]),
                    "right": (c["wall_right"], c["wall_right_err"])}
        if "walls" not in s:
            raise Error("walls(): this run has no walls (system.boundary)")
        return s["walls"]

    def __repr__(self):
        return (f"<hsbd.Simulation {self.model}: N = {len(self.diameters)}, box {self.box}, "
                f"{self.stage}, steps {self.steps}, t = {self.time:g}>")


# The C type's methods and properties are the class's own (help() and the API reference
# list them with the class's).
for _name, _member in vars(_hsbd.Simulation).items():
    if not _name.startswith("_") and _name not in vars(Simulation):
        setattr(Simulation, _name, _member)
del _name, _member


def __getattr__(name):
    # hsbd.plot, the plotting module (callable: hsbd.plot(DIR)), imported when first used
    # so that `import hsbd` needs no matplotlib and `python3 -m hsbd.plot` runs it fresh
    if name == "plot":
        import importlib
        return importlib.import_module(".plot", __name__)
    raise AttributeError(f"module 'hsbd' has no attribute {name!r}")

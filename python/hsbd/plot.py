"""Figures of hsbd runs: ``hsbd.plot(DIR)`` or ``python3 -m hsbd.plot DIR [DIR ...]``.

One PNG per run directory (default DIR/plot.png), whatever the run:

- rods: the density profile with error bars (per phase of a periodic drive when sampled
  so), the ideal-gas profile exp(-U/kT) of the same field, Percus' exact profile for rods
  in a cosine field (computed, or from ``theory=`` a table of ``hsbd theory percus``), the
  density at contact with each wall; the contact density; the MSD per species with free
  diffusion and the single-file law; the particle current over time when it was written;
  the drift, trap and current results in the title;
- disks and spheres: g(r) per species pair with its contact value and the equation of
  state's; the density profile along each axis with walls or the field, per species, with
  the density at contact with each wall (from the wall's impulses); S(k) when sampled;
  the MSD per species with 2dDt and the long-time 2dD_L t; F_s(k, t);
- active disks and spheres: the last frame coloured by each particle's orientation (3D:
  a slab through the middle), the distribution of the local packing fraction with its
  peaks (``local_density_peaks``), the MSD against the exact law of free active Brownian
  particles and the orientation correlation against exp(-(d-1) D_r t).

``hsbd.plot`` is this module and can be called: ``hsbd.plot(DIR)`` is
``hsbd.plot.plot(DIR)``. Needs matplotlib (Debian's python3-matplotlib); draws without
pyplot, so it changes no backend of the caller's.
"""
import argparse
import math
import os
import re
import sys
import types

import numpy as np

from ._load import Run, load

__all__ = ["plot", "main", "local_density_peaks"]


# ---- parameters of a run ---------------------------------------------------------------

class _Params:
    """The run's parameters by 'section.key' (summary.json's, else a table's header)."""

    def __init__(self, run):
        self.p = {f"{sec}.{k}": v for sec, keys in run.parameters.items()
                  for k, v in keys.items()}
        if not self.p:
            for table in list(run.tables.values()) + list(run.blocks.values()):
                self.p = dict(table.params)
                break

    def get(self, key, default=None):
        v = self.p.get(key, default)
        return default if v == "" else v

    def num(self, key, default=math.nan):
        try:
            return float(self.get(key, default))
        except (TypeError, ValueError):
            return default

    def list(self, key):
        v = self.get(key, "")
        return list(v) if isinstance(v, list) else str(v).replace(",", " ").split()

    def nums(self, key):
        return [float(v) for v in self.list(key)]


def _field_terms(p):
    return [t for t in str(p.get("field.type", "none")).split("+") if t and t != "none"]


def _describe_field(p):
    words = []
    for t in _field_terms(p):
        if t == "cosine":
            words.append(f"cosine U0 = {p.num('field.amplitude'):g} kT, wavelength "
                         f"{p.num('field.wavelength'):g}")
        elif t == "tilt":
            words.append(f"tilt force {p.num('field.force'):g}")
        elif t == "harmonic":
            words.append(f"harmonic k = {p.num('field.stiffness'):g} about "
                         f"{p.num('field.center'):g}")
        elif t == "table":
            words.append(f"tabulated {p.get('field.table_kind', 'potential')} "
                         f"({os.path.basename(str(p.get('field.table', '')))})")
        else:
            words.append(t)
    drive = p.get("drive.parameter", "none")
    if drive and drive != "none":
        words.append(f"driven {drive}")
    return " + ".join(words) if words else "no field"


def _value(s, key, digits=4):
    """'key = v ± e' from a summary, or None."""
    v, e = s.get(key), s.get(key + "_err")
    if v is None:
        return None
    return f"{key} = {v:.{digits}g}" + (f" ± {e:.2g}" if e is not None else "")


# ---- rods ------------------------------------------------------------------------------

def _ideal_gas(p, period, n, length):
    """exp(-U/kT) folded into the profile's period and normalised to N/L, or None and why."""
    terms = _field_terms(p)
    walls = p.get("system.boundary") == "walls"
    if p.get("drive.parameter", "none") not in ("none", None):
        return None, "driven field: no equilibrium reference"
    if "tilt" in terms and not walls:
        return None, "tilted ring: a driven steady state, no Boltzmann reference"
    if "table" in terms:
        return None, "tabulated field: no ideal-gas line drawn"
    if not terms:
        return None, None
    bins = 400
    xf = (np.arange(bins) + 0.5) * period / bins
    x = xf[None, :] + period * np.arange(math.ceil(length / period - 1e-9))[:, None]
    u = np.zeros_like(x)
    if "cosine" in terms:
        u += 0.5 * p.num("field.amplitude") * np.cos(2 * math.pi * x / p.num("field.wavelength"))
    if "tilt" in terms:
        u -= p.num("field.force") * x
    if "harmonic" in terms:
        u += 0.5 * p.num("field.stiffness") * (x - p.num("field.center")) ** 2
    w = np.where(x < length, np.exp(-(u - u.min()) / p.num("system.kT", 1.0)), 0.0)
    prof = w.sum(axis=0)
    prof *= (n / length) / prof.mean()
    return (xf, prof), None


def _percus(p, names):
    """Percus' exact profile when the run is the case it solves: one species of hard rods
    on a ring in a cosine field (no other term, no pair force, no drive), else None."""
    if (names or _field_terms(p) != ["cosine"] or p.get("system.boundary") == "walls"
            or p.get("pair.type", "none") != "none" or p.get("system.hard_core") == "off"
            or p.get("drive.parameter", "none") != "none"
            or p.get("system.contact_rule", "reflect") != "reflect"):
        return None
    from . import percus
    kt = p.num("system.kT", 1.0)
    x, rho, rho2 = percus(sigma=p.num("system.sigma"), rho=p.num("system.N") / p.num("system.L"),
                          amplitude=p.num("field.amplitude") / kt,
                          wavelength=p.num("field.wavelength"), points=1000)
    period = p.num("sample.period", p.num("system.L"))
    reps = max(1, round(period / p.num("field.wavelength")))
    w = p.num("field.wavelength")
    return (np.concatenate([x + k * w for k in range(reps)]), np.tile(rho, reps),
            np.tile(rho2, reps))


def _rods(run, fig, theory):
    p, s = _Params(run), run.summary
    n, length = p.num("system.N"), p.num("system.L")
    names = p.list("species.names")
    sigmas = p.nums("species.sigma") if names else [p.num("system.sigma")]
    diffs = p.nums("species.D") if names else [p.num("system.D")]
    counts = p.nums("species.count") if names else [n]
    walls = p.get("system.boundary") == "walls"
    current = run.tables.get("current")
    panels = ["density"] + (["contact"] if "contact" in run else []) + \
             (["msd"] if "msd" in run else []) + \
             (["current"] if current is not None and len(current.data) else [])
    ax = dict(zip(panels, _axes(fig, len(panels))))
    rods = (", ".join(f"{c:g} {nm} (sigma {sg:g}, D {d:g})"
                      for nm, c, sg, d in zip(names, counts, sigmas, diffs))
            if names else f"sigma = {sigmas[0]:g}, D = {diffs[0]:g}")
    results = [v for v in (_value(s, k) for k in (
        "mean_velocity", "particle_current", "d_eff_tagged", "trap_offset", "trap_variance",
        "mean_cluster_size")) if v]
    fig.suptitle(f"hard rods: N = {n:g} on {'a line between walls' if walls else 'a ring'} of "
                 f"L = {length:g} (mean density {n / length:.3g}), {rods}\n"
                 f"field: {_describe_field(p)}; kT = {p.num('system.kT', 1.0):g}"
                 + ("\n" + "; ".join(results) if results else ""), fontsize=9)

    a = ax["density"]
    exact = None
    if theory is not None:
        t = theory if hasattr(theory, "names") else _theory_table(theory)
        exact = (t.data[:, 0], t.data[:, 1], t.data[:, 2])
    else:
        exact = _percus(p, names)
    if exact is not None:
        a.plot(exact[0], exact[1], "k-", lw=1.2, label="Percus (exact)", zorder=4)
    if "density" in run:
        d = run["density"]
        many = len(d.data) > 100
        a.errorbar(d["x"], d["rho"], d["rho_err"], fmt="o-" if many else "o",
                   ms=2 if many else 2.5, lw=0.6, label="hsbd (BCD), error bars 1 s.e.",
                   zorder=3)
        period = p.num("sample.period", length)
        period = period if period > 0 else length
        ideal, why = _ideal_gas(p, period, n, length)
        if ideal is not None:
            a.plot(ideal[0], ideal[1], "-.", color="tab:red", lw=1.1, zorder=4,
                   label="ideal gas exp(-U/kT) (no hard core)")
        elif why:
            a.plot([], [], " ", label=why)
        phases = run.tables.get("density_phases")
        if phases is not None:
            for k, name in enumerate(c for c in phases.names if re.fullmatch(r"rho_\d+", c)):
                y = phases[name]
                if np.isfinite(y).any():
                    a.plot(phases["x"], y, "-", lw=0.8, alpha=0.8,
                           label=f"phase {name[4:]} of the drive (stroboscopic)")
        if walls and "contacts" in s:
            c = s["contacts"]
            a.errorbar([sigmas[0] / 2, length - sigmas[0] / 2],
                       [c.get("wall_left", math.nan), c.get("wall_right", math.nan)],
                       [c.get("wall_left_err", 0), c.get("wall_right_err", 0)], fmt="D",
                       color="k", mfc="none", ms=6, zorder=5,
                       label="density at contact with each wall (its force / kT)")
        a.set_xlabel("x" + (f" folded into one period {period:g}" if period < length else ""))
    a.set_ylabel(r"density $\rho(x)$  [rods per length]")
    a.set_title("density profile", fontsize=9)
    a.legend(fontsize=7)

    if "contact" in ax:
        c, cp = run["contact"], run["contact"].params
        window = p.num("sample.contact_width")
        default = ("extrapolated" if cp.get("system.contact_rule", "reflect") == "reflect"
                   else "contact theorem")
        b = ax["contact"]
        if "rho2_window" in c:
            b.errorbar(c["x"], c["rho2_window"], c["rho2_window_err"], fmt="s", ms=2, lw=0.5,
                       color="0.65", label=f"gaps < {window:.3g} (window, biased)")
        b.errorbar(c["x"], c["rho2"], c["rho2_err"], fmt="o-" if len(c.data) > 100 else "o",
                   ms=2, lw=0.6, label=f"{default} to zero gap (default)")
        if exact is not None:
            b.plot(exact[0], exact[2], "k-", lw=1, label="Percus (exact)")
        b.set_xlabel("x of the left rod")
        b.set_ylabel(r"$\rho_2(x, x+\sigma)$  [per length$^2$]")
        b.set_title("contact density", fontsize=9)
        b.legend(fontsize=7)

    if "msd" in ax:
        m, msd = ax["msd"], run["msd"]
        t = msd["t"]
        for k in range(len(names) or 1):
            col = f"msd_{names[k]}" if names else "msd"
            if diffs[k] == 0 or col not in msd:
                continue
            line = m.errorbar(t, msd[col], msd[col + "_err"], fmt="o", ms=3, lw=0.8,
                              label=f"MSD {names[k] if names else 'tagged rod'}")
            m.plot(t, 2 * diffs[k] * t, ":", color=line[0].get_color(), lw=1,
                   label=f"free 2Dt, D = {diffs[k]:g}")
        if not names and not walls and "tilt" not in _field_terms(p):
            from . import single_file_msd
            rho, sg = n / length, sigmas[0]
            if rho * sg < 1:
                m.plot(t, single_file_msd(t, rho, sg, diffs[0]), "k-", lw=1,
                       label="exact single-file law"
                       + (" (field-free)" if _field_terms(p) else ""))
        _log_axes(m)
        m.set_xlabel(r"lag time t  [$\sigma^2/D$]")
        m.set_ylabel(r"mean-squared displacement  [length$^2$]")
        m.set_title("tagged-rod MSD", fontsize=9)
        m.legend(fontsize=7)

    if "current" in ax:
        j = ax["current"]
        j.plot(current.data[:, 0], current.data[:, 1], "-", lw=0.6,
               label="J over each interval")
        if s.get("particle_current") is not None:
            j.axhline(s["particle_current"], color="k", lw=1,
                      label=f"mean {s['particle_current']:.4g} ± "
                            f"{s.get('particle_current_err', math.nan):.2g}")
        j.set_xlabel("t")
        j.set_ylabel(f"particle current {current.names[1]}")
        j.set_title("current", fontsize=9)
        j.legend(fontsize=7)


def _theory_table(path):
    from ._load import Table
    return Table(path)


# ---- disks and spheres -----------------------------------------------------------------

def _profile_axis(table):
    """The axis a density table is along ('x', 'y' or 'z'), from its title."""
    m = re.search(r"along ([xyz])\b", table.title)
    return m.group(1) if m else table.name[-1]


def _spheres(run, fig):
    p, s = _Params(run), run.summary
    dim = int(s.get("dimension") or p.num("system.dimension", 3))
    names = p.list("species.names")
    ns = max(1, len(names))
    diff = p.nums("species.D") if names else [p.num("system.D", 1.0)]
    sigmas = p.nums("species.sigma") if names else [p.num("system.sigma", 1.0)]
    poly = p.num("species.polydispersity", 0.0)
    poly = poly if poly == poly else 0.0
    colours = ["C0", "C1", "C2", "C3", "C4", "C5", "C6", "C7", "C8", "C9"]
    profiles, seen = [], set()
    for name in sorted(run.tables):
        if re.fullmatch(r"density(_[xyz])?", name):
            axis = _profile_axis(run[name])
            if axis not in seen:
                seen.add(axis)
                profiles.append((axis, run[name]))
    panels = (["gr"] if "gr" in run else []) + (["sk"] if "sk" in run else []) + \
             [f"density {a}" for a, _ in profiles] + \
             (["msd"] if "msd" in run else []) + (["fs"] if "fs" in run else [])
    ax = dict(zip(panels, _axes(fig, len(panels))))
    body = "disks" if dim == 2 else "spheres"
    phi = s.get("packing_fraction")
    field = _describe_field(p)
    fig.suptitle(f"hard {body} ({dim}D), N = {p.get('system.N')}"
                 + (f", packing fraction {phi:.3g}" if phi is not None else "")
                 + (f", species {', '.join(names)}" if names else "")
                 + (f", polydispersity {poly:g}" if poly > 0 else "")
                 + f"; boundary {p.get('system.boundary', 'periodic')}; field: {field}"
                 + (f"; t = {s['time_simulated']:g}" if "time_simulated" in s else ""),
                 fontsize=9)

    if "gr" in ax:
        g, gr = ax["gr"], run["gr"]
        contacts = s.get("contacts", [])
        pairs = [c for c in gr.names if c.startswith("g_") and not c.endswith("_err")]
        for k, col in enumerate(pairs):
            c = colours[k % len(colours)]
            g.plot(gr["r"], gr[col], "-", color=c, lw=1,
                   label=f"g(r) {col[2:].replace('_', '-')}" if ns > 1 else "g(r)")
            if k < len(contacts):
                ct = contacts[k]
                ia = names.index(ct["a"]) if names and ct["a"] in names else 0
                ib = names.index(ct["b"]) if names and ct["b"] in names else 0
                sab = 0.5 * (sigmas[ia] + sigmas[ib]) if not poly else 1.0
                frozen = diff[ia] == 0 and diff[ib] == 0
                g.errorbar([sab], [ct["g_contact"]], [ct["g_contact_err"]], fmt="o", color=c,
                           ms=5, capsize=3, label=f"contact {ct['g_contact']:.3f}"
                           + (" (frozen pair)" if frozen else f" ± {ct['g_contact_err']:.3f}"))
                if ct.get("theory") is not None:
                    g.plot([sab], [ct["theory"]], "*", color=c, ms=12, mec="k",
                           label=f"{ct.get('theory_eos', 'EOS')} {ct['theory']:.3f}")
        g.axhline(1.0, color="0.6", lw=0.6)
        g.set_xlabel(r"r  [$\sigma$]")
        g.set_ylabel("g(r)")
        z = _value(s, "Z_virial")
        if z and s.get("Z_theory") is not None:
            z += f" ({s.get('Z_theory_eos', 'EOS')} {s['Z_theory']:.4g})"
        g.set_title("pair distribution" + (f"; {z}" if z else ""), fontsize=9)
        if poly > 0:
            g.text(0.98, 0.5, "polydisperse: g(r) over centre distances is\nsmeared over "
                   "the contact distances sigma_ij", transform=g.transAxes, ha="right",
                   fontsize=7)
        g.legend(fontsize=7, ncol=1 if ns == 1 else 2)

    if "sk" in ax:
        k, sk = ax["sk"], run["sk"]
        k.errorbar(sk["k"], sk["S"], sk["S_err"], fmt="o-", ms=3, lw=0.8, label="S(k)")
        k.axhline(1.0, color="0.6", lw=0.6, label="ideal gas")
        k.set_xlabel(r"k  [$\sigma^{-1}$]")
        k.set_ylabel("S(k)")
        k.set_title("static structure factor", fontsize=9)
        k.legend(fontsize=7)

    box = [float(v) for v in (s.get("box") or p.nums("system.box"))]
    for axis, table in profiles:
        d = ax[f"density {axis}"]
        cols = [c for c in table.names if c.startswith("rho_") and not c.endswith("_err")]
        species_cols = cols if cols else ["rho"]
        if cols:
            d.errorbar(table["x"], table["rho"], table["rho_err"], fmt="-", color="0.4", lw=0.8,
                       label="all particles")
        for k, col in enumerate(species_cols):
            label = col[4:] if col != "rho" else ("all particles" if ns > 1 else "density")
            d.errorbar(table["x"], table[col], table[col + "_err"], fmt="-",
                       color=colours[k % len(colours)], lw=0.9, label=label)
        a = "xyz".index(axis)
        for wall in s.get("walls", []):
            if wall.get("axis") != axis:
                continue
            for k, sp in enumerate(wall.get("species", [])):
                sg = sigmas[k] if k < len(sigmas) else sigmas[0]
                z = sg / 2 if wall["side"] == "low" else (box[a] if a < len(box) else 0) - sg / 2
                d.errorbar([z], [sp["contact_density"]], [sp["contact_density_err"]], fmt="D",
                           color=colours[k % len(colours)] if len(species_cols) > 1 else "k",
                           mfc="none", ms=6, capsize=2,
                           label="density at contact with the walls (impulses)"
                           if k == 0 and wall["side"] == "low" else None)
        walls_here = any(w.get("axis") == axis for w in s.get("walls", []))
        d.set_xlabel(f"{axis}" + ("" if walls_here else " (folded into sample.period)"))
        d.set_ylabel(r"number density  [$\sigma^{-%d}$]" % dim)
        d.set_title(f"density profile along {axis}"
                    + (" (walls at 0 and the box length)" if walls_here else ""), fontsize=9)
        d.legend(fontsize=7)

    if "msd" in ax:
        m, msd = ax["msd"], run["msd"]
        t = msd["t"]
        dls = s.get("D_long_species", {})
        for k in range(ns):
            c = colours[k % len(colours)]
            name = names[k] if names else "all"
            col = f"msd_{name}" if names else "msd"
            if diff[k] == 0:
                m.plot([], [], " ", label=f"{name}: immobile (D = 0)")
                continue
            if col not in msd:
                continue
            m.errorbar(t, msd[col], msd[col + "_err"], fmt="o", ms=3, color=c,
                       label=f"MSD {name}" if names else "MSD")
            m.plot(t, 2 * dim * diff[k] * t, ":", color=c, lw=1,
                   label=f"2dDt, D = {diff[k]:g}")
            dl = dls.get(name) if names else [s.get("D_long"), s.get("D_long_err")]
            if dl and dl[0]:
                m.plot(t, 2 * dim * dl[0] * t, "--", color=c, lw=1,
                       label=f"2dD_L t, D_L = {dl[0]:.3f} ± {dl[1]:.3f}")
        _log_axes(m)
        m.set_xlabel(r"lag time t  [$\sigma^2/D$]")
        m.set_ylabel(r"MSD per particle  [$\sigma^2$]")
        m.set_title("mean-squared displacement", fontsize=9)
        m.legend(fontsize=7)

    if "fs" in ax:
        f, fs = ax["fs"], run["fs"]
        kk = p.num("sample.fs_k")
        for k in range(ns):
            c = colours[k % len(colours)]
            name = names[k] if names else "all"
            col = f"fs_{name}" if names else "fs"
            if col not in fs or diff[k] == 0:
                continue
            f.errorbar(fs["t"], fs[col], fs[col + "_err"], fmt="o-", ms=3, lw=0.8, color=c,
                       label=name if names else "F_s")
            f.plot(fs["t"], np.exp(-kk * kk * diff[k] * fs["t"]), ":", color=c, lw=1,
                   label="free diffusion exp(-k²Dt)" + (f" ({name})" if names else ""))
        if len(fs.data):
            f.set_xscale("log")
        f.set_xlabel(r"lag time t  [$\sigma^2/D$]")
        f.set_ylabel("F_s(k, t)")
        f.set_title(f"self-intermediate scattering, k = {kk:.3g}", fontsize=9)
        f.legend(fontsize=7)


# ---- active particles ------------------------------------------------------------------

def _first(v):
    """The first value of a parameter given once or per species."""
    return float(str(v).replace(",", " ").split()[0])


def _is_active(run):
    v0 = str(run.parameters.get("active", {}).get("v0") or "0")
    return run.model == "spheres" and any(float(x) > 0 for x in v0.replace(",", " ").split())


def _last_frame(path):
    """Positions (n x 3), radii, orientations (n x 3 or None) and box of the last frame of
    the run's trajectory.xyz or trajectory.gsd, or None."""
    xyz = os.path.join(path, "trajectory.xyz")
    if os.path.exists(xyz):
        with open(xyz) as f:
            lines = f.read().split("\n")
        start, i = None, 0
        while i < len(lines) and lines[i].strip():
            start, i = i, i + 2 + int(lines[i])
        n, head = int(lines[start]), lines[start + 1]
        box = [float(v) for v in head.split('Lattice="')[1].split('"')[0].split()[0::4]]
        props = head.split("Properties=")[1].split()[0].split(":")
        cols, col = {}, 0
        for k in range(0, len(props), 3):
            cols[props[k]] = col - 1  # the species' name is not among the numbers
            col += int(props[k + 2])
        rows = np.array([[float(v) for v in ln.split()[1:]]
                         for ln in lines[start + 2:start + 2 + n]])
        e = rows[:, cols["dipoles"]:cols["dipoles"] + 3] if "dipoles" in cols else None
        return rows[:, cols["pos"]:cols["pos"] + 3], rows[:, cols["radius"]], e, box
    gsd_path = os.path.join(path, "trajectory.gsd")
    if not os.path.exists(gsd_path):
        return None
    import gsd.hoomd
    traj = gsd.hoomd.open(gsd_path, "rb")  # Debian's python3-gsd 2.x: "rb"
    f = traj[-1]
    traj.close()
    box = [float(v) for v in f.configuration.box[:3]]
    e = None
    if f.particles.orientation is not None:  # e = q x q*: the body's x axis
        w, x, y, z = f.particles.orientation.astype(float).T
        e = np.stack([w * w + x * x - y * y - z * z, 2 * (x * y + w * z),
                      2 * (x * z - w * y)], 1)
    return f.particles.position + np.array(box) / 2, f.particles.diameter / 2, e, box


def local_density_peaks(phi, p, width=0.02):
    """The maxima of a local density distribution P(phi) smoothed over a Gaussian of
    ``width``, above a fifth of the largest and at least 0.1 apart (one peak in a
    homogeneous fluid, the dilute and the dense phase of a phase-separated one)."""
    phi, p = np.asarray(phi, float), np.asarray(p, float)
    kernel = np.exp(-0.5 * ((phi[:, None] - phi[None, :]) / width) ** 2)
    smooth = kernel @ p / kernel.sum(axis=1)
    peaks = []
    for i in np.argsort(-smooth):
        if smooth[i] < 0.2 * smooth.max():
            break
        is_max = ((i == 0 or smooth[i] >= smooth[i - 1])
                  and (i == len(p) - 1 or smooth[i] >= smooth[i + 1]))
        if is_max and all(abs(phi[i] - q) >= 0.1 for q in peaks):
            peaks.append(float(phi[i]))
    return sorted(peaks)


def _active(run, fig):
    from matplotlib.collections import PatchCollection
    from matplotlib.patches import Circle
    p, s = _Params(run), run.summary
    dim = int(s.get("dimension") or p.num("system.dimension", 3))
    v0, diff, sigma = _first(p.get("active.v0")), p.num("system.D", 1.0), p.num("system.sigma", 1.0)
    dr = _first(p.get("active.rotational_D")) if p.get("active.rotational_D") else 3 * diff / sigma ** 2
    k = (dim - 1) * dr
    ax = _axes(fig, 3)
    fig.suptitle(f"active Brownian {'disks' if dim == 2 else 'spheres'}, N = {p.get('system.N')}, "
                 f"packing fraction {s.get('packing_fraction', math.nan):.3g}, Pe = v0 sigma / D = "
                 f"{v0 * sigma / diff:g}, D_r = {dr:g}; t = {s.get('time_simulated', math.nan):g}")
    frame = _last_frame(run.path)
    if frame is not None:
        x, r, e, box = frame
        if dim == 3:  # a slab through the middle, 2 sigma thick
            keep = np.abs(x[:, 2] - box[2] / 2) < sigma
            x, r, e = x[keep], r[keep], e[keep] if e is not None else None
        pc = PatchCollection([Circle((xi[0], xi[1]), ri) for xi, ri in zip(x, r)],
                             cmap="hsv", linewidths=0)
        pc.set_array(np.arctan2(e[:, 1], e[:, 0]) if e is not None else np.zeros(len(r)))
        pc.set_clim(-math.pi, math.pi)
        ax[0].add_collection(pc)
        ax[0].set_xlim(0, box[0])
        ax[0].set_ylim(0, box[1])
        ax[0].set_aspect("equal")
        fig.colorbar(pc, ax=ax[0], label="orientation angle in the x-y plane")
        ax[0].set_title("last frame" + (" (the slab |z - L/2| < sigma)" if dim == 3 else ""))
    else:
        ax[0].text(0.5, 0.5, "no trajectory (output.trajectory)", ha="center",
                   transform=ax[0].transAxes)
    if "local_density" in run.tables:
        loc = run["local_density"]
        phi = loc["phi"]
        ax[1].errorbar(phi, loc["P"], yerr=loc["P_err"], fmt="-", lw=1, drawstyle="steps-mid")
        ax[1].axvline(float(s.get("packing_fraction", math.nan)), ls=":", c="k",
                      label="mean packing fraction")
        used = np.nonzero(loc["P"] > 0)[0]
        if len(used):
            ax[1].set_xlim(max(0, phi[used[0]] - 0.05), min(1, phi[used[-1]] + 0.05))
        for x in local_density_peaks(phi, loc["P"]):
            ax[1].axvline(x, c="C1", lw=1)
        ax[1].set(xlabel="local packing fraction", ylabel="P(phi)",
                  title="local density (peaks: orange)")
        ax[1].legend()
    else:
        ax[1].text(0.5, 0.5, "no local_density.tsv (sample.local_density_every)", ha="center",
                   transform=ax[1].transAxes)
    if "msd" in run.tables:
        msd = run["msd"]
        t = msd["t"]
        free = 2 * dim * diff * t
        law = free + (2 * v0 ** 2 / k ** 2 * (k * t - 1 + np.exp(-k * t)) if k > 0 else (v0 * t) ** 2)
        ax[2].errorbar(t, msd["msd"], yerr=msd["msd_err"], fmt="o", ms=3, label="MSD")
        ax[2].plot(t, law, "k--", label="free ABP: 2dDt + 2v0²/k²(kt-1+e^-kt)")
        ax[2].plot(t, free, "k:", label="2dDt")
        _log_axes(ax[2])
        ax[2].set(xlabel="lag time t  [σ²/D]", ylabel="MSD per particle  [σ²]",
                  title="MSD and orientation correlation")
        if "orientation" in run.tables:
            rot = run["orientation"]
            twin = ax[2].twinx()
            twin.errorbar(rot["t"], rot["C"], yerr=rot["C_err"], fmt="s", ms=2, c="C3",
                          label="<e(0).e(t)>")
            twin.plot(rot["t"], np.exp(-k * rot["t"]), c="C3", lw=1, label="exp(-(d-1) D_r t)")
            twin.set_ylabel("orientation correlation", color="C3")
            twin.set_ylim(0, 1.05)
            twin.legend(loc="lower right")
        ax[2].legend(loc="upper left")


# ---- figures ---------------------------------------------------------------------------

def _axes(fig, n):
    cols = 2 if n == 4 else min(3, max(1, n))
    rows = math.ceil(max(1, n) / cols)
    fig.set_size_inches(5.4 * cols, 4.4 * rows + 0.6)
    axes = fig.subplots(rows, cols, squeeze=False).ravel()
    for extra in axes[n:]:
        extra.set_axis_off()
    return list(axes[:n])


def _log_axes(a):
    if a.has_data():
        a.set_xscale("log")
        a.set_yscale("log")


def plot(source, out=None, theory=None):
    """Draw a run (a directory, or a Run from hsbd.load) into a PNG and return its path
    (default: DIR/plot.png, written under a temporary name and renamed). theory: for
    rods, a table of ``hsbd theory percus`` drawn as the exact profile (Percus' profile is
    otherwise computed when it applies: one species on a ring in a cosine field)."""
    from matplotlib.figure import Figure
    run = source if isinstance(source, Run) else load(source)
    model = run.model
    if model not in ("rods", "spheres"):
        raise ValueError(f"{run.path}: a run of an unknown model ({model!r})")
    fig = Figure(layout="constrained")
    if model == "rods":
        _rods(run, fig, theory)
    elif _is_active(run):
        _active(run, fig)
    else:
        _spheres(run, fig)
    out = os.fspath(out) if out else os.path.join(run.path, "plot.png")
    tmp = out + ".part.png"
    fig.savefig(tmp, dpi=110)
    os.replace(tmp, out)
    return out


def main(argv=None):
    """python3 -m hsbd.plot DIR [DIR ...] [--out FILE.png] [--theory PERCUS.tsv]"""
    ap = argparse.ArgumentParser(prog="python3 -m hsbd.plot",
                                 description="Draw runs of hsbd: one PNG per run directory "
                                             "(DIR/plot.png).")
    ap.add_argument("dirs", nargs="+", metavar="DIR", help="run directory")
    ap.add_argument("--out", help="the PNG's path (one DIR only)")
    ap.add_argument("--theory", help="rods: the exact profile from 'hsbd theory percus'")
    a = ap.parse_args(argv)
    if a.out and len(a.dirs) > 1:
        ap.error("--out takes one run directory")
    status = 0
    for d in a.dirs:
        try:
            print(f"plot: {plot(d, out=a.out, theory=a.theory)}")
        except (OSError, ValueError, KeyError) as e:
            print(f"hsbd.plot: {d}: {e}", file=sys.stderr)
            status = 2
    return status


class _CallableModule(types.ModuleType):
    """hsbd.plot(DIR) calls plot(DIR)."""

    def __call__(self, source, out=None, theory=None):
        return plot(source, out=out, theory=theory)


sys.modules[__name__].__class__ = _CallableModule

if __name__ == "__main__":
    sys.exit(main())

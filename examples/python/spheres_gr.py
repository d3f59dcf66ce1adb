#!/usr/bin/python3
"""A hard-sphere fluid at packing fraction 0.3: g(r) measured by hsbd next to the contact
value g(sigma+) of the Carnahan-Starling equation of state.
Run: examples/python/spheres_gr.py [out.png] with the package installed (pip install .)
or PYTHONPATH=build/python."""
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

import hsbd

phi = 0.3
sim = hsbd.Simulation(system={"model": "spheres", "N": 1000, "packing_fraction": phi},
                      run={"dt": 1e-3, "t_equil": 0.5, "t_total": 3},
                      sample={"gr_every": 10})
sim.run()  # to the end: 0.5 of equilibration, then 3 of production
r, g, err = sim.gr()
contact = sim.gr_pairs()[0]
cs = hsbd.hs_contact_cs(phi)
print(f"g(sigma+): hsbd {contact['contact']:.3f} +- {contact['contact_err']:.3f}, "
      f"Carnahan-Starling {cs:.3f}")

plt.errorbar(r, g, err, fmt="-", lw=1, label="hsbd (EDBD), N = 1000")
plt.errorbar([1.0], [contact["contact"]], [contact["contact_err"]], fmt="o",
             label=f"hsbd contact value {contact['contact']:.3f}")
plt.plot([1.0], [cs], "k*", ms=12, label=f"Carnahan-Starling g(sigma+) = {cs:.3f}")
plt.axhline(1, color="grey", lw=0.5)
plt.xlabel("r / sigma"); plt.ylabel("g(r)"); plt.title(f"hard spheres, packing fraction {phi}")
plt.legend()
plt.savefig(sys.argv[1] if len(sys.argv) > 1 else "spheres_gr.png", dpi=120)

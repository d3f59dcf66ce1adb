#!/usr/bin/python3
"""Hard rods (sigma 0.5, density 0.5) in U(x) = 3 cos(2 pi x) (field.amplitude 6, U =
(amplitude/2) cos): the simulated density profile against Percus' exact one.
Run: examples/python/percus.py [out.png] with the package installed (pip install .) or
PYTHONPATH=build/python."""
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

import hsbd

sim = hsbd.Simulation(system={"N": 50, "L": 100, "sigma": 0.5},
                      field={"type": "cosine", "amplitude": 6},
                      run={"dt": 1e-4, "t_equil": 1, "t_total": 20})
sim.run()  # to the end: 1 of equilibration (run.t_equil), then the 20 of production
print(f"{sim.stage} at t = {sim.time:g} ({sim.steps[0]} + {sim.steps[1]} steps)")
x, rho, err = sim.density()
xt, rho_exact, _ = hsbd.percus(sigma=0.5, rho=0.5, amplitude=6)
plt.errorbar(x, rho, err, fmt=".", label="hsbd (BCD), error bars: 1 standard error")
plt.plot(xt, rho_exact, label="Percus (exact)")
plt.xlabel("x / wavelength"); plt.ylabel("density rho(x) [1/wavelength]"); plt.legend()
plt.savefig(sys.argv[1] if len(sys.argv) > 1 else "percus.png")

/* The one schema table of the configuration: every key, its models, type, range, default
 * and doc. Parsing, the checks, --help, docs/config.md and the tables' headers all read it:
 * adding a key is adding a row (and its check in finalise.c, or in finalise_<model>.c for
 * one model, if it depends on other keys). Then the table of models: what each one reads,
 * its rules across keys and its memory estimate. */
#include "config/schema.h"

#include <string.h>

#define OFF(member) offsetof(hsbd_config, member)
#define INF         HUGE_VAL

/* Ranges are closed unless flagged open. */
const key_spec config_schema[] = {
    {"system", "model", ALL_MODELS, K_ENUM, OFF(system.model), 0, 0, 0, "rods", "rods|spheres",
     "particle model (rods: hard rods on a line, Brownian cluster dynamics; spheres: hard "
     "disks or spheres in a periodic box, event-driven Brownian dynamics)"},
    {"system", "dimension", SPHERES, K_INT, OFF(system.dimension), 2, 3, 0, "3", 0,
     "spheres: 2 (disks) or 3 (spheres)"},
    {"system", "box", SPHERES, K_STRING, OFF(system.box_text), 0, 0, 0, "", 0,
     "spheres: periodic box lengths, one value (square / cube) or one per dimension; or set "
     "system.packing_fraction instead"},
    {"system", "packing_fraction", SPHERES, K_DOUBLE, OFF(system.packing_fraction), 0, 1,
     OPEN_MIN | OPEN_MAX, "", 0,
     "spheres: packing fraction phi (volume of the particles over the box); gives a square / "
     "cubic box"},
    {"system", "drift", SPHERES, K_STRING, OFF(system.drift_text), 0, 0, 0, "", 0,
     "spheres: common drift velocity (one value per dimension, length/time), the same for "
     "every particle (Scala Sec. IV); empty: none"},
    {"system", "shell", SPHERES, K_DOUBLE, OFF(system.shell), 0, INF, OPEN_MAX, "0", 0,
     "spheres: neighbour shell radius (half the skin); 0: chosen from D and dt (docs/spheres.md)"},
    {"system", "N", ALL_MODELS, K_INT, OFF(system.n), 1, 2147483647.0, 0, "50", 0,
     "number of rods"},
    {"system", "L", RODS, K_DOUBLE, OFF(system.length), 0, INF, OPEN_MIN | OPEN_MAX, "100", 0,
     "ring length (periodic line); N*sigma must be < L"},
    {"system", "sigma", ALL_MODELS, K_DOUBLE, OFF(system.sigma), 0, INF, OPEN_MAX, "0.5", 0,
     "rod length / particle diameter (rods default 0.5; spheres default 1, and > 0)"},
    {"system", "D", ALL_MODELS, K_DOUBLE, OFF(system.diffusion), 0, INF, OPEN_MIN | OPEN_MAX, "1",
     0, "diffusion coefficient (length^2/time); mobility mu = D/kT"},
    {"system", "kT", ALL_MODELS, K_DOUBLE, OFF(system.kT), 0, INF, OPEN_MIN | OPEN_MAX, "1", 0,
     "thermal energy, in the units of every energy of the configuration (field.amplitude, "
     "field.force x length, field.stiffness x length^2, pair.strength, tabulated potentials "
     "and forces): only energy / kT matters, and mobility mu = D/kT; the authors' dialect uses "
     "kT = D (their mu = 1)"},
    {"system", "seed", ALL_MODELS, K_UINT64, OFF(system.seed), 0, 18446744073709551615.0, 0, "1", 0,
     "random seed (64-bit); same seed and binary give byte-identical tables"},
    {"system", "hard_core", ALL_MODELS, K_BOOL, OFF(system.hard_core), 0, 1, 0, "on", 0,
     "on: hard rods; off: free particles (benchmark bound, tests)"},
    {"system", "contact_rule", RODS, K_ENUM, OFF(system.contact_rule), 0, 0, 0, "reflect",
     "reflect|sticky",
     "reflect: each gap's Brownian-bridge minimum is drawn first and a crossing reflects it "
     "(no O(sqrt(dt)) contact layer; validated, docs/validation.md); sticky: the paper's BCD "
     "as printed (inelastic mergers), needs ~100x smaller dt in dense systems"},
    {"system", "boundary", ALL_MODELS, K_STRING, OFF(system.boundary_text), 0, 0, 0, "periodic", 0,
     "periodic or walls. Rods: periodic, a ring of length L; walls: hard walls at 0 and L (rod "
     "centres in [sigma/2, L - sigma/2]). Spheres: one value for every axis or one per axis "
     "(e.g. periodic periodic walls): walls are planes at 0 and the box length with centres in "
     "[sigma_i/2, box - sigma_i/2], acting also with hard_core = off"},
    {"contact", "gamma", RODS, K_DOUBLE, OFF(contact.gamma), 0, INF, OPEN_MAX, "0", 0,
     "Baxter stickiness gamma (Antonov Eqs. 29-30); 0: pure hard core"},
    {"contact", "order", RODS, K_DOUBLE, OFF(contact.order), 1, INF, OPEN_MIN | OPEN_MAX, "3", 0,
     "exponent p of the power-law delta_eps (Eq. 31); p > 1 keeps the force continuous"},
    {"contact", "epsilon", RODS, K_DOUBLE, OFF(contact.epsilon), 0, INF, OPEN_MIN | OPEN_MAX,
     "0.05", 0,
     "width of delta_eps (Eq. 31): the sticky force acts for gaps in [0, epsilon); the run "
     "checks mu max|f| dt / epsilon (Eq. 33): warns above 0.1, refuses above 1 (--force)"},
    {"pair", "type", RODS, K_ENUM, OFF(pair.type), 0, 0, 0, "none", "none|yukawa|lj|table",
     "continuous pair force between rods (Eq. 28): yukawa: V = strength sigma "
     "exp(-kappa (r - sigma))/r; lj: V = strength ((sigma/r)^12 - 2 (sigma/r)^6), a well of "
     "depth strength at contact; table: force f(r) from pair.table. Analytic forms are "
     "force-shifted to vanish continuously at pair.cutoff"},
    {"pair", "strength", RODS, K_DOUBLE, OFF(pair.strength), -INF, INF, OPEN_MIN | OPEN_MAX, "1", 0,
     "yukawa: V at contact (energy, units of system.kT; > 0 repulsive); lj: well depth (energy)"},
    {"pair", "kappa", RODS, K_DOUBLE, OFF(pair.kappa), 0, INF, OPEN_MIN | OPEN_MAX, "1", 0,
     "yukawa inverse screening length (1/length)"},
    {"pair", "cutoff", RODS, K_DOUBLE, OFF(pair.cutoff), 0, INF, OPEN_MAX, "0", 0,
     "centre distance where yukawa/lj end, > sigma and <= L/2 (0: yukawa sigma + 5/kappa, "
     "lj 2.5 sigma); a table ends at its last r"},
    {"pair", "table", RODS, K_STRING, OFF(pair.table), 0, 0, 0, "", 0,
     "pair.type = table: file with lines 'r f(r)' (force on the right rod, energy/length), r "
     "strictly increasing from <= sigma, f = 0 at the last r; natural cubic spline"},
    {"field", "type", ALL_MODELS, K_TERMS, OFF(field.type), 0, 0, 0, "cosine",
     "none|cosine|tilt|harmonic|table",
     "external field, a sum of terms joined by '+' (e.g. cosine+tilt): cosine U = (amplitude/2) "
     "cos(2 pi x/wavelength); tilt: constant force (linear potential U = -force x, gravity); "
     "harmonic: U = (stiffness/2)(x - center)^2 (nearest image on a ring); table: U(x) or f(x) "
     "from field.table (rods default cosine; spheres default none, the field acting along "
     "field.axis)"},
    {"field", "amplitude", ALL_MODELS, K_DOUBLE, OFF(field.amplitude), -INF, INF,
     OPEN_MIN | OPEN_MAX, "6", 0,
     "cosine amplitude U0 (energy, units of system.kT), Antonov Eq. 21"},
    {"field", "wavelength", ALL_MODELS, K_DOUBLE, OFF(field.wavelength), 0, INF,
     OPEN_MIN | OPEN_MAX, "1", 0, "cosine wavelength lambda; must divide L"},
    {"field", "force", ALL_MODELS, K_DOUBLE, OFF(field.force), -INF, INF, OPEN_MIN | OPEN_MAX, "0",
     0, "constant force f (energy/length) of the tilt term; f < 0 pushes rods towards x = 0"},
    {"field", "stiffness", ALL_MODELS, K_DOUBLE, OFF(field.stiffness), 0, INF, OPEN_MAX, "1", 0,
     "harmonic trap stiffness k (energy/length^2)"},
    {"field", "center", ALL_MODELS, K_DOUBLE, OFF(field.center), -INF, INF, OPEN_MIN | OPEN_MAX, "",
     0, "harmonic trap centre (default: L/2; spheres: half the box along field.axis)"},
    {"field", "axis", SPHERES, K_ENUM, OFF(field.axis), 0, 0, 0, "z", "x|y|z",
     "spheres: the coordinate the field acts on (default z in 3D, y in 2D); a cosine's "
     "wavelength must divide a periodic box length there"},
    {"field", "table", ALL_MODELS, K_STRING, OFF(field.table), 0, 0, 0, "", 0,
     "field.type with table: file with lines 'x value', x strictly increasing; on a ring x runs "
     "from 0 to L exactly, the values at 0 and L agree and the spline is periodic (the force is "
     "continuous across x = 0 = L); between walls x covers [0, L] and the spline is natural"},
    {"field", "table_kind", ALL_MODELS, K_ENUM, OFF(field.table_kind), 0, 0, 0, "potential",
     "potential|force",
     "what field.table holds: potential U(x) (energy; force -U') or force f(x) (energy/length)"},
    {"drive", "parameter", RODS, K_ENUM, OFF(drive.parameter), 0, 0, 0, "none",
     "none|force|amplitude|shift|stiffness|center",
     "the field parameter that changes in time, p(t) = p + velocity t + amplitude w(2 pi t / "
     "period + phase), t the simulated time from the initial state: force (tilt: a rocking "
     "tilt), amplitude (cosine: flashing or modulated U0), shift (cosine: U = (U0/2) cos(2 pi (x "
     "- shift)/wavelength), a travelling wave), stiffness or center (harmonic: a dragged or "
     "oscillating trap); its term must be in field.type. The field is evaluated at each step's "
     "start (docs/theory.md)"},
    {"drive", "wave", RODS, K_ENUM, OFF(drive.wave), 0, 0, 0, "none", "none|cosine|square",
     "waveform w: cos, or the square wave sign(cos) (+1 where cos = 0); none: only the velocity"},
    {"drive", "amplitude", RODS, K_DOUBLE, OFF(drive.amplitude), -INF, INF, OPEN_MIN | OPEN_MAX,
     "0", 0, "amplitude of the wave, in the units of the parameter (F1 of F0 + F1 cos)"},
    {"drive", "period", RODS, K_DOUBLE, OFF(drive.period), 0, INF, OPEN_MAX, "0", 0,
     "period of the wave (time); at least run.dt and run.dt_equil"},
    {"drive", "phase", RODS, K_DOUBLE, OFF(drive.phase), -INF, INF, OPEN_MIN | OPEN_MAX, "0", 0,
     "phase of the wave at t = 0 (radians)"},
    {"drive", "velocity", RODS, K_DOUBLE, OFF(drive.velocity), -INF, INF, OPEN_MIN | OPEN_MAX, "0",
     0,
     "rate of change of the parameter (its units per time): the speed of a travelling wave "
     "(shift) or of a dragged trap (center)"},
    {"species", "names", ALL_MODELS, K_STRING, OFF(species.names_text), 0, 0, 0, "", 0,
     "a mixture: species names (letters, digits, '_'), separated by spaces or commas; empty: "
     "one species with system.sigma and system.D"},
    {"species", "count", ALL_MODELS, K_STRING, OFF(species.count_text), 0, 0, 0, "", 0,
     "particles of each species (whole numbers >= 1), summing to system.N; rods: the order "
     "along the line is a uniformly random arrangement unless init.positions gives it"},
    {"species", "fraction", SPHERES, K_STRING, OFF(species.fraction_text), 0, 0, 0, "", 0,
     "spheres: number fraction of each species (> 0, summing to 1), instead of species.count; "
     "counts are rounded to sum to system.N"},
    {"species", "sigma", ALL_MODELS, K_STRING, OFF(species.sigma_text), 0, 0, 0, "", 0,
     "rod length of each species (>= 0); contact distance (sigma_a + sigma_b)/2"},
    {"species", "D", ALL_MODELS, K_STRING, OFF(species.d_text), 0, 0, 0, "", 0,
     "diffusion coefficient of each species (> 0; spheres also 0: immobile obstacles); "
     "mobility D/kT"},
    {"species", "polydispersity", SPHERES, K_DOUBLE, OFF(species.polydispersity), 0, 0.3, 0, "0", 0,
     "spheres: continuous polydispersity, the relative standard deviation of the diameters "
     "about each species' sigma (or system.sigma); 0: monodisperse species"},
    {"species", "distribution", SPHERES, K_ENUM, OFF(species.distribution), 0, 0, 0, "gaussian",
     "gaussian|uniform",
     "spheres: distribution of the diameters with species.polydispersity (gaussian: truncated "
     "beyond 3.04 widths, variance kept; uniform: a flat band of that standard deviation)"},
    {"species", "D_law", SPHERES, K_ENUM, OFF(species.d_law), 0, 0, 0, "given",
     "given|stokes-einstein",
     "spheres: given: D of the species (or system.D) for every particle; stokes-einstein: "
     "D_i = D_0 sigma_0 / sigma_i with D_0 = system.D at sigma_0 = system.sigma (then no "
     "species.D)"},
    {"species", "coupling", SPHERES, K_STRING, OFF(species.coupling_text), 0, 0, 0, "", 0,
     "spheres: the field's factor on each species (finite numbers, buoyant mass or charge; the "
     "force on particle i is coupling_i F(x)); empty: 1 for every species, so a field with an "
     "immobile species (D = 0) needs this key, with 0 for that species"},
    {"species", "coupling_law", SPHERES, K_ENUM, OFF(species.coupling_law), 0, 0, 0, "given",
     "given|volume",
     "spheres: given: species.coupling (or 1) for every particle; volume: coupling_i = "
     "(sigma_i / system.sigma)^d, proportional to the particle's volume (buoyant mass of "
     "polydisperse colloids; then no species.coupling)"},
    {"active", "v0", SPHERES, K_STRING, OFF(active.v0_text), 0, 0, 0, "", 0,
     "spheres: active Brownian particles: the propulsion speed v0 (length/time, >= 0) along "
     "each particle's orientation, one value for every species or one per species (0 for a "
     "species with D = 0, which cannot be active); the orientations start uniformly random "
     "(or from init.positions) and diffuse with active.rotational_D; Pe = v0 sigma / D. "
     "Empty: no active particles (docs/active.md)"},
    {"active", "rotational_D", SPHERES, K_STRING, OFF(active.rotational_text), 0, 0, 0, "", 0,
     "spheres: rotational diffusion coefficient D_r (1/time, >= 0; 0: straight swimmers) of "
     "the orientations, one value or one per species; empty: 3 D_i / sigma_i^2 for each "
     "particle (Stokes-Einstein for a sphere). The orientations decorrelate as exp(-(d-1) D_r t)"},
    {"run", "dt", ALL_MODELS, K_DOUBLE, OFF(run.dt), 0, INF, OPEN_MIN | OPEN_MAX, "1e-4", 0,
     "time step"},
    {"run", "t_equil", ALL_MODELS, K_DOUBLE, OFF(run.t_equil), 0, INF, OPEN_MAX, "10", 0,
     "unsampled dynamics after the initial state"},
    {"run", "t_total", ALL_MODELS, K_DOUBLE, OFF(run.t_total), 0, INF, OPEN_MIN | OPEN_MAX, "100",
     0, "sampled (production) time"},
    {"run", "dt_equil", RODS, K_DOUBLE, OFF(run.dt_equil), 0, INF, OPEN_MAX, "0", 0,
     "time step during equilibration (0: run.dt); a coarser step relaxes slow modes (barrier "
     "hopping) cheaply, the Euler distortion of dt then relaxes within a short time"},
    {"run", "replicas", ALL_MODELS, K_INT, OFF(run.replicas), 0, 1e6, 0, "0", 0,
     "independent replicas of the run, each with its own noise (the replica index mixed into "
     "the seed) and its own initial state and equilibration, in DIR/replica-K; DIR gets their "
     "merged tables with errors from the replica scatter (docs/scaling.md). 0: one per MPI "
     "rank under mpirun, else a single run"},
    {"run", "replica", ALL_MODELS, K_INT, OFF(run.replica), -1, 1e6, 0, "-1", 0,
     "run replica K of an ensemble alone (hsbd run --replica K, e.g. one task of a job array; "
     "join them with hsbd merge); -1: not a replica"},
    {"run", "threads", ALL_MODELS, K_INT, OFF(run.threads), 0, 1024, NO_HEADER, "0", 0,
     "threads of one run (hsbd run --threads N); 0: the cores the process may use (under "
     "mpirun: its rank's share of them). Rods: the "
     "noise, field and contact pushes in parallel, results identical for every count; "
     "spheres: the noise, the start-of-step scan, the event groups (not the global calendar) "
     "and the final move in parallel, results identical for every count "
     "(docs/scaling.md)"},
    {"run", "field_step", ALL_MODELS, K_ENUM, OFF(run.field_step), 0, 0, 0, "heun", "euler|heun",
     "how the external field's force enters a step. heun: the mean of the force at the start "
     "and at the end point of a free predictor with the step's own noise: the stationary "
     "density is off by O(dt^2), about (dt mu max|U''|)^2 / 8 at a well's bottom (rods: with "
     "either contact rule, though the sticky rule keeps its own O(sqrt(dt)) contact layer; "
     "spheres: walls and collisions unchanged), one force evaluation more per step, about 20x "
     "less CPU than Euler for a 0.1 % profile; euler: the force at the step's start, off by "
     "O(dt), about dt mu max|U''| / 4 (the papers' step); pair forces stay at the step's "
     "start (docs/algorithms.md)"},
    {"run", "pair_rule", SPHERES, K_ENUM, OFF(run.pair_rule), 0, 0, 0, "exact", "exact|mirror",
     "spheres: how a pair collides when the two particles' drifts differ (a field with "
     "per-species couplings or a force that varies in space, immobile obstacles in a "
     "field). exact: the pair's free end gap moved to the gap of the same quantile in the law "
     "of its normal gap reflected with the relative drift (Scala Eq. 9, exact for a pair "
     "alone in the flat-contact limit), then the elastic collisions as before; mirror: the "
     "elastic collisions alone, exact only without relative drift. Pairs without relative "
     "drift give the same bits either way (docs/spheres.md, pair collisions under a "
     "relative drift)"},
    {"run", "events", SPHERES, K_ENUM, OFF(run.events), 0, 0, 0, "auto", "auto|global|groups",
     "spheres: how a step's events run: one time-ordered calendar for the whole box (global), "
     "group by group (groups: cache-friendly for large N, and on threads; a step whose "
     "groups percolate, re-runs beyond its predicted pairs, goes to the global calendar), "
     "or auto (groups from N = 65536 on when the box has no walls, else from 131072, on any "
     "number of threads, unless they grow too large); the same trajectories and tables either way "
     "(contact times depend on the paths alone; the virial and wall impulses are exact "
     "sums)"},
    {"sample", "bin_width", ALL_MODELS, K_DOUBLE, OFF(sample.bin_width), 0, INF,
     OPEN_MIN | OPEN_MAX, "1e-2", 0,
     "density bin width Delta_x (Eq. 24); must divide sample.period (spheres: of the profiles "
     "along the walls and field axes, default sigma/20, must divide their lengths)"},
    {"sample", "contact_width", RODS, K_DOUBLE, OFF(sample.contact_width), 0, INF, OPEN_MAX, "0", 0,
     "contact window Delta' (Eq. 26): gaps in [0, Delta'] count as contact (0: max(0.01, three "
     "rms relative steps 3 sqrt(4 D dt)), largest D; narrower windows bias rho2_extrap low, "
     "docs/observables.md)"},
    {"sample", "period", ALL_MODELS, K_DOUBLE, OFF(sample.period), 0, INF, OPEN_MIN | OPEN_MAX, "",
     0,
     "profiles are folded into one period (default: field.wavelength); must divide L (spheres: "
     "the field axis's profile, folded when that axis is periodic with a cosine field)"},
    {"sample", "blocking", RODS, K_ENUM, OFF(sample.blocking), 0, 0, 0, "time",
     "time|space|replicas",
     "error bars of profiles and the MSD from blocks of time, or of space (segments of the "
     "ring, for long rings whose slow modes outlast time blocks; blocks must divide L/period), "
     "or from independent replicas (rods: each block restarts from its own initial state, "
     "the exact field-free sample or init.positions, and equilibrates run.t_equil; errors "
     "then include modes slower than any run)"},
    {"sample", "every", ALL_MODELS, K_INT, OFF(sample.every), 1, 1e15, 0, "1", 0,
     "sample every this many steps (spheres: the MSD and F_s; default 10 there)"},
    {"sample", "blocks", ALL_MODELS, K_INT, OFF(sample.blocks), 2, 10000, 0, "20", 0,
     "number of blocks for block-average error bars"},
    {"sample", "msd_max_lag", ALL_MODELS, K_DOUBLE, OFF(sample.msd_max_lag), 0, INF, OPEN_MAX, "0",
     0, "largest MSD lag time (0: t_total/10)"},
    {"sample", "msd_points_per_decade", ALL_MODELS, K_INT, OFF(sample.msd_points_per_decade), 1,
     1000, 0, "10", 0, "log-spaced MSD lags per decade"},
    {"sample", "phases", RODS, K_INT, OFF(sample.phases), 0, 100, 0, "0", 0,
     "profiles resolved by the drive's phase: K bins of drive.period, each sample goes to the "
     "bin of its time (stroboscopic), written to density_phases.tsv; 0: none; needs drive.wave"},
    {"sample", "current_every", RODS, K_DOUBLE, OFF(sample.current_every), 0, INF, OPEN_MAX, "0", 0,
     "write the particle current every this much time to current.tsv (0: off)"},
    {"sample", "gr_every", SPHERES, K_INT, OFF(sample.gr_every), 0, 1e15, 0, "0", 0,
     "spheres: sample g(r) every this many steps (a pair search up to sample.gr_max, costly); "
     "0: every 0.05 time units (sigma^2/D), samples closer in time are strongly correlated"},
    {"sample", "gr_max", SPHERES, K_DOUBLE, OFF(sample.gr_max), 0, INF, OPEN_MAX, "0", 0,
     "spheres: largest distance of g(r) (0: 3 sigma_max, at most half the shortest periodic box "
     "length)"},
    {"sample", "gr_bin", SPHERES, K_DOUBLE, OFF(sample.gr_bin), 0, INF, OPEN_MIN | OPEN_MAX, "0.02",
     0, "spheres: g(r) bin width"},
    {"sample", "contact_fit", SPHERES, K_DOUBLE, OFF(sample.contact_fit), 0, INF,
     OPEN_MIN | OPEN_MAX, "0.1", 0,
     "spheres: contact values g_ab(sigma_ab+) by a quadratic fit of g over gaps in [0, "
     "contact_fit)"},
    {"sample", "fs_k", SPHERES, K_DOUBLE, OFF(sample.fs_k), 0, INF, OPEN_MAX, "0", 0,
     "spheres: wavenumber of F_s(k, t) (0: 2 pi / sigma of species 0)"},
    {"sample", "sk_every", SPHERES, K_INT, OFF(sample.sk_every), 0, 1e15, 0, "0", 0,
     "spheres in a periodic box: sample the static structure factor S(k) (sk.tsv) every this "
     "many steps along the axes and the diagonals of the box's wavevector lattice; 0: off"},
    {"sample", "sk_max", SPHERES, K_DOUBLE, OFF(sample.sk_max), 0, INF, OPEN_MAX, "0", 0,
     "spheres: the largest |k| of S(k) (0: 20 / system.sigma, past the third peak of a dense "
     "fluid)"},
    {"sample", "local_density_every", SPHERES, K_INT, OFF(sample.local_density_every), 0, 1e15, 0,
     "0", 0,
     "spheres: every this many steps, the histogram of the local packing fraction over cells "
     "of side sample.local_density_cell (local_density.tsv: two peaks in a phase-separated "
     "fluid, the motility-induced phase separation of active particles); 0: off"},
    {"sample", "local_density_cell", SPHERES, K_DOUBLE, OFF(sample.local_density_cell), 0, INF,
     OPEN_MAX, "0", 0,
     "spheres: the side of the cells of local_density.tsv, rounded to divide each box length "
     "(0: 5 system.sigma); a cell's packing fraction is the volume of the particles whose "
     "centres it holds over its own"},
    {"output", "dir", ALL_MODELS, K_STRING, OFF(output.dir), 0, 0, NO_HEADER, "", 0,
     "run directory (default: runs/<config name>); --out overrides"},
    {"output", "trajectory", ALL_MODELS, K_ENUM, OFF(output.trajectory), 0, 0, 0, "none",
     "none|xyz|gsd",
     "trajectory format (xyz: extended XYZ, read by OVITO/ASE/VMD; gsd: GSD, HOOMD schema)"},
    {"output", "trajectory_every", ALL_MODELS, K_DOUBLE, OFF(output.trajectory_every), 0, INF,
     OPEN_MAX, "0", 0, "time between trajectory frames (0: t_total/100, at least run.dt)"},
    {"output", "log_every", ALL_MODELS, K_DOUBLE, OFF(output.log_every), 0, INF, OPEN_MAX, "", 0,
     "time between the lines of log.tsv, a time series of the production's quantities (rods: "
     "the particle current, the mean cluster size, the walls' contact densities; spheres: "
     "collisions per particle-step, the virial pressure, the walls' pressures); default "
     "run.t_total/1000, at least run.dt; 0: no log.tsv"},
    {"output", "checkpoints", ALL_MODELS, K_BOOL, OFF(output.checkpoints), 0, 1, NO_HEADER, "on", 0,
     "write checkpoints into the run directory (checkpoint.hsbd, the one before it kept as "
     "checkpoint.prev.hsbd), so that 'hsbd resume DIR' continues an interrupted run bit for "
     "bit; taking one never changes the results"},
    {"output", "checkpoint_every", ALL_MODELS, K_DOUBLE, OFF(output.checkpoint_every), 0, INF,
     OPEN_MAX | NO_HEADER, "0", 0,
     "simulated time between checkpoints (0: by wall time, output.checkpoint_wall); a "
     "stopped or finished run always writes one"},
    {"output", "checkpoint_wall", ALL_MODELS, K_DOUBLE, OFF(output.checkpoint_wall), 0, INF,
     OPEN_MIN | OPEN_MAX | NO_HEADER, "600", 0,
     "wall-clock seconds between checkpoints when output.checkpoint_every = 0; the first "
     "comes after a tenth of it (1 minute by default), also with checkpoint_every, so that "
     "a run killed at any moment (kill -9, a lost node) loses at most one interval"},
    {"init", "positions", ALL_MODELS, K_STRING, OFF(init.positions), 0, 0, 0, "", 0,
     "file with initial positions; rods: one per line ('#' comments), default an exact "
     "equilibrium sample of the field-free ring; spheres: extended XYZ (species name and x y "
     "[z] per particle, as hsbd writes it; its count and Lattice give system.N and the box); "
     "either model: a GSD file (HOOMD schema, as hsbd, HOOMD-blue or gsd write it), whose "
     "frame gives N, the box, the species (its types) and diameters; a key that restates "
     "them must agree (docs/trajectories.md)"},
    {"init", "frame", ALL_MODELS, K_INT, OFF(init.frame), -1, 1e15, 0, "-1", 0,
     "the frame of a GSD init.positions file to start from (0: the first; -1: the last)"},
    {"init", "method", SPHERES, K_ENUM, OFF(init.method), 0, 0, 0, "auto",
     "auto|random|lattice|compress",
     "spheres without init.positions: random sequential insertion (up to phi 0.30 in 3D, 0.45 "
     "in 2D); compress: insertion at smaller diameters, then Brownian steps with growth into "
     "the gaps (a fluid up to phi 0.58 in 3D, 0.72 in 2D); or a lattice (fcc / centred "
     "rectangular, up to close packing of the largest diameter) melted during run.t_equil; "
     "auto: random, else compress, else lattice"},
};
enum { NKEYS = sizeof config_schema / sizeof config_schema[0] };
_Static_assert((int)NKEYS <= (int)HSBD_CONFIG_MAX_KEYS, "raise HSBD_CONFIG_MAX_KEYS");
const size_t config_nkeys = NKEYS;

/* The models, in the order of enum hsbd_model and of system.model's choices. */
const model_spec config_models[] = {
    [HSBD_MODEL_RODS] = {.name = "rods",
                         .keys = RODS,
                         .point_particles = 1,
                         .finalise = config_finalise_rods,
                         .memory = config_memory_rods},
    [HSBD_MODEL_SPHERES] = {.name = "spheres",
                            .keys = SPHERES,
                            .immobile_species = 1,
                            .finalise = config_finalise_spheres,
                            .memory = config_memory_spheres},
};
const size_t config_nmodels = sizeof config_models / sizeof config_models[0];

const model_spec *config_model(const hsbd_config *cfg) {
    const unsigned m = (unsigned)cfg->system.model;
    return m < config_nmodels ? &config_models[m] : NULL;
}

void *config_slot(hsbd_config *cfg, const key_spec *k) {
    return (char *)cfg + k->offset;
}
const void *config_cslot(const hsbd_config *cfg, const key_spec *k) {
    return (const char *)cfg + k->offset;
}

const key_spec *config_find_key(const char *section, const char *key) {
    for (size_t i = 0; i < NKEYS; ++i)
        if (!strcmp(config_schema[i].section, section) && !strcmp(config_schema[i].key, key))
            return &config_schema[i];
    return NULL;
}

size_t config_key_index(const key_spec *k) {
    return (size_t)(k - config_schema);
}

int config_section_known(const char *name) {
    for (size_t i = 0; i < NKEYS; ++i)
        if (!strcmp(config_schema[i].section, name)) return 1;
    return 0;
}

void config_section_list(char *buf, size_t len) {
    size_t used = 0;
    buf[0] = '\0';
    for (size_t i = 0; i < NKEYS; ++i)
        if ((i == 0 || strcmp(config_schema[i - 1].section, config_schema[i].section)) &&
            used < len)
            used += (size_t)snprintf(buf + used, len - used, "%s[%s]", used ? ", " : "",
                                     config_schema[i].section);
}

int config_key_read(const hsbd_config *cfg, const key_spec *k) {
    const model_spec *model = config_model(cfg);
    return model && (k->models & model->keys) != 0;
}

/* ---- names near a misspelt one ------------------------------------------------------ */

static size_t edit_distance(const char *a, const char *b) {
    size_t la = strlen(a), lb = strlen(b), prev[128], cur[128];
    if (la > 120 || lb > 120) return 1000;
    for (size_t j = 0; j <= lb; ++j)
        prev[j] = j;
    for (size_t i = 1; i <= la; ++i) {
        cur[0] = i;
        for (size_t j = 1; j <= lb; ++j) {
            size_t best = prev[j - 1] + ((a[i - 1] | 32) != (b[j - 1] | 32));
            if (prev[j] + 1 < best) best = prev[j] + 1;
            if (cur[j - 1] + 1 < best) best = cur[j - 1] + 1;
            cur[j] = best;
        }
        memcpy(prev, cur, (lb + 1) * sizeof *prev);
    }
    return prev[lb];
}

const char *config_nearest_section(const char *name, size_t *distance) {
    size_t best = 1000;
    const char *near = NULL;
    for (size_t i = 0; i < NKEYS; ++i) {
        const size_t d = edit_distance(name, config_schema[i].section);
        if (d < best) best = d, near = config_schema[i].section;
    }
    *distance = best;
    return near;
}

const char *config_suggest(const char *section, const char *key, char *buf, size_t len) {
    char want[256], cand[256];
    snprintf(want, sizeof want, "%s.%s", section, key);
    size_t best = 1000;
    buf[0] = '\0';
    for (size_t i = 0; i < NKEYS; ++i) {
        snprintf(cand, sizeof cand, "%s.%s", config_schema[i].section, config_schema[i].key);
        size_t d = edit_distance(want, cand);
        const size_t dk =
            edit_distance(key, config_schema[i].key) + 1; /* right key, wrong section */
        if (dk < d) d = dk;
        if (d < best) best = d, snprintf(buf, len, "%s", cand);
    }
    return best <= 3 || best * 3 <= strlen(want) ? buf : NULL;
}

void config_format_range(const key_spec *k, char *buf, size_t len) {
    char lo[64], hi[64];
    switch (k->type) {
    case K_ENUM:
        snprintf(buf, len, "one of %s", k->choices);
        return;
    case K_TERMS:
        snprintf(buf, len, "none, or terms from %s joined by '+'", strchr(k->choices, '|') + 1);
        return;
    case K_BOOL:
        snprintf(buf, len, "on/off (also true/false, yes/no, 1/0)");
        return;
    case K_STRING:
        snprintf(buf, len, "a text of at most %d characters", HSBD_PATH_MAX - 1);
        return;
    default:
        break;
    }
    if (k->type == K_UINT64) {
        snprintf(buf, len, "0 <= %s <= 18446744073709551615 (integer)", k->key);
        return;
    }
    snprintf(lo, sizeof lo, "%.15g", k->min);
    snprintf(hi, sizeof hi, "%.15g", k->max);
    snprintf(buf, len, "%s %s %s %s %s%s", isinf(k->min) ? "-inf" : lo,
             (k->flags & OPEN_MIN) ? "<" : "<=", k->key,
             (k->flags & OPEN_MAX) ? "<" : "<=", isinf(k->max) ? "inf" : hi,
             k->type == K_INT ? " (integer)" : "");
}

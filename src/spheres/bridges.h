/* Brownian-bridge pushes (internal to src/spheres): a gap whose Brownian motion with a
 * constant drift is reflected at contact ends where its free path ends plus the depth of
 * the path's lowest point below contact (Skorokhod; docs/theory.md, "Exact shortcuts").
 * The walls use it for one particle's gap (edbd.c), the exact pair rule for the gap of a
 * pair in its Brownian centre-of-mass frame (docs/spheres.md, "Pair collisions under a
 * relative drift"). */
#ifndef HSBD_SPHERES_BRIDGES_H
#define HSBD_SPHERES_BRIDGES_H

#include "spheres/state.h"

/* The uniforms U in (0, 1) of src/core/rng.c have -ln U <= 54 ln 2 = 37.43: a bridge
 * with g0 g1 >= SPH_BRIDGE_REACH D dt never reaches contact, so it needs no draw. */
#define SPH_BRIDGE_REACH 37.5

/* The push of a gap whose Brownian path (diffusion D, D dt = d_dt) goes from g0 >= 0 to
 * the free end gap g1 in the step: minus the minimum m of the Brownian bridge between them
 * when m < 0, m = (g0 + g1 - sqrt((g1 - g0)^2 - 4 D dt ln U)) / 2, U the uniform of
 * `index` in `stream` at this step; else 0. Exact for any drift constant in the step (the
 * bridge does not depend on the drift; the drift is in g1). */
double sph_bridge_push(const hsbd_spheres *s, double g0, double g1, double d_dt, uint32_t stream,
                       uint64_t index);

/* The neighbour rows' skin for the exact pair rule: a pair whose shells lie more than the
 * skin beyond sigma_ij + 2 shell apart starts and, unless a straight path leaves its
 * shell, ends its step more than the skin apart, where its bridge reaches contact with
 * probability below exp(-SPH_SKIN_REACH) = 2e-9. */
#define SPH_SKIN_REACH 20.0

/* That skin at time step dt, sqrt(2 SPH_SKIN_REACH D_max dt), or what a small periodic box
 * leaves room for (half of it at least sigma_max + 2 shell + skin); 0 when the rule is off. */
double sph_pair_skin(const hsbd_spheres *s, double dt);

/* The exact pair rule's pushes of a step (s->pair_bridges): every neighbour pair's gap
 * |r_j - r_i| - sigma_ij from the start to the free end of the step (the fictive
 * velocities, drifts and wall pushes included) gets its bridge, and a pair whose bridge
 * dips below contact is pushed apart along its end separation by the dip, particle i by
 * D_i / (D_i + D_j) of it and j by D_j / (D_i + D_j) (sum dr / D kept). The pushes enter
 * the fictive velocities before any event; their share of the virial goes to
 * s->push_virial, their count to the statistics. Returns 0, or -1 when out of memory
 * (velocities unchanged). */
int sph_pair_pushes(hsbd_spheres *s);

#endif

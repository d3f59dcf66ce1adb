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
 * bridge does not depend on the drift; the drift is in g1). A bridge with g0 g1 >= reach
 * D dt (it reaches contact with probability exp(-g0 g1 / (D dt)) <= e^-reach) is not
 * drawn: SPH_BRIDGE_REACH loses nothing, SPH_PAIR_REACH below 2e-9 per bridge. */
double sph_bridge_push(const hsbd_spheres *s, double g0, double g1, double d_dt, double reach,
                       uint32_t stream, uint64_t index);

/* The exact pair rule's cut-off: a pair's bridge with g0 g1 >= SPH_PAIR_REACH (D_i + D_j) dt
 * reaches contact with probability below e^-20 = 2e-9 and is not drawn; the neighbour rows'
 * skin is such that a pair whose shells lie more than the skin beyond sigma_ij + 2 shell
 * apart starts and, unless a straight path leaves its shell, ends its step more than the
 * skin apart, beyond that cut-off. */
#define SPH_PAIR_REACH 20.0

/* That skin at time step dt, sqrt(2 SPH_PAIR_REACH D_max dt), or what a small periodic box
 * leaves room for (half of it at least sigma_max + 2 shell + skin); 0 when the rule is off. */
double sph_pair_skin(const hsbd_spheres *s, double dt);

/* The exact pair rule's pushes of a step (s->pair_bridges): every neighbour pair's gap
 * |r_j - r_i| - sigma_ij from the start to the free end of the step (the fictive
 * velocities, drifts and wall pushes included) gets its bridge; a pair whose bridge dips
 * below contact is to be opened along its end separation n by the dip P (its end gap then
 * is the exactly reflected one). The displacements d_k that do it for all such pairs at
 * once with the least sum_k |d_k|^2 / D_k (friction 1 / D; sum_k d_k / D_k = 0 pair by
 * pair): a pair alone moves i by -D_i / (D_i + D_j) P n and j by D_j / (D_i + D_j) P n;
 * pairs that share a particle are solved together (projected Gauss-Seidel on their
 * impulses, in the order of the user labels). The displacements enter the fictive
 * velocities before any event; the impulses' share of the virial goes to s->push_virial,
 * the pairs to the statistics. Returns 0, or -1 when out of memory (velocities
 * unchanged). */
int sph_pair_pushes(hsbd_spheres *s);

#endif

/* A gap's Brownian motion with drift reflected at contact (internal to src/spheres; the
 * physics in docs/theory.md, "Pair collisions under a relative drift"): the walls' pushes
 * (the Brownian bridge of one particle's gap, Skorokhod) and the exact pair rule (the
 * normal gap of a pair in its Brownian centre-of-mass frame, run.pair_rule = exact). */
#ifndef HSBD_SPHERES_REFLECT_H
#define HSBD_SPHERES_REFLECT_H

#include "spheres/state.h"

/* The uniforms U in (0, 1) of src/core/rng.c have -ln U <= 54 ln 2 = 37.43: a bridge
 * with g0 g1 >= SPH_BRIDGE_REACH D dt never reaches contact, so it needs no draw. */
#define SPH_BRIDGE_REACH 37.5

/* The push off a wall of a particle whose Brownian path (diffusion D, D dt = d_dt) goes
 * from gap g0 >= 0 to the free end gap g1 in the step: minus the minimum m of the Brownian
 * bridge between them when m < 0, m = (g0 + g1 - sqrt((g1 - g0)^2 - 4 D dt ln U)) / 2, U
 * the uniform of `index` in the bridge stream at this step; else 0. The free end point
 * plus this push is the end point of the path reflected at the wall (Skorokhod): exact
 * for any drift constant in the step (the drift is in g1). */
double sph_bridge_push(const hsbd_spheres *s, double g0, double g1, double d_dt, uint64_t index);

/* The exact gap of one pair (Scala Eq. 9 in the flat-contact limit, docs/theory.md): the
 * end gap X, from start gap x0 >= 0 with relative diffusion d and relative normal drift c
 * (> 0: apart) over dt, whose law P(X <= x) = Phi((x - x0 - c dt) / s) - e^(c x / d)
 * Phi((-x - x0 - c dt) / s), s = sqrt(2 d dt), has at X the quantile that the mirror
 * rule's law P(|Y| <= y) = Phi((y - x0 - c dt) / s) - Phi((-y - x0 - c dt) / s) has at y
 * = |Y|, Y the free end gap. c = 0 gives y (the two laws are one). Exposed for tests. */
double sph_exact_gap(double y, double x0, double c, double d, double dt);

/* The neighbour rows' skin for the exact pair rule at time step dt: a pair whose shells lie
 * more than the skin beyond sigma_ij + 2 shell apart starts and, unless a straight path
 * leaves its shell, ends its step more than the skin from contact, where the pair rule
 * moves its end gap by a fraction below Phi(-6) = 1e-9 of the step; sqrt(72 D_max dt), or
 * what a small periodic box leaves room for (half of it at least sigma_max + 2 shell +
 * skin); 0 when the rule is off. */
double sph_pair_skin(const hsbd_spheres *s, double dt);

/* The exact pair rule of a step (s->pair_exact): for every neighbour pair near contact
 * whose drifts differ (s->drift, the particles' drift velocities of the step), the free end
 * gap Y (|r_j - r_i| - sigma_ij at the end of the fictive velocities, drifts and wall
 * pushes included) becomes sign(Y) X with X = sph_exact_gap(|Y|, ...): the elastic
 * collision of the events then leaves the gap X where the mirror rule would have left |Y|.
 * The change is along the end separation, shared in proportion to D_i and D_j (sum_k
 * dr_k / D_k kept); a particle's changes from all its pairs are added up exactly
 * (sph_exact_sum: the same bits in any order, on any number of threads). The displacements
 * enter the fictive velocities before any event; the changes' share of the virial goes to
 * s->push_virial, the pairs to the statistics. Returns 0, or -1 when out of memory
 * (velocities unchanged). */
int sph_pair_corrections(hsbd_spheres *s);

#endif

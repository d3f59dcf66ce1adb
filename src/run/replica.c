/* The noise of a replica of an ensemble (see run.h; the ensembles themselves are
 * src/rundir/). */
#include "run/run.h"

/* Replica k's Philox key: the seed moved by k steps of the golden-ratio Weyl sequence
 * (replica 0, and a run that is no replica, keep the seed itself). */
uint64_t run_noise_seed(const hsbd_config *cfg) {
    const uint64_t k = cfg->run.replica > 0 ? (uint64_t)cfg->run.replica : 0;
    return cfg->system.seed + k * UINT64_C(0x9E3779B97F4A7C15);
}

/* The EDBD object, shared by the files of src/spheres. */
#ifndef HSBD_SPHERES_INTERNAL_H
#define HSBD_SPHERES_INTERNAL_H

#include "hsbd/spheres.h"
#include "spheres/calendar.h"
#include "spheres/cells.h"
#include "spheres/kernels.h"

struct hsbd_spheres {
    hsbd_spheres_params par;
    int dim;
    size_t n;
    double box[3], inv_box[3];
    /* per particle (x, v, centre, image: 3 per particle; z = 0 in 2D) */
    double *x;       /* position at the particle's local time t_local (wrapped at step ends) */
    double *v;       /* fictive velocity of the current step */
    double *t_local; /* time within the step of x */
    double *centre;  /* neighbour-shell centre (wrapped) */
    int64_t *image;
    uint32_t *counter;                     /* collisions so far: invalidates older events */
    double *sigma, *diffusion, *noise_amp; /* sqrt(2 D_i / dt) */
    int *species;
    double *sp_sigma, *sp_diffusion;
    size_t nspecies;
    double sigma_max, shell;
    /* neighbours: pairs whose shells overlap, |c_i - c_j| < sigma_ij + 2 shell */
    uint32_t nb_cap;
    uint32_t *nb_count, *nb_upper; /* entries of each row; those with j > i (first) */
    int32_t *nb;                   /* n x nb_cap */
    sph_cells cells;               /* of the shell centres, cells >= sigma_max + 2 shell wide */
    sph_calendar calendar;
    sph_predict_row_fn predict_row; /* scalar or AVX2 (the same results) */
    sph_cells_near_fn cells_near;   /* scalar or AVX2 */
    sph_half_scan_fn half_scan;     /* scalar or AVX2 */
    int32_t *scan_i, *scan_j;       /* hits of a scan: a chunk of rows, or one row (no i) */
    double *scan_t;
    size_t scan_cap; /* >= nb_cap */
    int32_t *near;   /* points found around one particle */
    size_t near_cap;
    double *normals;       /* dim x n draws of a step */
    uint32_t noise_stream; /* HSBD_STREAM_NOISE; the compression uses its own */
    double dt, time;
    uint64_t step;
    /* spatial order (order.c): internal particle i is the user's particle label[i] */
    int32_t *label;
    int reordered;     /* label is not the identity: views show the user_ copies */
    int sort_enabled;  /* 0 while the compression runs (it indexes by user order) */
    double sort_clock; /* D_max t since the last sort (length^2) */
    double diffusion_max;
    int32_t *cell_rank; /* of each cell along the Z curve; NULL until the first sort */
    double *user_x, *user_sigma, *user_diffusion; /* the view's arrays in user order */
    int64_t *user_image;
    int *user_species;
    int oom; /* an allocation failed inside a step (the step is then not exact) */
    hsbd_spheres_stats stats;
};

/* The cached per-particle quantities that follow from dt and D: the noise amplitudes. */
void sph_set_noise_amplitudes(hsbd_spheres *s);

/* Places every particle's shell at its position and builds all neighbour lists. */
int sph_rebuild_neighbours(hsbd_spheres *s);

/* Puts the particles in the Z-curve order of their cells, the neighbour lists and cells
 * renumbered (between steps). Returns 0, or -1 when out of memory (the order is then kept). */
int sph_sort_spatially(hsbd_spheres *s);
/* Back to the user's order (before anything writes per-particle values by user index).
 * Returns 0, or -1 when out of memory. */
int sph_restore_user_order(hsbd_spheres *s);
/* Writes the positions and image counters in user order into user_x and user_image. */
void sph_fill_user_view(const hsbd_spheres *s);

#endif

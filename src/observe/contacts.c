/* Contact densities per ordered species pair and at the walls, from the contact impulses
 * of each step (contact theorem), block-averaged. */
#include <math.h>
#include <stdlib.h>

#include "hsbd/observe.h"
#include "observe/checkpoint.h"

struct hsbd_contacts {
    size_t n, nspecies;
    double length;
    double *impulse;     /* N + 1 per sample */
    hsbd_blocks *blocks; /* nspecies^2 pairs (a * nspecies + b), then left and right wall */
    double *scratch;     /* 2 x the values: the results' means and errors */
};

hsbd_contacts *hsbd_contacts_alloc(size_t n, size_t nspecies, size_t nblocks,
                                   uint64_t nsamples_total, hsbd_error *err) {
    hsbd_contacts *c = calloc(1, sizeof *c);
    if (c) {
        c->n = n;
        c->nspecies = nspecies ? nspecies : 1;
        c->impulse = malloc((n + 1) * sizeof *c->impulse);
        c->scratch = malloc(2 * (c->nspecies * c->nspecies + 2) * sizeof *c->scratch);
        c->blocks = hsbd_blocks_alloc(c->nspecies * c->nspecies + 2, nblocks, nsamples_total);
    }
    if (!c || !c->impulse || !c->scratch || !c->blocks) {
        hsbd_contacts_free(c);
        hsbd_error_set(err, HSBD_ENOMEM, "contacts: out of memory");
        return NULL;
    }
    return c;
}

void hsbd_contacts_free(hsbd_contacts *c) {
    if (!c) return;
    free(c->impulse);
    free(c->scratch);
    hsbd_blocks_free(c->blocks);
    free(c);
}

void hsbd_contacts_sample(hsbd_contacts *c, const hsbd_rods_view *v) {
    const size_t n = v->n, ns = c->nspecies;
    double *acc = hsbd_blocks_acc(c->blocks);
    c->length = v->length;
    hsbd_contact_impulses(v, c->impulse);
    const size_t npairs = v->periodic ? (n > 1 ? n : 0) : n - 1;
    for (size_t i = 0; i < npairs; ++i) {
        const size_t j = i + 1 < n ? i + 1 : 0;
        const size_t a = v->species ? (size_t)v->species[i] : 0;
        const size_t b = v->species ? (size_t)v->species[j] : 0;
        acc[a * ns + b] += c->impulse[i] / v->length;
    }
    if (!v->periodic) {
        acc[ns * ns] += c->impulse[n];
        acc[ns * ns + 1] += c->impulse[n - 1];
    }
    hsbd_blocks_end_sample(c->blocks);
}

/* one value of the block averages */
static void result_at(const hsbd_contacts *c, size_t k, double *val, double *err) {
    const size_t nv = c->nspecies * c->nspecies + 2;
    double *mean = c->scratch, *e = c->scratch + nv;
    hsbd_blocks_result(c->blocks, mean, e);
    *val = mean[k];
    *err = e[k];
}

void hsbd_contacts_pair(const hsbd_contacts *c, size_t a, size_t b, double *val, double *err) {
    result_at(c, a * c->nspecies + b, val, err);
}

void hsbd_contacts_wall(const hsbd_contacts *c, int right, double *val, double *err) {
    result_at(c, c->nspecies * c->nspecies + (right ? 1 : 0), val, err);
}

/* ---- checkpoints ---- */
void hsbd_contacts_save(const hsbd_contacts *c, hsbd_writer *w) {
    hsbd_put_tag(w, "contacts");
    hsbd_put_u64(w, c->nspecies);
    hsbd_blocks_save(c->blocks, w);
}

int hsbd_contacts_load(hsbd_contacts *c, hsbd_reader *r) {
    if (hsbd_get_tag(r, "contacts") || hsbd_get_count(r, c->nspecies, "contact species")) return -1;
    return hsbd_blocks_load(c->blocks, r);
}

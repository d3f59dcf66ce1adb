/* Pair forces between rods: Baxter sticky contact (Antonov Eqs. 31-32), Yukawa, a
 * Lennard-Jones well, and tabulated forces. */
#include "hsbd/pair.h"

#include <math.h>

#include "hsbd/table.h"

/* ---- Baxter sticky contact, power-law delta_eps ---------------------------------------- */
enum { ST_SIGMA, ST_GAMMA, ST_ORDER, ST_EPS, ST_KT };

/* Eq. (32) times kT (the paper has kT = 1): f = -kT gamma p (eps - h)^(p-1) /
 * (eps^(p+1)/(p+1) + gamma (eps - h)^p), h = r - sigma in [0, eps); energy/length */
static double sticky_force(const hsbd_pair_term *t, double r) {
    if (r >= t->range) return 0.0;
    const double h = r - t->p[ST_SIGMA], eps = t->p[ST_EPS];
    const double g = t->p[ST_GAMMA], p = t->p[ST_ORDER], w = eps - (h > 0 ? h : 0.0);
    const double wp1 = pow(w, p - 1.0);
    return -t->p[ST_KT] * g * p * wp1 / (pow(eps, p + 1.0) / (p + 1.0) + g * wp1 * w);
}

/* Eqs. (30)-(31): V = -kT ln(1 + gamma delta_eps(h)), delta_eps = (p+1) (eps - h)^p /
 * eps^(p+1): the Boltzmann factor 1 + gamma delta_eps does not depend on kT */
static double sticky_potential(const hsbd_pair_term *t, double r) {
    if (r >= t->range) return 0.0;
    const double h = r - t->p[ST_SIGMA], eps = t->p[ST_EPS];
    const double g = t->p[ST_GAMMA], p = t->p[ST_ORDER], w = eps - (h > 0 ? h : 0.0);
    return -t->p[ST_KT] * log1p(g * (p + 1.0) * pow(w / eps, p) / eps);
}

static const hsbd_pair_ops sticky_ops = {"sticky", sticky_force, sticky_potential};

hsbd_pair_term hsbd_pair_sticky(double sigma, double gamma, double order, double epsilon,
                                double kT) {
    hsbd_pair_term t = {&sticky_ops, sigma + epsilon, {0}, NULL};
    t.p[ST_SIGMA] = sigma;
    t.p[ST_GAMMA] = gamma;
    t.p[ST_ORDER] = order;
    t.p[ST_EPS] = epsilon;
    t.p[ST_KT] = kT;
    return t;
}

/* ---- force-shifted analytic pair potentials ------------------------------------------- */
/* p[SH_FC], p[SH_VC]: unshifted force and potential at the cutoff (= range) */
enum { SH_SIGMA, SH_A, SH_B, SH_FC, SH_VC };

static double shifted_force(const hsbd_pair_term *t, double r, double f_raw) {
    return r >= t->range ? 0.0 : f_raw - t->p[SH_FC];
}
static double shifted_potential(const hsbd_pair_term *t, double r, double v_raw) {
    return r >= t->range ? 0.0 : v_raw - t->p[SH_VC] + (r - t->range) * t->p[SH_FC];
}

/* Yukawa: V = A sigma e^(-kappa (r - sigma)) / r, f = V (kappa + 1/r) */
static double yukawa_raw_v(const hsbd_pair_term *t, double r) {
    return t->p[SH_A] * t->p[SH_SIGMA] * exp(-t->p[SH_B] * (r - t->p[SH_SIGMA])) / r;
}
static double yukawa_raw_f(const hsbd_pair_term *t, double r) {
    return yukawa_raw_v(t, r) * (t->p[SH_B] + 1.0 / r);
}
static double yukawa_force(const hsbd_pair_term *t, double r) {
    return shifted_force(t, r, yukawa_raw_f(t, r));
}
static double yukawa_potential(const hsbd_pair_term *t, double r) {
    return shifted_potential(t, r, yukawa_raw_v(t, r));
}
static const hsbd_pair_ops yukawa_ops = {"yukawa", yukawa_force, yukawa_potential};

/* LJ well with its minimum -depth at r = sigma: V = depth (s^12 - 2 s^6), s = sigma / r */
static double lj_raw_v(const hsbd_pair_term *t, double r) {
    const double s2 = (t->p[SH_SIGMA] / r) * (t->p[SH_SIGMA] / r), s6 = s2 * s2 * s2;
    return t->p[SH_A] * (s6 * s6 - 2.0 * s6);
}
static double lj_raw_f(const hsbd_pair_term *t, double r) {
    const double s2 = (t->p[SH_SIGMA] / r) * (t->p[SH_SIGMA] / r), s6 = s2 * s2 * s2;
    return 12.0 * t->p[SH_A] * (s6 * s6 - s6) / r;
}
static double lj_force(const hsbd_pair_term *t, double r) {
    return shifted_force(t, r, lj_raw_f(t, r));
}
static double lj_potential(const hsbd_pair_term *t, double r) {
    return shifted_potential(t, r, lj_raw_v(t, r));
}
static const hsbd_pair_ops lj_ops = {"lj", lj_force, lj_potential};

static hsbd_pair_term shifted_term(const hsbd_pair_ops *ops,
                                   double (*raw_f)(const hsbd_pair_term *, double),
                                   double (*raw_v)(const hsbd_pair_term *, double), double sigma,
                                   double a, double b, double cutoff) {
    hsbd_pair_term t = {ops, cutoff, {0}, NULL};
    t.p[SH_SIGMA] = sigma;
    t.p[SH_A] = a;
    t.p[SH_B] = b;
    t.p[SH_FC] = raw_f(&t, cutoff);
    t.p[SH_VC] = raw_v(&t, cutoff);
    return t;
}

hsbd_pair_term hsbd_pair_yukawa(double sigma, double contact_value, double kappa, double cutoff) {
    return shifted_term(&yukawa_ops, yukawa_raw_f, yukawa_raw_v, sigma, contact_value, kappa,
                        cutoff);
}

hsbd_pair_term hsbd_pair_lj(double sigma, double depth, double cutoff) {
    return shifted_term(&lj_ops, lj_raw_f, lj_raw_v, sigma, depth, 0.0, cutoff);
}

/* ---- tabulated force ------------------------------------------------------------------ */
static double table_force(const hsbd_pair_term *t, double r) {
    return r >= t->range ? 0.0 : hsbd_table_value(t->table, r);
}
/* V(r) = int_r^end f */
static double table_potential(const hsbd_pair_term *t, double r) {
    if (r >= t->range) return 0.0;
    return hsbd_table_integral(t->table, t->range) - hsbd_table_integral(t->table, r);
}
static const hsbd_pair_ops table_ops = {"table", table_force, table_potential};

hsbd_pair_term hsbd_pair_table(const hsbd_table *force_table) {
    hsbd_pair_term t = {&table_ops, hsbd_table_x_max(force_table), {0}, force_table};
    return t;
}

/* ---- lists ----------------------------------------------------------------------------- */
int hsbd_pair_add(hsbd_pair *pair, hsbd_pair_term term) {
    if (pair->nterms >= HSBD_MAX_PAIR_TERMS) return -1;
    pair->term[pair->nterms++] = term;
    return 0;
}

double hsbd_pair_range(const hsbd_pair *pair) {
    double r = 0.0;
    for (size_t k = 0; k < pair->nterms; ++k)
        if (pair->term[k].range > r) r = pair->term[k].range;
    return r;
}

double hsbd_pair_force(const hsbd_pair *pair, double r) {
    double f = 0.0;
    for (size_t k = 0; k < pair->nterms; ++k)
        f += pair->term[k].ops->force(&pair->term[k], r);
    return f;
}

double hsbd_pair_potential(const hsbd_pair *pair, double r) {
    double v = 0.0;
    for (size_t k = 0; k < pair->nterms; ++k)
        v += pair->term[k].ops->potential(&pair->term[k], r);
    return v;
}

double hsbd_pair_max_curvature(const hsbd_pair *pair, double r_lo, double r_hi) {
    enum { SAMPLES = 4096 };
    const double step = (r_hi - r_lo) / SAMPLES;
    double best = 0.0, f_prev = hsbd_pair_force(pair, r_lo);
    for (int k = 1; k <= SAMPLES; ++k) {
        const double f = hsbd_pair_force(pair, r_lo + k * step);
        best = fmax(best, fabs(f - f_prev) / step);
        f_prev = f;
    }
    return best;
}

double hsbd_pair_max_force(const hsbd_pair *pair, double r_lo, double r_hi) {
    enum { SAMPLES = 4096 };
    const double step = (r_hi - r_lo) / SAMPLES;
    double best = 0.0, at = r_lo;
    for (int k = 0; k <= SAMPLES; ++k) {
        const double r = r_lo + k * step, f = fabs(hsbd_pair_force(pair, r));
        if (f > best) best = f, at = r;
    }
    /* golden-section refinement around the best sample */
    double a = fmax(r_lo, at - step), b = fmin(r_hi, at + step);
    const double g = 0.6180339887498949;
    for (int it = 0; it < 60; ++it) {
        const double c = b - g * (b - a), d = a + g * (b - a);
        if (fabs(hsbd_pair_force(pair, c)) > fabs(hsbd_pair_force(pair, d)))
            b = d;
        else
            a = c;
    }
    const double f = fabs(hsbd_pair_force(pair, 0.5 * (a + b)));
    return f > best ? f : best;
}

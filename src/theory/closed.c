/* Closed forms for homogeneous hard and sticky rods. */
#include <math.h>
#include <stdlib.h>

#include "hsbd/theory.h"

static const double PI = 3.141592653589793238462643383280;

double hsbd_tonks_pressure(double rho, double sigma) {
    return rho / (1.0 - rho * sigma);
}

double hsbd_tonks_beta_mu(double rho, double sigma) {
    const double e = rho * sigma;
    return log(rho / (1.0 - e)) + e / (1.0 - e);
}

double hsbd_tonks_contact(double rho, double sigma) {
    return rho * rho / (1.0 - rho * sigma);
}

double hsbd_tonks_ring_contact(double n, double length, double sigma) {
    return n / length * (n - 1.0) / (length - n * sigma);
}

/* g(r) = sum_k p_k(r) / rho with p_k the density of the k-th neighbour: a gamma
 * distribution of order k in the free distance r - k sigma, rate beta P. */
double hsbd_tonks_g(double r, double rho, double sigma) {
    const double bp = hsbd_tonks_pressure(rho, sigma);
    double g = 0.0;
    for (int k = 1; k < 100000; ++k) {
        const double s = r - k * sigma;
        if (s <= 0) break;
        /* p_k(s) = bp^k s^(k-1) e^(-bp s) / (k-1)! */
        const double logp = k * log(bp) + (k - 1) * log(s) - bp * s - lgamma(k);
        const double term = exp(logp);
        g += term;
        if (k > bp * s + 10 * sqrt(k) + 10 && term < 1e-18 * g) break;
    }
    return g / rho;
}

/* Isobaric nearest-neighbour law: gap weight (Theta(r) + gamma delta(r)) e^(-beta P r);
 * 1/rho - sigma = 1 / (bP (1 + gamma bP)), so gamma bP^2 + bP - rho/(1 - rho sigma) = 0. */
double hsbd_sticky_pressure(double rho, double sigma, double gamma) {
    const double c = rho / (1.0 - rho * sigma);
    if (gamma == 0.0) return c;
    return 2.0 * c / (1.0 + sqrt(1.0 + 4.0 * gamma * c)); /* stable root */
}

/* beta mu = -ln Z(P) = bP sigma - ln(1/bP + gamma) (thermal wavelength 1) */
double hsbd_sticky_beta_mu(double rho, double sigma, double gamma) {
    const double bp = hsbd_sticky_pressure(rho, sigma, gamma);
    return bp * sigma - log(1.0 / bp + gamma);
}

double hsbd_single_file_msd(double t, double rho, double sigma, double diffusion) {
    return (1.0 - rho * sigma) / rho * sqrt(4.0 * diffusion * t / PI);
}

/* ---- exact single-file MSD at any time (infinite system, equilibrium start) ----
 * Free coordinates z_i = x_i - i sigma turn hard rods into point particles at density
 * rho' = rho / (1 - rho sigma) that keep their order; the tagged rod's displacement is
 * that of the tagged point. Label-free, the points are independent Brownian walkers, so
 * (s = sqrt(2 D t), u = y / s, c = rho' s) the tag ends at or left of y exactly when
 * A + e - B >= 1, where A = walkers from the right that end left of y (Poisson, mean
 * c G(u)), B = walkers from the left that end right of y (Poisson, mean c G(-u)), e = 1 if
 * the tag's own walker ends left of y (probability Phi(u)), and G(u) = u Phi(u) + phi(u).
 * Hence F(u) = Phi(u) P(A - B >= 0) + (1 - Phi(u)) P(A - B >= 1) and
 * MSD = 4 s^2 int_0^inf u (1 - F(u)) du (the law is even in u). */
static double normal_pdf(double u) {
    return exp(-0.5 * u * u) / sqrt(2.0 * PI);
}

static double poisson_pmf(long n, double mean) {
    if (mean <= 0) return n == 0 ? 1.0 : 0.0;
    return exp((double)n * log(mean) - mean - lgamma((double)n + 1.0));
}

/* P(A - B >= k) for independent Poisson A (mean a), B (mean b): sum over B of
 * P(B = j) P(A >= j + k), both summed over mean +- 40 sd (the rest is below 1e-300). */
static double skellam_tail(double a, double b, long k) {
    const long jmax = (long)ceil(b + 40.0 * sqrt(b) + 40.0);
    const long nmax = jmax + k + (long)ceil(a + 40.0 * sqrt(a) + 40.0);
    const long lo = (long)fmax(0.0, floor(a - 40.0 * sqrt(a) - 40.0));
    /* upper tail of A from the top down: tail[n] = P(A >= n) for n in [lo, nmax] */
    double tail_above = 0.0, sum = 0.0;
    double *tail = malloc((size_t)(nmax + 2) * sizeof *tail);
    if (!tail) return NAN;
    for (long n = nmax; n >= 0; --n) {
        if (n >= lo) tail_above += poisson_pmf(n, a);
        tail[n] = n >= lo ? tail_above : 1.0;
    }
    for (long j = 0; j <= jmax; ++j)
        if (j + k >= 0)
            sum += poisson_pmf(j, b) * (j + k <= nmax ? tail[j + k] : 0.0);
        else
            sum += poisson_pmf(j, b);
    free(tail);
    return sum;
}

static double single_file_tail(double u, double c) {
    const double phi = normal_pdf(u), q = 0.5 * erfc(u / sqrt(2.0)); /* q = 1 - Phi(u) */
    const double g_plus = u * (1.0 - q) + phi;                       /* G(u) */
    const double g_minus = fmax(0.0, phi - u * q); /* G(-u), >= 0 up to rounding */
    const double s0 = skellam_tail(c * g_plus, c * g_minus, 0);
    const double s1 = skellam_tail(c * g_plus, c * g_minus, 1);
    return (1.0 - s0) + q * (s0 - s1); /* 1 - F(u) */
}

double hsbd_single_file_msd_exact(double t, double rho, double sigma, double diffusion) {
    if (!(t > 0)) return 0.0;
    const double s = sqrt(2.0 * diffusion * t), c = rho / (1.0 - rho * sigma) * s;
    /* the tag's spread in units of s: 1 (free) down to (2/(c sqrt(2 pi)))^(1/2) */
    const double spread = 1.0 / sqrt(1.0 + c * sqrt(PI / 2.0));
    const double u_max = 14.0 * spread;
    const int m = 1200; /* Simpson panels: the integrand is smooth on this scale */
    const double h = u_max / m;
    double sum = 0.0;
    for (int i = 1; i <= m; ++i) {
        const double u = i * h, w = i == m ? 1.0 : (i % 2 ? 4.0 : 2.0);
        sum += w * u * single_file_tail(u, c);
    }
    return 4.0 * s * s * sum * h / 3.0;
}

double hsbd_short_time_msd(double t, double rho_gap, double diffusion) {
    return 2.0 * diffusion * t *
           (1.0 - 4.0 / (3.0 * sqrt(2.0 * PI)) * rho_gap * sqrt(4.0 * diffusion * t));
}

/* ---- a reflecting wall with drift (Scala Eq. 9, corrected: docs/theory.md, slips in the papers)
 * ---- */

double hsbd_reflected_drift_density(double x, double x0, double c, double diffusion, double t) {
    const double pi = 3.14159265358979323846, four_dt = 4.0 * diffusion * t;
    const double norm = 1.0 / sqrt(pi * four_dt);
    const double free = norm * exp(-(x - x0 - c * t) * (x - x0 - c * t) / four_dt);
    const double image =
        norm * exp(-c * x0 / diffusion - (x + x0 - c * t) * (x + x0 - c * t) / four_dt);
    const double flux =
        -c / (2.0 * diffusion) * exp(c * x / diffusion) * erfc((x + x0 + c * t) / sqrt(four_dt));
    return free + image + flux;
}

double hsbd_reflected_drift_moment(int k, double x0, double c, double diffusion, double t) {
    /* Simpson's rule on [0, x_max], x_max beyond the free Gaussian and the barometric tail */
    const double spread = sqrt(2.0 * diffusion * t);
    double x_max = x0 + fabs(c) * t + 40.0 * spread;
    if (c < 0 && 40.0 * diffusion / -c < x_max)
        x_max = fmax(x0 + 40.0 * spread, 40.0 * diffusion / -c);
    const int m = 200000;
    const double h = x_max / m;
    double sum = 0;
    for (int j = 0; j <= m; ++j) {
        const double x = j * h, w = j == 0 || j == m ? 1 : j % 2 ? 4 : 2;
        sum += w * pow(x, k) * hsbd_reflected_drift_density(x, x0, c, diffusion, t);
    }
    return sum * h / 3.0;
}

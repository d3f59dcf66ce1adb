/* Closed forms for homogeneous hard and sticky rods. */
#include <math.h>

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

double hsbd_short_time_msd(double t, double rho_gap, double diffusion) {
    return 2.0 * diffusion * t *
           (1.0 - 4.0 / (3.0 * sqrt(2.0 * PI)) * rho_gap * sqrt(4.0 * diffusion * t));
}

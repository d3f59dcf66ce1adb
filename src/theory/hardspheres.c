/* Equations of state and contact values of hard disks and spheres: Carnahan-Starling (3D,
 * one size), Boublik-Mansoori-Carnahan-Starling-Leland (3D mixtures), Henderson (2D disks),
 * and the virial route from contact values to the compressibility factor. */
#include <complex.h>
#include <math.h>

#include "hsbd/theory.h"

static const double PI = 3.14159265358979323846;

double hsbd_hs_contact_cs(double phi) {
    const double q = 1.0 - phi;
    return (1.0 - 0.5 * phi) / (q * q * q);
}

double hsbd_hs_z_cs(double phi) {
    const double q = 1.0 - phi;
    return (1.0 + phi + phi * phi - phi * phi * phi) / (q * q * q);
}

/* Kolafa-Labik-Malijevsky (2004): CS with -(2/3)(phi^3 + phi^4) in the numerator; within
 * ~0.01 % of simulations in the fluid, where CS is 0.26 % low at phi = 0.3 */
double hsbd_hs_z_klm(double phi) {
    const double q = 1.0 - phi;
    return (1.0 + phi + phi * phi - 2.0 / 3.0 * (phi * phi * phi + phi * phi * phi * phi)) /
           (q * q * q);
}

double hsbd_hs_contact_klm(double phi) {
    return (hsbd_hs_z_klm(phi) - 1.0) / (4.0 * phi); /* Z = 1 + 4 phi g(sigma+) */
}

double hsbd_hd_contact_henderson(double phi) {
    const double q = 1.0 - phi;
    return (1.0 - 7.0 / 16.0 * phi) / (q * q);
}

double hsbd_hd_z_henderson(double phi) {
    const double q = 1.0 - phi;
    return (1.0 + phi * phi / 8.0) / (q * q);
}

/* Hard disks: the virial series Z = 1 + sum_k b_k (B2 rho)^(k-1), B2 rho = 2 phi, with the
 * reduced coefficients b_k = B_k / B2^(k-1) for k = 2..10 (Clisby and McCoy, J. Stat. Phys.
 * 122, 15 (2006), Table 1; b3, b4 exact), and the remainder summed as a geometric series
 * with the ratio of the last two terms. The remainder is 0.07 % of Z at phi = 0.4 and
 * 0.6 % at 0.5, so its own uncertainty stays well below 0.1 % up to phi = 0.45. */
double hsbd_hd_z_virial(double phi) {
    static const double b[] = {1.0,       0.782004,  0.53223180, 0.33355604, 0.1988425,
                               0.1148728, 0.0649930, 0.0362193,  0.0199537};
    const size_t nb = sizeof b / sizeof b[0];
    const double x = 2.0 * phi;
    double z = 1.0, power = 1.0, last = 0.0;
    for (size_t k = 0; k < nb; ++k) {
        power *= x;
        last = b[k] * power;
        z += last;
    }
    const double ratio = b[nb - 1] / b[nb - 2] * x;
    return z + last * ratio / (1.0 - ratio);
}

double hsbd_hd_contact_virial(double phi) {
    return (hsbd_hd_z_virial(phi) - 1.0) / (2.0 * phi); /* Z = 1 + 2 phi g(sigma+) in 2D */
}

/* BMCSL contact value of species a and b at number density rho with number fractions x:
 * 1/(1-xi3) + 3 xi2 s/(1-xi3)^2 + 2 xi2^2 s^2/(1-xi3)^3, s = sigma_a sigma_b/(sigma_a+sigma_b),
 * xi_k = (pi/6) rho sum_i x_i sigma_i^k */
double hsbd_hs_contact_bmcsl(size_t ns, const double *x, const double *sigma, double rho, size_t a,
                             size_t b) {
    double xi2 = 0, xi3 = 0;
    for (size_t i = 0; i < ns; ++i) {
        xi2 += x[i] * sigma[i] * sigma[i];
        xi3 += x[i] * sigma[i] * sigma[i] * sigma[i];
    }
    xi2 *= PI / 6 * rho;
    xi3 *= PI / 6 * rho;
    const double q = 1.0 - xi3, s = sigma[a] * sigma[b] / (sigma[a] + sigma[b]);
    return 1.0 / q + 3.0 * xi2 * s / (q * q) + 2.0 * xi2 * xi2 * s * s / (q * q * q);
}

double hsbd_hs_z_from_contacts(int dim, size_t ns, const double *x, const double *sigma, double rho,
                               const double *contact) {
    double sum = 0;
    for (size_t a = 0; a < ns; ++a)
        for (size_t b = 0; b < ns; ++b) {
            const double s = 0.5 * (sigma[a] + sigma[b]);
            sum += x[a] * x[b] * (dim == 3 ? s * s * s : s * s) * contact[a * ns + b];
        }
    return 1.0 + (dim == 3 ? 2.0 * PI / 3.0 : PI / 2.0) * rho * sum;
}

/* ---- dynamics without hydrodynamic interactions (docs/theory.md, "Brownian hard spheres:
 * mixture dynamics") ---- */

static double contact_value(const hsbd_hs_mixture *m, size_t a, size_t b) {
    return m->contact ? m->contact[a * m->nspecies + b] : 1.0;
}

/* the contact surface S_d sigma^(d-1): 4 pi sigma^2 (3D), 2 pi sigma (2D) */
static double contact_surface(int dim, double sigma) {
    return dim == 3 ? 4 * PI * sigma * sigma : 2 * PI * sigma;
}

/* c_a = sum_b rho_b g_ab S_d sigma_ab^(d-1) K(2 (D_a + D_b))^(3/2) s (3 s* - 2 s), with
 * K = 4 / (3 sqrt(2 pi)) the first-collision integral of one reflected coordinate, s* =
 * D_a / (D_a + D_b) and s the share a takes (s = s*: s*^2) */
double hsbd_hs_msd_deficit(const hsbd_hs_mixture *m, size_t a, double share) {
    const double k = 4.0 / (3.0 * sqrt(2.0 * PI)), da = m->diffusion[a];
    double c = 0;
    for (size_t b = 0; b < m->nspecies; ++b) {
        const double drel = da + m->diffusion[b];
        if (!(drel > 0)) continue;
        const double natural = da / drel, s = share < 0 ? natural : share;
        const double sab = 0.5 * (m->sigma[a] + m->sigma[b]);
        c += m->density[b] * contact_value(m, a, b) * contact_surface(m->dimension, sab) * k *
             pow(2 * drel, 1.5) * s * (3 * natural - 2 * s);
    }
    return c;
}

double hsbd_hs_long_time_ratio(const hsbd_hs_mixture *m, size_t a) {
    const double da = m->diffusion[a], d = m->dimension;
    if (!(da > 0)) return NAN;
    const double ball = d == 3 ? 4.0 / 3.0 * PI : PI;
    double sum = 0;
    for (size_t b = 0; b < m->nspecies; ++b) {
        const double sab = 0.5 * (m->sigma[a] + m->sigma[b]);
        sum += m->density[b] * ball * pow(sab, d) * da / (da + m->diffusion[b]);
    }
    return 1 - sum / (d - 1);
}

/* The two-body problem at all times (3D): the relative coordinate started uniformly outside
 * the excluded sphere (radius a, diffusion D) loses (8 pi a^5 / V) Gamma(D t / a^2) of its
 * MSD, where Gamma is the time integral of the mean outward displacement at contact (the
 * l = 1 radial diffusion problem with unit flux); its Laplace transform in P = p a^2 / D is
 * (Z + 1) / ((Z^2 + 2 Z + 2) P^2), Z = sqrt(P) (docs/theory.md). Inverted by the fixed
 * Talbot contour (Abate and Valko 2004) with 24 nodes: 1e-12 relative in double. */
static double excluded_sphere_gamma(double tau) {
    enum { M = 24 };
    const double r = 2.0 * M / (5.0 * tau);
    double sum = 0.5 * exp(r * tau) * (sqrt(r) + 1) / ((r + 2 * sqrt(r) + 2) * r * r);
    for (int k = 1; k < M; ++k) {
        const double th = k * PI / M, cot = cos(th) / sin(th);
        const double complex p = r * th * (cot + I), z = csqrt(p);
        const double complex f = (z + 1) / ((p + 2 * z + 2) * p * p);
        sum += creal(cexp(tau * p) * f * (1 + I * (th + (th * cot - 1) * cot)));
    }
    return r / M * sum;
}

double hsbd_hs_excluded_sphere_gamma(double tau) {
    return tau > 0 ? excluded_sphere_gamma(tau) : 0;
}

/* D_L,a / D_a as the MSD slope between lags t0 < t1 measures it, first order in density:
 * each partner's term of hsbd_hs_long_time_ratio times R = (Gamma(tau1) - Gamma(tau0)) /
 * ((tau1 - tau0) / 2), tau = (D_a + D_b) t / sigma_ab^2 (R -> 1 at long lags) */
double hsbd_hs_msd_slope_ratio(const hsbd_hs_mixture *m, size_t a, double t0, double t1) {
    const double da = m->diffusion[a];
    if (!(da > 0) || m->dimension != 3 || !(t0 >= 0) || !(t1 > t0)) return NAN;
    double sum = 0;
    for (size_t b = 0; b < m->nspecies; ++b) {
        const double sab = 0.5 * (m->sigma[a] + m->sigma[b]), drel = da + m->diffusion[b];
        const double u0 = drel * t0 / (sab * sab), u1 = drel * t1 / (sab * sab);
        const double ratio =
            (hsbd_hs_excluded_sphere_gamma(u1) - hsbd_hs_excluded_sphere_gamma(u0)) /
            (0.5 * (u1 - u0));
        sum += m->density[b] * 4.0 / 3.0 * PI * sab * sab * sab * da / drel * ratio;
    }
    return 1 - sum / 2;
}

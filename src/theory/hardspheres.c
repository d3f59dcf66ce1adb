/* Equations of state and contact values of hard disks and spheres: Carnahan-Starling (3D,
 * one size), Boublik-Mansoori-Carnahan-Starling-Leland (3D mixtures), Henderson (2D disks),
 * and the virial route from contact values to the compressibility factor. */
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

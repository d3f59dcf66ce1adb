/* A user's program built against the installed libhsbd.so (tests/install/test_install.sh):
 * the version, an exact theory value, and a short run of hard rods through the public API
 * (configuration from keys, finalize, the run written to a directory). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <hsbd/hsbd.h>

int main(int argc, char **argv) {
    if (argc != 2) return 2;
    printf("hsbd %s\n", hsbd_version());
    /* Tonks gas: beta P = rho / (1 - rho sigma) */
    const double p = hsbd_tonks_pressure(0.5, 0.5);
    if (fabs(p - 2.0 / 3.0) > 1e-15) {
        fprintf(stderr, "tonks pressure %.17g\n", p);
        return 1;
    }
    hsbd_config cfg;
    hsbd_error err;
    hsbd_config_defaults(&cfg);
    const char *keys[] = {"system.N=20",   "system.L=20", "run.t_total=0.05",
                          "run.t_equil=0", "run.dt=1e-3", "sample.blocks=2"};
    for (size_t k = 0; k < sizeof keys / sizeof *keys; ++k)
        if (hsbd_config_set(&cfg, keys[k], "use_hsbd", &err) != HSBD_OK) {
            fprintf(stderr, "%s\n", err.message);
            return 1;
        }
    snprintf(cfg.output.dir, sizeof cfg.output.dir, "%s", argv[1]);
    if (hsbd_config_finalize(&cfg, &err) != HSBD_OK) {
        fprintf(stderr, "%s\n", err.message);
        return 1;
    }
    const hsbd_run_options opt = {.force = 1};
    if (hsbd_run(&cfg, &opt, &err) != HSBD_OK) {
        fprintf(stderr, "%s\n", err.message);
        return 1;
    }
    /* bad input: an error naming the key */
    if (hsbd_config_set(&cfg, "system.N=-3", "use_hsbd", &err) != HSBD_EINPUT ||
        !strstr(err.message, "system.N")) {
        fprintf(stderr, "no error for N = -3: %s\n", err.message);
        return 1;
    }
    printf("ran %llu steps into %s\n", (unsigned long long)hsbd_config_steps(&cfg), argv[1]);
    return 0;
}

/* The built-in damping policies (docs/optimizer.md). Each is a read-only
 * vtable; per-run state, where needed, lives in the optimizer. */
#include <math.h>

#include "brdffit/optim.h"

#define BF_START_LAMBDA 1e-3

/* Thesis and Marquardt keep no state: lambda starts at 1e-3. */

static void plain_init(void *state, double *lambda, void *user)
{
    (void)state;
    (void)user;
    *lambda = BF_START_LAMBDA;
}

/* --- thesis: x2 on rejection up to 1, /2 on acceptance down to 1e-4 ------- */

static void thesis_accept(void *state, double rho, double *lambda, void *user)
{
    (void)state;
    (void)rho;
    (void)user;
    *lambda = fmax(*lambda * 0.5, 1e-4);
}

static void thesis_reject(void *state, double rho, double *lambda, void *user)
{
    (void)state;
    (void)rho;
    (void)user;
    *lambda = fmin(*lambda * 2.0, 1.0);
}

/* --- Marquardt: x10 on rejection, /10 on acceptance ------------------------ */

static void marquardt_accept(void *state, double rho, double *lambda, void *user)
{
    (void)state;
    (void)rho;
    (void)user;
    *lambda *= 0.1;
}

static void marquardt_reject(void *state, double rho, double *lambda, void *user)
{
    (void)state;
    (void)rho;
    (void)user;
    *lambda *= 10.0;
}

/* --- Nielsen: smooth update from the gain ratio, growing factor nu -------- */

typedef struct nielsen_state {
    double nu;
} nielsen_state;

static void nielsen_init(void *state, double *lambda, void *user)
{
    nielsen_state *s = state;
    (void)user;
    s->nu = 2.0;
    *lambda = BF_START_LAMBDA;
}

static void nielsen_accept(void *state, double rho, double *lambda, void *user)
{
    nielsen_state *s = state;
    double q = 2.0 * rho - 1.0;
    (void)user;
    *lambda *= fmax(1.0 / 3.0, 1.0 - q * q * q);
    s->nu = 2.0;
}

static void nielsen_reject(void *state, double rho, double *lambda, void *user)
{
    nielsen_state *s = state;
    (void)rho;
    (void)user;
    *lambda *= s->nu;
    if (s->nu < 1e150) s->nu *= 2.0;
}

static const brdffit_damping thesis_policy = {
    sizeof(brdffit_damping), "thesis", 0, plain_init, thesis_accept, thesis_reject, NULL};

static const brdffit_damping marquardt_policy = {
    sizeof(brdffit_damping), "marquardt", 0, plain_init, marquardt_accept, marquardt_reject, NULL};

static const brdffit_damping nielsen_policy = {
    sizeof(brdffit_damping), "nielsen", sizeof(nielsen_state), nielsen_init, nielsen_accept,
    nielsen_reject,          NULL};

const brdffit_damping *brdffit_damping_thesis(void)
{
    return &thesis_policy;
}

const brdffit_damping *brdffit_damping_marquardt(void)
{
    return &marquardt_policy;
}

const brdffit_damping *brdffit_damping_nielsen(void)
{
    return &nielsen_policy;
}

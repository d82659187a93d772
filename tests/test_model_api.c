/* The model API: built-in names and metadata, the parameter vector layout,
 * user models through brdffit_model_def (creation, validation, evaluation,
 * Jacobian check, destroy callback), evaluation errors and allocation
 * failures. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "model_fixtures.h"
#include "models/model_internal.h"
#include "test_support.h"

#define PI 3.14159265358979323846

/* ---- a user model -------------------------------------------------------- */

/* value_c = cd_c / pi + t_c^2 nv exp(-g (1 - nh)), parameters in the order
 * (cd: per-channel, linear; g: shared, log-scale; t: per-channel), so that
 * a shared parameter sits between two per-channel ones. */
typedef enum user_mode { USER_OK, USER_FAIL, USER_NAN, USER_WRONG_DERIVATIVE } user_mode;

typedef struct user_state {
    user_mode mode;
    int evals, destroys;
    double skew; /* USER_WRONG_DERIVATIVE: relative error of d/dt on channel 1 */
} user_state;

static brdffit_status user_eval(const brdffit_batch *b, const double *p, size_t nc, double *values,
                                double *jac, void *user)
{
    user_state *us = user;
    const double g = p[nc];
    size_t c, s, n = b->n;
    us->evals++;
    assert_true(b->struct_size >= sizeof(brdffit_batch));
    if (us->mode == USER_FAIL) return BRDFFIT_E_RANGE;
    for (c = 0; c < nc; c++) {
        const double cd = p[c], t = p[nc + 1 + c];
        for (s = 0; s < n; s++) {
            const double e = exp(-g * (1.0 - b->nh[s])) * b->nv[s];
            values[c * n + s] = cd / PI + t * t * e;
            if (jac == NULL) continue;
            jac[(0 * nc + c) * n + s] = 1.0 / PI;
            jac[(1 * nc + c) * n + s] = -(1.0 - b->nh[s]) * t * t * e;
            jac[(2 * nc + c) * n + s] = 2.0 * t * e;
            if (us->mode == USER_WRONG_DERIVATIVE && c == 1)
                jac[(2 * nc + c) * n + s] *= 1.0 + us->skew;
        }
    }
    if (us->mode == USER_NAN) values[1 * n + (n > 3 ? 3 : 0)] = NAN;
    return BRDFFIT_OK;
}

static void user_destroy(void *user)
{
    ((user_state *)user)->destroys++;
}

static const brdffit_param_info user_params[] = {
    {"cd", BRDFFIT_PARAM_PER_CHANNEL | BRDFFIT_PARAM_LINEAR, 0.0, HUGE_VAL, 0.3},
    {"g", BRDFFIT_PARAM_LOG_SCALE, 0.5, 100.0, 5.0},
    {"t", BRDFFIT_PARAM_PER_CHANNEL, -2.0, 2.0, 0.5},
};

static brdffit_model_def user_def(user_state *us, brdffit_param_info *params)
{
    brdffit_model_def def;
    brdffit_model_def_init(&def);
    memcpy(params, user_params, sizeof user_params);
    def.name = "user";
    def.n_params = 3;
    def.params = params;
    def.eval = user_eval;
    def.user = us;
    def.destroy = user_destroy;
    return def;
}

static brdffit_model *create_user(user_state *us)
{
    brdffit_param_info params[3];
    brdffit_model_def def = user_def(us, params);
    brdffit_model *m = NULL;
    brdffit_error err;
    assert_int_equal(brdffit_model_create_custom(&m, &def, NULL, &err), BRDFFIT_OK);
    return m;
}

static void assert_report_below(const brdffit_jacobian_report *r, double tol)
{
    if (!(r->worst_error < tol))
        fail_msg("worst relative error %.3g >= %g at param %zu, channel %zu, sample %zu "
                 "(analytic %.17g, numeric %.17g)",
                 r->worst_error, tol, r->param, r->channel, r->sample, r->analytic, r->numeric);
}

/* ---- built-in names and metadata ------------------------------------------ */

static void test_builtin_names(void **state)
{
    static const char *const expected[] = {
        "lambert",
        "phong",
        "blinn-phong",
        "ashikhmin-shirley",
        "ashikhmin-shirley-fresnel",
        "ashikhmin-shirley-2",
        "cook-torrance",
        "cook-torrance-2",
        "ggx",
        "ggx-2",
        "ward",
        "ward-duer",
        "lafortune",
        "gltf",
        "gltf-clearcoat",
        "openpbr",
        "openpbr-coat",
    };
    const size_t n = sizeof expected / sizeof expected[0];
    size_t i, j;
    (void)state;
    assert_int_equal(brdffit_model_builtin_count(), n);
    for (i = 0; i < n; i++) {
        int found = 0;
        brdffit_model *m = NULL;
        for (j = 0; j < n; j++) found += strcmp(brdffit_model_builtin_name(j), expected[i]) == 0;
        assert_int_equal(found, 1);
        assert_int_equal(brdffit_model_create(&m, expected[i], NULL, NULL), BRDFFIT_OK);
        assert_string_equal(brdffit_model_name(m), expected[i]);
        brdffit_model_destroy(m);
    }
    assert_null(brdffit_model_builtin_name(n));
    assert_null(brdffit_model_builtin_name((size_t)-1));
}

static void test_create_errors(void **state)
{
    brdffit_model *m = (brdffit_model *)&m;
    brdffit_error err;
    brdffit_allocator half = {NULL, NULL, NULL};
    (void)state;
    assert_int_equal(brdffit_model_create(&m, "no-such-model", NULL, &err), BRDFFIT_E_NOT_FOUND);
    assert_null(m);
    assert_int_equal(err.status, BRDFFIT_E_NOT_FOUND);
    assert_non_null(strstr(err.message, "no-such-model"));
    assert_int_equal(brdffit_model_create(&m, "", NULL, NULL), BRDFFIT_E_NOT_FOUND);
    assert_int_equal(brdffit_model_create(&m, "GGX", NULL, NULL), BRDFFIT_E_NOT_FOUND);
    assert_int_equal(brdffit_model_create(&m, NULL, NULL, NULL), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_model_create(NULL, "ggx", NULL, NULL), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_model_create(&m, "ggx", &half, NULL), BRDFFIT_E_INVALID_ARGUMENT);
    assert_null(m);
    brdffit_model_destroy(NULL);
}

static int is_flag(const brdffit_param_info *p, unsigned f)
{
    return (p->flags & f) != 0;
}

/* Shapes first, colours per-channel linear in [0, inf), exponents and
 * roughness log-scale with the documented ranges, Fresnel terms in [0, 1],
 * F0 fixed at 0.04 by default. */
static void test_builtin_metadata(void **state)
{
    size_t i, k;
    (void)state;
    for (i = 0; i < brdffit_model_builtin_count(); i++) {
        brdffit_model *m = NULL;
        int seen_linear = 0;
        if (strncmp(brdffit_model_builtin_name(i), "gltf", 4) == 0 ||
            strncmp(brdffit_model_builtin_name(i), "openpbr", 7) == 0)
            continue; /* test_gltf_metadata, test_openpbr_metadata */
        assert_int_equal(brdffit_model_create(&m, brdffit_model_builtin_name(i), NULL, NULL),
                         BRDFFIT_OK);
        for (k = 0; k < brdffit_model_param_count(m); k++) {
            const brdffit_param_info *p = brdffit_model_param(m, k);
            size_t found = 99;
            assert_true(p->lower <= p->start && p->start <= p->upper);
            assert_int_equal(brdffit_model_param_find(m, p->name, &found), BRDFFIT_OK);
            assert_int_equal(found, k);
            if (is_flag(p, BRDFFIT_PARAM_LINEAR)) {
                seen_linear = 1;
                assert_true(is_flag(p, BRDFFIT_PARAM_PER_CHANNEL));
                assert_true(p->name[0] == 'c');
                assert_true(p->lower == 0.0 && p->upper == HUGE_VAL);
                continue;
            }
            assert_false(seen_linear);
            assert_false(is_flag(p, BRDFFIT_PARAM_PER_CHANNEL));
            if (is_flag(p, BRDFFIT_PARAM_LOG_SCALE) && p->upper > 10.0) {
                assert_true(p->lower == 1e-3 && p->upper == 1e6);
            } else if (is_flag(p, BRDFFIT_PARAM_LOG_SCALE)) {
                assert_true(p->lower == 1e-4 && p->upper == 1.0);
                assert_true(p->start >= 0.05 && p->start <= 0.5);
            } else {
                assert_true(p->lower == 0.0 && p->upper == 1.0);
            }
            if (strcmp(p->name, "F0") == 0) {
                assert_true(is_flag(p, BRDFFIT_PARAM_FIXED));
                assert_true(p->start == 0.04);
            } else {
                assert_false(is_flag(p, BRDFFIT_PARAM_FIXED));
            }
        }
        assert_true(seen_linear);
        assert_null(brdffit_model_param(m, brdffit_model_param_count(m)));
        brdffit_model_destroy(m);
    }
}

/* The OpenPBR models: OpenPBR Surface 1.1's own names and ranges
 * (roughnesses floored at 0.01 as glTF's, specular_ior 1.1 .. 3), shapes
 * first, base_color per channel but not LINEAR; openpbr-coat adds the
 * coat's weight and roughness and holds specular_ior at 1.5. */
static void test_openpbr_metadata(void **state)
{
    static const struct {
        const char *name;
        unsigned flags;
        double lower, upper, start;
    } want[] = {
        {"specular_roughness", BRDFFIT_PARAM_LOG_SCALE, 0.01, 1.0, 0.5},
        {"base_metalness", 0, 0.0, 1.0, 0.5},
        {"specular_ior", 0, 1.1, 3.0, 1.5},
        {"coat_weight", BRDFFIT_PARAM_LOG_SCALE, 0.01, 1.0, 0.5},
        {"coat_roughness", BRDFFIT_PARAM_LOG_SCALE, 0.01, 1.0, 0.1},
        {"base_color", BRDFFIT_PARAM_PER_CHANNEL, 0.0, 1.0, 0.5},
    };
    static const size_t plain[] = {0, 1, 2, 5}, coat[] = {0, 1, 2, 3, 4, 5};
    brdffit_model *m = NULL;
    size_t k, pass;
    (void)state;
    for (pass = 0; pass < 2; pass++) {
        const size_t *idx = pass == 0 ? plain : coat, n = pass == 0 ? 4 : 6;
        assert_int_equal(brdffit_model_create(&m, pass == 0 ? "openpbr" : "openpbr-coat", NULL,
                                              NULL),
                         BRDFFIT_OK);
        assert_int_equal(brdffit_model_param_count(m), n);
        for (k = 0; k < n; k++) {
            const brdffit_param_info *p = brdffit_model_param(m, k);
            const unsigned fixed = pass == 1 && k == 2 ? BRDFFIT_PARAM_FIXED : 0;
            assert_string_equal(p->name, want[idx[k]].name);
            assert_int_equal(p->flags, want[idx[k]].flags | fixed);
            assert_true(p->lower == want[idx[k]].lower && p->upper == want[idx[k]].upper);
            assert_true(p->start == want[idx[k]].start);
        }
        assert_int_equal(brdffit_model_vector_size(m, 3), n + 2);
        brdffit_model_destroy(m);
    }
}

/* The glTF models: glTF's own names and ranges (roughnesses floored at
 * 0.01, alpha = 1e-4), shapes first, the colour per channel but not LINEAR
 * (the models are affine in it, docs/models.md), nothing fixed. */
static void test_gltf_metadata(void **state)
{
    static const struct {
        const char *name;
        unsigned flags;
        double lower, upper, start;
    } want[] = {
        {"roughness", BRDFFIT_PARAM_LOG_SCALE, 0.01, 1.0, 0.5},
        {"metallic", 0, 0.0, 1.0, 0.5},
        {"baseColor", BRDFFIT_PARAM_PER_CHANNEL, 0.0, 1.0, 0.5},
    };
    brdffit_model *m = NULL;
    size_t k;
    (void)state;
    assert_int_equal(brdffit_model_create(&m, "gltf", NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_model_param_count(m), 3);
    for (k = 0; k < 3; k++) {
        const brdffit_param_info *p = brdffit_model_param(m, k);
        assert_string_equal(p->name, want[k].name);
        assert_int_equal(p->flags, want[k].flags);
        assert_true(p->lower == want[k].lower && p->upper == want[k].upper);
        assert_true(p->start == want[k].start);
    }
    assert_int_equal(brdffit_model_vector_size(m, 3), 5);
    brdffit_model_destroy(m);
    /* gltf-clearcoat: the same, with the coat's two after metallic */
    assert_int_equal(brdffit_model_create(&m, "gltf-clearcoat", NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_model_param_count(m), 5);
    for (k = 0; k < 5; k++) {
        const brdffit_param_info *p = brdffit_model_param(m, k);
        const size_t w = k < 2 ? k : (k == 4 ? 2 : 0);
        if (k == 2 || k == 3) {
            assert_string_equal(p->name, k == 2 ? "clearcoat" : "clearcoatRoughness");
            assert_int_equal(p->flags, BRDFFIT_PARAM_LOG_SCALE);
            assert_true(p->lower == 0.01 && p->upper == 1.0);
            assert_true(p->start == (k == 2 ? 0.5 : 0.1));
            continue;
        }
        assert_string_equal(p->name, want[w].name);
        assert_int_equal(p->flags, want[w].flags);
        assert_true(p->lower == want[w].lower && p->upper == want[w].upper);
        assert_true(p->start == want[w].start);
    }
    assert_int_equal(brdffit_model_vector_size(m, 3), 7);
    brdffit_model_destroy(m);
}

static void test_param_find(void **state)
{
    brdffit_model *m = NULL;
    size_t index = 99;
    (void)state;
    assert_int_equal(brdffit_model_create(&m, "ashikhmin-shirley-fresnel", NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_model_param_find(m, "Rs", &index), BRDFFIT_OK);
    assert_int_equal(index, 1);
    assert_int_equal(brdffit_model_param_find(m, "rs", &index), BRDFFIT_E_NOT_FOUND);
    assert_int_equal(brdffit_model_param_find(m, "", &index), BRDFFIT_E_NOT_FOUND);
    assert_int_equal(brdffit_model_param_find(m, NULL, &index), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_model_param_find(m, "ns", NULL), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_model_param_find(NULL, "ns", &index), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(index, 1);
    assert_string_equal(brdffit_model_param(m, 0)->name, "ns");
    assert_null(brdffit_model_name(NULL));
    assert_int_equal(brdffit_model_param_count(NULL), 0);
    assert_null(brdffit_model_param(NULL, 0));
    brdffit_model_destroy(m);
}

/* ---- the vector layout ----------------------------------------------------- */

static void test_vector_layout_builtin(void **state)
{
    brdffit_model *m = NULL;
    double x[16];
    (void)state;
    /* cook-torrance-2: m1, m2, F0 shared; cd, cs1, cs2 per channel */
    assert_int_equal(brdffit_model_create(&m, "cook-torrance-2", NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_model_vector_size(m, 1), 6);
    assert_int_equal(brdffit_model_vector_size(m, 3), 12);
    assert_int_equal(brdffit_model_vector_size(m, 0), 0);
    assert_int_equal(brdffit_model_vector_size(NULL, 3), 0);
    assert_int_equal(brdffit_model_vector_index(m, 0, 0, 3), 0);
    assert_int_equal(brdffit_model_vector_index(m, 1, 2, 3), 1); /* channel ignored */
    assert_int_equal(brdffit_model_vector_index(m, 2, 77, 3), 2);
    assert_int_equal(brdffit_model_vector_index(m, 3, 0, 3), 3);
    assert_int_equal(brdffit_model_vector_index(m, 3, 2, 3), 5);
    assert_int_equal(brdffit_model_vector_index(m, 4, 1, 3), 7);
    assert_int_equal(brdffit_model_vector_index(m, 5, 2, 3), 11);
    assert_int_equal(brdffit_model_vector_index(m, 5, 3, 3), (size_t)-1);
    assert_int_equal(brdffit_model_vector_index(m, 6, 0, 3), (size_t)-1);
    assert_int_equal(brdffit_model_vector_index(m, 0, 0, 0), (size_t)-1);
    assert_int_equal(brdffit_model_vector_index(NULL, 0, 0, 3), (size_t)-1);
    assert_int_equal(brdffit_model_default_params(m, 3, x), BRDFFIT_OK);
    assert_true(x[0] == 0.3 && x[1] == 0.1 && x[2] == 0.04);
    assert_true(x[3] == 0.2 && x[5] == 0.2 && x[6] == 1.0 && x[11] == 1.0);
    assert_int_equal(brdffit_model_default_params(m, 0, x), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_model_default_params(m, 3, NULL), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_model_default_params(NULL, 3, x), BRDFFIT_E_INVALID_ARGUMENT);
    brdffit_model_destroy(m);
}

static void test_vector_layout_user(void **state)
{
    user_state us = {USER_OK, 0, 0, 0.0};
    brdffit_model *m = create_user(&us);
    double x[8];
    size_t c;
    (void)state;
    /* cd (per-channel), g (shared), t (per-channel) with 2 channels:
     * [cd0, cd1, g, t0, t1] */
    assert_int_equal(brdffit_model_vector_size(m, 2), 5);
    for (c = 0; c < 2; c++) {
        assert_int_equal(brdffit_model_vector_index(m, 0, c, 2), c);
        assert_int_equal(brdffit_model_vector_index(m, 1, c, 2), 2);
        assert_int_equal(brdffit_model_vector_index(m, 2, c, 2), 3 + c);
    }
    assert_int_equal(brdffit_model_default_params(m, 2, x), BRDFFIT_OK);
    assert_true(x[0] == 0.3 && x[1] == 0.3 && x[2] == 5.0 && x[3] == 0.5 && x[4] == 0.5);
    brdffit_model_destroy(m);
    assert_int_equal(us.destroys, 1);
}

/* ---- user models ------------------------------------------------------------ */

static void test_user_model_eval(void **state)
{
    user_state us = {USER_OK, 0, 0, 0.0};
    brdffit_model *m = create_user(&us);
    const double ti[2] = {0.3, 0.0}, pi[2] = {PI, 1.0}, to[2] = {0.5, 0.0}, po[2] = {0.2, 2.0};
    const double x[5] = {0.2, 0.4, 3.0, 0.7, -1.5};
    double v[4], jac[3 * 2 * 2];
    brdffit_error err;
    size_t s, c;
    (void)state;
    assert_int_equal(brdffit_model_eval_angles(m, 2, ti, pi, to, po, 2, x, v, jac, &err),
                     BRDFFIT_OK);
    assert_int_equal(us.evals, 1);
    for (s = 0; s < 2; s++) {
        double l[3], vv[3], h[3], len, nh;
        l[0] = sin(ti[s]) * cos(pi[s]);
        l[1] = sin(ti[s]) * sin(pi[s]);
        l[2] = cos(ti[s]);
        vv[0] = sin(to[s]) * cos(po[s]);
        vv[1] = sin(to[s]) * sin(po[s]);
        vv[2] = cos(to[s]);
        for (c = 0; c < 3; c++) h[c] = l[c] + vv[c];
        len = sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
        nh = h[2] / len;
        for (c = 0; c < 2; c++) {
            const double e = exp(-x[2] * (1.0 - nh)) * vv[2];
            assert_close(v[c * 2 + s], x[c] / PI + x[3 + c] * x[3 + c] * e, 1e-12);
            assert_close(jac[(2 * 2 + c) * 2 + s], 2.0 * x[3 + c] * e, 1e-12);
        }
    }
    brdffit_model_destroy(m);
    assert_int_equal(us.destroys, 1);
}

static void test_user_model_jacobian_check(void **state)
{
    user_state us = {USER_OK, 0, 0, 0.0};
    brdffit_model *m = create_user(&us);
    brdffit_grid *grid = mf_default_grid(2);
    brdffit_jacobian_report r;
    brdffit_error err;
    double x[5] = {0.2, 0.4, 3.0, 0.7, -1.5};
    (void)state;
    assert_non_null(grid);
    memset(&r, 0, sizeof r);
    r.struct_size = sizeof r;
    assert_int_equal(brdffit_model_check_jacobian(m, grid, x, &r, &err), BRDFFIT_OK);
    assert_report_below(&r, 1e-6);
    assert_true(us.evals > 0);

    /* at the bounds the stencil is one-sided and stays inside them */
    x[2] = 0.5; /* g at its lower bound */
    x[4] = 2.0; /* t1 at its upper bound */
    assert_int_equal(brdffit_model_check_jacobian(m, grid, x, &r, &err), BRDFFIT_OK);
    assert_report_below(&r, 1e-6);
    x[2] = 100.0; /* g at its upper bound */
    x[3] = -2.0;  /* t0 at its lower bound */
    assert_int_equal(brdffit_model_check_jacobian(m, grid, x, &r, &err), BRDFFIT_OK);
    assert_report_below(&r, 1e-6);

    /* outside the bounds, NaN, bad report size */
    x[2] = 200.0;
    assert_int_equal(brdffit_model_check_jacobian(m, grid, x, &r, &err),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "\"g\""));
    x[2] = NAN;
    assert_int_equal(brdffit_model_check_jacobian(m, grid, x, &r, &err),
                     BRDFFIT_E_INVALID_ARGUMENT);
    x[2] = 3.0;
    r.struct_size = 8;
    assert_int_equal(brdffit_model_check_jacobian(m, grid, x, &r, &err),
                     BRDFFIT_E_INVALID_ARGUMENT);
    r.struct_size = sizeof r;
    assert_int_equal(brdffit_model_check_jacobian(NULL, grid, x, &r, &err),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_model_check_jacobian(m, NULL, x, &r, &err),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_model_check_jacobian(m, grid, NULL, &r, &err),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_model_check_jacobian(m, grid, x, NULL, &err),
                     BRDFFIT_E_INVALID_ARGUMENT);

    /* a wrong derivative is found and located: t (param 2), channel 1 */
    us.mode = USER_WRONG_DERIVATIVE;
    us.skew = 0.01;
    assert_int_equal(brdffit_model_check_jacobian(m, grid, x, &r, &err), BRDFFIT_OK);
    assert_true(r.worst_error > 0.0099 && r.worst_error < 0.0101);
    assert_int_equal(r.param, 2);
    assert_int_equal(r.channel, 1);
    assert_true(r.sample < brdffit_grid_sample_count(grid));
    assert_close(r.analytic, 1.01 * r.numeric, 1e-6);
    assert_true(mf_independent_jacobian_error(m, grid, x, NULL) > 0.0099);
    /* also a small one: the rounding allowance does not hide it */
    us.skew = 1e-4;
    assert_int_equal(brdffit_model_check_jacobian(m, grid, x, &r, &err), BRDFFIT_OK);
    assert_true(r.worst_error > 0.99e-4 && r.worst_error < 1.01e-4);
    assert_int_equal(r.param, 2);
    assert_int_equal(r.channel, 1);

    brdffit_grid_destroy(grid);
    brdffit_model_destroy(m);
    assert_int_equal(us.destroys, 1);
}

/* A parameter whose bounds leave no room for a step is not checked. */
static void test_jacobian_check_degenerate_bounds(void **state)
{
    user_state us = {USER_WRONG_DERIVATIVE, 0, 0, 0.01};
    brdffit_param_info params[3];
    brdffit_model_def def = user_def(&us, params);
    brdffit_model *m = NULL;
    brdffit_grid *grid = mf_default_grid(2);
    brdffit_jacobian_report r;
    const double x[5] = {0.2, 0.4, 3.0, 0.7, 0.7};
    (void)state;
    params[2].lower = params[2].upper = params[2].start = 0.7; /* t: a constant */
    assert_int_equal(brdffit_model_create_custom(&m, &def, NULL, NULL), BRDFFIT_OK);
    r.struct_size = sizeof r;
    assert_int_equal(brdffit_model_check_jacobian(m, grid, x, &r, NULL), BRDFFIT_OK);
    assert_report_below(&r, 1e-6);
    brdffit_grid_destroy(grid);
    brdffit_model_destroy(m);
}

static void test_user_model_failures(void **state)
{
    user_state us = {USER_FAIL, 0, 0, 0.0};
    brdffit_model *m = create_user(&us);
    brdffit_grid *grid = mf_default_grid(2);
    const double x[5] = {0.2, 0.4, 3.0, 0.7, -1.5};
    const double ti[5] = {0}, pi[5] = {0}, to[5] = {0}, po[5] = {0};
    double v[10], big[2 * 100];
    brdffit_jacobian_report r;
    brdffit_error err;
    (void)state;
    assert_non_null(grid);
    r.struct_size = sizeof r;
    assert_int_equal(brdffit_model_eval_angles(m, 5, ti, pi, to, po, 2, x, v, NULL, &err),
                     BRDFFIT_E_MODEL_FAILED);
    assert_int_equal(err.status, BRDFFIT_E_MODEL_FAILED);
    assert_non_null(strstr(err.message, "\"user\""));
    assert_non_null(strstr(err.message, "BRDFFIT_E_RANGE"));
    assert_int_equal(brdffit_model_eval_grid(m, grid, 10, 100, x, big, NULL, &err),
                     BRDFFIT_E_MODEL_FAILED);
    assert_int_equal(brdffit_model_check_jacobian(m, grid, x, &r, &err), BRDFFIT_E_MODEL_FAILED);

    us.mode = USER_NAN; /* NaN at sample 3 of channel 1 */
    assert_int_equal(brdffit_model_eval_angles(m, 5, ti, pi, to, po, 2, x, v, NULL, &err),
                     BRDFFIT_E_NONFINITE);
    assert_int_equal(err.status, BRDFFIT_E_NONFINITE);
    assert_non_null(strstr(err.message, "\"user\""));
    assert_non_null(strstr(err.message, "sample 3,"));
    assert_non_null(strstr(err.message, "channel 1"));
    /* in a grid range the sample is the grid's */
    assert_int_equal(brdffit_model_eval_grid(m, grid, 10, 100, x, big, NULL, &err),
                     BRDFFIT_E_NONFINITE);
    assert_non_null(strstr(err.message, "sample 13,"));
    assert_int_equal(brdffit_model_check_jacobian(m, grid, x, &r, &err), BRDFFIT_E_NONFINITE);

    brdffit_grid_destroy(grid);
    brdffit_model_destroy(m);
    assert_int_equal(us.destroys, 1);
}

/* A NaN derivative is named with its parameter. */
static brdffit_status nan_derivative_eval(const brdffit_batch *b, const double *p, size_t nc,
                                          double *values, double *jac, void *user)
{
    size_t i;
    (void)p;
    (void)user;
    for (i = 0; i < nc * b->n; i++) values[i] = 1.0;
    if (jac != NULL) {
        for (i = 0; i < 2 * nc * b->n; i++) jac[i] = 0.0;
        jac[(1 * nc + 0) * b->n + 2] = HUGE_VAL;
    }
    return BRDFFIT_OK;
}

static void test_nonfinite_derivative(void **state)
{
    const brdffit_param_info params[2] = {
        {"alpha", 0, -1.0, 1.0, 0.0},
        {"beta", BRDFFIT_PARAM_PER_CHANNEL, -1.0, 1.0, 0.0},
    };
    brdffit_model_def def = BRDFFIT_MODEL_DEF_INIT;
    brdffit_model *m = NULL;
    const double a[4] = {0.1, 0.2, 0.3, 0.4}, x[2] = {0.0, 0.0};
    double v[4], jac[8];
    brdffit_error err;
    (void)state;
    def.name = "nanjac";
    def.n_params = 2;
    def.params = params;
    def.eval = nan_derivative_eval;
    assert_int_equal(brdffit_model_create_custom(&m, &def, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_model_eval_angles(m, 4, a, a, a, a, 1, x, v, NULL, &err), BRDFFIT_OK);
    assert_int_equal(brdffit_model_eval_angles(m, 4, a, a, a, a, 1, x, v, jac, &err),
                     BRDFFIT_E_NONFINITE);
    assert_non_null(strstr(err.message, "\"beta\""));
    assert_non_null(strstr(err.message, "sample 2,"));
    brdffit_model_destroy(m);
}

/* Near DBL_MAX the check's own steps may overflow: a stencil point beyond
 * DBL_MAX, or values that overflow only at a stencil point, move the check
 * to a one-sided stencil instead of blaming the model. f = 4 x with the
 * derivative *user (4 is right). */
static brdffit_status linear_eval(const brdffit_batch *b, const double *p, size_t nc,
                                  double *values, double *jac, void *user)
{
    size_t i;
    for (i = 0; i < nc * b->n; i++) {
        values[i] = 4.0 * p[0];
        if (jac != NULL) jac[i] = *(const double *)user;
    }
    return BRDFFIT_OK;
}

static void check_linear_at(double x, double slope, double want_lo, double want_hi)
{
    const brdffit_param_info param = {"x", 0, 0.0, HUGE_VAL, 1.0};
    brdffit_model_def def = BRDFFIT_MODEL_DEF_INIT;
    brdffit_model *m = NULL;
    brdffit_grid *grid = mf_default_grid(1);
    brdffit_jacobian_report r;
    brdffit_error err;
    def.name = "four-x";
    def.n_params = 1;
    def.params = &param;
    def.eval = linear_eval;
    def.user = &slope;
    assert_int_equal(brdffit_model_create_custom(&m, &def, NULL, NULL), BRDFFIT_OK);
    memset(&r, 0, sizeof r);
    r.struct_size = sizeof r;
    if (brdffit_model_check_jacobian(m, grid, &x, &r, &err) != BRDFFIT_OK)
        fail_msg("x = %g: %s", x, err.message);
    if (!(r.worst_error >= want_lo && r.worst_error <= want_hi))
        fail_msg("x = %g: worst error %g outside [%g, %g]", x, r.worst_error, want_lo, want_hi);
    brdffit_grid_destroy(grid);
    brdffit_model_destroy(m);
}

static void test_jacobian_check_near_dbl_max(void **state)
{
    const double edge = DBL_MAX / 4.0 * (1.0 - 1e-7); /* 4 (x + h) overflows, 4 x not */
    brdffit_model *m = NULL;
    brdffit_grid *grid = mf_default_grid(3);
    brdffit_jacobian_report r;
    brdffit_error err;
    double x[3] = {DBL_MAX, DBL_MAX, 1e308};
    (void)state;
    check_linear_at(edge, 4.0, 0.0, 1e-6);
    check_linear_at(edge, 8.0, 0.99, 1.01); /* a wrong derivative is still found there */
    check_linear_at(DBL_MAX / 4.0, 4.0, 0.0, 1e-6);
    assert_int_equal(brdffit_model_create(&m, "lambert", NULL, NULL), BRDFFIT_OK);
    memset(&r, 0, sizeof r);
    r.struct_size = sizeof r;
    if (brdffit_model_check_jacobian(m, grid, x, &r, &err) != BRDFFIT_OK)
        fail_msg("lambert at cd = DBL_MAX: %s", err.message);
    assert_report_below(&r, 1e-6);
    brdffit_grid_destroy(grid);
    brdffit_model_destroy(m);
}

/* ---- create_custom validation ------------------------------------------------ */

typedef void (*def_mutator)(brdffit_model_def *def, brdffit_param_info *params);

static void mut_struct_size_zero(brdffit_model_def *d, brdffit_param_info *p)
{
    (void)p;
    d->struct_size = 0;
}
static void mut_struct_size_small(brdffit_model_def *d, brdffit_param_info *p)
{
    (void)p;
    d->struct_size = offsetof(brdffit_model_def, destroy);
}
static void mut_name_null(brdffit_model_def *d, brdffit_param_info *p)
{
    (void)p;
    d->name = NULL;
}
static void mut_name_empty(brdffit_model_def *d, brdffit_param_info *p)
{
    (void)p;
    d->name = "";
}
static void mut_no_params(brdffit_model_def *d, brdffit_param_info *p)
{
    (void)p;
    d->n_params = 0;
}
static void mut_too_many_params(brdffit_model_def *d, brdffit_param_info *p)
{
    (void)p;
    d->n_params = 1025;
}
static void mut_params_null(brdffit_model_def *d, brdffit_param_info *p)
{
    (void)p;
    d->params = NULL;
}
static void mut_eval_null(brdffit_model_def *d, brdffit_param_info *p)
{
    (void)p;
    d->eval = NULL;
}
static void mut_param_name_null(brdffit_model_def *d, brdffit_param_info *p)
{
    (void)d;
    p[1].name = NULL;
}
static void mut_param_name_empty(brdffit_model_def *d, brdffit_param_info *p)
{
    (void)d;
    p[1].name = "";
}
static void mut_duplicate_name(brdffit_model_def *d, brdffit_param_info *p)
{
    (void)d;
    p[2].name = "cd";
}
static void mut_start_below(brdffit_model_def *d, brdffit_param_info *p)
{
    (void)d;
    p[1].start = 0.25;
}
static void mut_start_above(brdffit_model_def *d, brdffit_param_info *p)
{
    (void)d;
    p[2].start = 2.5;
}
static void mut_lower_above_upper(brdffit_model_def *d, brdffit_param_info *p)
{
    (void)d;
    p[2].lower = 3.0;
    p[2].upper = 1.0;
    p[2].start = 2.0;
}
static void mut_nan_lower(brdffit_model_def *d, brdffit_param_info *p)
{
    (void)d;
    p[2].lower = NAN;
}
static void mut_nan_upper(brdffit_model_def *d, brdffit_param_info *p)
{
    (void)d;
    p[2].upper = NAN;
}
static void mut_nan_start(brdffit_model_def *d, brdffit_param_info *p)
{
    (void)d;
    p[2].start = NAN;
}
static void mut_infinite_start(brdffit_model_def *d, brdffit_param_info *p)
{
    (void)d;
    p[0].start = HUGE_VAL;
}
static void mut_log_lower_zero(brdffit_model_def *d, brdffit_param_info *p)
{
    (void)d;
    p[1].lower = 0.0;
}
static void mut_log_lower_negative(brdffit_model_def *d, brdffit_param_info *p)
{
    (void)d;
    p[2].flags |= BRDFFIT_PARAM_LOG_SCALE; /* t has lower -2 */
}
static void mut_unknown_flag(brdffit_model_def *d, brdffit_param_info *p)
{
    (void)d;
    p[1].flags |= 16u;
}
static void mut_linear_shared(brdffit_model_def *d, brdffit_param_info *p)
{
    (void)d;
    p[1].flags |= BRDFFIT_PARAM_LINEAR;
}

static void test_create_custom_validation(void **state)
{
    static const struct {
        const char *what;
        def_mutator mutate;
    } cases[] = {
        {"struct_size 0", mut_struct_size_zero},
        {"struct_size too small", mut_struct_size_small},
        {"name NULL", mut_name_null},
        {"name empty", mut_name_empty},
        {"no parameters", mut_no_params},
        {"too many parameters", mut_too_many_params},
        {"params NULL", mut_params_null},
        {"eval NULL", mut_eval_null},
        {"parameter name NULL", mut_param_name_null},
        {"parameter name empty", mut_param_name_empty},
        {"duplicate names", mut_duplicate_name},
        {"start below lower", mut_start_below},
        {"start above upper", mut_start_above},
        {"lower above upper", mut_lower_above_upper},
        {"NaN lower", mut_nan_lower},
        {"NaN upper", mut_nan_upper},
        {"NaN start", mut_nan_start},
        {"infinite start", mut_infinite_start},
        {"log scale with lower 0", mut_log_lower_zero},
        {"log scale with lower < 0", mut_log_lower_negative},
        {"unknown flag bits", mut_unknown_flag},
        {"linear but shared", mut_linear_shared},
    };
    size_t i;
    (void)state;
    for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        user_state us = {USER_OK, 0, 0, 0.0};
        brdffit_param_info params[3];
        brdffit_model_def def = user_def(&us, params);
        brdffit_model *m = (brdffit_model *)&m;
        brdffit_error err;
        counting_alloc ca;
        counting_alloc_init(&ca, 0);
        cases[i].mutate(&def, params);
        err.status = BRDFFIT_OK;
        if (brdffit_model_create_custom(&m, &def, &ca.hook, &err) != BRDFFIT_E_INVALID_ARGUMENT)
            fail_msg("%s: not rejected", cases[i].what);
        assert_int_equal(err.status, BRDFFIT_E_INVALID_ARGUMENT);
        assert_true(strlen(err.message) > 0);
        assert_null(m);
        assert_int_equal(us.destroys, 0);
        assert_int_equal(ca.live, 0);
    }
}

static void test_create_custom_arguments(void **state)
{
    user_state us = {USER_OK, 0, 0, 0.0};
    brdffit_param_info params[3];
    brdffit_model_def def = user_def(&us, params);
    brdffit_allocator half = {NULL, NULL, NULL};
    brdffit_model *m = NULL;
    struct {
        brdffit_model_def def;
        double appended_field;
    } bigger;
    (void)state;
    half.alloc = NULL;
    assert_int_equal(brdffit_model_create_custom(NULL, &def, NULL, NULL),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_model_create_custom(&m, NULL, NULL, NULL), BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_model_create_custom(&m, &def, &half, NULL),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_null(m);
    /* a definition from a newer header (fields appended) is accepted */
    bigger.def = def;
    bigger.def.struct_size = sizeof bigger;
    bigger.appended_field = 1.0;
    assert_int_equal(brdffit_model_create_custom(&m, &bigger.def, NULL, NULL), BRDFFIT_OK);
    brdffit_model_destroy(m);
    /* no destroy callback */
    def.destroy = NULL;
    assert_int_equal(brdffit_model_create_custom(&m, &def, NULL, NULL), BRDFFIT_OK);
    brdffit_model_destroy(m);
    assert_int_equal(us.destroys, 1);
}

/* Everything in the definition is copied (names too). */
static void test_create_custom_copies(void **state)
{
    user_state us = {USER_OK, 0, 0, 0.0};
    brdffit_param_info params[3];
    brdffit_model_def def = user_def(&us, params);
    char name[16] = "mine", pname[8] = "cd";
    brdffit_model *m = NULL;
    (void)state;
    def.name = name;
    params[0].name = pname;
    assert_int_equal(brdffit_model_create_custom(&m, &def, NULL, NULL), BRDFFIT_OK);
    strcpy(name, "changed");
    strcpy(pname, "zz");
    params[1].upper = 7.0;
    memset(&def, 0, sizeof def);
    assert_string_equal(brdffit_model_name(m), "mine");
    assert_string_equal(brdffit_model_param(m, 0)->name, "cd");
    assert_true(brdffit_model_param(m, 1)->upper == 100.0);
    brdffit_model_destroy(m);
    assert_int_equal(us.destroys, 1);
}

static void test_def_init(void **state)
{
    brdffit_model_def def;
    (void)state;
    memset(&def, 0xab, sizeof def);
    brdffit_model_def_init(&def);
    assert_int_equal(def.struct_size, sizeof(brdffit_model_def));
    assert_null(def.name);
    assert_int_equal(def.n_params, 0);
    assert_null(def.params);
    assert_null(def.eval);
    assert_null(def.user);
    assert_null(def.destroy);
    brdffit_model_def_init(NULL);
}

/* ---- evaluation argument errors -------------------------------------------- */

static void test_eval_argument_errors(void **state)
{
    brdffit_model *m = NULL;
    brdffit_grid *grid = mf_default_grid(3);
    const size_t n = brdffit_grid_sample_count(grid);
    const double ti[2] = {0.1, 0.2}, pi[2] = {0.0, 1.0};
    double x[7], v[3 * 2], bad[2];
    brdffit_error err;
    struct brdffit_model fake;
    (void)state;
    assert_non_null(grid);
    assert_int_equal(brdffit_model_create(&m, "ashikhmin-shirley", NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_model_default_params(m, 3, x), BRDFFIT_OK);

    assert_int_equal(brdffit_model_eval_grid(NULL, grid, 0, 2, x, v, NULL, &err),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_model_eval_grid(m, NULL, 0, 2, x, v, NULL, &err),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_model_eval_grid(m, grid, 0, 2, NULL, v, NULL, &err),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_model_eval_grid(m, grid, 0, 2, x, NULL, NULL, &err),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_model_eval_grid(m, grid, n - 1, 2, x, v, NULL, &err),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_model_eval_grid(m, grid, n + 1, 0, x, v, NULL, &err),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_model_eval_grid(m, grid, 2, (size_t)-1, x, v, NULL, &err),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_model_eval_grid(m, grid, n - 2, 2, x, v, NULL, &err), BRDFFIT_OK);
    assert_int_equal(brdffit_model_eval_grid(m, grid, n, 0, x, v, NULL, &err), BRDFFIT_OK);

    memset(&fake, 0, sizeof fake);
    assert_int_equal(brdffit_model_eval_grid(&fake, grid, 0, 2, x, v, NULL, &err),
                     BRDFFIT_E_BAD_HANDLE);
    assert_int_equal(brdffit_model_eval_angles(&fake, 2, ti, pi, ti, pi, 3, x, v, NULL, &err),
                     BRDFFIT_E_BAD_HANDLE);
    assert_int_equal(brdffit_model_vector_size(&fake, 3), 0);
    assert_null(brdffit_model_name(&fake));
    brdffit_model_destroy(&fake); /* ignored */

    x[0] = NAN;
    assert_int_equal(brdffit_model_eval_grid(m, grid, 0, 2, x, v, NULL, &err), BRDFFIT_E_NONFINITE);
    assert_non_null(strstr(err.message, "\"ns\""));
    x[0] = 50.0;
    x[5] = HUGE_VAL;
    assert_int_equal(brdffit_model_eval_angles(m, 2, ti, pi, ti, pi, 3, x, v, NULL, &err),
                     BRDFFIT_E_NONFINITE);
    assert_non_null(strstr(err.message, "\"cs\""));
    x[5] = 0.2;

    assert_int_equal(brdffit_model_eval_angles(m, 2, ti, pi, ti, pi, 0, x, v, NULL, &err),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_model_eval_angles(m, 2, NULL, pi, ti, pi, 3, x, v, NULL, &err),
                     BRDFFIT_E_INVALID_ARGUMENT);
    assert_int_equal(brdffit_model_eval_angles(m, 2, ti, pi, ti, NULL, 3, x, v, NULL, &err),
                     BRDFFIT_E_INVALID_ARGUMENT);
    bad[0] = 0.1;
    bad[1] = -0.01;
    assert_int_equal(brdffit_model_eval_angles(m, 2, ti, pi, bad, pi, 3, x, v, NULL, &err),
                     BRDFFIT_E_RANGE);
    assert_non_null(strstr(err.message, "theta_o[1]"));
    bad[1] = PI / 2 + 1e-9;
    assert_int_equal(brdffit_model_eval_angles(m, 2, bad, pi, ti, pi, 3, x, v, NULL, &err),
                     BRDFFIT_E_RANGE);
    bad[1] = NAN;
    assert_int_equal(brdffit_model_eval_angles(m, 2, ti, bad, ti, pi, 3, x, v, NULL, &err),
                     BRDFFIT_E_RANGE);
    bad[1] = HUGE_VAL;
    assert_int_equal(brdffit_model_eval_angles(m, 2, ti, pi, ti, bad, 3, x, v, NULL, &err),
                     BRDFFIT_E_RANGE);
    bad[1] = PI / 2; /* the bounds themselves are fine, azimuths are free */
    assert_int_equal(brdffit_model_eval_angles(m, 2, bad, pi, bad, pi, 3, x, v, NULL, &err),
                     BRDFFIT_OK);
    bad[1] = -20.0;
    assert_int_equal(brdffit_model_eval_angles(m, 2, ti, bad, ti, bad, 3, x, v, NULL, &err),
                     BRDFFIT_OK);
    assert_int_equal(brdffit_model_eval_angles(m, 0, ti, pi, ti, pi, 3, x, v, NULL, &err),
                     BRDFFIT_OK);
    brdffit_grid_destroy(grid);
    brdffit_model_destroy(m);
}

/* eval_grid over a range equals eval_angles at the grid's directions. */
static void test_eval_grid_matches_angles(void **state)
{
    brdffit_model *m = NULL;
    brdffit_grid *grid = mf_default_grid(2);
    const size_t first = 4000, count = 700;
    double x[16], *v = malloc(2 * count * sizeof(double)), *w = malloc(2 * count * sizeof(double));
    double *ja = malloc(6 * 2 * count * sizeof(double)),
           *jb = malloc(6 * 2 * count * sizeof(double));
    double ti[700], pi[700], to[700], po[700];
    size_t s, i;
    (void)state;
    assert_non_null(grid);
    assert_int_equal(brdffit_model_create(&m, "ggx-2", NULL, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_model_default_params(m, 2, x), BRDFFIT_OK);
    for (s = 0; s < count; s++)
        assert_int_equal(
            brdffit_grid_sample_angles(grid, first + s, &ti[s], &pi[s], &to[s], &po[s]),
            BRDFFIT_OK);
    assert_int_equal(brdffit_model_eval_grid(m, grid, first, count, x, v, ja, NULL), BRDFFIT_OK);
    assert_int_equal(brdffit_model_eval_angles(m, count, ti, pi, to, po, 2, x, w, jb, NULL),
                     BRDFFIT_OK);
    for (i = 0; i < 2 * count; i++) assert_close(v[i], w[i], 1e-12);
    for (i = 0; i < 6 * 2 * count; i++) assert_close(ja[i], jb[i], 1e-10);
    free(v);
    free(w);
    free(ja);
    free(jb);
    brdffit_grid_destroy(grid);
    brdffit_model_destroy(m);
}

/* ---- allocation failures ------------------------------------------------------ */

static void test_alloc_failure_create(void **state)
{
    size_t i, n;
    (void)state;
    for (i = 0; i < brdffit_model_builtin_count(); i++) {
        for (n = 1;; n++) {
            counting_alloc ca;
            brdffit_model *m = (brdffit_model *)&m;
            brdffit_error err;
            brdffit_status st;
            counting_alloc_init(&ca, n);
            st = brdffit_model_create(&m, brdffit_model_builtin_name(i), &ca.hook, &err);
            if (st == BRDFFIT_OK) {
                assert_true(ca.allocs < n); /* nothing failed */
                brdffit_model_destroy(m);
                assert_int_equal(ca.live, 0);
                break;
            }
            assert_int_equal(st, BRDFFIT_E_OUT_OF_MEMORY);
            assert_int_equal(err.status, BRDFFIT_E_OUT_OF_MEMORY);
            assert_null(m);
            assert_int_equal(ca.live, 0);
        }
        assert_true(n > 2);
    }
}

static void test_alloc_failure_create_custom(void **state)
{
    size_t n;
    (void)state;
    for (n = 1;; n++) {
        user_state us = {USER_OK, 0, 0, 0.0};
        brdffit_param_info params[3];
        brdffit_model_def def = user_def(&us, params);
        counting_alloc ca;
        brdffit_model *m = NULL;
        brdffit_status st;
        counting_alloc_init(&ca, n);
        st = brdffit_model_create_custom(&m, &def, &ca.hook, NULL);
        if (st == BRDFFIT_OK) {
            brdffit_model_destroy(m);
            assert_int_equal(us.destroys, 1);
            assert_int_equal(ca.live, 0);
            break;
        }
        assert_int_equal(st, BRDFFIT_E_OUT_OF_MEMORY);
        assert_null(m);
        assert_int_equal(us.destroys, 0);
        assert_int_equal(ca.live, 0);
    }
    assert_int_equal(n, 7); /* model, name, table, three names: six allocations */
}

static void test_alloc_failure_eval_and_check(void **state)
{
    const double ti[3] = {0.1, 0.5, 1.0}, pi[3] = {PI, PI, 0.3};
    brdffit_grid *grid = mf_default_grid(1);
    size_t which, n;
    (void)state;
    assert_non_null(grid);
    for (which = 0; which < 2; which++) {
        counting_alloc ca;
        brdffit_model *m = NULL;
        double x[4], v[3], jac[4 * 3];
        size_t live0;
        counting_alloc_init(&ca, 0);
        assert_int_equal(brdffit_model_create(&m, "cook-torrance", &ca.hook, NULL), BRDFFIT_OK);
        assert_int_equal(brdffit_model_default_params(m, 1, x), BRDFFIT_OK);
        live0 = ca.live;
        for (n = 1;; n++) {
            brdffit_jacobian_report r;
            brdffit_error err;
            brdffit_status st;
            r.struct_size = sizeof r;
            ca.fail_at = ca.allocs + n;
            if (which == 0)
                st = brdffit_model_eval_angles(m, 3, ti, pi, ti, pi, 1, x, v, jac, &err);
            else
                st = brdffit_model_check_jacobian(m, grid, x, &r, &err);
            assert_int_equal(ca.live, live0);
            if (st == BRDFFIT_OK) break;
            assert_int_equal(st, BRDFFIT_E_OUT_OF_MEMORY);
            assert_int_equal(err.status, BRDFFIT_E_OUT_OF_MEMORY);
        }
        assert_int_equal(n, 2); /* one allocation, which failed once */
        brdffit_model_destroy(m);
        assert_int_equal(ca.live, 0);
    }
    brdffit_grid_destroy(grid);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_builtin_names),
        cmocka_unit_test(test_create_errors),
        cmocka_unit_test(test_builtin_metadata),
        cmocka_unit_test(test_gltf_metadata),
        cmocka_unit_test(test_openpbr_metadata),
        cmocka_unit_test(test_param_find),
        cmocka_unit_test(test_vector_layout_builtin),
        cmocka_unit_test(test_vector_layout_user),
        cmocka_unit_test(test_user_model_eval),
        cmocka_unit_test(test_user_model_jacobian_check),
        cmocka_unit_test(test_jacobian_check_degenerate_bounds),
        cmocka_unit_test(test_user_model_failures),
        cmocka_unit_test(test_nonfinite_derivative),
        cmocka_unit_test(test_jacobian_check_near_dbl_max),
        cmocka_unit_test(test_create_custom_validation),
        cmocka_unit_test(test_create_custom_arguments),
        cmocka_unit_test(test_create_custom_copies),
        cmocka_unit_test(test_def_init),
        cmocka_unit_test(test_eval_argument_errors),
        cmocka_unit_test(test_eval_grid_matches_angles),
        cmocka_unit_test(test_alloc_failure_create),
        cmocka_unit_test(test_alloc_failure_create_custom),
        cmocka_unit_test(test_alloc_failure_eval_and_check),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

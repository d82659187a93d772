/* Directional albedo (brdffit_model_albedo()): against closed forms that
 * do not share the library's quadrature (Lambert, the normalised Phong
 * lobe, the Blinn-Phong lobe at normal incidence, sharp lobes at oblique
 * incidence, a near-mirror GGX lobe), the quality setting, every bad
 * input with its status, and the tabulated bound of the built-in lobes
 * (models/lobes.h) against the integral, Lafortune's against an integral
 * of the test's own. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/quadrature.h"
#include "models/lobes.h"
#include "test_support.h"

#define PI 3.14159265358979323846

static brdffit_model *make(const char *name)
{
    brdffit_model *m = NULL;
    assert_int_equal(brdffit_model_create(&m, name, NULL, NULL), BRDFFIT_OK);
    return m;
}

static void albedo_ok(const brdffit_model *m, const double *p, size_t nc, const double *ti,
                      size_t count, unsigned quality, double *out)
{
    brdffit_error err;
    brdffit_status st = brdffit_model_albedo(m, p, nc, ti, count, quality, out, &err);
    if (st != BRDFFIT_OK) print_error("%s: %s\n", brdffit_status_name(st), err.message);
    assert_int_equal(st, BRDFFIT_OK);
}

static void expect_rel(double got, double want, double tol, const char *what, double ti)
{
    double rel = fabs(got / want - 1.0);
    if (!(rel <= tol)) {
        print_error("%s at theta_i = %g deg: %.17g, expected %.17g (relative %.3g > %.3g)\n", what,
                    ti * 180 / PI, got, want, rel, tol);
        fail();
    }
}

/* cd / pi reflects cd at every incidence angle, grazing included. */
static void test_lambert_is_exact(void **state)
{
    static const double deg[] = {0, 10, 30, 45, 60, 75, 85, 88, 89.5, 90};
    const double cd[3] = {0.2, 0.5, 0.9};
    double ti[10], out[30];
    size_t k, c;
    brdffit_model *m = make("lambert");
    (void)state;
    for (k = 0; k < 10; k++) ti[k] = DEG(deg[k]);
    albedo_ok(m, cd, 3, ti, 10, 0, out);
    for (k = 0; k < 10; k++)
        for (c = 0; c < 3; c++) expect_rel(out[k * 3 + c], cd[c], 1e-12, "lambert", ti[k]);
    brdffit_model_destroy(m);
}

/* The normalised Phong lobe (ns + 2) / (2 pi) cos^ns at normal incidence
 * reflects exactly cs, however sharp. At oblique incidence a lobe so sharp
 * that none of it reaches the horizon reflects cs cos(theta_i) (the
 * integral of cos^ns(alpha) v_z around r, v_z averaging cos(alpha)
 * cos(theta_i) over the circle). */
static void test_phong_closed_forms(void **state)
{
    static const double ns[] = {1, 10, 1e4, 1e6};
    static const struct {
        double ns, deg;
    } oblique[] = {{1e4, 30}, {1e4, 60}, {1e4, 80}, {1e6, 45}, {1e6, 85}};
    brdffit_model *m = make("phong");
    double p[3], ti, out;
    size_t k;
    (void)state;
    for (k = 0; k < 4; k++) {
        p[0] = ns[k], p[1] = 0.25, p[2] = 0.5, ti = 0.0;
        albedo_ok(m, p, 1, &ti, 1, 0, &out);
        expect_rel(out, 0.75, 1e-9, "phong at normal incidence", ti);
    }
    for (k = 0; k < sizeof oblique / sizeof oblique[0]; k++) {
        p[0] = oblique[k].ns, p[1] = 0.0, p[2] = 1.0, ti = DEG(oblique[k].deg);
        albedo_ok(m, p, 1, &ti, 1, 0, &out);
        expect_rel(out, cos(ti), 1e-9, "sharp phong", ti);
    }
    brdffit_model_destroy(m);
}

/* Blinn-Phong at normal incidence: with c = cos(theta_h), v_z = 2c^2 - 1
 * and d(omega_o) = 4 c d(omega_h), the albedo of (ns + 8) / (8 pi) c^ns is
 * (ns + 8) times the integral from 1/sqrt(2) to 1 of c^(ns+1) (2c^2 - 1)
 * dc. */
static double blinn_normal(double ns)
{
    double a = 2.0 * (1.0 - pow(2.0, -(ns + 4) / 2)) / (ns + 4);
    double b = (1.0 - pow(2.0, -(ns + 2) / 2)) / (ns + 2);
    return (ns + 8) * (a - b);
}

static void test_blinn_phong_normal_incidence(void **state)
{
    static const double ns[] = {1, 30, 1e3, 1e4, 1e6};
    brdffit_model *m = make("blinn-phong");
    double p[3], ti = 0.0, out;
    size_t k;
    (void)state;
    for (k = 0; k < 5; k++) {
        p[0] = ns[k], p[1] = 0.0, p[2] = 1.0;
        albedo_ok(m, p, 1, &ti, 1, 0, &out);
        print_message("blinn-phong ns %g: %.15g, closed form %.15g\n", ns[k], out,
                      blinn_normal(ns[k]));
        expect_rel(out, blinn_normal(ns[k]), 1e-9, "blinn-phong", ti);
    }
    brdffit_model_destroy(m);
}

/* GGX with roughness a = 1e-4 is nearly a mirror: D integrates to 1 over
 * the half vectors, and the shadowing and the spread of l.h across the
 * lobe change the albedo by O(a^2 tan^2(theta_i)) (1.4e-7 at 75 degrees),
 * so the lobe reflects F(F0, cos(theta_i)) cs (Schlick's Fresnel term). */
static void test_near_mirror_ggx(void **state)
{
    static const double deg[] = {0, 30, 45, 60, 75};
    brdffit_model *m = make("ggx");
    double p[4] = {1e-4, 0.04, 0.1, 2.0}, ti[5], out[5];
    size_t k;
    (void)state;
    for (k = 0; k < 5; k++) ti[k] = DEG(deg[k]);
    albedo_ok(m, p, 1, ti, 5, 0, out);
    for (k = 0; k < 5; k++) {
        double f = 0.04 + 0.96 * pow(1.0 - cos(ti[k]), 5.0);
        expect_rel(out[k], 0.1 + 2.0 * f, 1e-6, "ggx", ti[k]);
    }
    brdffit_model_destroy(m);
}

/* A finer rule changes a smooth model's albedo by less than the stated
 * bound, and the two channels of a model are independent. */
static void test_quality(void **state)
{
    static const double deg[] = {0, 40, 70, 85};
    brdffit_model *m = make("ashikhmin-shirley");
    double p[5] = {300.0, 0.1, 0.4, 0.6, 0.2}, ti[4], a1[8], a3[8], one[4];
    size_t k;
    (void)state;
    for (k = 0; k < 4; k++) ti[k] = DEG(deg[k]);
    albedo_ok(m, p, 2, ti, 4, 0, a1);
    albedo_ok(m, p, 2, ti, 4, 3, a3);
    for (k = 0; k < 8; k++) expect_rel(a1[k], a3[k], 1e-6, "quality 1 against 3", ti[k / 2]);
    {
        double q[3] = {300.0, 0.1, 0.6}; /* channel 0 alone */
        albedo_ok(m, q, 1, ti, 4, 0, one);
    }
    for (k = 0; k < 4; k++) assert_true(one[k] == a1[2 * k]);
    brdffit_model_destroy(m);
}

static brdffit_status failing_eval(const brdffit_batch *b, const double *p, size_t nc, double *v,
                                   double *j, void *user)
{
    (void)b, (void)p, (void)nc, (void)v, (void)j, (void)user;
    return BRDFFIT_E_RANGE;
}

static brdffit_status nan_eval(const brdffit_batch *b, const double *p, size_t nc, double *v,
                               double *j, void *user)
{
    size_t s;
    (void)p, (void)j, (void)user;
    for (s = 0; s < b->n * nc; s++) v[s] = s == 7 ? NAN : 1.0;
    return BRDFFIT_OK;
}

static brdffit_model *custom(brdffit_model_eval_fn fn)
{
    static const brdffit_param_info info = {"k", BRDFFIT_PARAM_PER_CHANNEL, 0.0, 1.0, 0.5};
    brdffit_model_def def = BRDFFIT_MODEL_DEF_INIT;
    brdffit_model *m = NULL;
    def.name = "custom";
    def.n_params = 1;
    def.params = &info;
    def.eval = fn;
    assert_int_equal(brdffit_model_create_custom(&m, &def, NULL, NULL), BRDFFIT_OK);
    return m;
}

static void expect_status(const brdffit_model *m, const double *p, size_t nc, const double *ti,
                          size_t count, unsigned quality, double *out, brdffit_status want,
                          const char *fragment)
{
    brdffit_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(brdffit_model_albedo(m, p, nc, ti, count, quality, out, &err), want);
    assert_int_equal(err.status, want);
    if (fragment != NULL && strstr(err.message, fragment) == NULL) {
        print_error("message '%s' lacks '%s'\n", err.message, fragment);
        fail();
    }
}

static void test_bad_input(void **state)
{
    static const uint64_t foreign[16] = {0x1234567812345678u}; /* not a model */
    const brdffit_model *other = (const brdffit_model *)(const void *)foreign;
    brdffit_model *m = make("lambert");
    brdffit_model *fails = custom(failing_eval), *nan = custom(nan_eval);
    double cd = 0.5, ti[2] = {0.1, 0.2}, out[2] = {0, 0}, bad;
    const brdffit_status inv = BRDFFIT_E_INVALID_ARGUMENT;
    (void)state;
    expect_status(NULL, &cd, 1, ti, 2, 0, out, inv, "model is NULL");
    expect_status(other, &cd, 1, ti, 2, 0, out, BRDFFIT_E_BAD_HANDLE, NULL);
    expect_status(m, NULL, 1, ti, 2, 0, out, inv, "NULL");
    expect_status(m, &cd, 1, NULL, 2, 0, out, inv, "NULL");
    expect_status(m, &cd, 1, ti, 2, 0, NULL, inv, "NULL");
    expect_status(m, &cd, 0, ti, 2, 0, out, inv, "n_channels");
    expect_status(m, &cd, 1, ti, 2, 17, out, inv, "quality 17");
    ti[1] = -1e-9;
    expect_status(m, &cd, 1, ti, 2, 0, out, BRDFFIT_E_RANGE, "theta_i[1]");
    ti[1] = PI / 2 + 1e-9;
    expect_status(m, &cd, 1, ti, 2, 0, out, BRDFFIT_E_RANGE, "theta_i[1]");
    ti[1] = NAN;
    expect_status(m, &cd, 1, ti, 2, 0, out, BRDFFIT_E_RANGE, "theta_i[1]");
    ti[1] = 0.2;
    bad = INFINITY;
    expect_status(m, &bad, 1, ti, 2, 0, out, BRDFFIT_E_NONFINITE, "entry 0");
    expect_status(fails, &cd, 1, ti, 2, 0, out, BRDFFIT_E_MODEL_FAILED, "custom");
    expect_status(nan, &cd, 1, ti, 2, 0, out, BRDFFIT_E_NONFINITE, "non-finite value");
    /* count 0 does nothing */
    out[0] = 7.0;
    expect_status(m, &cd, 1, ti, 0, 0, out, BRDFFIT_OK, NULL);
    assert_true(out[0] == 7.0);
    brdffit_model_destroy(m);
    brdffit_model_destroy(fails);
    brdffit_model_destroy(nan);
}

/* The largest albedo over the bound's angles of lobe l of model m with
 * colour 1, the other colours 0, at sharpness x and Fresnel parameter f. */
static double lobe_top(const brdffit_model *m, const bf_lobe_desc *l, double x, double f)
{
    static const double deg[BF_ALBEDO_ANGLES] = BF_ALBEDO_ANGLES_DEG;
    double v[16], ti[BF_ALBEDO_ANGLES], a[BF_ALBEDO_ANGLES], top = 0.0;
    size_t k, t, n = brdffit_model_param_count(m);
    for (k = 0; k < n; k++) {
        const brdffit_param_info *info = brdffit_model_param(m, k);
        v[k] = info->flags & BRDFFIT_PARAM_LINEAR ? 0.0 : info->start;
    }
    v[l->shape] = x;
    v[l->colour] = 1.0;
    if (l->fresnel != BF_NO_PARAM) v[l->fresnel] = f;
    for (t = 0; t < BF_ALBEDO_ANGLES; t++) ti[t] = deg[t] * PI / 180.0;
    albedo_ok(m, v, 1, ti, BF_ALBEDO_ANGLES, 0, a);
    for (t = 0; t < BF_ALBEDO_ANGLES; t++) top = fmax(top, a[t]);
    return top;
}

/* For every built-in lobe with a table, at shapes between the nodes over
 * its whole range (5; BRDFFIT_TEST_QUICK: the first, middle and last of
 * them) (and two Fresnel values where it has one): the bound is never
 * below the integral and at most 3 % above it. Also: user models and
 * models without a lobe of a linear colour have no lobes, and a sharpness
 * outside the table gives no bound (0). */
static void test_lobe_bound(void **state)
{
    static const char *const names[] = {"phong", "blinn-phong", "ashikhmin-shirley",
                                        "ashikhmin-shirley-fresnel", "cook-torrance", "ggx",
                                        "ward", "ward-duer", "ggx-2"};
    static const double F[2] = {0.04, 0.7};
    const size_t stride = test_quick() ? 2 : 1;
    double worst = 0.0;
    size_t i, j, s;
    (void)state;
    for (i = 0; i < sizeof names / sizeof names[0]; i++) {
        brdffit_model *m = make(names[i]);
        const bf_lobes *lobes = bf_model_lobes(m);
        const bf_lobe_desc *l;
        assert_non_null(lobes);
        l = &lobes->lobe[lobes->n - 1];
        assert_non_null(l->albedo);
        for (s = 0; s < 5; s += stride) {
            /* 0.37, 2.74, ... cells into the table: between nodes */
            double cell = 0.37 + (double)s * ((double)(l->albedo->n - 2) / 4.6);
            double x = pow(10.0, l->albedo->log10_lo + cell / l->albedo->per_decade);
            for (j = 0; j < (l->fresnel == BF_NO_PARAM ? 1u : 2u); j++) {
                double truth = lobe_top(m, l, x, F[j]), bound = bf_lobe_albedo_bound(l, x, F[j]);
                if (!(bound >= truth && bound <= 1.03 * truth))
                    print_error("%s at %g, F %g: bound %.9g, integral %.9g\n", names[i], x,
                                F[j], bound, truth);
                assert_true(bound >= truth && bound <= 1.03 * truth);
                worst = fmax(worst, bound / truth - 1.0);
            }
        }
        assert_true(bf_lobe_albedo_bound(l, pow(10.0, l->albedo->log10_lo - 1.0), 0.5) == 0.0);
        brdffit_model_destroy(m);
    }
    printf("largest excess of the bound over the integral: %.3g\n", worst);
    {
        brdffit_model *m = make("gltf"), *lam = make("lambert");
        assert_null(bf_model_lobes(m));
        assert_null(bf_model_lobes(lam));
        brdffit_model_destroy(m);
        brdffit_model_destroy(lam);
    }
}

/* Lafortune's lobe with colour 1 (base = u.v, u = (-sin ti, 0, cz cos ti)
 * for the light in the xz plane) by its definition: the integral over the
 * upper hemisphere of v of max(0, u.v)^n v_z, taken in the coordinates of
 * v about u (angle g from it, azimuth p about it), where the lobe is
 * (|u| cos g)^n, a spike at g = 0 however large n: 8-point Gauss-Legendre
 * panels in g halving towards 0, the midpoint rule over p with v_z
 * clipped at 0. It shares nothing with the library's quadrature nor with
 * the table's integral (which takes p in closed form); 2e-4 or better. */
#define REF_P 256

static double lafortune_reference(double n, double cz, double ti)
{
    const double ux = -sin(ti), uz = cz * cos(ti), m = sqrt(ux * ux + uz * uz);
    double x[8], w[8], cos_p[REF_P], hi = PI / 2, sum = 0.0;
    size_t k, j, q;
    if (!(m > 0.0)) return 0.0;
    bf_gauss_legendre(8, x, w);
    for (q = 0; q < REF_P; q++) cos_p[q] = cos(PI * ((double)q + 0.5) / REF_P);
    for (k = 0; k < 32; k++) {
        double lo = k == 31 ? 0.0 : 0.5 * hi, mid = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
        for (j = 0; j < 8; j++) {
            /* v = cos g a + sin g (cos p e1 + sin p e2), a = u / m, e1 = (a_z, 0, -a_x):
             * v_z = cos g a_z - sin g cos p a_x */
            double g = mid + half * x[j], az = cos(g) * uz / m, ax = sin(g) * ux / m, ring = 0.0;
            for (q = 0; q < REF_P; q++) ring += fmax(az - ax * cos_p[q], 0.0);
            sum += w[j] * half * sin(g) * pow(m * cos(g), n) * ring * (2.0 * PI / REF_P);
        }
        hi = lo;
    }
    return sum;
}

/* Lafortune's bound (its axial table) at points between the table's nodes
 * over the whole range of n (7; BRDFFIT_TEST_QUICK: the first, middle and
 * last of them) and over cz: never below the largest albedo
 * over the bound's angles, by the reference above, and at most 3 % above
 * it. Also the reference against the library's integral where that
 * resolves the lobe (n >= 3, cz = 1: the mirror lobe), and no bound outside
 * the table's range of n. */
static void test_lafortune_bound(void **state)
{
    static const double deg[BF_ALBEDO_ANGLES] = BF_ALBEDO_ANGLES_DEG;
    static const double CZ[] = {0.0, 0.013, 0.21, 0.58, 0.87, 0.996, 1.0};
    brdffit_model *m = make("lafortune");
    const bf_lobes *lobes = bf_model_lobes(m);
    const bf_lobe_desc *l;
    const size_t stride = test_quick() ? 3 : 1;
    double worst = 0.0, ti[BF_ALBEDO_ANGLES], lib[BF_ALBEDO_ANGLES];
    size_t s, k, t;
    (void)state;
    assert_non_null(lobes);
    l = &lobes->lobe[0];
    assert_null(l->albedo);
    assert_non_null(l->axial);
    assert_string_equal(brdffit_model_param(m, l->fresnel)->name, "cz");
    for (t = 0; t < BF_ALBEDO_ANGLES; t++) ti[t] = deg[t] * PI / 180.0;
    for (s = 0; s < 7; s += stride) {
        /* 0.37, 12.0, ... cells into the table of n: between nodes */
        double cell = 0.37 + (double)s * ((double)(l->axial->n - 2) / 6.1);
        double n = pow(10.0, l->axial->log10_lo + cell / l->axial->per_decade);
        double v[4] = {0.0, 1.0, 0.0, 1.0};
        for (k = 0; k < sizeof CZ / sizeof CZ[0]; k++) {
            double truth = 0.0, bound = bf_lobe_albedo_bound(l, n, CZ[k]);
            for (t = 0; t < BF_ALBEDO_ANGLES; t++)
                truth = fmax(truth, lafortune_reference(n, CZ[k], ti[t]));
            if (!(truth > 1e-300)) continue; /* m^n underflows: nothing to bound */
            if (!(bound >= truth && bound <= 1.03 * truth))
                print_error("lafortune at n %g, cz %g: bound %.9g, integral %.9g\n", n, CZ[k],
                            bound, truth);
            assert_true(bound >= truth && bound <= 1.03 * truth);
            worst = fmax(worst, bound / truth - 1.0);
        }
        /* the reference against the library where both are accurate */
        if (n < 3.0) continue;
        v[0] = n;
        albedo_ok(m, v, 1, ti, BF_ALBEDO_ANGLES, 0, lib);
        for (t = 0; t < BF_ALBEDO_ANGLES; t++)
            expect_rel(lafortune_reference(n, 1.0, ti[t]), lib[t], 2e-4, "lafortune reference",
                       ti[t]);
    }
    printf("lafortune: largest excess of the bound over the integral: %.3g\n", worst);
    assert_true(bf_lobe_albedo_bound(l, 1e-4, 0.5) == 0.0);
    assert_true(bf_lobe_albedo_bound(l, 2e6, 0.5) == 0.0);
    brdffit_model_destroy(m);
}

/* The lobe descriptions agree with the declared parameters: every
 * lobe's colour is a linear parameter and its sharpness a shared one
 * (log-scaled), a Fresnel parameter lies in [0, 1]; the two-lobe models
 * (exactly the built-ins with two lobes) have interchangeable lobes whose
 * parameters differ in their last digit only (ns1 / ns2, cs1 / cs2); the
 * coat models have no described lobes (their coat is a lobe of its own
 * kind). */
static void test_lobe_descriptions(void **state)
{
    size_t i, j, two = 0;
    (void)state;
    for (i = 0; i < brdffit_model_builtin_count(); i++) {
        brdffit_model *m = make(brdffit_model_builtin_name(i));
        const bf_lobes *lobes = bf_model_lobes(m);
        for (j = 0; lobes != NULL && j < lobes->n; j++) {
            const bf_lobe_desc *l = &lobes->lobe[j];
            assert_true(brdffit_model_param(m, l->colour)->flags & BRDFFIT_PARAM_LINEAR);
            assert_false(brdffit_model_param(m, l->shape)->flags & BRDFFIT_PARAM_PER_CHANNEL);
            assert_true(brdffit_model_param(m, l->shape)->flags & BRDFFIT_PARAM_LOG_SCALE);
            if (l->fresnel != BF_NO_PARAM) {
                assert_true(brdffit_model_param(m, l->fresnel)->lower == 0.0);
                assert_true(brdffit_model_param(m, l->fresnel)->upper == 1.0);
            }
        }
        if (lobes != NULL && lobes->n == 2) {
            const char *a = brdffit_model_param(m, lobes->lobe[0].shape)->name;
            const char *b = brdffit_model_param(m, lobes->lobe[1].shape)->name;
            size_t len = strlen(a);
            two++;
            assert_true(lobes->interchangeable);
            assert_true(strncmp(a, b, len - 1) == 0 && a[len - 1] == '1' && b[len - 1] == '2');
            assert_string_equal(brdffit_model_param(m, lobes->lobe[0].colour)->name, "cs1");
            assert_string_equal(brdffit_model_param(m, lobes->lobe[1].colour)->name, "cs2");
            assert_true(lobes->lobe[0].sharper_larger == (a[0] == 'n'));
        }
        if (strstr(brdffit_model_builtin_name(i), "coat") != NULL) assert_null(lobes);
        brdffit_model_destroy(m);
    }
    assert_int_equal(two, 3); /* ashikhmin-shirley-2, cook-torrance-2, ggx-2 */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_lambert_is_exact),
        cmocka_unit_test(test_phong_closed_forms),
        cmocka_unit_test(test_blinn_phong_normal_incidence),
        cmocka_unit_test(test_near_mirror_ggx),
        cmocka_unit_test(test_quality),
        cmocka_unit_test(test_bad_input),
        cmocka_unit_test(test_lobe_bound),
        cmocka_unit_test(test_lafortune_bound),
        cmocka_unit_test(test_lobe_descriptions),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

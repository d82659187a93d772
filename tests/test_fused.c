/* The fused loop of the basis route (lib/fit/pass_fused.c): its versions
 * give the same bits within each family (with fused multiply-add: the
 * AVX-512 and AVX2 ones and the plain C one with fma(); without: the
 * baseline and the plain C one, on what this CPU runs), the families
 * agree to rounding, and the loop, which reads its per-sample inputs in
 * single precision (weights, lobe geometry, measured values), agrees with
 * the unfused basis route (double inputs, scratch arrays and dot
 * products) to the bound that rounding sets (FUSED_TOL), for every kind of
 * pass it serves, every model of the lobe form (Lambert, the one-lobe
 * models, the two-lobe Ashikhmin-Shirley) and of the microfacet form
 * (GGX, Cook-Torrance, one lobe and two; Ward, Ward-Duer; the
 * Ashikhmin-Shirley shader form with Fresnel), values read in place and
 * loaded (channel mean, clear coat), regular grids whose chunks end in a
 * partial group of lanes and scattered ones with and without given sample
 * weights, both weightings with the solid angle. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fit/pass.h"
#include "fit/pass_fused.h"
#include "pass_fixtures.h"
#include "test_support.h"

#define DEG2RAD (3.14159265358979323846 / 180.0)
#define MAX_ACC 256
/* The fused loop against the unfused route, relative to the largest
 * entry: each single-precision input is within 2^-24 of its double, the
 * lobe's exp(ns x) within |ns x| 2^-24 and a product of them within a few
 * times that; the sums are weighted averages of such terms. */
#define FUSED_TOL 1e-6
/* The two families against each other: rounding alone. */
#define FAMILY_TOL 1e-12

typedef struct setup {
    brdffit_grid *grid;
    brdffit_model *model;
    bf_weight_plan plan;
    bf_problem pb;
    size_t vindex[32]; /* n_params x nc */
    double params[16];
    double *work;
    int lobe; /* pb.lobe as bf_pass_prepare() set it */
} setup;

/* Grids of the cases: the default axes, or their directions scattered
 * (in a shuffled order, with given sample weights or without). */
enum { REGULAR, SCATTERED, WEIGHTED };

static brdffit_grid *case_grid(int kind)
{
    const brdffit_axes *ax = brdffit_axes_default();
    const size_t n = ax->n_theta_i * ax->n_theta_o * ax->n_phi_o;
    brdffit_grid *regular = fx_pass_grid(3), *g = NULL;
    double *a, *v, *w;
    size_t s, t, c;
    if (kind == REGULAR) return regular;
    a = malloc(4 * n * sizeof *a), v = malloc(3 * n * sizeof *v), w = malloc(n * sizeof *w);
    assert_true(a != NULL && v != NULL && w != NULL);
    for (s = 0; s < n; s++) {
        t = (s * 7919) % n; /* a permutation: 7919 is prime to n */
        assert_int_equal(
            brdffit_grid_sample_angles(regular, t, &a[s], &a[n + s], &a[2 * n + s], &a[3 * n + s]),
            BRDFFIT_OK);
        for (c = 0; c < 3; c++) {
            const double *vals;
            assert_int_equal(brdffit_grid_values(regular, c, &vals), BRDFFIT_OK);
            v[s * 3 + c] = vals[t];
        }
        w[s] = 0.5 + (double)(s % 13) / 7.0;
    }
    assert_int_equal(brdffit_grid_create_scattered(&g, n, a, a + n, a + 2 * n, a + 3 * n, 3, v,
                                                   NULL, kind == WEIGHTED ? w : NULL, NULL, NULL),
                     BRDFFIT_OK);
    brdffit_grid_destroy(regular);
    free(a);
    free(v);
    free(w);
    return g;
}

static void setup_grid(setup *s, const char *model, size_t nc, bf_source source, double coat,
                       double cap_deg, int grid, unsigned weighting)
{
    bf_problem *pb = &s->pb;
    size_t k, size;
    memset(s, 0, sizeof *s);
    s->grid = case_grid(grid);
    assert_int_equal(brdffit_model_create(&s->model, model, NULL, NULL), BRDFFIT_OK);
    assert_int_equal(
        bf_weight_plan_init(&s->plan, s->grid, cap_deg * DEG2RAD, weighting, &s->grid->alloc, NULL),
        BRDFFIT_OK);
    fx_pass_problem(pb, s->grid, s->model, &s->plan, nc, source, coat);
    assert_true(pb->ly.n_vec <= 16 && brdffit_model_param_count(s->model) * nc <= 32);
    bf_layout_entries(&pb->ly, s->model, s->vindex, NULL);
    pb->vindex = s->vindex;
    bf_pass_prepare(pb);
    assert_true(pb->lobe);
    /* ns 40 (exp over a wide range), cd and cs per channel */
    s->params[0] = 40.0;
    for (k = 1; k < pb->ly.n_vec; k++) s->params[k] = 0.05 + 0.1 * (double)k;
    /* the second lobe of the two-lobe model sharper than the first */
    if (strcmp(model, "ashikhmin-shirley-2") == 0) s->params[s->vindex[nc]] = 300.0;
    /* the microfacet form: roughness 0.3 (and 0.08 for a second lobe),
     * F0 0.2 */
    if (pb->mf == BF_MF_AS_FRESNEL) {
        /* ns 40 as above, Rs 0.3 (the diffuse scaled by 0.7) */
        s->params[s->vindex[nc]] = 0.3;
    } else if (pb->mf != BF_MF_NONE) {
        const size_t nl = (size_t)pb->lobe - 1;
        s->params[s->vindex[0]] = 0.3;
        if (nl == 2) s->params[s->vindex[nc]] = 0.08;
        if (pb->mf == BF_MF_GGX || pb->mf == BF_MF_CT) s->params[s->vindex[nl * nc]] = 0.2;
    }
    /* room for either route (the unfused one has the larger scratch, the
     * fused one of two microfacet lobes the larger accumulator) */
    s->lobe = pb->lobe;
    size = bf_pass_work_size(pb);
    pb->lobe = 0;
    if (bf_pass_work_size(pb) > size) size = bf_pass_work_size(pb);
    s->work = calloc(size, sizeof(double));
    assert_non_null(s->work);
    pb->work = s->work;
    pb->lobe = s->lobe;
}

static void setup_init(setup *s, const char *model, size_t nc, bf_source source, double coat,
                       double cap_deg)
{
    setup_grid(s, model, nc, source, coat, cap_deg, REGULAR, BRDFFIT_WEIGHT_DEFAULT);
}

static void setup_free(setup *s)
{
    free(s->work);
    bf_weight_plan_free(&s->plan, &s->grid->alloc);
    brdffit_model_destroy(s->model);
    brdffit_grid_destroy(s->grid);
}

static void run(setup *s, bf_pass_kind kind, double *acc)
{
    brdffit_error err;
    memset(acc, 0, MAX_ACC * sizeof *acc);
    assert_true(bf_pass_acc_size(&s->pb, kind) <= MAX_ACC);
    assert_int_equal(bf_pass(&s->pb, kind, s->params, acc, &err), BRDFFIT_OK);
}

static const char *isa_name(unsigned isa)
{
    static const char *const names[] = {"plain C", "baseline", "AVX2", "AVX-512",
                                        "plain C with fma()"};
    return names[isa];
}

/* |a - b| <= tol * top over n entries, else print the first that is not. */
static void expect_near(const char *what, const char *model, int kind, const double *a,
                        const double *b, size_t n, double tol)
{
    double top = 0.0;
    size_t i;
    for (i = 0; i < n; i++) top = fmax(top, fabs(b[i]));
    assert_true(top > 0.0);
    for (i = 0; i < n; i++)
        if (!(fabs(a[i] - b[i]) <= tol * top)) {
            printf("%s, %s kind %d entry %zu: %.17g against %.17g (largest entry %.3g)\n", what,
                   model, kind, i, a[i], b[i], top);
            fail();
        }
}

static void expect_same(const char *model, int kind, unsigned isa, unsigned ref, const double *a,
                        const double *b, size_t n)
{
    if (memcmp(a, b, n * sizeof *a) == 0) return;
    printf("%s kind %d: the %s version differs from the %s one\n", model, kind, isa_name(isa),
           isa_name(ref));
    fail();
}

/* Within each family every version this CPU runs gives the plain C one's
 * bits, the families agree to FAMILY_TOL, and the plain one agrees with
 * the unfused route to FUSED_TOL of the largest entry. */
static void check_setup(setup *s, const char *model)
{
    static const bf_pass_kind kinds[] = {BF_PASS_COST, BF_PASS_NORMAL, BF_PASS_VARPRO};
    double ref[MAX_ACC], plain[MAX_ACC], plain_fma[MAX_ACC], acc[MAX_ACC];
    size_t k, n;
    unsigned best = s->pb.isa;
    for (k = 0; k < sizeof kinds / sizeof kinds[0]; k++) {
        const int kd = (int)kinds[k];
        n = bf_pass_acc_size(&s->pb, kinds[k]);
        assert_true(bf_fused_serves(&s->pb, kinds[k]));
        s->pb.lobe = 0;
        run(s, kinds[k], ref);
        s->pb.lobe = s->lobe;
        s->pb.isa = BF_ISA_PLAIN;
        run(s, kinds[k], plain);
        s->pb.isa = BF_ISA_PLAIN_FMA;
        run(s, kinds[k], plain_fma);
        expect_near("fused and unfused", model, kd, plain, ref, n, FUSED_TOL);
        expect_near("with and without fma", model, kd, plain_fma, plain, n, FAMILY_TOL);
        if (best >= BF_ISA_BASE) {
            s->pb.isa = BF_ISA_BASE;
            run(s, kinds[k], acc);
            expect_same(model, kd, BF_ISA_BASE, BF_ISA_PLAIN, acc, plain, n);
        }
        if (best >= BF_ISA_AVX2) {
            s->pb.isa = BF_ISA_AVX2;
            run(s, kinds[k], acc);
            expect_same(model, kd, BF_ISA_AVX2, BF_ISA_PLAIN_FMA, acc, plain_fma, n);
        }
        if (best >= BF_ISA_AVX512) {
            s->pb.isa = BF_ISA_AVX512;
            run(s, kinds[k], acc);
            expect_same(model, kd, BF_ISA_AVX512, BF_ISA_PLAIN_FMA, acc, plain_fma, n);
        }
        s->pb.isa = best;
    }
}

static void check_case(const char *model, size_t nc, bf_source source, double coat, double cap)
{
    setup s;
    setup_init(&s, model, nc, source, coat, cap);
    check_setup(&s, model);
    setup_free(&s);
}

static void test_versions_this_cpu_runs(void **state)
{
    unsigned best = bf_fused_best_isa();
    (void)state;
    printf("fused loop versions checked: plain C, plain C with fma()");
    if (best >= BF_ISA_BASE) printf(", baseline");
    if (best >= BF_ISA_AVX2) printf(", AVX2");
    if (best >= BF_ISA_AVX512) printf(", AVX-512");
    printf("\n");
    if (best < BF_ISA_AVX512)
        printf("not checked: the AVX-512 version (this CPU or build does not run it)\n");
    if (best < BF_ISA_AVX2)
        printf("not checked: the AVX2 version (this CPU or build does not run it)\n");
    assert_true(best <= BF_ISA_AVX512);
}

static void test_ashikhmin_shirley(void **state)
{
    (void)state;
    check_case("ashikhmin-shirley", 3, BF_SOURCE_CHANNELS, 0.0, 90.0);
    check_case("ashikhmin-shirley", 3, BF_SOURCE_CHANNELS, 0.0, 75.0);
}

static void test_phong_and_blinn(void **state)
{
    (void)state;
    check_case("phong", 3, BF_SOURCE_CHANNELS, 0.0, 90.0);
    check_case("blinn-phong", 3, BF_SOURCE_CHANNELS, 0.0, 75.0);
}

/* The lobe form without lobes and with two. */
static void test_lambert_and_two_lobes(void **state)
{
    setup s;
    (void)state;
    /* pb.lobe is 1 + the lobes; the accumulators hold 8 lanes per sum */
    setup_init(&s, "lambert", 3, BF_SOURCE_CHANNELS, 0.0, 90.0);
    assert_int_equal(s.pb.lobe, 1);
    assert_int_equal(bf_fused_acc_size(&s.pb, BF_PASS_NORMAL), (1 + 3 * (1 + 1)) * 8);
    setup_free(&s);
    setup_init(&s, "ashikhmin-shirley-2", 3, BF_SOURCE_CHANNELS, 0.0, 90.0);
    assert_int_equal(s.pb.lobe, 3);
    assert_int_equal(bf_fused_acc_size(&s.pb, BF_PASS_NORMAL), (15 + 3 * (1 + 5)) * 8);
    assert_int_equal(bf_fused_acc_size(&s.pb, BF_PASS_VARPRO), (6 + 3 * 4) * 8);
    setup_free(&s);
    check_case("lambert", 3, BF_SOURCE_CHANNELS, 0.0, 90.0);
    check_case("lambert", 1, BF_SOURCE_MEAN, 0.0, 75.0);
    check_case("ashikhmin-shirley-2", 3, BF_SOURCE_CHANNELS, 0.0, 90.0);
    check_case("ashikhmin-shirley-2", 3, BF_SOURCE_CHANNELS, 0.0, 75.0);
    check_case("ashikhmin-shirley-2", 1, BF_SOURCE_MEAN, 0.0, 90.0);
    check_case("ashikhmin-shirley-2", 3, BF_SOURCE_CHANNELS, 0.04, 75.0);
}

/* The microfacet form: GGX and Cook-Torrance, one lobe and two, and
 * Ward's lobes (Ward, Ward-Duer: no F0), on 3
 * channels read in place and on 1 loaded (the channel mean), at both caps
 * (the 75 degree cap leaves chunks ending in a partial group). */
static void test_microfacet(void **state)
{
    static const char *const models[] = {"ggx",  "ggx-2",    "cook-torrance", "cook-torrance-2",
                                         "ward", "ward-duer"};
    setup s;
    size_t m;
    (void)state;
    /* GGX: NE = 1 + 3 nl functions (1/pi, B, dB/da, dB/dF0) */
    setup_init(&s, "ggx", 3, BF_SOURCE_CHANNELS, 0.0, 90.0);
    assert_int_equal(s.pb.lobe, 2);
    assert_int_equal(s.pb.mf, BF_MF_GGX);
    assert_int_equal(bf_fused_acc_size(&s.pb, BF_PASS_NORMAL), (10 + 3 * (1 + 4)) * 8);
    setup_free(&s);
    setup_init(&s, "cook-torrance-2", 3, BF_SOURCE_CHANNELS, 0.0, 90.0);
    assert_int_equal(s.pb.lobe, 3);
    assert_int_equal(s.pb.mf, BF_MF_CT);
    assert_int_equal(bf_fused_acc_size(&s.pb, BF_PASS_NORMAL), (28 + 3 * (1 + 7)) * 8);
    assert_int_equal(bf_fused_acc_size(&s.pb, BF_PASS_VARPRO), (6 + 3 * 4) * 8);
    setup_free(&s);
    /* Ward: one lobe, no F0, NE = 3 (1/pi, B, dB/da) */
    setup_init(&s, "ward-duer", 3, BF_SOURCE_CHANNELS, 0.0, 90.0);
    assert_int_equal(s.pb.lobe, 2);
    assert_int_equal(s.pb.mf, BF_MF_WARD_DUER);
    assert_int_equal(bf_fused_acc_size(&s.pb, BF_PASS_NORMAL), (6 + 3 * (1 + 3)) * 8);
    setup_free(&s);
    for (m = 0; m < sizeof models / sizeof models[0]; m++) {
        check_case(models[m], 3, BF_SOURCE_CHANNELS, 0.0, 90.0);
        check_case(models[m], 3, BF_SOURCE_CHANNELS, 0.0, 75.0);
        check_case(models[m], 1, BF_SOURCE_MEAN, 0.0, 75.0);
    }
    check_case("ggx", 3, BF_SOURCE_CHANNELS, 0.04, 90.0);
}

/* The Ashikhmin-Shirley shader form (Rs in place of F0, the diffuse
 * (1 - Rs) fd in place of 1/pi): one lobe, NE = 5 (B_0, B_1, dB_1/dns,
 * dB_0/dRs, dB_1/dRs), fused for every kind the route serves. */
static void test_ashikhmin_shirley_fresnel(void **state)
{
    setup s;
    (void)state;
    setup_init(&s, "ashikhmin-shirley-fresnel", 3, BF_SOURCE_CHANNELS, 0.0, 90.0);
    assert_int_equal(s.pb.lobe, 2);
    assert_int_equal(s.pb.mf, BF_MF_AS_FRESNEL);
    assert_true(bf_fused_serves(&s.pb, BF_PASS_COST));
    assert_true(bf_fused_serves(&s.pb, BF_PASS_NORMAL));
    assert_true(bf_fused_serves(&s.pb, BF_PASS_VARPRO));
    assert_true(bf_fused_in_place(&s.pb, BF_PASS_NORMAL));
    assert_int_equal(bf_fused_acc_size(&s.pb, BF_PASS_NORMAL), (15 + 3 * (1 + 5)) * 8);
    assert_int_equal(bf_fused_acc_size(&s.pb, BF_PASS_VARPRO), (3 + 3 * 3) * 8);
    assert_int_equal(bf_fused_acc_size(&s.pb, BF_PASS_COST), 3 * 8);
    setup_free(&s);
    check_case("ashikhmin-shirley-fresnel", 3, BF_SOURCE_CHANNELS, 0.0, 90.0);
    check_case("ashikhmin-shirley-fresnel", 3, BF_SOURCE_CHANNELS, 0.0, 75.0);
    check_case("ashikhmin-shirley-fresnel", 1, BF_SOURCE_MEAN, 0.0, 75.0);
    check_case("ashikhmin-shirley-fresnel", 3, BF_SOURCE_CHANNELS, 0.04, 90.0);
}

/* Scattered grids, with given sample weights and without, and the
 * weighting by the solid angle alone (the plan of the log and cube-root
 * objectives, whose VARPRO passes the loop runs). */
static void test_scattered_and_weightings(void **state)
{
    static const char *const models[] = {"ashikhmin-shirley", "ggx", "ashikhmin-shirley-fresnel"};
    setup s;
    size_t m;
    (void)state;
    for (m = 0; m < sizeof models / sizeof models[0]; m++) {
        setup_grid(&s, models[m], 3, BF_SOURCE_CHANNELS, 0.0, 75.0, SCATTERED,
                   BRDFFIT_WEIGHT_DEFAULT);
        check_setup(&s, models[m]);
        setup_free(&s);
        setup_grid(&s, models[m], 3, BF_SOURCE_CHANNELS, 0.0, 90.0, WEIGHTED,
                   BRDFFIT_WEIGHT_DEFAULT);
        check_setup(&s, models[m]);
        setup_free(&s);
        setup_grid(&s, models[m], 1, BF_SOURCE_MEAN, 0.0, 75.0, WEIGHTED,
                   BRDFFIT_WEIGHT_SOLID_ANGLE);
        check_setup(&s, models[m]);
        setup_free(&s);
    }
    setup_grid(&s, "ashikhmin-shirley", 3, BF_SOURCE_CHANNELS, 0.0, 75.0, REGULAR,
               BRDFFIT_WEIGHT_SOLID_ANGLE);
    check_setup(&s, "ashikhmin-shirley");
    setup_free(&s);
    /* the weightings without the solid angle have no base form: the fused
     * loop leaves them to the unfused route */
    setup_grid(&s, "ashikhmin-shirley", 3, BF_SOURCE_CHANNELS, 0.0, 75.0, REGULAR,
               BRDFFIT_WEIGHT_COSINE);
    assert_false(bf_fused_serves(&s.pb, BF_PASS_NORMAL));
    setup_free(&s);
}

/* Values loaded by the driver instead of read in place. */
static void test_loaded_values(void **state)
{
    (void)state;
    check_case("ashikhmin-shirley", 1, BF_SOURCE_MEAN, 0.0, 75.0);
    check_case("ashikhmin-shirley", 3, BF_SOURCE_CHANNELS, 0.04, 90.0);
    check_case("phong", 1, BF_SOURCE_MEAN, 0.0, 90.0);
}

/* The route serves only what it can: other models, METRICS and other
 * channel counts go elsewhere. */
static void test_what_it_serves(void **state)
{
    setup s;
    (void)state;
    setup_init(&s, "ashikhmin-shirley", 3, BF_SOURCE_CHANNELS, 0.0, 90.0);
    assert_true(bf_fused_serves(&s.pb, BF_PASS_NORMAL));
    assert_true(bf_fused_in_place(&s.pb, BF_PASS_NORMAL));
    assert_false(bf_fused_serves(&s.pb, BF_PASS_METRICS));
    s.pb.nc = 2;
    assert_false(bf_fused_serves(&s.pb, BF_PASS_NORMAL));
    s.pb.nc = 3;
    s.pb.clearcoat = 0.04;
    assert_false(bf_fused_in_place(&s.pb, BF_PASS_NORMAL));
    {
        brdffit_model *m = NULL;
        bf_problem pb;
        memset(&pb, 0, sizeof pb);
        assert_int_equal(brdffit_model_create(&m, "lafortune", NULL, NULL), BRDFFIT_OK);
        pb.model = m;
        pb.grid = s.grid;
        pb.objective = BRDFFIT_OBJECTIVE_SQUARES;
        pb.nc = 3;
        pb.threads = 1;
        bf_pass_prepare(&pb);
        assert_non_null(pb.kernel); /* in basis form, but not fused */
        assert_false(pb.lobe);
        brdffit_model_destroy(m);
    }
    setup_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_versions_this_cpu_runs),
        cmocka_unit_test(test_ashikhmin_shirley),
        cmocka_unit_test(test_phong_and_blinn),
        cmocka_unit_test(test_lambert_and_two_lobes),
        cmocka_unit_test(test_microfacet),
        cmocka_unit_test(test_ashikhmin_shirley_fresnel),
        cmocka_unit_test(test_scattered_and_weightings),
        cmocka_unit_test(test_loaded_values),
        cmocka_unit_test(test_what_it_serves),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

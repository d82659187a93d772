/* The picture checks of fuzz_eval.c (included once, by fuzz_eval_checks.h):
 * every picture function with decoded options, strides and sizes, in a
 * buffer whose row padding and trailing guard must keep their bytes. */
#ifndef BRDFFIT_FUZZ_EVAL_PICTURES_H
#define BRDFFIT_FUZZ_EVAL_PICTURES_H

#define FILL 0x5a

typedef struct canvas {
    unsigned char *px;
    size_t width, height, stride, bytes;
} canvas;

/* A buffer of exactly (height - 1) * stride + 3 * width bytes plus the guard. */
static int canvas_make(canvas *c, size_t width, size_t height, unsigned pad)
{
    c->width = width, c->height = height, c->stride = 3 * width + pad % 8u;
    c->bytes = (height - 1) * c->stride + 3 * width;
    c->px = malloc(c->bytes + GUARD);
    if (c->px != NULL) memset(c->px, FILL, c->bytes + GUARD);
    return c->px != NULL;
}

/* Nothing written outside the pixels; frees the buffer. */
static void canvas_check(canvas *c)
{
    size_t y, i;
    for (y = 0; y + 1 < c->height; y++)
        for (i = 3 * c->width; i < c->stride; i++) fuzz_require(c->px[y * c->stride + i] == FILL);
    for (i = 0; i < GUARD; i++) fuzz_require(c->px[c->bytes + i] == FILL);
    free(c->px);
}

/* Runs `call` (a picture into c) normally, then, for a call that
 * succeeded, with its `fail`-th allocation failing: exactly OUT_OF_MEMORY
 * when it allocates that often, else the same success. */
#define PICTURE(c, fa, fail, st, call)                                            \
    do {                                                                          \
        st = (call);                                                              \
        if (st == BRDFFIT_OK && (fail) > 0) {                                     \
            brdffit_status again;                                                 \
            (fa)->allocs = 0;                                                     \
            (fa)->fail_at = (fail);                                               \
            again = (call);                                                       \
            fuzz_require(again == ((fa)->allocs >= (fail) ? BRDFFIT_E_OUT_OF_MEMORY \
                                                           : BRDFFIT_OK));        \
            (fa)->fail_at = 0;                                                    \
        }                                                                         \
    } while (0)

static void check_textures(reader *r, const brdffit_grid *g, const brdffit_model *m,
                           const double *x, const brdffit_image_options *o, fuzz_alloc *fa,
                           unsigned fail)
{
    static const brdffit_status size_errors[] = {BRDFFIT_E_INVALID_ARGUMENT, BRDFFIT_E_UNSUPPORTED,
                                                 BRDFFIT_E_TOO_LARGE};
    size_t w = 0, h = 0;
    unsigned kind;
    brdffit_error err;
    brdffit_status st = brdffit_image_texture_size(g, o, &w, &h, &err);
    expect_one_of(st, &err, size_errors, 3);
    if (st != BRDFFIT_OK) return;
    fuzz_require(w >= 1 && h >= 1 && w <= 4096 && h <= 4096);
    for (kind = 0; kind < 3; kind++) {
        canvas c;
        if (!canvas_make(&c, w, h, next(r))) return;
        PICTURE(&c, fa, fail, st,
                brdffit_image_texture(c.px, c.stride, (brdffit_texture_kind)kind, g, m, x, o,
                                      &fa->hook, &err));
        expect_one_of(st, &err, model_errors, 2);
        canvas_check(&c);
    }
}

static void check_spheres(reader *r, const brdffit_grid *g, const brdffit_model *m,
                          const double *x, const brdffit_image_options *o, fuzz_alloc *fa,
                          unsigned fail)
{
    static const brdffit_status measured_errors[] = {BRDFFIT_E_INVALID_ARGUMENT,
                                                     BRDFFIT_E_UNSUPPORTED};
    static const brdffit_status model_sphere_errors[] = {
        BRDFFIT_E_INVALID_ARGUMENT, BRDFFIT_E_NONFINITE, BRDFFIT_E_MODEL_FAILED};
    size_t size = 1 + next(r) % 24u, nc = brdffit_grid_channel_count(g);
    unsigned t = next(r);
    double theta = t == 255u ? 3.5 : angle_code(t, 0.0, PI);
    double phi = angle_code(next(r), -10.0, 10.0);
    brdffit_error err;
    brdffit_status st;
    canvas c;
    if (!canvas_make(&c, size, size, next(r))) return;
    PICTURE(&c, fa, fail, st,
            brdffit_image_sphere_measured(c.px, c.stride, size, g, theta, phi, o, &fa->hook,
                                          &err));
    expect_one_of(st, &err, measured_errors, 2);
    PICTURE(&c, fa, fail, st,
            brdffit_image_sphere_model(c.px, c.stride, size, m, x, nc, theta, phi, o, &fa->hook,
                                       &err));
    expect_one_of(st, &err, model_sphere_errors, 3);
    canvas_check(&c);
}

static void check_plot(reader *r, const brdffit_image_options *o)
{
    static const brdffit_status plot_errors[] = {BRDFFIT_E_INVALID_ARGUMENT,
                                                 BRDFFIT_E_NONFINITE};
    size_t w = 16 + next(r) % 32u, h = 16 + next(r) % 32u, count = next(r) % 9u, k;
    double values[8];
    brdffit_error err;
    brdffit_status st;
    canvas c;
    for (k = 0; k < count; k++) {
        unsigned v = next(r);
        values[k] = v == 255u ? NAN : (v & 1u ? -1.0 : 1.0) * value_code(v);
    }
    if (!canvas_make(&c, w, h, next(r))) return;
    st = brdffit_image_plot(c.px, c.stride, w, h, count ? values : NULL, count, o, &err);
    expect_one_of(st, &err, plot_errors, 2);
    canvas_check(&c);
}

static void check_pictures(reader *r, const brdffit_grid *g, const brdffit_model *m,
                           const double *x, const brdffit_image_options *o, fuzz_alloc *fa)
{
    unsigned fail = (r->size > 0 && (r->data[0] & 64u)) ? 1 + next(r) % 2u : 0;
    check_textures(r, g, m, x, o, fa, fail);
    check_spheres(r, g, m, x, o, fa, fail);
    check_plot(r, o);
}

#endif

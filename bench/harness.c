/* The benchmark harness: see harness.h. */
#include "harness.h"

#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

brdffit_status bh_error(brdffit_error *err, const char *fmt, ...)
{
    va_list ap;
    err->status = BRDFFIT_E_INVALID_ARGUMENT;
    va_start(ap, fmt);
    vsnprintf(err->message, sizeof err->message, fmt, ap);
    va_end(ap);
    return err->status;
}

/* ---- options ------------------------------------------------------------ */

static const char *base_name(const char *path)
{
    const char *slash = strrchr(path, '/');
    return slash ? slash + 1 : path;
}

static void usage(FILE *f, const char *program, const char *summary)
{
    fprintf(f,
            "usage: %s [--smoke] [--json | --json=FILE] [--repeats=N] [--filter=TEXT]\n"
            "%s\n"
            "  --smoke      one tiny iteration of everything (checks only, no figures)\n"
            "  --json       JSON lines on stdout instead of the table\n"
            "  --json=FILE  append JSON lines to FILE, the table still goes to stdout\n"
            "  --repeats=N  timed runs per measurement (overrides the defaults)\n"
            "  --filter=TEXT only the measurements whose name contains TEXT\n",
            program, summary);
}

static int parse_repeats(const char *s, size_t *out)
{
    char *end;
    unsigned long v = strtoul(s, &end, 10);
    if (*s == '\0' || *end != '\0' || v == 0 || v > 100000) return 0;
    *out = (size_t)v;
    return 1;
}

static int parse_one(const char *a, bh_options *opt)
{
    if (strcmp(a, "--smoke") == 0)
        opt->smoke = 1;
    else if (strcmp(a, "--json") == 0)
        opt->json_only = 1;
    else if (strncmp(a, "--json=", 7) == 0 && a[7] != '\0')
        opt->json_path = a + 7;
    else if (strncmp(a, "--repeats=", 10) == 0)
        return parse_repeats(a + 10, &opt->repeats);
    else if (strncmp(a, "--filter=", 9) == 0 && a[9] != '\0')
        opt->filter = a + 9;
    else
        return 0;
    return 1;
}

int bh_parse_args(int argc, char **argv, const char *summary, bh_options *opt, int *exit_code)
{
    int i;
    memset(opt, 0, sizeof *opt);
    opt->program = base_name(argc > 0 ? argv[0] : "bench");
    for (i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            usage(stdout, opt->program, summary);
            *exit_code = 0;
            return 0;
        }
        if (!parse_one(argv[i], opt)) {
            fprintf(stderr, "%s: unknown or malformed option '%s'\n", opt->program, argv[i]);
            usage(stderr, opt->program, summary);
            *exit_code = 2;
            return 0;
        }
    }
    return 1;
}

size_t bh_repeats(const bh_options *opt, size_t normal)
{
    if (opt->repeats > 0) return opt->repeats;
    return opt->smoke ? 1 : normal;
}

int bh_selected(const bh_options *opt, const char *name)
{
    return opt->filter == NULL || strstr(name, opt->filter) != NULL;
}

/* ---- timing ----------------------------------------------------------------- */

uint64_t bh_now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * UINT64_C(1000000000) + (uint64_t)ts.tv_nsec;
}

uint64_t bh_cpu_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (uint64_t)ts.tv_sec * UINT64_C(1000000000) + (uint64_t)ts.tv_nsec;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

void bh_stats_from(double *ns, size_t n, bh_stats *out)
{
    out->samples = n;
    out->median_cpu_ns = NAN;
    if (n == 0) {
        out->median_ns = out->min_ns = out->max_ns = NAN;
        return;
    }
    qsort(ns, n, sizeof *ns, cmp_double);
    out->min_ns = ns[0];
    out->max_ns = ns[n - 1];
    out->median_ns = n % 2 ? ns[n / 2] : 0.5 * (ns[n / 2 - 1] + ns[n / 2]);
}

int bh_measure(bh_run_fn fn, void *ctx, size_t warmup, size_t repeats, bh_stats *out)
{
    double *ns, *cpu;
    bh_stats cpu_stats;
    size_t i;
    int rc = 0;
    if (repeats == 0) repeats = 1;
    ns = malloc(2 * repeats * sizeof *ns);
    if (ns == NULL) return -1;
    cpu = ns + repeats;
    for (i = 0; i < warmup && rc == 0; i++) rc = fn(ctx);
    for (i = 0; i < repeats && rc == 0; i++) {
        uint64_t c0 = bh_cpu_ns(), t0 = bh_now_ns();
        rc = fn(ctx);
        ns[i] = (double)(bh_now_ns() - t0);
        cpu[i] = (double)(bh_cpu_ns() - c0);
    }
    bh_stats_from(ns, rc == 0 ? repeats : 0, out);
    bh_stats_from(cpu, rc == 0 ? repeats : 0, &cpu_stats);
    out->median_cpu_ns = cpu_stats.median_ns;
    free(ns);
    return rc;
}

/* ---- the machine ------------------------------------------------------------ */

static void trim(char *s)
{
    size_t n = strlen(s);
    while (n > 0 && (s[n - 1] == '\n' || s[n - 1] == ' ' || s[n - 1] == '\t')) s[--n] = '\0';
}

void bh_cpu_model(char *buf, size_t size)
{
    char line[512];
    FILE *f = fopen("/proc/cpuinfo", "r");
    snprintf(buf, size, "unknown");
    if (f == NULL) return;
    while (fgets(line, sizeof line, f) != NULL) {
        char *colon = strchr(line, ':');
        if (strncmp(line, "model name", 10) != 0 || colon == NULL) continue;
        colon++;
        while (*colon == ' ' || *colon == '\t') colon++;
        trim(colon);
        snprintf(buf, size, "%s", colon);
        break;
    }
    fclose(f);
}

const char *bh_compiler(void)
{
#if defined(__clang__)
    return "clang " __VERSION__;
#elif defined(__GNUC__)
    return "gcc " __VERSION__;
#else
    return "unknown compiler";
#endif
}

long bh_cpu_count(void)
{
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n > 0 ? n : 1;
}

double bh_load_average(void)
{
    double load = -1.0;
    FILE *f = fopen("/proc/loadavg", "r");
    if (f == NULL) return load;
    if (fscanf(f, "%lf", &load) != 1) load = -1.0;
    fclose(f);
    return load;
}

/* ---- counting allocator ------------------------------------------------------ */

/* Every block carries its size in a header as large as the strictest
 * alignment, so the pointer handed out stays aligned for any type. */
#define BH_HEADER (sizeof(max_align_t))

void bh_counter_init(bh_counter *c)
{
    atomic_init(&c->live, 0);
    atomic_init(&c->peak, 0);
    atomic_init(&c->total, 0);
    atomic_init(&c->calls, 0);
}

void bh_counter_reset_peak(bh_counter *c)
{
    atomic_store(&c->peak, atomic_load(&c->live));
}

static void raise_peak(bh_counter *c, size_t live)
{
    size_t peak = atomic_load(&c->peak);
    while (live > peak && !atomic_compare_exchange_weak(&c->peak, &peak, live)) {
    }
}

static void *counting_alloc(size_t size, void *ctx)
{
    bh_counter *c = ctx;
    unsigned char *p;
    if (size > (size_t)-1 - BH_HEADER) return NULL;
    p = malloc(size + BH_HEADER);
    if (p == NULL) return NULL;
    memcpy(p, &size, sizeof size);
    atomic_fetch_add(&c->calls, 1);
    atomic_fetch_add(&c->total, size);
    raise_peak(c, atomic_fetch_add(&c->live, size) + size);
    return p + BH_HEADER;
}

static void counting_free(void *ptr, void *ctx)
{
    bh_counter *c = ctx;
    unsigned char *p = (unsigned char *)ptr - BH_HEADER;
    size_t size;
    memcpy(&size, p, sizeof size);
    atomic_fetch_sub(&c->live, size);
    free(p);
}

brdffit_allocator bh_counter_allocator(bh_counter *c)
{
    brdffit_allocator a;
    a.alloc = counting_alloc;
    a.free = counting_free;
    a.ctx = c;
    return a;
}

/* ---- random numbers (splitmix64) --------------------------------------------- */

void bh_rng_seed(bh_rng *r, uint64_t seed)
{
    r->state = seed;
}

static uint64_t next_u64(bh_rng *r)
{
    uint64_t z = (r->state += UINT64_C(0x9e3779b97f4a7c15));
    z = (z ^ (z >> 30)) * UINT64_C(0xbf58476d1ce4e5b9);
    z = (z ^ (z >> 27)) * UINT64_C(0x94d049bb133111eb);
    return z ^ (z >> 31);
}

double bh_rng_uniform(bh_rng *r)
{
    return (double)(next_u64(r) >> 11) * (1.0 / 9007199254740992.0);
}

double bh_rng_normal(bh_rng *r)
{
    double u1 = 1.0 - bh_rng_uniform(r), u2 = bh_rng_uniform(r); /* u1 in (0, 1] */
    return sqrt(-2.0 * log(u1)) * cos(2.0 * 3.14159265358979323846 * u2);
}

/* ---- output --------------------------------------------------------------------- */

static void header(bh_output *out, const char *title)
{
    char cpu[256];
    bh_record r;
    bh_cpu_model(cpu, sizeof cpu);
    bh_table(out, "%s: %s\n", out->opt->program, title);
    bh_table(out, "cpu: %s (%ld online, load %.2f)   compiler: %s   libbrdffit %s%s\n\n", cpu,
             bh_cpu_count(), bh_load_average(), bh_compiler(), brdffit_version_string(),
             out->opt->smoke ? "   SMOKE RUN (no figures)" : "");
    bh_rec_begin(&r, out, "machine");
    bh_rec_str(&r, "cpu", cpu);
    bh_rec_int(&r, "cpus", (size_t)bh_cpu_count());
    bh_rec_num(&r, "load_average", bh_load_average());
    bh_rec_str(&r, "compiler", bh_compiler());
    bh_rec_str(&r, "library", brdffit_version_string());
    bh_rec_bool(&r, "smoke", out->opt->smoke);
    bh_rec_end(&r, out);
}

int bh_output_open(bh_output *out, const bh_options *opt, const char *title)
{
    memset(out, 0, sizeof *out);
    out->opt = opt;
    out->table = opt->json_only ? NULL : stdout;
    if (opt->json_only)
        out->json = stdout;
    else if (opt->json_path != NULL)
        out->json = fopen(opt->json_path, "a");
    if (opt->json_path != NULL && !opt->json_only && out->json == NULL) {
        fprintf(stderr, "%s: cannot open %s for appending\n", opt->program, opt->json_path);
        return 0;
    }
    header(out, title);
    return 1;
}

int bh_output_close(bh_output *out)
{
    if (out->json != NULL && out->json != stdout) fclose(out->json);
    if (out->table != NULL) fflush(out->table);
    if (out->failed) fprintf(stderr, "%s: FAILED (see the messages above)\n", out->opt->program);
    return out->failed ? 1 : 0;
}

void bh_table(bh_output *out, const char *fmt, ...)
{
    va_list ap;
    if (out->table == NULL) return;
    va_start(ap, fmt);
    vfprintf(out->table, fmt, ap);
    va_end(ap);
}

void bh_fail(bh_output *out, const char *fmt, ...)
{
    va_list ap;
    fprintf(stderr, "%s: check failed: ", out->opt->program);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
    out->failed = 1;
}

static void rec_append(bh_record *r, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

static void rec_append(bh_record *r, const char *fmt, ...)
{
    va_list ap;
    int n;
    if (r->len >= sizeof r->buf) return;
    va_start(ap, fmt);
    n = vsnprintf(r->buf + r->len, sizeof r->buf - r->len, fmt, ap);
    va_end(ap);
    if (n > 0) r->len += (size_t)n;
    if (r->len >= sizeof r->buf) r->len = sizeof r->buf - 1;
}

static void rec_key(bh_record *r, const char *key)
{
    rec_append(r, ",\"%s\":", key);
}

static void rec_quoted(bh_record *r, const char *s)
{
    rec_append(r, "\"");
    for (; *s != '\0'; s++) {
        unsigned char ch = (unsigned char)*s;
        if (ch == '"' || ch == '\\')
            rec_append(r, "\\%c", ch);
        else if (ch < 0x20)
            rec_append(r, "\\u%04x", ch);
        else
            rec_append(r, "%c", ch);
    }
    rec_append(r, "\"");
}

void bh_rec_begin(bh_record *r, const bh_output *out, const char *name)
{
    r->len = 0;
    r->buf[0] = '\0';
    rec_append(r, "{\"bench\":");
    rec_quoted(r, out->opt->program);
    rec_key(r, "name");
    rec_quoted(r, name);
}

void bh_rec_str(bh_record *r, const char *key, const char *value)
{
    rec_key(r, key);
    rec_quoted(r, value);
}

void bh_rec_num(bh_record *r, const char *key, double value)
{
    rec_key(r, key);
    if (isfinite(value))
        rec_append(r, "%.17g", value);
    else
        rec_append(r, "null");
}

void bh_rec_int(bh_record *r, const char *key, size_t value)
{
    rec_key(r, key);
    rec_append(r, "%zu", value);
}

void bh_rec_bool(bh_record *r, const char *key, int value)
{
    rec_key(r, key);
    rec_append(r, value ? "true" : "false");
}

void bh_rec_stats(bh_record *r, const bh_stats *s, size_t rows)
{
    bh_rec_int(r, "samples", s->samples);
    bh_rec_int(r, "rows", rows);
    bh_rec_num(r, "median_ns", s->median_ns);
    bh_rec_num(r, "min_ns", s->min_ns);
    bh_rec_num(r, "max_ns", s->max_ns);
    bh_rec_num(r, "ns_per_row", rows ? s->median_ns / (double)rows : NAN);
    bh_rec_num(r, "median_cpu_ns", s->median_cpu_ns);
}

void bh_rec_end(bh_record *r, bh_output *out)
{
    if (out->json == NULL) return;
    fprintf(out->json, "%s}\n", r->buf);
    fflush(out->json);
}

void bh_target(bh_output *out, const char *what, const char *measured, const char *limit, int met)
{
    bh_record r;
    bh_table(out, "target: %-58s %-36s (%s)  %s\n", what, measured, limit,
             out->opt->smoke ? "-" : (met ? "met" : "MISSED"));
    bh_rec_begin(&r, out, "target");
    bh_rec_str(&r, "target", what);
    bh_rec_str(&r, "measured", measured);
    bh_rec_str(&r, "limit", limit);
    bh_rec_bool(&r, "met", met);
    bh_rec_end(&r, out);
}

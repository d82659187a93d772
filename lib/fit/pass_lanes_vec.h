/* The vector version of the fused loop's lanes, VW lanes at a time (VW =
 * 8 or 4), with the GNU C vector extensions, with fused multiply-add (VFMA
 * 1: the AVX-512 and AVX2 intrinsics) or without (VFMA 0). Included three
 * times by pass_lanes.h; every name ends in _VSUFFIX. The arithmetic per
 * lane is that of the plain version in pass_lanes.h, operation for
 * operation. Not installed. */
#define VCAT2(a, b) a##_##b
#define VCAT(a, b) VCAT2(a, b)
#define VN(name) VCAT(name, VSUFFIX)
#define VD VN(vd)
#define VF VN(vf)
#define VI VN(vi)
#define VU VN(vu)

typedef double VD __attribute__((vector_size(VW * sizeof(double))));
typedef float VF __attribute__((vector_size(VW * sizeof(float))));
typedef long long VI __attribute__((vector_size(VW * sizeof(double))));
typedef unsigned long long VU __attribute__((vector_size(VW * sizeof(double))));

static inline VD VN(vload)(const double *p)
{
    VD v;
    memcpy(&v, p, sizeof v);
    return v;
}

/* VW floats widened to doubles (exactly) */
static inline VD VN(vloadf)(const float *p)
{
#if VFMA && VW == 8
    return _mm512_cvtps_pd(_mm256_loadu_ps(p));
#elif VFMA
    return _mm256_cvtps_pd(_mm_loadu_ps(p));
#else
    VF v;
    memcpy(&v, p, sizeof v);
    return __builtin_convertvector(v, VD);
#endif
}

static inline VD VN(vsplat)(double x)
{
#if VW == 8
    VD v = {x, x, x, x, x, x, x, x};
#else
    VD v = {x, x, x, x};
#endif
    return v;
}

/* a b + c: one rounding (VFMA) or two */
static inline VD VN(vmadd)(VD a, VD b, VD c)
{
#if VFMA && VW == 8
    return _mm512_fmadd_pd(a, b, c);
#elif VFMA
    return _mm256_fmadd_pd(a, b, c);
#else
    return a * b + c;
#endif
}

/* c - a b: one rounding (VFMA) or two */
static inline VD VN(vnmadd)(VD a, VD b, VD c)
{
#if VFMA && VW == 8
    return _mm512_fnmadd_pd(a, b, c);
#elif VFMA
    return _mm256_fnmadd_pd(a, b, c);
#else
    return c - a * b;
#endif
}

/* m ? a : b lane by lane (m all ones or all zeros per lane) */
static inline VD VN(vsel)(VI m, VD a, VD b)
{
    return (VD)((m & (VI)a) | (~m & (VI)b));
}

/* lane_exp_t() of pass_lanes.h lane by lane: e^y from t = y log2(e) +
 * 1.5 2^52, 0 where y < EXP_LO (those lanes masked off bit by bit,
 * whatever their arithmetic gave). */
static inline VD VN(vexp_t)(VD y, VD t)
{
    const VD k = t - VN(vsplat)(EXP_SHIFTER);
    VD r, r2, r4, r8, q0, q1, q2, q3, q4, q5, p, scale;
    r = VN(vnmadd)(k, VN(vsplat)(EXP_LN2_HI), y);
    r = VN(vnmadd)(k, VN(vsplat)(EXP_LN2_LO), r);
    r2 = r * r;
    r4 = r2 * r2;
    r8 = r4 * r4;
    q0 = r + VN(vsplat)(1.0);
    q1 = VN(vmadd)(VN(vsplat)(EXP_C3), r, VN(vsplat)(EXP_C2));
    q2 = VN(vmadd)(VN(vsplat)(EXP_C5), r, VN(vsplat)(EXP_C4));
    q3 = VN(vmadd)(VN(vsplat)(EXP_C7), r, VN(vsplat)(EXP_C6));
    q4 = VN(vmadd)(VN(vsplat)(EXP_C9), r, VN(vsplat)(EXP_C8));
    q5 = VN(vmadd)(VN(vsplat)(EXP_C11), r, VN(vsplat)(EXP_C10));
    q0 = VN(vmadd)(q1, r2, q0);
    q2 = VN(vmadd)(q3, r2, q2);
    q4 = VN(vmadd)(q5, r2, q4);
    q0 = VN(vmadd)(q2, r4, q0);
    p = VN(vmadd)(q4, r8, q0);
    scale = (VD)(((VU)t + 1023u) << 52);
#if VFMA && VW == 8
    return _mm512_maskz_mul_pd(_mm512_cmp_pd_mask(y, VN(vsplat)(EXP_LO), _CMP_GE_OQ), p, scale);
#elif VFMA
    return _mm256_and_pd(_mm256_cmp_pd(y, VN(vsplat)(EXP_LO), _CMP_GE_OQ), p * scale);
#else
    return (VD)((VI)(p * scale) & (y >= VN(vsplat)(EXP_LO)));
#endif
}

/* lane_exp() of pass_lanes.h lane by lane. */
static inline VD VN(vexp)(VD y)
{
    return VN(vexp_t)(y, VN(vmadd)(y, VN(vsplat)(EXP_LOG2E), VN(vsplat)(EXP_SHIFTER)));
}

/* sqrt() lane by lane (the compilers make one vector square root of it) */
static inline VD VN(vsqrt)(VD x)
{
    VD r;
    int l;
    for (l = 0; l < VW; l++) r[l] = sqrt(x[l]);
    return r;
}

/* a < b ? a : b lane by lane (bf_min() of models/kernel.h) */
static inline VD VN(vmin)(VD a, VD b)
{
    return VN(vsel)(a < b, a, b);
}

/* The lobe form's basis: lane_basis() of pass_lanes.h. */
static inline void VN(lobe_basis)(const lobe_in *in, size_t i, size_t nl, int gk, int derivs, VD w,
                                  VD *u, VD *b)
{
    size_t q;
    VD x, g, gw;
    u[0] = w * VN(vsplat)(INV_PI);
    if (nl == 0) return;
    x = VN(vload)(in->x + i);
    if (gk == G_READ)
        g = VN(vloadf)(in->g + i);
    else if (gk == G_ONE)
        g = VN(vsplat)(1.0);
    else
        g = (VD)((x > VN(vsplat)(X_RV_LIVE)) & (VI)VN(vsplat)(1.0));
    gw = g * w;
    for (q = 0; q < nl; q++) {
        const VD kk = VN(vsplat)(in->k[q]);
        const VD e = VN(vexp_t)(VN(vsplat)(in->ns[q]) * x,
                                VN(vmadd)(x, VN(vsplat)(in->nsl[q]), VN(vsplat)(EXP_SHIFTER)));
        b[q] = e * (kk * g);
        u[1 + q] = e * (kk * gw);
        if (derivs) u[1 + nl + q] = e * (VN(vmadd)(kk, x, VN(vsplat)(in->dk[q])) * gw);
    }
}

/* The microfacet form's weighted basis u, lobe values b (and the
 * Ashikhmin-Shirley shader form's B_0 bd) of VW samples from i:
 * lane_mf_basis() of pass_lanes.h, operation for operation. */
static inline void VN(mf_basis)(const lobe_in *in, size_t i, size_t nl, int mf, int derivs, VD w,
                                VD *u, VD *b, VD *bd)
{
    const VD one = VN(vsplat)(1.0);
    const VD nh = VN(vload)(in->dot[0] + i), nl_ = VN(vload)(in->dot[1] + i);
    const VD nv = VN(vload)(in->dot[2] + i), hv = VN(vload)(in->dot[3] + i);
    const VD hv1 = one - hv, hv2 = hv1 * hv1, f5 = hv2 * hv2 * hv1;
    const VD fr = VN(vmadd)(VN(vsplat)(1.0 - in->f0), f5, VN(vsplat)(in->f0)), omf = one - f5;
    size_t q;
    u[0] = w * VN(vsplat)(INV_PI);
    if (mf == BF_MF_GGX) {
        const VD t = (one - nh) * (one + nh), c2 = nh * nh;
        const VD w4 = one / (VN(vsplat)(4.0) * nl_ * nv);
        const VD tl = (one - nl_) * (one + nl_) / (nl_ * nl_);
        const VD tv = (one - nv) * (one + nv) / (nv * nv);
        for (q = 0; q < nl; q++) {
            const VD a2 = VN(vsplat)(in->r2[q]), iq = one / VN(vmadd)(a2, c2, t);
            const VD d = a2 * iq * iq / VN(vsplat)(BF_PI);
            const VD sl = VN(vsqrt)(VN(vmadd)(a2, tl, one)), sv = VN(vsqrt)(VN(vmadd)(a2, tv, one));
            const VD r = one / ((sl + sv) * sl * sv);
            const VD gg = VN(vsplat)(2.0) * sl * sv * r;
            const VD dgs = d * gg * w4;
            b[q] = dgs * fr;
            u[1 + q] = w * b[q];
            if (derivs) {
                const VD dd =
                    d * (VN(vsplat)(in->two_r[q]) - VN(vsplat)(in->four_r[q]) * c2 * iq);
                const VD dg =
                    VN(vsplat)(in->m2_r[q]) * VN(vmadd)(tl, sv, tv * sl) * sl * sv * r * r;
                u[1 + nl + q] = w * (VN(vmadd)(dd, gg, d * dg) * w4 * fr);
                u[1 + 2 * nl + q] = w * (dgs * omf);
            }
        }
    } else if (is_asf(mf)) {
        const VD x = VN(vload)(in->x + i), kk = VN(vsplat)(in->k[0]);
        const VD p = VN(vexp_t)(VN(vsplat)(in->ns[0]) * x,
                                VN(vmadd)(x, VN(vsplat)(in->nsl[0]), VN(vsplat)(EXP_SHIFTER))) *
                     VN(vloadf)(in->g + i);
        const VD half = VN(vsplat)(0.5);
        const VD ol = one - half * nl_, ol2 = ol * ol, ov = one - half * nv, ov2 = ov * ov;
        const VD fd = VN(vsplat)(ASF_KD) * (one - ol2 * ol2 * ol) * (one - ov2 * ov2 * ov);
        const VD lobe = kk * p;
        (void)nh;
        *bd = VN(vsplat)(1.0 - in->f0) * fd;
        b[0] = lobe * fr;
        u[0] = w * *bd;
        u[1] = w * b[0];
        if (derivs) {
            u[2] = w * ((VN(vmadd)(kk, x, VN(vsplat)(in->dk[0])) * p) * fr);
            u[3] = w * -fd;
            u[4] = w * (lobe * omf);
        }
    } else if (mf == BF_MF_WARD || mf == BF_MF_WARD_DUER) {
        const VD k = VN(vsplat)(in->four_r[0]);
        const VD inv_n = mf == BF_MF_WARD_DUER ? k / (nl_ * nv) : k / VN(vsqrt)(nl_ * nv);
        const VD x = (one - nh) * (one + nh) / (nh * nh) * VN(vsplat)(in->r2[0]);
        (void)fr;
        (void)omf;
        b[0] = VN(vexp)(-x) * inv_n;
        u[1] = w * b[0];
        if (derivs) u[2] = w * (b[0] * VN(vsplat)(in->two_r[0]) * (x - one));
    } else {
        const VD c2 = nh * nh;
        const VD gx = VN(vsplat)(2.0) * nh * VN(vmin)(nl_, nv) / hv;
        const VD gg = VN(vmin)(one, gx);
        const VD t = (one - nh) * (one + nh) / (nh * nh);
        const VD wc = gg / (VN(vsplat)(4.0 * BF_PI) * c2 * c2 * nl_ * nv);
        for (q = 0; q < nl; q++) {
            const VD r2 = VN(vsplat)(in->r2[q]), x = t * r2;
            const VD dgs = VN(vexp)(-x) * r2 * wc;
            b[q] = dgs * fr;
            u[1 + q] = w * b[q];
            if (derivs) {
                u[1 + nl + q] = w * (b[q] * VN(vsplat)(in->two_r[q]) * (x - one));
                u[1 + 2 * nl + q] = w * (dgs * omf);
            }
        }
    }
}

/* The residual from the buffered basis (bd, b), in the order of the
 * plain version. */
static inline VD VN(vresidual)(const lobe_in *in, size_t i, size_t c, size_t nl, int mf, VD bd,
                               const VD *b, VD w)
{
    const VD m = VN(vloadf)(in->m[c] + i);
    VD d = is_asf(mf) ? VN(vmadd)(VN(vsplat)(in->cd[c]), bd, -m) : VN(vsplat)(in->cdpi[c]) - m;
    size_t q;
    for (q = 0; q < nl; q++) d = VN(vmadd)(VN(vsplat)(in->cs[q][c]), b[q], d);
    return d * w;
}

/* The first phase of a sweep: the weight w, the weighted basis u (NE or
 * L functions), the lobes' values b and B_0 (bd) of VW samples from i
 * into rows of the buffer at column p (rows of SWEEP_BLOCK: u, then b,
 * bd, w). The lanes' arithmetic has no dependence from one group to the
 * next, so groups overlap in the processor. */
static inline void VN(basis_group)(const lobe_in *in, size_t i, size_t nl, int mf, int gk,
                                   bf_pass_kind kind, double *buf, size_t p)
{
    const size_t ne = n_basis(kind, nl, mf);
    const VD w = VN(vloadf)(in->w + i) * VN(vsplat)(in->wf);
    VD u[MAX_EXT], b[MAX_LOBES], bd = VN(vsplat)(INV_PI);
    if (mf != BF_MF_NONE) VN(mf_basis)(in, i, nl, mf, kind == BF_PASS_NORMAL, w, u, b, &bd);
    else
        VN(lobe_basis)(in, i, nl, gk, kind == BF_PASS_NORMAL, w, u, b);
        /* constant indices only, so that u and b stay in registers */
#define VPUT(row, v) memcpy(buf + (row)*SWEEP_BLOCK + p, &(v), sizeof(VD))
#define VPUT_U(a) \
    if ((a) < ne) VPUT(a, u[a])
#define VPUT_B(q) \
    if ((q) < nl) VPUT(ne + (q), b[q])
    VPUT_U(0);
    VPUT_U(1);
    VPUT_U(2);
    VPUT_U(3);
    VPUT_U(4);
    VPUT_U(5);
    VPUT_U(6);
    VPUT_B(0);
    VPUT_B(1);
    VPUT(ne + nl, bd);
    VPUT(ne + nl + 1, w);
#undef VPUT
#undef VPUT_U
#undef VPUT_B
}

/* The second phase: the sums of blocks lo .. hi (pass_lanes.h) of VW
 * samples from column p of the buffer (their measured values from i of
 * `in`), s[k] holding sum block_first(lo) + k. */
static inline void VN(sum_group)(const lobe_in *in, size_t i, size_t nc, size_t nl, int mf,
                                 bf_pass_kind kind, size_t lo, size_t hi, const double *buf,
                                 size_t p, VD *s)
{
    const size_t ne = n_basis(kind, nl, mf), s0 = block_first(kind, nl, mf, lo);
    const VD bd = VN(vload)(buf + (ne + nl) * SWEEP_BLOCK + p);
    const VD w = VN(vload)(buf + (ne + nl + 1) * SWEEP_BLOCK + p);
    VD u[MAX_EXT], b[MAX_LOBES];
    size_t a, e, c, t, q;
    for (a = 0; a < ne; a++) u[a] = VN(vload)(buf + a * SWEEP_BLOCK + p);
    for (q = 0; q < nl; q++) b[q] = VN(vload)(buf + (ne + q) * SWEEP_BLOCK + p);
    t = 0;
    if (lo == 0 && kind != BF_PASS_COST)
        for (a = 0; a < ne; a++)
            for (e = a; e < ne; e++) {
                s[t] = VN(vmadd)(u[a], u[e], s[t]);
                t++;
            }
    for (c = lo == 0 ? 0 : lo - 1; c < nc && c < hi; c++) {
        const size_t f = block_first(kind, nl, mf, 1 + c) - s0;
        if (kind == BF_PASS_VARPRO) {
            const VD r = w * VN(vloadf)(in->m[c] + i);
            for (a = 0; a < ne; a++) s[f + a] = VN(vmadd)(u[a], r, s[f + a]);
            s[f + ne] = VN(vmadd)(r, r, s[f + ne]);
        } else {
            const VD d = VN(vresidual)(in, i, c, nl, mf, bd, b, w);
            s[f] = VN(vmadd)(d, d, s[f]);
            if (kind == BF_PASS_NORMAL)
                for (a = 0; a < ne; a++) s[f + 1 + a] = VN(vmadd)(u[a], d, s[f + 1 + a]);
        }
    }
}

#define VLOAD(k) \
    if ((k) < n_sums) s[k] = VN(vload)(acc + (s0 + (k)) * LANES + off)
#define VSTORE(k) \
    if ((k) < n_sums) memcpy(acc + (s0 + (k)) * LANES + off, &s[k], sizeof s[k])
#define VLOAD8(k) \
    VLOAD(k); VLOAD(k + 1); VLOAD(k + 2); VLOAD(k + 3); \
    VLOAD(k + 4); VLOAD(k + 5); VLOAD(k + 6); VLOAD(k + 7)
#define VSTORE8(k) \
    VSTORE(k); VSTORE(k + 1); VSTORE(k + 2); VSTORE(k + 3); \
    VSTORE(k + 4); VSTORE(k + 5); VSTORE(k + 6); VSTORE(k + 7)

/* Lanes [off, off + VW) of the sums of blocks lo .. hi over the g groups
 * of the buffer, whose samples start at i0 of `in` (the last group's
 * measured values from the padded tail t when tail is set), in
 * registers: s[] of 32 sums or of MAX_SUMS, so that the smaller one is
 * never held in memory for the larger's sake. */
#define SUM_PART(name, size, LOADS, STORES)                                                       \
    static inline void VN(name)(const lobe_in *in, const lobe_in *t, int tail, size_t i0,         \
                                size_t g, size_t nc, size_t nl, int mf, bf_pass_kind kind,        \
                                size_t lo, size_t hi, const double *buf, double *acc, size_t off) \
    {                                                                                             \
        VD s[size];                                                                               \
        const size_t s0 = block_first(kind, nl, mf, lo);                                          \
        const size_t n_sums = block_first(kind, nl, mf, hi + 1) - s0;                             \
        size_t k;                                                                                 \
        /* written out, so that s[] has constant indices only and stays in                    \
         * registers */   \
        LOADS;                                                                                    \
        for (k = 0; k + (tail ? 1 : 0) < g; k++)                                                  \
            VN(sum_group)                                                                         \
            (in, i0 + k * LANES + off, nc, nl, mf, kind, lo, hi, buf, k * LANES + off, s);        \
        if (tail) VN(sum_group)(t, off, nc, nl, mf, kind, lo, hi, buf, k * LANES + off, s);       \
        STORES;                                                                                   \
    }
#define LOADS32 VLOAD8(0); VLOAD8(8); VLOAD8(16); VLOAD8(24)
#define STORES32 VSTORE8(0); VSTORE8(8); VSTORE8(16); VSTORE8(24)
#define LOADS64 LOADS32; VLOAD8(32); VLOAD8(40); VLOAD8(48); VLOAD8(56)
#define STORES64 STORES32; VSTORE8(32); VSTORE8(40); VSTORE8(48); VSTORE8(56)
SUM_PART(sum_part32, 32, LOADS32, STORES32)
SUM_PART(sum_part64, MAX_SUMS, LOADS64, STORES64)
#undef SUM_PART
#undef LOADS32
#undef STORES32
#undef LOADS64
#undef STORES64

/* The sums of blocks lo .. hi, lanes [off, off + VW). */
static inline void VN(sum_blocks)(const lobe_in *in, const lobe_in *t, int tail, size_t i0,
                                  size_t g, size_t nc, size_t nl, int mf, bf_pass_kind kind,
                                  size_t lo, size_t hi, const double *buf, double *acc, size_t off)
{
    if (block_first(kind, nl, mf, hi + 1) - block_first(kind, nl, mf, lo) <= 32)
        VN(sum_part32)(in, t, tail, i0, g, nc, nl, mf, kind, lo, hi, buf, acc, off);
    else
        VN(sum_part64)(in, t, tail, i0, g, nc, nl, mf, kind, lo, hi, buf, acc, off);
}

/* A run of n samples, SWEEP_BLOCK at a time in two phases: the basis of
 * every sample of the block into a buffer, then the sums from the
 * buffer: every lane and block of sums at once (VW = 8), or lanes 0-3
 * and then 4-7 of one block of sums at a time (VW = 4: 16 registers hold
 * one block's sums). */
static inline void VN(sweep)(const lobe_in *in, size_t n, size_t nc, size_t nl, int mf, int gk,
                             bf_pass_kind kind, double *acc)
{
    double buf[(MAX_EXT + MAX_LOBES + 2) * SWEEP_BLOCK];
    tail_buf tb;
    lobe_in t;
    size_t i0, i, off;
    for (i0 = 0; i0 < n; i0 += SWEEP_BLOCK) {
        const size_t len = n - i0 < SWEEP_BLOCK ? n - i0 : SWEEP_BLOCK;
        const size_t full = len / LANES, g = (len + LANES - 1) / LANES;
        const int tail = g > full;
        for (i = 0; i < full * LANES; i += VW)
            VN(basis_group)(in, i0 + i, nl, mf, gk, kind, buf, i);
        if (tail) {
            pad_tail(in, i0 + full * LANES, n, nc, nl, mf, gk, &tb, &t);
            for (off = 0; off < LANES; off += VW)
                VN(basis_group)(&t, off, nl, mf, gk, kind, buf, full * LANES + off);
        }
        for (off = 0; off < LANES; off += VW) {
            const lobe_in *tp = tail ? &t : in;
            if (VW == LANES) {
                VN(sum_blocks)(in, tp, tail, i0, g, nc, nl, mf, kind, 0, nc, buf, acc, off);
                continue;
            }
            /* the blocks one by one, with constant bounds */
            if (kind != BF_PASS_COST)
                VN(sum_blocks)(in, tp, tail, i0, g, nc, nl, mf, kind, 0, 0, buf, acc, off);
            VN(sum_blocks)(in, tp, tail, i0, g, nc, nl, mf, kind, 1, 1, buf, acc, off);
            if (nc == 3) {
                VN(sum_blocks)(in, tp, tail, i0, g, nc, nl, mf, kind, 2, 2, buf, acc, off);
                VN(sum_blocks)(in, tp, tail, i0, g, nc, nl, mf, kind, 3, 3, buf, acc, off);
            }
        }
    }
}

#undef VLOAD
#undef VSTORE
#undef VLOAD8
#undef VSTORE8
#undef VD
#undef VF
#undef VI
#undef VU
#undef VN
#undef VCAT
#undef VCAT2

/* The vector version of the fused loop's lanes, VW lanes at a time (VW =
 * 8 or 4), with the GNU C vector extensions. Included twice by
 * pass_lanes.h, once per width; every name ends in _w8 or _w4. The
 * arithmetic per lane is that of the plain version in pass_lanes.h and of
 * bf_exp() in core/fastmath.h, operation for operation. Not installed. */
#define VCAT2(a, b) a##_w##b
#define VCAT(a, b) VCAT2(a, b)
#define VN(name) VCAT(name, VW)
#define VD VN(vd)
#define VI VN(vi)
#define VU VN(vu)

typedef double VD __attribute__((vector_size(VW * sizeof(double))));
typedef long long VI __attribute__((vector_size(VW * sizeof(double))));
typedef unsigned long long VU __attribute__((vector_size(VW * sizeof(double))));

static inline VD VN(vload)(const double *p)
{
    VD v;
    memcpy(&v, p, sizeof v);
    return v;
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

/* m ? a : b lane by lane (m all ones or all zeros per lane) */
static inline VD VN(vsel)(VI m, VD a, VD b)
{
    return (VD)((m & (VI)a) | (~m & (VI)b));
}

/* bf_exp() lane by lane. */
static inline VD VN(vexp)(VD x)
{
    const VD lo = VN(vsplat)(-708.0), hi = VN(vsplat)(709.0);
    const VD shifter = VN(vsplat)(6755399441055744.0);
    const VD keep = (VD)((x >= lo) & (VI)VN(vsplat)(1.0));
    VD t, k, r, p;
    x = VN(vsel)(x < lo, lo, VN(vsel)(x > hi, hi, x));
    t = x * VN(vsplat)(1.4426950408889634) + shifter;
    k = t - shifter;
    r = (x - k * VN(vsplat)(6.93147180369123816490e-01)) -
        k * VN(vsplat)(1.90821492927058770002e-10);
    p = VN(vsplat)(1.0 / 6227020800.0);
    p = p * r + VN(vsplat)(1.0 / 479001600.0);
    p = p * r + VN(vsplat)(1.0 / 39916800.0);
    p = p * r + VN(vsplat)(1.0 / 3628800.0);
    p = p * r + VN(vsplat)(1.0 / 362880.0);
    p = p * r + VN(vsplat)(1.0 / 40320.0);
    p = p * r + VN(vsplat)(1.0 / 5040.0);
    p = p * r + VN(vsplat)(1.0 / 720.0);
    p = p * r + VN(vsplat)(1.0 / 120.0);
    p = p * r + VN(vsplat)(1.0 / 24.0);
    p = p * r + VN(vsplat)(1.0 / 6.0);
    p = p * r + VN(vsplat)(0.5);
    p = p * r + VN(vsplat)(1.0);
    p = p * r + VN(vsplat)(1.0);
    return p * (VD)(((VU)t + 1023u) << 52) * keep;
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
    const VD fr = VN(vsplat)(in->f0) + VN(vsplat)(1.0 - in->f0) * f5, omf = one - f5;
    size_t q;
    u[0] = w * VN(vsplat)(INV_PI);
    if (mf == BF_MF_GGX) {
        const VD t = (one - nh) * (one + nh), c2 = nh * nh;
        const VD w4 = one / (VN(vsplat)(4.0) * nl_ * nv);
        const VD tl = (one - nl_) * (one + nl_) / (nl_ * nl_);
        const VD tv = (one - nv) * (one + nv) / (nv * nv);
        for (q = 0; q < nl; q++) {
            const VD a2 = VN(vsplat)(in->r2[q]), iq = one / (t + a2 * c2);
            const VD d = a2 * iq * iq / VN(vsplat)(BF_PI);
            const VD sl = VN(vsqrt)(one + a2 * tl), sv = VN(vsqrt)(one + a2 * tv);
            const VD r = one / ((sl + sv) * sl * sv);
            const VD gg = VN(vsplat)(2.0) * sl * sv * r;
            const VD dgs = d * gg * w4;
            b[q] = dgs * fr;
            u[1 + q] = w * b[q];
            if (derivs) {
                const VD dd =
                    d * (VN(vsplat)(in->two_r[q]) - VN(vsplat)(in->four_r[q]) * c2 * iq);
                const VD dg = VN(vsplat)(in->m2_r[q]) * (tl * sv + tv * sl) * sl * sv * r * r;
                u[1 + nl + q] = w * ((dd * gg + d * dg) * w4 * fr);
                u[1 + 2 * nl + q] = w * (dgs * omf);
            }
        }
    } else if (is_asf(mf)) {
        const VD x = VN(vload)(in->x + i), kk = VN(vsplat)(in->k[0]);
        const VD p = VN(vexp)(VN(vsplat)(in->ns[0]) * x) * VN(vload)(in->g + i);
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
            u[2] = w * (((VN(vsplat)(in->dk[0]) + kk * x) * p) * fr);
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

/* The residual, in the order of the plain version. */
static inline VD VN(vresidual)(const lobe_in *in, size_t i, size_t c, size_t nl, int mf, VD bd,
                               const VD *b, VD w)
{
    VD d = -VN(vload)(in->m[c] + i) +
           (is_asf(mf) ? VN(vsplat)(in->cd[c]) * bd : VN(vsplat)(in->cd[c] * INV_PI));
    size_t q;
    for (q = 0; q < nl; q++) d = d + VN(vsplat)(in->cs[q][c]) * b[q];
    return d * w;
}

/* The sums of VW samples from i, in the layout of the plain version. */
static inline void VN(group)(const lobe_in *in, size_t i, size_t nc, size_t nl, int mf,
                             bf_pass_kind kind, VD *s)
{
    const size_t ne = kind == BF_PASS_NORMAL ? n_ext(nl, mf) : 1 + nl;
    const size_t ng = ne * (ne + 1) / 2;
    const VD w = VN(vload)(in->w + i);
    VD u[MAX_EXT], b[MAX_LOBES], bd = VN(vsplat)(INV_PI);
    size_t q, a, e, c, t;
    u[0] = w * VN(vsplat)(INV_PI);
    if (mf != BF_MF_NONE) VN(mf_basis)(in, i, nl, mf, kind == BF_PASS_NORMAL, w, u, b, &bd);
    else
        for (q = 0; q < nl; q++) {
            const VD x = VN(vload)(in->x + i), kk = VN(vsplat)(in->k[q]);
            const VD p = VN(vexp)(VN(vsplat)(in->ns[q]) * x) * VN(vload)(in->g + i);
            b[q] = kk * p;
            u[1 + q] = w * b[q];
            if (kind == BF_PASS_NORMAL)
                u[1 + nl + q] = w * ((VN(vsplat)(in->dk[q]) + kk * x) * p);
        }
    t = kind == BF_PASS_NORMAL ? 1 : 0;
    if (kind != BF_PASS_COST)
        for (a = 0; a < ne; a++)
            for (e = a; e < ne; e++) s[t++] += u[a] * u[e];
    for (c = 0; c < nc; c++) {
        if (kind == BF_PASS_VARPRO) {
            const VD r = w * VN(vload)(in->m[c] + i);
            for (a = 0; a < ne; a++) s[ng + c * ne + a] += u[a] * r;
            s[ng + nc * ne + c] += r * r;
        } else {
            const VD d = VN(vresidual)(in, i, c, nl, mf, bd, b, w);
            s[0] += d * d;
            if (kind == BF_PASS_NORMAL)
                for (a = 0; a < ne; a++) s[1 + ng + c * ne + a] += u[a] * d;
        }
    }
}

#define VLOAD(k) \
    if ((k) < n_sums) s[k] = VN(vload)(acc + (k) * LANES + off)
#define VSTORE(k) \
    if ((k) < n_sums) memcpy(acc + (k) * LANES + off, &s[k], sizeof s[k])
#define VLOAD8(k) \
    VLOAD(k); VLOAD(k + 1); VLOAD(k + 2); VLOAD(k + 3); \
    VLOAD(k + 4); VLOAD(k + 5); VLOAD(k + 6); VLOAD(k + 7)
#define VSTORE8(k) \
    VSTORE(k); VSTORE(k + 1); VSTORE(k + 2); VSTORE(k + 3); \
    VSTORE(k + 4); VSTORE(k + 5); VSTORE(k + 6); VSTORE(k + 7)

/* Lanes [off, off + VW) of every sum over one chunk, in registers: s[]
 * of 32 sums (the lobe form, at most 31) or of MAX_SUMS (the microfacet
 * form), so that the smaller one is never held in memory for the
 * larger's sake. */
#define SWEEP_PART(name, size, LOADS, STORES)                                                   \
    static inline void VN(name)(const lobe_in *in, size_t n, size_t nc, size_t nl, int mf,    \
                                bf_pass_kind kind, double *acc, size_t off)                   \
    {                                                                                         \
        VD s[size];                                                                           \
        const size_t n_sums = sums_of(kind, nc, nl, mf);                                      \
        size_t i = 0;                                                                         \
        /* written out, so that s[] has constant indices only and stays in                    \
         * registers */                                                                       \
        LOADS;                                                                                \
        for (; i + LANES <= n; i += LANES) VN(group)(in, i + off, nc, nl, mf, kind, s);       \
        if (i < n) {                                                                          \
            tail_buf b;                                                                       \
            lobe_in t;                                                                        \
            pad_tail(in, i, n, nc, nl, mf, &b, &t);                                           \
            VN(group)(&t, off, nc, nl, mf, kind, s);                                          \
        }                                                                                     \
        STORES;                                                                               \
    }
#define LOADS32 VLOAD8(0); VLOAD8(8); VLOAD8(16); VLOAD8(24)
#define STORES32 VSTORE8(0); VSTORE8(8); VSTORE8(16); VSTORE8(24)
#define LOADS64 LOADS32; VLOAD8(32); VLOAD8(40); VLOAD8(48); VLOAD8(56)
#define STORES64 STORES32; VSTORE8(32); VSTORE8(40); VSTORE8(48); VSTORE8(56)
SWEEP_PART(sweep_part32, 32, LOADS32, STORES32)
SWEEP_PART(sweep_part64, MAX_SUMS, LOADS64, STORES64)
#undef SWEEP_PART
#undef LOADS32
#undef STORES32
#undef LOADS64
#undef STORES64

static inline void VN(sweep)(const lobe_in *in, size_t n, size_t nc, size_t nl, int mf,
                             bf_pass_kind kind, double *acc)
{
    size_t off;
    for (off = 0; off < LANES; off += VW) {
        if (sums_of(kind, nc, nl, mf) <= 32) VN(sweep_part32)(in, n, nc, nl, mf, kind, acc, off);
        else VN(sweep_part64)(in, n, nc, nl, mf, kind, acc, off);
    }
}

#undef VLOAD
#undef VSTORE
#undef VLOAD8
#undef VSTORE8
#undef VD
#undef VI
#undef VU
#undef VN
#undef VCAT
#undef VCAT2

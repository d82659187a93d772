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

static inline VD VN(vresidual)(const lobe_in *in, size_t i, size_t c, VD b1, VD w)
{
    return ((-VN(vload)(in->m[c] + i) + VN(vsplat)(in->cd[c] * INV_PI)) +
            VN(vsplat)(in->cs[c]) * b1) *
           w;
}

/* The sums of VW samples from i, in the layout of the plain version. */
static inline void VN(group)(const lobe_in *in, size_t i, size_t nc, bf_pass_kind kind, VD *s)
{
    const VD w = VN(vload)(in->w + i), x = VN(vload)(in->x + i), kk = VN(vsplat)(in->k);
    const VD p = VN(vexp)(VN(vsplat)(in->ns) * x) * VN(vload)(in->g + i);
    const VD b1 = kk * p, u0 = w * VN(vsplat)(INV_PI), u1 = w * b1;
    size_t c;
    if (kind == BF_PASS_NORMAL) {
        const VD u2 = w * ((VN(vsplat)(in->dk) + kk * x) * p);
        s[1] += u0 * u0;
        s[2] += u0 * u1;
        s[3] += u0 * u2;
        s[4] += u1 * u1;
        s[5] += u1 * u2;
        s[6] += u2 * u2;
        for (c = 0; c < nc; c++) {
            const VD d = VN(vresidual)(in, i, c, b1, w);
            s[0] += d * d;
            s[7 + 3 * c] += u0 * d;
            s[8 + 3 * c] += u1 * d;
            s[9 + 3 * c] += u2 * d;
        }
    } else if (kind == BF_PASS_COST) {
        for (c = 0; c < nc; c++) {
            const VD d = VN(vresidual)(in, i, c, b1, w);
            s[0] += d * d;
        }
    } else {
        s[0] += u0 * u0;
        s[1] += u0 * u1;
        s[2] += u1 * u1;
        for (c = 0; c < nc; c++) {
            const VD r = w * VN(vload)(in->m[c] + i);
            s[3 + 2 * c] += u0 * r;
            s[4 + 2 * c] += u1 * r;
            s[3 + 2 * nc + c] += r * r;
        }
    }
}

#define VLOAD(k) \
    if ((k) < n_sums) s[k] = VN(vload)(acc + (k) * LANES + off)
#define VSTORE(k) \
    if ((k) < n_sums) memcpy(acc + (k) * LANES + off, &s[k], sizeof s[k])

/* Lanes [off, off + VW) of every sum over one chunk, in registers. */
static inline void VN(sweep_part)(const lobe_in *in, size_t n, size_t nc, bf_pass_kind kind,
                                  double *acc, size_t off)
{
    VD s[MAX_SUMS];
    const size_t n_sums = sums_of(kind, nc);
    size_t i = 0;
    /* written out, so that s[] has constant indices only and stays in
     * registers */
    VLOAD(0); VLOAD(1); VLOAD(2); VLOAD(3); VLOAD(4); VLOAD(5); VLOAD(6); VLOAD(7);
    VLOAD(8); VLOAD(9); VLOAD(10); VLOAD(11); VLOAD(12); VLOAD(13); VLOAD(14); VLOAD(15);
    for (; i + LANES <= n; i += LANES) VN(group)(in, i + off, nc, kind, s);
    if (i < n) {
        tail_buf b;
        lobe_in t;
        pad_tail(in, i, n, nc, &b, &t);
        VN(group)(&t, off, nc, kind, s);
    }
    VSTORE(0); VSTORE(1); VSTORE(2); VSTORE(3); VSTORE(4); VSTORE(5); VSTORE(6); VSTORE(7);
    VSTORE(8); VSTORE(9); VSTORE(10); VSTORE(11); VSTORE(12); VSTORE(13); VSTORE(14); VSTORE(15);
}

static inline void VN(sweep)(const lobe_in *in, size_t n, size_t nc, bf_pass_kind kind,
                             double *acc)
{
    size_t off;
    for (off = 0; off < LANES; off += VW) VN(sweep_part)(in, n, nc, kind, acc, off);
}

#undef VLOAD
#undef VSTORE
#undef VD
#undef VI
#undef VU
#undef VN
#undef VCAT
#undef VCAT2

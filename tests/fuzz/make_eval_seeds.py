#!/usr/bin/env python3
"""Write the hand-made seed inputs of the eval fuzz harness (fuzz_eval.c)
into a folder: python3 tests/fuzz/make_eval_seeds.py tests/fuzz/corpus/eval

The byte layout is described at the top of fuzz_eval.c. Inputs found by
fuzzing (crash-*) are kept in the corpus as they are and not written here."""
import os
import sys

out = sys.argv[1]

ORDINARY = [0xa0 + (i * 7) % 64 for i in range(256)]   # value codes 0 .. 15
TINY, DENORMAL, HUGE, NEAR_MAX = 0x20, 0x40, 0x60, 0x80


def options(gain=0xa8, gamma=42, scale=1, cols=2, gap=1):
    """gain, difference gain, exposure (value codes), gamma byte, scale,
    block columns, gap."""
    return [gain, gain, 0xb0, gamma, scale, cols, gap]


def tail(cap=255, weighting=3, coat=10, fail=0, model=3, params=(), opts=None,
         pads=(1, 0, 5), sphere=(12, 40, 128, 3), plot=(8, 20, 5, 0xa1, 0xa5, 0x22, 0x61, 0xb0)):
    pairs = [30, 128, 60, 0, 128, 200, 10, 64, 255, 0, 255, 255]
    b = [cap, weighting] + pairs + [coat, fail, model] + list(params)
    b += (opts if opts is not None else options()) + list(pads) + list(sphere) + list(plot)
    return b + [0x2b] * 16


def regular(nti, nto, npo, nc, start0=1, endmax=1, flags=0, gaps=None, values=None, miss=()):
    sizes = (nti - 1) | (nto - 1) << 2 | (npo - 1) << 4 | start0 << 6 | endmax << 7
    n = nti * nto * npo
    gaps = gaps if gaps is not None else [40] * (nti + nto + npo)
    values = values if values is not None else ORDINARY[:n * nc]
    return [flags | (nc - 1) << 4, sizes] + gaps + values + list(miss)


def scattered(n, nc, flags=0, weights=None, values=None):
    angles = []
    for s in range(n):
        angles += [(s * 37) % 256, (s * 91) % 256, (s * 53 + 11) % 256, (s * 17 + 200) % 256]
    values = values if values is not None else ORDINARY[:n * nc]
    b = [flags | 1 | (nc - 1) << 4, n - 1] + angles + values
    if weights is not None:
        b += weights
    return b


def seed(name, data):
    with open(os.path.join(out, name), "wb") as f:
        f.write(bytes(data))


# Regular grids: one and three channels, the built-in models, odd options.
seed("regular_rgb", regular(3, 3, 3, 3) + tail(params=[128] * 7))
seed("regular_one_value", regular(1, 1, 1, 1, start0=0, endmax=0) + tail(model=0, params=[9]))
seed("regular_missing", regular(2, 3, 4, 2, flags=2, miss=[0x55, 0x0f, 0xf0]) +
     tail(model=5, params=[200, 30, 30, 90, 90, 40, 40]))
seed("regular_extremes", regular(2, 2, 2, 1, values=[0, TINY, DENORMAL, HUGE, NEAR_MAX,
                                                     0xa3, 0xa9, 0]) + tail(model=2))
seed("params_at_dbl_max", regular(2, 2, 3, 1) + tail(model=0, params=[255]))
seed("params_at_bounds", regular(2, 2, 3, 2) + tail(model=4, params=[0, 255, 0, 255, 255, 0]))
seed("newer_options_oom", regular(3, 2, 2, 3, flags=8 | 64) +
     tail(fail=3, params=[100] * 7, opts=options(scale=3, cols=3, gap=2)))
seed("bad_options", regular(2, 2, 2, 1) + tail(opts=options(gamma=0, scale=0)))
seed("log_plot", regular(2, 2, 2, 1, flags=128) +
     tail(plot=(30, 17, 8, 0xa1, 0xe0, 0x22, 0x61, 0x01, 0x80, 0x40, 0xff)))
seed("clearcoat_refused", regular(2, 2, 2, 1) + tail(coat=255))
# Scattered grids, with given weights: ordinary, subnormal, huge, all zero.
seed("scattered", scattered(8, 3) + tail(model=3, params=[128] * 7))
seed("scattered_weights", scattered(6, 1, flags=4, weights=ORDINARY[:6]) + tail(model=0))
seed("scattered_subnormal_weights", scattered(4, 1, flags=4, weights=[0, DENORMAL, 0, DENORMAL])
     + tail(model=0))
seed("scattered_huge_weights", scattered(4, 2, flags=4, weights=[NEAR_MAX] * 4) + tail(model=1))
seed("scattered_zero_weights", scattered(3, 1, flags=4 | 2, weights=[0, 0, 0], values=[0xa1] * 3)
     + [0x05] + tail(model=0))

#!/usr/bin/env python3
"""Write the hand-made seed inputs of the fit fuzz harness (fuzz_fit.c) into
a folder: python3 tests/fuzz/make_fit_seeds.py tests/fuzz/corpus/fit

The byte layout is described at the top of fuzz_fit.c. Inputs found by
fuzzing (crash-*) are kept in the corpus as they are and not written here."""
import os
import struct
import sys

out = sys.argv[1]


def seed(name, model, pipeline, weighting, threads2, missing, oom, own_start,
         nc, damping, raw, iters, cap, coat, nti, nto, npo, start0, endmax,
         axis_gaps, values, miss_bits=b'', start=b'', fixed=0, s=0):
    flags = pipeline | weighting << 2 | threads2 << 4 | missing << 5 | oom << 6 | own_start << 7
    layout = (nc - 1) | damping << 2 | raw << 4
    sizes = (nti - 1) | (nto - 1) << 2 | (npo - 1) << 4 | start0 << 6 | endmax << 7
    b = bytes([model, flags, layout, iters, cap, coat, sizes]) + bytes(axis_gaps) + values
    b += miss_bits + start + bytes([fixed, s])
    open(os.path.join(out, name), 'wb').write(b)


def ordinary(n, k=0):
    """n value codes of ordinary values (0 .. 15)."""
    return bytes(0xa0 + ((i * 7 + k) % 64) for i in range(n))


g = [60, 60, 60, 60]
# model indices: 0 lambert 1 phong 2 blinn-phong 3 ashikhmin-shirley 4 as-fresnel
# 5 as-2 6 cook-torrance 7 ct-2 8 ggx 9 ggx-2 10 ward 11 ward-duer 12 lafortune
seed('auto_as_rgb', 3, 3, 3, 0, 0, 0, 0, 3, 0, 0, 19, 255, 0, 4, 4, 4, 1, 1, g * 3, ordinary(64 * 3))
seed('joint_phong_missing', 1, 1, 3, 0, 1, 0, 0, 1, 1, 0, 10, 255, 0, 3, 4, 3, 1, 0,
     [40, 80, 30] + g + [20, 90, 50], ordinary(36), miss_bits=bytes([0x11, 0x80, 0, 0, 0x01]))
seed('two_stage_ggx_coat_threads', 8, 2, 1, 1, 0, 0, 0, 2, 2, 0, 8, 200, 200, 4, 3, 4, 0, 1,
     g + [10, 100, 100] + g, ordinary(96, 3))
seed('huge_values', 6, 0, 3, 0, 0, 0, 0, 1, 0, 0, 5, 255, 0, 2, 2, 2, 1, 1, [1] * 6,
     bytes([0x60, 0x7f, 0x80, 0x9f, 0x60, 0x81, 0x70, 0xa5]))
seed('tiny_denormal', 10, 1, 2, 0, 0, 0, 0, 1, 3, 0, 12, 255, 0, 2, 2, 2, 1, 1, [9] * 6,
     bytes([0x20, 0x21, 0x40, 0x41, 0x3f, 0x5f, 0x00, 0x22]))
seed('all_zero', 2, 2, 3, 0, 0, 0, 0, 2, 0, 0, 3, 255, 0, 2, 2, 2, 1, 1, [5] * 6, bytes(16))
seed('cap_zero', 3, 0, 3, 0, 0, 0, 0, 1, 0, 0, 3, 0, 0, 2, 2, 2, 0, 0, [5] * 6, ordinary(8))
seed('raw_doubles', 0, 1, 0, 0, 0, 0, 0, 1, 0, 1, 4, 255, 0, 2, 1, 2, 1, 1, [30] * 5,
     struct.pack('<4d', 0.5, float('nan'), -2.0, float('inf')))
seed('oom_lafortune', 12, 3, 3, 0, 0, 1, 0, 3, 0, 0, 6, 255, 0, 3, 3, 3, 1, 1,
     [70] * 9, ordinary(81, 5), s=77)
seed('oom_joint_threads', 9, 1, 3, 1, 0, 1, 0, 2, 1, 0, 6, 255, 150, 3, 3, 3, 1, 1,
     [70] * 9, ordinary(54, 2), s=13)
seed('oom_two_stage', 4, 2, 3, 0, 1, 1, 0, 3, 2, 0, 6, 255, 0, 3, 3, 3, 1, 1,
     [70] * 9, ordinary(81, 9), miss_bits=bytes([0x21] * 11), s=200)
seed('start_fixed_ward_duer', 11, 1, 3, 0, 0, 0, 1, 2, 0, 0, 20, 255, 0, 3, 4, 4, 1, 1,
     [50, 50, 50] + g + g, ordinary(96, 11), start=bytes([0, 255, 128, 3, 250, 17, 90, 1]),
     fixed=0x02)
seed('start_bounds_ct2', 7, 1, 1, 0, 0, 0, 1, 1, 0, 0, 20, 255, 0, 3, 3, 3, 0, 1,
     [80] * 9, ordinary(27, 4), start=bytes([255, 0, 255, 0, 255, 0, 255, 0]), fixed=0)
seed('grazing_only', 5, 0, 3, 0, 0, 0, 0, 1, 0, 0, 8, 254, 0, 1, 1, 2, 0, 1,
     [255, 255, 0, 255], ordinary(2))
open(os.path.join(out, 'empty'), 'wb').write(b'')


# the lobe model (index 13) cancelling its fit from inside
def cancel_seed(name, pipeline, cancel, nc=1, oom=0):
    seed(name, 13, pipeline, 3, 0, 0, oom, 0, nc, 0, 0, 19, 255, 0, 4, 4, 4, 1, 1, g * 3,
         ordinary(64 * nc, 1), s=(31 if oom else 0))
    with open(os.path.join(out, name), 'ab') as f:
        f.write(bytes([cancel]))


cancel_seed('cancel_in_scan', 3, 3)
cancel_seed('cancel_in_scan_late', 0, 20, nc=2)
cancel_seed('cancel_joint', 1, 4, nc=3)
cancel_seed('cancel_two_stage_oom', 2, 6, nc=2, oom=1)
cancel_seed('lobe_no_cancel_oom', 0, 0, nc=2, oom=1)

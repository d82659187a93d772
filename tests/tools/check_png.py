#!/usr/bin/env python3
"""Checks of `brdffit fit --preview` pictures for the tool tests (standard
library only: the PNG is decoded here with zlib).

    check_png.py size PNG MAX_W MAX_H
        the picture is at most MAX_W x MAX_H pixels (and at least 400 x 300).
    check_png.py dots PNG X0 Y0 X1 Y1 MIN
        inside the rectangle X0 <= x < X1, Y0 <= y < Y1 there are at least MIN
        pixels of the model's colour (orange) and MIN of the measured values'
        colour (light grey): the half-angle plot shows both series.
"""
import struct
import sys
import zlib


def fail(msg):
    sys.stderr.write("check_png: %s\n" % msg)
    sys.exit(1)


def read_png(path):
    data = open(path, "rb").read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        fail("%s is not a PNG file" % path)
    pos, idat, width = 8, b"", None
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            width, height, depth, colour = struct.unpack(">IIBB", body[:10])
            if depth != 8 or colour not in (2, 6):
                fail("unexpected PNG format: depth %d, colour type %d" % (depth, colour))
            bpp = 3 if colour == 2 else 4
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    if width is None:
        fail("no IHDR chunk")
    return width, height, bpp, unfilter(zlib.decompress(idat), width, height, bpp)


def paeth(a, b, c):
    p = a + b - c
    pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
    return a if pa <= pb and pa <= pc else b if pb <= pc else c


def unfilter(raw, width, height, bpp):
    stride, rows, prev = width * bpp, [], bytearray(width * bpp)
    for y in range(height):
        f = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b = prev[i]
            c = prev[i - bpp] if i >= bpp else 0
            if f == 1:
                line[i] = (line[i] + a) & 255
            elif f == 2:
                line[i] = (line[i] + b) & 255
            elif f == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                line[i] = (line[i] + paeth(a, b, c)) & 255
        rows.append(line)
        prev = line
    return rows


def main():
    if len(sys.argv) == 5 and sys.argv[1] == "size":
        data = open(sys.argv[2], "rb").read(24)
        w, h = struct.unpack(">II", data[16:24])
        if w > int(sys.argv[3]) or h > int(sys.argv[4]) or w < 400 or h < 300:
            fail("%s is %d x %d pixels, expected 400 x 300 .. %s x %s"
                 % (sys.argv[2], w, h, sys.argv[3], sys.argv[4]))
        print("%d x %d" % (w, h))
    elif len(sys.argv) == 8 and sys.argv[1] == "dots":
        w, h, bpp, rows = read_png(sys.argv[2])
        x0, y0, x1, y1, least = (int(v) for v in sys.argv[3:8])
        orange = grey = 0
        for y in range(max(y0, 0), min(y1, h)):
            for x in range(max(x0, 0), min(x1, w)):
                r, g, b = rows[y][bpp * x:bpp * x + 3]
                if r > 180 and 120 < g < 210 and b < 110:
                    orange += 1
                elif min(r, g, b) > 150 and max(r, g, b) - min(r, g, b) < 30:
                    grey += 1
        if orange < least or grey < least:
            fail("%s: %d model (orange) and %d measured (grey) pixels in the plot, "
                 "expected %d of each" % (sys.argv[2], orange, grey, least))
        print("orange %d, grey %d" % (orange, grey))
    else:
        fail("usage: see the file comment")


main()

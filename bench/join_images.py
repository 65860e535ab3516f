#!/usr/bin/env python3
"""Joins PPM images (P6, 8 bit, equal heights) side by side into one PNG, for the pictures of
docs/EXPORT.md. An argument "diff:A.ppm:B.ppm:GAIN" is the absolute difference of two images
times GAIN (clipped at 255): where a file and its table differ.

    bench/join_images.py A.ppm diff:A.ppm:B.ppm:8 ... -o OUT.png
"""
import os
import struct
import sys
import zlib


def read_ppm(path):
    data = open(path, "rb").read()
    fields, pos = [], 0
    while len(fields) < 4:  # P6 width height maxval, separated by whitespace
        while data[pos:pos + 1].isspace():
            pos += 1
        end = pos
        while not data[end:end + 1].isspace():
            end += 1
        fields.append(data[pos:end])
        pos = end
    if fields[0] != b"P6" or int(fields[3]) != 255:
        sys.exit(f"{path}: not an 8-bit P6 image")
    w, h = int(fields[1]), int(fields[2])
    return w, h, data[pos + 1:pos + 1 + 3 * w * h]


def panel(arg):
    if not arg.startswith("diff:"):
        return read_ppm(arg)
    _, a, b, gain = arg.split(":")
    (wa, ha, pa), (wb, hb, pb) = read_ppm(a), read_ppm(b)
    if (wa, ha) != (wb, hb):
        sys.exit(f"{a} and {b} differ in size")
    g = float(gain)
    return wa, ha, bytes(min(255, int(abs(x - y) * g)) for x, y in zip(pa, pb))


def main():
    args = sys.argv[1:]
    if "-o" not in args or args.index("-o") + 1 >= len(args):
        sys.exit(__doc__)
    out = args[args.index("-o") + 1]
    inputs = [a for i, a in enumerate(args) if a != "-o" and (i == 0 or args[i - 1] != "-o")]
    panels = [panel(a) for a in inputs]
    height = panels[0][1]
    if any(h != height for _, h, _ in panels):
        sys.exit("the images differ in height")
    width = sum(w for w, _, _ in panels)
    rows = b"".join(b"\0" + b"".join(p[3 * w * y:3 * w * (y + 1)] for w, _, p in panels) for y in range(height))

    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))

    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)) + \
        chunk(b"IDAT", zlib.compress(rows, 9)) + chunk(b"IEND", b"")
    open(out + ".tmp", "wb").write(png)
    os.replace(out + ".tmp", out)


if __name__ == "__main__":
    main()

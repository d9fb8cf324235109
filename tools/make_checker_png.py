#!/usr/bin/env python3
"""Writes scenes/textures/checker.png: the colour checker of spar's built-in
`builtin:checker` texture (src/scene/builtin.rs), 8 x 8 squares of 8 x 8
pixels, sRGB-encoded 8-bit, with the Python standard library only."""
import struct, zlib, sys

COLOURS = [(0.9, 0.05, 0.05), (0.9, 0.75, 0.05), (0.05, 0.8, 0.1),
           (0.05, 0.6, 0.9), (0.1, 0.1, 0.9), (0.8, 0.1, 0.8)]

def encode(v):  # sRGB transfer function, IEC 61966-2-1
    return 12.92 * v if v <= 0.0031308 else 1.055 * v ** (1 / 2.4) - 0.055

def texel(x, y):
    return (1.0, 1.0, 1.0) if (x + y) % 2 == 0 else COLOURS[(x // 2 + 3 * y) % 6]

def main(path):
    n, s = 8, 8
    rows = b""
    for py in range(n * s):
        rows += b"\0" + bytes(round(255 * encode(c)) for px in range(n * s) for c in texel(px // s, py // s))
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", n * s, n * s, 8, 2, 0, 0, 0))
    png += chunk(b"sRGB", b"\0") + chunk(b"IDAT", zlib.compress(rows, 9)) + chunk(b"IEND", b"")
    open(path, "wb").write(png)

main(sys.argv[1] if len(sys.argv) > 1 else "scenes/textures/checker.png")

#!/usr/bin/env python3
"""Write small seed inputs for the `ply_decode` fuzz target into corpus/ply_decode/.

Seeds are generated, not committed: a few tiny PLY files in each encoding,
with attributes, an origin comment, face/list elements before and after the
vertices, plus a few broken ones (the fuzzer mutates from all of them).
Usage: python3 make_seeds.py   (run from fuzz/)
"""

import os
import struct

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "corpus", "ply_decode")

POINTS = [(0.5, -1.25, 3.0, 12.0, 6, 7), (637012.25, 849321.5, 12.0, 0.0, 2, 0)]


def header(fmt, n_vertex, extra=""):
    return (
        "ply\n"
        f"format {fmt} 1.0\n"
        "comment seed\n"
        f"{extra}"
        "element face 1\n"
        "property list uchar int vertex_indices\n"
        f"element vertex {n_vertex}\n"
        "property double x\nproperty double y\nproperty double z\n"
        "property float intensity\nproperty uchar classification\nproperty uint building\n"
        "element edge 1\nproperty int a\nproperty int b\n"
        "end_header\n"
    ).encode()


def binary(fmt, endian):
    body = struct.pack(endian + "B3i", 3, 0, 1, 1)
    for x, y, z, i, c, b in POINTS:
        body += struct.pack(endian + "dddfBI", x, y, z, i, c, b)
    body += struct.pack(endian + "ii", 0, 1)
    return header(fmt, len(POINTS)) + body


def ascii_seed():
    rows = ["3 0 1 1"] + [f"{x} {y} {z} {i} {c} {b}" for x, y, z, i, c, b in POINTS] + ["0 1"]
    return header("ascii", len(POINTS), "comment skyground origin 1 2 3\n") + "\n".join(rows).encode() + b"\n"


def main():
    os.makedirs(OUT, exist_ok=True)
    seeds = {
        "ascii.ply": ascii_seed(),
        "le.ply": binary("binary_little_endian", "<"),
        "be.ply": binary("binary_big_endian", ">"),
        "truncated.ply": binary("binary_little_endian", "<")[:-9],
        "header_only.ply": b"ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nend_header\n",
    }
    for name, data in seeds.items():
        with open(os.path.join(OUT, name), "wb") as f:
            f.write(data)
    print(f"wrote {len(seeds)} seeds to {OUT}")


if __name__ == "__main__":
    main()

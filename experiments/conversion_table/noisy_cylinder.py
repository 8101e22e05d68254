#!/usr/bin/env python3
"""Split conversion of a capped cylinder of long thin rectangles whose corners are moved by noise.

    noisy_cylinder.py SDMESH [--sides N] [--length L] [--radius R] [--seeds K]

The cylinder is what CAD exporters write for a shaft: N rectangles of width about 2πR/N and
length L, each cut by one diagonal, and two fans for the caps. Exactly placed, the corners of
each rectangle are co-circular and the mesh is self-Delaunay. Moved by a little noise, some
diagonals fall out of locally Delaunay by about the noise over the width, and split must add
vertices. The table shows how many, for noise from 1e-11 to 1e-7 of the coordinates: near the
tolerance of the locally-Delaunay test (1e-10 rad) rings of split points around the cylinder
come out of step and the count grows by two orders of magnitude (experiments/README.md).
Python 3 standard library only.
"""

import argparse
import json
import math
import random
import subprocess
import sys
import tempfile
from pathlib import Path

NOISE = (1e-11, 1e-10, 3e-10, 1e-9, 3e-9, 1e-8, 1e-7)


def write_cylinder(path, sides, length, radius, noise, seed):
    rng = random.Random(seed)
    corners = []
    for z in (0.0, length):
        for i in range(sides):
            angle = 2 * math.pi * i / sides
            corners.append([radius * math.cos(angle), radius * math.sin(angle), z])
    corners = [[x + noise * rng.gauss(0, 1) for x in corner] for corner in corners]
    bottom, top = len(corners), len(corners) + 1
    corners += [[0.0, 0.0, 0.0], [0.0, 0.0, length]]
    faces = []
    for i in range(sides):
        j = (i + 1) % sides
        faces += [(i, j, sides + j), (i, sides + j, sides + i), (bottom, j, i), (top, sides + i, sides + j)]
    with open(path, "w") as out:
        out.writelines(f"v {x:.17g} {y:.17g} {z:.17g}\n" for x, y, z in corners)
        out.writelines(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in faces)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("sdmesh")
    parser.add_argument("--sides", type=int, default=36)
    parser.add_argument("--length", type=float, default=884)
    parser.add_argument("--radius", type=float, default=20)
    parser.add_argument("--seeds", type=int, default=2)
    args = parser.parse_args()
    print("| noise | seed | non-Delaunay folds | added vertices | status |")
    print("|---:|---:|---:|---:|---|")
    with tempfile.TemporaryDirectory(prefix="sdmesh_cylinder_") as scratch:
        mesh, report = Path(scratch) / "cylinder.obj", Path(scratch) / "report.json"
        for noise in NOISE:
            for seed in range(1, args.seeds + 1):
                write_cylinder(mesh, args.sides, args.length, args.radius, noise, seed)
                done = subprocess.run([args.sdmesh, "convert", str(mesh), str(Path(scratch) / "out.obj"),
                                       "--report", str(report)], capture_output=True, text=True)
                if done.returncode not in (0, 1):
                    sys.exit(f"noisy_cylinder.py: sdmesh convert failed: {done.stderr.strip()}")
                r = json.loads(report.read_text())
                print(f"| {noise:g} | {seed} | {r['input_nonflat_non_delaunay_edges']} | "
                      f"{r['output_vertices'] - r['input_vertices']:,} | {r['status']} |")


if __name__ == "__main__":
    main()

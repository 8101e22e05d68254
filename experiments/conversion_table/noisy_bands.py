#!/usr/bin/env python3
"""Split conversion of CAD-like bands of long thin faces whose corners are moved by noise.

    noisy_bands.py SDMESH [--seeds K] [--shapes NAME ...] [--jobs J]

CAD exporters tessellate shafts, holes and fillets as bands of long faces between two rims.
Exactly placed, many of those bands are self-Delaunay (the corners of each rectangle are
co-circular) or need one ring of split points; moved by a little noise, some faces fall out of
locally Delaunay or out of coplanar, and the rings of split points must stay in step around the
band. The table gives the vertices that split adds for each shape, noise and seed (the noise is
Gaussian, of that standard deviation, on every corner but the caps' centres), with a budget of
20,000 added vertices. experiments/conversion_table/JOURNAL.md tells what each shape once cost.

Shapes: shaft (36 rectangles of 884 x 3.5, one diagonal each, capped), zigzag (48 rectangles of
300 x 2.6 cut alternately, capped), rows (a shaft of 72 sides in 3 rows), box (a closed box
100 x 3 x 1 whose faces are strips of 40 rectangles), washer (an annulus of 64 sectors, walls
20 high), rims (two rims of 100 and 97 points joined by one band of long faces, capped).
Python 3 standard library only.
"""

import argparse
import json
import math
import random
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

NOISE = (0.0, 1e-10, 3e-10, 1e-9, 1e-8, 1e-6, 1e-4)
BUDGET = 20000


def ring(V, n, radius, z, shift=0.0):
    first = len(V)
    for i in range(n):
        angle = 2 * math.pi * (i + shift) / n
        V.append([radius * math.cos(angle), radius * math.sin(angle), z])
    return list(range(first, first + n))


def band(F, lower, upper, zigzag=False):
    """Faces between two rings of as many points, each quad cut by a diagonal."""
    n = len(lower)
    for i in range(n):
        j = (i + 1) % n
        a, b, c, d = lower[i], lower[j], upper[j], upper[i]
        F += [(a, b, d), (b, c, d)] if zigzag and i % 2 else [(a, b, c), (a, c, d)]


def caps(V, F, bottom, top, z_bottom, z_top):
    """Fans from the axis: the exact centres stay out of the noise (see `noisy`)."""
    centre = len(V)
    V += [[0.0, 0.0, z_bottom], [0.0, 0.0, z_top]]
    n, m = len(bottom), len(top)
    F += [(centre, bottom[(i + 1) % n], bottom[i]) for i in range(n)]
    F += [(centre + 1, top[i], top[(i + 1) % m]) for i in range(m)]
    return 2


def shaft(sides, length, zigzag=False, rows=1):
    V, F = [], []
    rings = [ring(V, sides, 20.0, length * r / rows) for r in range(rows + 1)]
    for lower, upper in zip(rings, rings[1:]):
        band(F, lower, upper, zigzag)
    return V, F, caps(V, F, rings[0], rings[-1], 0.0, length)


def box(strips, length=100.0, width=3.0, height=1.0):
    V, F, index = [], [], {}

    def vertex(p):
        key = tuple(round(c, 12) for c in p)
        if key not in index:
            index[key] = len(V)
            V.append(list(p))
        return index[key]

    def grid(origin, u, v, nu, nv):  # a quad grid on origin + s·u + t·v, normals along u × v
        g = [[vertex([origin[k] + u[k] * i / nu + v[k] * j / nv for k in range(3)]) for j in range(nv + 1)]
             for i in range(nu + 1)]
        for i in range(nu):
            for j in range(nv):
                F.extend([(g[i][j], g[i + 1][j], g[i + 1][j + 1]), (g[i][j], g[i + 1][j + 1], g[i][j + 1])])

    L, W, H = length, width, height
    grid([0, 0, 0], [0, W, 0], [L, 0, 0], 3, strips)
    grid([0, 0, H], [L, 0, 0], [0, W, 0], strips, 3)
    grid([0, 0, 0], [L, 0, 0], [0, 0, H], strips, 1)
    grid([0, W, 0], [0, 0, H], [L, 0, 0], 1, strips)
    grid([0, 0, 0], [0, 0, H], [0, W, 0], 1, 3)
    grid([L, 0, 0], [0, W, 0], [0, 0, H], 3, 1)
    return V, F, 0


def washer(sectors, inner=10.0, outer=12.0, height=20.0):
    V, F = [], []
    inner_bottom, inner_top = ring(V, sectors, inner, 0.0), ring(V, sectors, inner, height)
    outer_bottom, outer_top = ring(V, sectors, outer, 0.0), ring(V, sectors, outer, height)
    band(F, inner_top, inner_bottom)
    band(F, outer_bottom, outer_top)
    band(F, outer_top, inner_top)
    band(F, inner_bottom, outer_bottom)
    return V, F, 0


def rims(bottom_points, top_points, height=5.0):
    """Each face takes the next point of the rim whose next point comes first around the axis."""
    V, F = [], []
    bottom, top = ring(V, bottom_points, 1.0, 0.0), ring(V, top_points, 1.0, height, 0.37)
    bottom_angle = lambda i: 2 * math.pi * i / bottom_points
    top_angle = lambda j: 2 * math.pi * (j + 0.37) / top_points
    i = j = 0
    for _ in range(bottom_points + top_points):
        if j == top_points or (i < bottom_points and bottom_angle(i + 1) < 0.5 * (top_angle(j) + top_angle(j + 1))):
            F.append((bottom[i % bottom_points], bottom[(i + 1) % bottom_points], top[j % top_points]))
            i += 1
        else:
            F.append((bottom[i % bottom_points], top[(j + 1) % top_points], top[j % top_points]))
            j += 1
    return V, F, caps(V, F, bottom, top, 0.0, height)


SHAPES = {
    "shaft": lambda: shaft(36, 884.0),
    "zigzag": lambda: shaft(48, 300.0, zigzag=True),
    "rows": lambda: shaft(72, 884.0, rows=3),
    "box": lambda: box(40),
    "washer": lambda: washer(64),
    "rims": lambda: rims(100, 97),
}


def noisy(shape, noise, seed):
    V, F, exact = SHAPES[shape]()
    rng = random.Random(seed)
    moved = len(V) - exact
    V = [[x + noise * rng.gauss(0, 1) for x in p] if k < moved else p for k, p in enumerate(V)]
    return V, F


def convert(sdmesh, scratch, shape, noise, seed):
    V, F = noisy(shape, noise, seed)
    mesh = Path(scratch) / f"{shape}_{noise:g}_{seed}.obj"
    report = mesh.with_suffix(".json")
    with open(mesh, "w") as out:
        out.writelines(f"v {x:.17g} {y:.17g} {z:.17g}\n" for x, y, z in V)
        out.writelines(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in F)
    done = subprocess.run([sdmesh, "convert", str(mesh), str(mesh.with_suffix(".out.obj")), "--no-hausdorff",
                           "--max-vertices", str(len(V) + BUDGET), "--report", str(report)],
                          capture_output=True, text=True)
    if done.returncode not in (0, 1):
        sys.exit(f"noisy_bands.py: sdmesh convert {mesh.name} failed: {done.stderr.strip()}")
    r = json.loads(report.read_text())
    added = r["output_vertices"] - r["input_vertices"]
    return f"{added:,}" + ("" if r["status"] == "certified" else f" ({r['status']})")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("sdmesh")
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--shapes", nargs="+", choices=sorted(SHAPES), default=list(SHAPES))
    parser.add_argument("--jobs", type=int, default=2)
    args = parser.parse_args()
    seeds = range(1, args.seeds + 1)
    runs = [(shape, noise, seed) for shape in args.shapes for noise in NOISE for seed in seeds]
    with tempfile.TemporaryDirectory(prefix="sdmesh_bands_") as scratch, ThreadPoolExecutor(args.jobs) as pool:
        added = dict(zip(runs, pool.map(lambda run: convert(args.sdmesh, scratch, *run), runs)))
    print("Vertices added by split, seeds " + ", ".join(map(str, seeds)) + ":\n")
    print("| shape | " + " | ".join(f"{noise:g}" for noise in NOISE) + " |")
    print("|---|" + "---:|" * len(NOISE))
    for shape in args.shapes:
        cells = (", ".join(added[(shape, noise, seed)] for seed in seeds) for noise in NOISE)
        print(f"| {shape} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()

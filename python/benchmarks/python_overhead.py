#!/usr/bin/env python3
"""Overhead of the Python module: sdmesh.operators(V, F) against the same C++ calls.

    /usr/bin/python3 python/benchmarks/python_overhead.py [--build build] [--mesh FILE] [--rounds 5] [--repeats 5]

The mesh defaults to the corpus's c3d_nefertiti.obj (99,938 faces). The C++ side is the program
python_overhead_cpp of the build folder (Triangulation, L, M, d0, d1 and the three stars, timed in
C++ on a mesh already in memory); the Python side times sdmesh.operators() on arrays already in
memory, conversions and scipy.sparse wrapping included. Prints medians and their ratio as JSON.
"""

import argparse
import json
import os
import pathlib
import statistics
import subprocess
import sys
import time

ROOT = pathlib.Path(__file__).resolve().parents[2]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--build", default=str(ROOT / "build"), help="build folder (default: build)")
    corpus = pathlib.Path(os.environ.get("SDMESH_CORPUS_DIR", ROOT.parent / "shared" / "data" / "meshes"))
    parser.add_argument("--mesh", default=str(corpus / "c3d_nefertiti.obj"))
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--repeats", type=int, default=5, help="calls per round and side")
    args = parser.parse_args()

    build = pathlib.Path(args.build).resolve()
    sys.path.insert(0, str(build / "python"))
    import sdmesh

    V, F = sdmesh.read_mesh(args.mesh)
    V, F = V.copy(order="C"), F.copy(order="C")  # the usual NumPy layout, not the module's own
    sdmesh.operators(V, F)  # an untimed warm-up, as on the C++ side
    # Rounds alternate between the two sides, so that a change of machine load hits both alike.
    cpp_seconds, python_seconds = [], []
    for _ in range(args.rounds):
        done = subprocess.run([str(build / "python" / "python_overhead_cpp"), args.mesh, str(args.repeats)],
                              check=True, capture_output=True, text=True)
        cpp = json.loads(done.stdout)
        cpp_seconds += cpp["seconds"]
        for _ in range(args.repeats):
            start = time.perf_counter()
            result = sdmesh.operators(V, F)
            python_seconds.append(time.perf_counter() - start)
            del result  # freed outside the timing, as the C++ side frees its matrices

    cpp_median, python_median = statistics.median(cpp_seconds), statistics.median(python_seconds)
    print(json.dumps({
        "mesh": pathlib.Path(args.mesh).name,
        "faces": cpp["faces"],
        "runs_per_side": len(cpp_seconds),
        "cpp_median_seconds": cpp_median,
        "python_median_seconds": python_median,
        "python_over_cpp": python_median / cpp_median,
    }, indent=2))


if __name__ == "__main__":
    main()

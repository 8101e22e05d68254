#!/usr/bin/env python3
"""SciPy's eigsh on the matrices `sdmesh operators` writes, for comparison with `sdmesh eigs`.

    sdmesh operators MESH --out OPS            # L.mtx, M.mtx
    sdmesh eigs MESH -k K --out EIGS           # eigenvalues.csv, report.json (seconds)
    python3 scipy_eigsh.py OPS -k K [--compare EIGS]

Solves L x = lambda M x for the K eigenvalues nearest the same shift sdmesh picks,
sigma = -trace(L) / (n trace(M)), with shift-invert mode (which='LM'), and prints one JSON line:
the time of eigsh (its sparse LU factorization included, as sdmesh's time includes its Cholesky
factorization), and with --compare, sdmesh's time, the speed-up and the largest relative
eigenvalue difference |a - b| / max(|b|, |sigma|) (the shift's scale for the zero eigenvalue).
"""

import argparse
import json
import pathlib
import time

import numpy as np
import scipy.io
import scipy.sparse.linalg


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("ops", type=pathlib.Path, help="folder with L.mtx and M.mtx")
    parser.add_argument("-k", type=int, required=True, help="number of eigenpairs")
    parser.add_argument("--compare", type=pathlib.Path, help="folder written by `sdmesh eigs`")
    parser.add_argument("--tol", type=float, default=1e-10, help="eigsh tolerance (sdmesh's default)")
    args = parser.parse_args()

    L = scipy.io.mmread(args.ops / "L.mtx").tocsc()
    M = scipy.io.mmread(args.ops / "M.mtx").tocsc()
    n = L.shape[0]
    sigma = -L.diagonal().sum() / (n * M.diagonal().sum())

    start = time.perf_counter()
    values = scipy.sparse.linalg.eigsh(L, k=args.k, M=M, sigma=sigma, which="LM", tol=args.tol,
                                       return_eigenvectors=False)
    seconds = time.perf_counter() - start
    values = np.sort(values)

    result = {"n": n, "k": args.k, "sigma": sigma, "scipy_seconds": seconds}
    if args.compare:
        ours = np.loadtxt(args.compare / "eigenvalues.csv")
        report = json.loads((args.compare / "report.json").read_text())
        result["sdmesh_seconds"] = report["seconds"]
        result["speedup"] = seconds / report["seconds"]
        result["max_relative_difference"] = float(
            np.max(np.abs(ours - values) / np.maximum(np.abs(values), abs(sigma))))
    print(json.dumps(result))


if __name__ == "__main__":
    main()

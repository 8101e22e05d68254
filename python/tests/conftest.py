"""Shared fixtures: the CLI to compare with, the bundled bunny, small meshes made in code."""

import json
import os
import pathlib
import subprocess

import numpy as np
import pytest

import sdmesh

HERE = pathlib.Path(__file__).resolve().parent
DATA_DIR = pathlib.Path(os.environ.get("SDMESH_TEST_DATA_DIR", HERE.parent.parent / "tests" / "data"))

# Keys whose values are wall-clock times, hence differ between two runs.
TIMING_KEYS = {"seconds", "intrinsic_seconds", "flip_seconds", "precompute_seconds", "query_seconds"}


def without_timings(report):
    return {key: value for key, value in report.items() if key not in TIMING_KEYS}


@pytest.fixture(scope="session")
def cli():
    """Runs the sdmesh executable; returns the completed process (stdout parsed when asked)."""
    path = os.environ.get("SDMESH_CLI")
    if not path:
        pytest.fail("SDMESH_CLI is not set: run the suite through ctest (it passes the CLI's path)")

    def run(*args, expect=(0,)):
        done = subprocess.run([path, *map(str, args)], capture_output=True, text=True)
        assert done.returncode in (expect if isinstance(expect, tuple) else (expect,)), done.stderr
        return done

    return run


def cli_json(done):
    return json.loads(done.stdout)


@pytest.fixture(scope="session")
def bunny_path():
    return DATA_DIR / "bunny.obj"


@pytest.fixture(scope="session")
def bunny(bunny_path):
    return sdmesh.read_mesh(bunny_path)


def grid(nx, ny):
    """Planar grid on [0, 1]² with the diagonals of a regular triangulation, int32 faces."""
    x, y = np.meshgrid(np.linspace(0, 1, nx + 1), np.linspace(0, 1, ny + 1), indexing="xy")
    V = np.column_stack([x.ravel(), y.ravel(), np.zeros(x.size)])
    index = np.arange((nx + 1) * (ny + 1)).reshape(ny + 1, nx + 1)
    a, b = index[:-1, :-1].ravel(), index[:-1, 1:].ravel()
    c, d = index[1:, 1:].ravel(), index[1:, :-1].ravel()
    F = np.concatenate([np.column_stack([a, b, c]), np.column_stack([a, c, d])]).astype(np.int32)
    return V, F


def octahedron():
    V = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], dtype=np.float64)
    F = np.array([[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]],
                 dtype=np.int32)
    return V, F

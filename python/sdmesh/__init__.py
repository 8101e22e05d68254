"""sdmesh: self-Delaunay meshes, the cotan Laplacian, DEC operators and solvers.

Meshes are NumPy arrays: V, float64 of shape (n, 3), and F, int32 of shape (m, 3). Other real
dtypes for V (and for every per-vertex array) are read as float64, other integer dtypes for F (and
every index array) as int32 when their values fit; other dtypes raise TypeError and a wrong shape
raises InvalidArgumentError (a ValueError) naming the shape received. Inputs are copied once into
the C++ library's own arrays; results are never copied: arrays and scipy.sparse.csc_matrix objects
view the C++ buffers (matrices come out Fortran-ordered). Options are keyword arguments with the
C++ defaults and the CLI's names; reports are dicts with the keys of the CLI's JSON.

    import sdmesh
    V, F = sdmesh.read_mesh("bunny.obj")
    V, F, repaired = sdmesh.repair(V, F)                    # a messy mesh: the safe repairs first
    V2, F2, report = sdmesh.convert(V, F, method="hybrid")
    ops = sdmesh.operators(V2, F2, mass="circumcentric")      # ops["L"], ops["M"], ops["d0"], ...
    evals, evecs = sdmesh.eigs(ops["L"], ops["M"], k=20)

Errors raise subclasses of sdmesh.Error with the C++ message: IoError (also an OSError),
UnsupportedFormatError, ParseError, InvalidMeshError, InvalidArgumentError (also a ValueError),
NumericalError. Long calls release the GIL.
"""

from ._sdmesh import (
    Error,
    InvalidArgumentError,
    InvalidMeshError,
    IoError,
    NumericalError,
    ParseError,
    UnsupportedFormatError,
    __version__,
    check,
    convert,
    decimate,
    eigs,
    geodesic,
    heat,
    intrinsic_operators,
    operators,
    poisson,
    read_mesh,
    repair,
    write_mesh,
)

__all__ = [
    "Error",
    "InvalidArgumentError",
    "InvalidMeshError",
    "IoError",
    "NumericalError",
    "ParseError",
    "UnsupportedFormatError",
    "__version__",
    "check",
    "convert",
    "decimate",
    "eigs",
    "geodesic",
    "heat",
    "intrinsic_operators",
    "operators",
    "poisson",
    "read_mesh",
    "repair",
    "write_mesh",
]

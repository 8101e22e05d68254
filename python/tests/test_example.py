"""The example script runs and prints the spectra it promises."""

import os
import pathlib
import subprocess
import sys

EXAMPLE = pathlib.Path(__file__).resolve().parents[1] / "examples" / "spectrum.py"


def test_spectrum_example_prints_three_spectra(bunny_path):
    done = subprocess.run([sys.executable, str(EXAMPLE), str(bunny_path), "-k", "3"], capture_output=True,
                          text=True, env=os.environ, check=True)
    lines = done.stdout.splitlines()
    assert "converted (certified)" in lines[0] and "0 negative cotan weights" in lines[0]
    rows = [line.split() for line in lines[2:]]
    assert [row[0] for row in rows] == ["0", "1", "2"]
    for row in rows:  # input, converted, intrinsic: close low eigenvalues of the same surface
        values = [float(v) for v in row[1:]]
        assert len(values) == 3 and max(values) - min(values) <= 1e-2 * max(1.0, max(values))

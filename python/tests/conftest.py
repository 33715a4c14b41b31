"""Shared fixtures: the repository's scenes and data, and the `talus` CLI built from the
same workspace (the reference the package is compared with)."""
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]
FOOTING = REPO / "scenes" / "footing.toml"
SICONOS = REPO / "data" / "siconos-plasticity"


@pytest.fixture(scope="session")
def cli() -> Path:
    """The `talus` binary: $TALUS_BIN, else built in release from this workspace."""
    if "TALUS_BIN" in os.environ:
        return Path(os.environ["TALUS_BIN"])
    subprocess.run(
        ["cargo", "build", "--release", "--quiet", "-p", "talus", "--bin", "talus"],
        cwd=REPO,
        check=True,
    )
    return REPO / "target" / "release" / "talus"


def read_csv(path: Path):
    """history.csv as {column: float64 array}, parsed by Python's own float()."""
    lines = path.read_text().splitlines()
    header = lines[0].split(",")
    rows = [[float(v) for v in line.split(",")] for line in lines[1:]]
    return {name: np.array([r[j] for r in rows], dtype=np.float64) for j, name in enumerate(header)}


def run_cli(cli: Path, scene: Path, out: Path):
    subprocess.run([str(cli), "run", str(scene), "--out", str(out)], check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return read_csv(out / "history.csv")


def assert_same_bits(python_history, cli_history):
    """Every column but the wall-clock `seconds`, bit for bit, in the same order."""
    assert list(python_history) == list(cli_history)
    for name, values in cli_history.items():
        if name == "seconds":
            continue
        got = python_history[name]
        assert got.dtype == np.float64
        assert got.shape == values.shape, name
        assert got.tobytes() == values.tobytes(), (
            f"{name}: largest difference {np.max(np.abs(got - values)):.3e}"
        )

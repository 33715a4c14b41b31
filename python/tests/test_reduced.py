"""solve_reduced on read_siconos against `talus reduced FILE` (the same solver and
settings: σ to 1e-14, same status and iteration count)."""
import json
import subprocess

import numpy as np
import pytest

import talus
from conftest import SICONOS

FILES = sorted(SICONOS.glob("*.dat"))


def cli_reduced(cli, path, tmp_path, *extra):
    solution = tmp_path / "sigma.txt"
    done = subprocess.run(
        [str(cli), "reduced", str(path), "--json", "--solution", str(solution), *extra],
        capture_output=True, text=True,
    )
    assert done.returncode in (0, 2, 3), done.stderr
    report = json.loads(done.stdout.splitlines()[0])
    return np.loadtxt(solution), report, done.returncode


def test_there_are_siconos_files():
    assert len(FILES) >= 9


@pytest.mark.parametrize("path", FILES, ids=lambda p: p.stem)
def test_solve_reduced_equals_cli(cli, path, tmp_path):
    expected, report, code = cli_reduced(cli, path, tmp_path)
    assert code == 0
    W, q, cones = talus.read_siconos(path)
    sigma, got = talus.solve_reduced(W, q, cones, tol=1e-12)
    assert sigma.shape == q.shape == expected.shape
    scale = max(1.0, np.max(np.abs(expected)))
    assert np.max(np.abs(sigma - expected)) <= 1e-14 * scale
    assert got["status"] == report["status"] == "converged"
    assert got["iterations"] == report["iterations"]
    assert got["residual_history"] == pytest.approx(report["residual_history"], rel=1e-14)


def test_dense_and_sparse_w_give_the_same_solution():
    from scipy.sparse import csr_matrix

    W, q, cones = talus.read_siconos(SICONOS / "plasticity_2d_footing_10.dat")
    dense = np.asarray(W.toarray() if hasattr(W, "toarray") else W)
    a, _ = talus.solve_reduced(dense, q, cones)
    b, _ = talus.solve_reduced(csr_matrix(dense), q, cones)
    np.testing.assert_allclose(a, b, rtol=0, atol=1e-14 * max(1.0, np.max(np.abs(a))))


def test_not_converged_carries_the_report_and_the_cli_iterate(cli, tmp_path):
    path = SICONOS / "plasticity_2d_footing_100.dat"
    expected, report, code = cli_reduced(cli, path, tmp_path, "--max-iterations", "2")
    assert code == 3  # not converged (README, exit codes)
    W, q, cones = talus.read_siconos(path)
    with pytest.raises(talus.NotConverged) as caught:
        talus.solve_reduced(W, q, cones, max_iterations=2)
    e = caught.value
    assert e.report["status"] == report["status"] == "max_iterations"
    assert e.report["iterations"] == 2
    np.testing.assert_allclose(e.solution, expected, rtol=0, atol=1e-14 * max(1.0, np.max(np.abs(expected))))


def test_bad_problem_is_an_error_not_a_crash():
    W, q, cones = talus.read_siconos(SICONOS / "plasticity_2d_footing_10.dat")
    with pytest.raises(talus.InvalidProblem, match="length"):
        talus.solve_reduced(W, q[:-3], cones)
    with pytest.raises(talus.InvalidProblem, match="eta"):
        talus.solve_reduced(W, q, {"model": "drucker_prager", "eta": -np.ones(len(q) // 3), "theta": np.zeros(len(q) // 3)})
    with pytest.raises(talus.SiconosError):
        talus.read_siconos(SICONOS.parent / "does-not-exist.dat")

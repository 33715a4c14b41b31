"""Non-associative footing on a fine mesh: two relaxed runs and Richardson's extrapolation.

On fine meshes the paper's non-associative footing folds (docs/solver.md, 'Why the full
step fails there') and its rate-independent run halves most steps. Duvaut-Lions relaxation
(``[material] relaxation_time = τ``, docs/derivations.md, DL1-DL9) takes every step whole,
but its reaction is off by about ``a τ`` (DL9). Two relaxed runs at τ and τ/2 combined
step by step as ``2 R(τ/2) − R(τ)`` cancel that first-order term (DL10). This script runs
``scenes/footing.toml`` (the paper's grading spread over the cells, as
``builtin_footing_with_cells``) at τ and τ/2, and rate-independent unless told not to,
and writes ``relaxation_extrapolation.csv`` (one row per step) and
``relaxation_extrapolation.png`` (reaction against settlement) into ``--out``.

The combination holds only while the reaction is first order in τ. On 320×156 it is not
past the mechanism's onset (DL10), so ``--check-order`` adds a run at τ/4 and the observed
order ``p = log2((R(τ) − R(τ/2)) / (R(τ/2) − R(τ/4)))`` per step: trust the pair where p
is near 1.

    pip install './python[examples]'
    python examples/python/relaxation_extrapolation.py                  # paper mesh, 10 s
    python examples/python/relaxation_extrapolation.py --cells 104 48   # 104×48: about
        # 6 min for the relaxed pair, 30 min more for the rate-independent reference
    python examples/python/relaxation_extrapolation.py --cells 104 48 --no-reference
    python examples/python/relaxation_extrapolation.py --quick          # 16×7, 120 steps
    python examples/python/relaxation_extrapolation.py --quick --check-order
"""
import argparse
import csv
import math
import time
from pathlib import Path

import talus

REPO = Path(__file__).resolve().parents[2]


def footing(cells, steps, tau):
    """The paper footing on ``cells``, ``steps`` steps, relaxed by ``tau`` (s) if given."""
    scene = talus.Scene.load(REPO / "scenes" / "footing.toml")
    # The paper's 14-cell grading (1.1 per cell) spread over ny cells.
    ratio = 1.1 ** (14.0 / cells[1])
    for field, value in [
        ("mesh.rectangle.cells", list(cells)),
        ("mesh.rectangle.ratio", [1.0, ratio]),
        ("time.steps", steps),
        ("output.plots", False),
    ] + ([("material.relaxation_time", tau)] if tau is not None else []):
        scene = scene.set(field, value)
    return scene


def run(scene, label):
    start = time.perf_counter()
    result = talus.run(scene, progress=False)
    seconds = time.perf_counter() - start
    h = result.history
    steps = len(h["step"]) - 1
    iterations = h["newton_iterations"][1:].sum() + h["failed_newton_iterations"][1:].sum()
    halved = int((h["substeps"][1:] > 1).sum())
    print(f"{label}: {seconds:.1f} s, {iterations / steps:.1f} Newton iterations per step, "
          f"{halved} of {steps} steps halved, final reaction "
          f"{h['reaction_force'][-1] / 1e3:.2f} kN/m")
    return {
        "settlement": abs(h["footing_displacement"][1:]),
        "reaction": h["reaction_force"][1:] / 1e3,
        "seconds": seconds,
        "iterations_per_step": iterations / steps,
        "halved": halved,
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cells", type=int, nargs=2, default=[32, 14], metavar=("NX", "NY"))
    parser.add_argument("--steps", type=int, default=300)
    parser.add_argument("--tau", type=float, default=0.02,
                        help="the larger relaxation time as a fraction of h (default 0.02; "
                             "the smaller is half of it)")
    parser.add_argument("--no-reference", action="store_true",
                        help="skip the rate-independent run (slow on fine meshes)")
    parser.add_argument("--check-order", action="store_true",
                        help="a third run at τ/4 and the observed order in τ per step")
    parser.add_argument("--quick", action="store_true", help="16×7 cells, 120 steps")
    parser.add_argument("--out", type=Path, default=Path("."))
    args = parser.parse_args()
    cells, steps = ((16, 7), 120) if args.quick else (tuple(args.cells), args.steps)
    h = talus.Scene.load(REPO / "scenes" / "footing.toml").get("time.step")
    taus = [args.tau * h, args.tau * h / 2.0]
    mesh = f"{cells[0]}×{cells[1]} P2"
    coarse = run(footing(cells, steps, taus[0]), f"{mesh}, τ = {args.tau:g} h")
    fine = run(footing(cells, steps, taus[1]), f"{mesh}, τ = {args.tau / 2:g} h")
    extrapolated = 2.0 * fine["reaction"] - coarse["reaction"]
    quarter = (run(footing(cells, steps, taus[1] / 2.0), f"{mesh}, τ = {args.tau / 4:g} h")
               if args.check_order else None)
    reference = None if args.no_reference else run(footing(cells, steps, None),
                                                    f"{mesh}, rate-independent")
    if coarse["halved"] or fine["halved"] or (quarter is not None and quarter["halved"]):
        print("warning: a relaxed run halved steps; DL10 assumes both take every step whole")

    rows = []
    for k in range(steps):
        row = {
            "step": k + 1,
            "settlement_mm": 1e3 * fine["settlement"][k],
            "reaction_tau_kN_per_m": coarse["reaction"][k],
            "reaction_half_tau_kN_per_m": fine["reaction"][k],
            "reaction_extrapolated_kN_per_m": extrapolated[k],
        }
        if quarter is not None:
            row["reaction_quarter_tau_kN_per_m"] = quarter["reaction"][k]
            row["observed_order"] = observed_order(
                coarse["reaction"][k], fine["reaction"][k], quarter["reaction"][k])
        if reference is not None:
            row["reaction_rate_independent_kN_per_m"] = reference["reaction"][k]
        rows.append(row)
    args.out.mkdir(parents=True, exist_ok=True)
    with open(args.out / "relaxation_extrapolation.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    if reference is not None:
        last = reference["reaction"][-1]
        for label, r in [(f"τ = {args.tau:g} h", coarse["reaction"]),
                         (f"τ = {args.tau / 2:g} h", fine["reaction"]),
                         ("2 R(τ/2) − R(τ)", extrapolated)]:
            worst = abs(r - reference["reaction"]).max() / abs(reference["reaction"]).max()
            print(f"{label}: final reaction {100 * (r[-1] / last - 1):+.2f}% against the "
                  f"rate-independent run, largest difference {100 * worst:.2f}% of its "
                  f"largest reaction")
    if quarter is not None:
        p = rows[-1]["observed_order"]
        print(f"observed order in τ at the last step: {p:.2f} (DL10 needs about 1)")
        if not 0.7 <= p <= 1.3:
            print("warning: the reaction is not first order in τ here; the pair's "
                  "combination is not trustworthy (docs/derivations.md, DL10)")
    plot(rows, mesh, h, args.tau, (coarse, fine, reference),
         args.out / "relaxation_extrapolation.png")


def observed_order(r_tau, r_half, r_quarter):
    """``log2((R(τ) − R(τ/2)) / (R(τ/2) − R(τ/4)))``: 1 for an O(τ) error, NaN where
    the differences vanish or change sign."""
    a, b = r_tau - r_half, r_half - r_quarter
    return math.log2(a / b) if a * b > 0.0 else math.nan


def plot(rows, mesh, h, tau, runs, path):
    coarse, fine, reference = runs
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    s = [r["settlement_mm"] for r in rows]
    fig, ax = plt.subplots(figsize=(7, 5))
    if reference is not None:
        ax.plot(s, [r["reaction_rate_independent_kN_per_m"] for r in rows], color="black",
                label=f"rate-independent ({reference['seconds']:.0f} s, "
                      f"{reference['iterations_per_step']:.1f} its/step)")
    ax.plot(s, [r["reaction_tau_kN_per_m"] for r in rows], color="tab:orange",
            label=f"τ = {tau:g} h ({coarse['seconds']:.0f} s, "
                  f"{coarse['iterations_per_step']:.1f} its/step)")
    ax.plot(s, [r["reaction_half_tau_kN_per_m"] for r in rows], color="tab:blue",
            label=f"τ = {tau / 2:g} h ({fine['seconds']:.0f} s, "
                  f"{fine['iterations_per_step']:.1f} its/step)")
    ax.plot(s, [r["reaction_extrapolated_kN_per_m"] for r in rows], color="tab:green",
            linestyle="--", label="2 R(τ/2) − R(τ) (Richardson, DL10)")
    ax.set_xlabel("footing settlement (mm)")
    ax.set_ylabel("footing reaction (kN/m)")
    ax.set_title(f"Paper footing, {mesh}, non-associative: Richardson in τ\n"
                 f"steps 1–{len(rows)} of h = {h:g} s, t = 0 to {len(rows) * h:g} s")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, loc="lower right")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()

"""Speed against accuracy on Prandtl's strip footing: limit-load error against wall time.

Each run pushes the smooth rigid footing of ``scenes/prandtl_phi30.toml`` (φ = 30°,
associative, weightless; the domain widened to 9 × 4 b as in the verification suite) into
the soil and reads the limit pressure off the last step: q_u / c = 2 F / (b c), against
Prandtl's closed form N_c = (N_q − 1) cot φ, N_q = e^{π tan φ} tan²(45° + φ/2)
(Prandtl 1920; N_c(30°) = 30.14). The knobs: element order (P1, P2), mesh (cells per
axis) and the Newton tolerance. Writes ``speed_accuracy.csv`` and ``speed_accuracy.png``
into ``--out`` (default: the working directory).

    pip install './python[examples]'
    python examples/python/speed_accuracy.py            # 24 runs, about 2 min
    python examples/python/speed_accuracy.py --quick    # 8 runs, about 5 s
    python examples/python/speed_accuracy.py --replot   # redraw from speed_accuracy.csv
"""
import argparse
import csv
import math
import time
from pathlib import Path

import talus

REPO = Path(__file__).resolve().parents[2]
PHI = 30.0


def prandtl_nc(phi_deg):
    phi = math.radians(phi_deg)
    nq = math.exp(math.pi * math.tan(phi)) * math.tan(math.pi / 4 + phi / 2) ** 2
    return (nq - 1.0) / math.tan(phi)


def footing(order, cells, tolerance):
    scene = talus.Scene.load(REPO / "scenes" / "prandtl_phi30.toml")
    for field, value in [
        ("mesh.rectangle.x", [0.0, 9.0]),
        ("mesh.rectangle.y", [-4.0, 0.0]),
        ("mesh.rectangle.cells", list(cells)),
        ("mesh.rectangle.order", order),
        ("solver.tolerance", tolerance),
        ("output.plots", False),
    ]:
        scene = scene.set(field, value)
    return scene


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="coarse meshes only")
    parser.add_argument("--out", type=Path, default=Path("."))
    parser.add_argument("--replot", action="store_true",
                        help="redraw the figure from the CSV of the last run")
    args = parser.parse_args()
    if args.replot:
        with open(args.out / "speed_accuracy.csv", newline="") as f:
            rows = [{**r, "tolerance": float(r["tolerance"]), "seconds": float(r["seconds"]),
                     "error": float(r["error"])} for r in csv.DictReader(f)]
        plot(rows, prandtl_nc(PHI), args.out / "speed_accuracy.png")
        return
    meshes = [(10, 7), (20, 14)] if args.quick else [(10, 7), (20, 14), (40, 28), (80, 56)]
    tolerances = [1e-4, 1e-8] if args.quick else [1e-4, 1e-8, 1e-12]
    nc = prandtl_nc(PHI)
    b = 1.0  # footing width (m)
    rows = []
    for order in ("P1", "P2"):
        for cells in meshes:
            for tol in tolerances:
                scene = footing(order, cells, tol)
                start = time.perf_counter()
                result = talus.run(scene, progress=False)
                seconds = time.perf_counter() - start
                c = scene.get("material.cohesion")
                q = 2.0 * result.history["reaction_force"][-1] / (b * c)  # half model
                rows.append({
                    "order": order,
                    "cells": f"{cells[0]}x{cells[1]}",
                    "tolerance": tol,
                    "newton_iterations": int(result.history["newton_iterations"].sum()),
                    "seconds": seconds,
                    "q_over_c": q,
                    "error": abs(q - nc) / nc,
                })
                r = rows[-1]
                print(f"{order} {r['cells']:>6} tol {tol:.0e}: q/c = {q:.4f} "
                      f"(error {100 * r['error']:.2f}%), {seconds:.2f} s, "
                      f"{r['newton_iterations']} Newton iterations")
    args.out.mkdir(parents=True, exist_ok=True)
    with open(args.out / "speed_accuracy.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    plot(rows, nc, args.out / "speed_accuracy.png")


def plot(rows, nc, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 5))
    markers = {"P1": "s", "P2": "o"}
    tolerances = sorted({r["tolerance"] for r in rows}, reverse=True)
    colours = dict(zip(tolerances, plt.cm.viridis([0.1, 0.5, 0.85][: len(tolerances)])))
    for order in markers:
        for tol in tolerances:
            pts = [r for r in rows if r["order"] == order and r["tolerance"] == tol]
            ax.loglog([r["seconds"] for r in pts], [100 * r["error"] for r in pts],
                      marker=markers[order], color=colours[tol], linestyle="-",
                      label=f"{order}, tolerance {tol:.0e}")
            for r in pts if tol == tolerances[0] else []:  # one label per mesh
                ax.annotate(r["cells"], (r["seconds"], 100 * r["error"]), fontsize=7,
                            textcoords="offset points", xytext=(4, 4))
    ax.set_xlabel("wall time per run (s)")
    ax.set_ylabel("limit-load error |q_u/c − N_c| / N_c (%)")
    ax.set_title(f"Prandtl strip footing, φ = {PHI:.0f}°: error against cost\n"
                 f"N_c = {nc:.3f} (Prandtl 1920); limit load at settlement 0.16 b")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()

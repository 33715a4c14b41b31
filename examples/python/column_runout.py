"""Granular column collapse: runout against the scaling of Lube et al. (2005).

Runs the columns of ``scenes/column_a*.toml`` (aspect ratios a = H0/L0 = 0.5, 1, 2, 4;
cohesionless, non-dilatant Drucker-Prager sand on a rough floor, docs/mpm.md) to rest and
compares the final runout (L∞ − L0)/L0 with the law Lube, Huppert, Sparks & Freundt
(J. Fluid Mech. 508, 2004; Phys. Rev. E 72, 2005) measured in quasi-2D channels:
1.2 a for a < 1.8 and 1.9 a^(2/3) above. Writes ``column_runout.csv`` and
``column_runout.png`` into ``--out`` (default: the working directory).

    pip install './python[examples]'
    python examples/python/column_runout.py              # the scenes' h = 1e-3 s, 10–20 min
    python examples/python/column_runout.py --step 2e-3  # half the steps, about twice as fast
"""
import argparse
import csv
import time
from pathlib import Path

import talus

REPO = Path(__file__).resolve().parents[2]
ASPECTS = {"0.5": 0.5, "1": 1.0, "2": 2.0, "4": 4.0}


def lube(a):
    """(L∞ − L0)/L0 of Lube et al. (2005): 1.2 a below a = 1.8, 1.9 a^(2/3) above."""
    return 1.2 * a if a < 1.8 else 1.9 * a ** (2.0 / 3.0)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--step", type=float, default=None,
                        help="time step h (s); the same end time (default: the scenes' h)")
    parser.add_argument("--aspects", default=",".join(ASPECTS),
                        help="comma-separated aspect ratios among 0.5,1,2,4")
    parser.add_argument("--out", type=Path, default=Path("."))
    args = parser.parse_args()
    rows = []
    for name in args.aspects.split(","):
        a = ASPECTS[name]
        scene = talus.Scene.load(REPO / "scenes" / f"column_a{name}.toml")
        scene = scene.set("output.plots", False)
        if args.step is not None:
            end = scene.get("time.step") * scene.get("time.steps")
            scene = scene.set("time.steps", round(end / args.step)).set("time.step", args.step)
        start = time.perf_counter()
        result = talus.run(scene)
        seconds = time.perf_counter() - start
        runout = result.history["runout_normalized"][-1]
        rows.append({"a": a, "runout": runout, "lube": lube(a), "ratio": runout / lube(a),
                     "h": scene.get("time.step"), "steps": scene.get("time.steps"),
                     "particles": len(result.state["positions"]), "seconds": seconds})
        print(f"a = {a}: runout {runout:.3f}, Lube et al. {lube(a):.3f} "
              f"(ratio {runout / lube(a):.2f}), {seconds:.1f} s")
    args.out.mkdir(parents=True, exist_ok=True)
    with open(args.out / "column_runout.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    plot(rows, args.out / "column_runout.png")


def plot(rows, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    fig, ax = plt.subplots(figsize=(6, 4.5))
    a = np.linspace(0.3, 5.0, 200)
    ax.plot(a[a < 1.8], 1.2 * a[a < 1.8], "k-", label="Lube et al. (2005): 1.2 a")
    ax.plot(a[a >= 1.8], 1.9 * a[a >= 1.8] ** (2 / 3), "k--",
            label="Lube et al. (2005): 1.9 a^(2/3)")
    ax.plot([r["a"] for r in rows], [r["runout"] for r in rows], "o", color="C1",
            label="Talus MPM (plane strain)")
    ax.set_xlabel("aspect ratio a = H0/L0")
    ax.set_ylabel("runout (L∞ − L0)/L0 (dimensionless)")
    h = sorted({r["h"] for r in rows})
    t_end = max(r["h"] * r["steps"] for r in rows)
    ax.set_title("Granular column collapse: final runout, φ = 30°, c = 0\n"
                 f"h = {', '.join(f'{x:g}' for x in h)} s, at rest by t ≤ {t_end:.2f} s")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()

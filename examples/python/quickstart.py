"""Quick start of the Python package `boundary-particles`: read a frame, detect its boundary
particles with three methods, score them against the exact labels, and plot the labels.

    pip install ./crates/boundary-py         # once (maturin builds the Rust extension)
    python examples/python/quickstart.py     # [--plot quickstart.png] [--no-plot]

Reads a frame of the vortex scene bundled in `fixtures/`. The plot needs matplotlib
(`pip install matplotlib`); without it the script says so and skips the plot. `cargo xtask
test` runs this script.
"""

import argparse
import time
from pathlib import Path

import numpy as np

import boundary_particles as bp

REPO = Path(__file__).resolve().parents[2]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--plot", type=Path, default=Path("quickstart.png"))
    parser.add_argument("--no-plot", action="store_true")
    args = parser.parse_args()

    # A frame and its particle resolution r (fixtures/scenes.toml).
    frame = REPO / "fixtures" / "vortex2d_t1.csv"
    r = 0.0075
    points, point_data = bp.read(frame)
    print(f"{frame.name}: {len(points)} particles, {points.shape[1]}D, r = {r}")

    exact = bp.detect(points, r)  # the reference labels (JCP 2020)
    print(f"exact: {exact.sum()} boundary particles")
    results = {}
    for detector in [bp.Detector("ge", depth=4), bp.Detector("muller"), bp.Detector("hpr")]:
        start = time.perf_counter()
        labels = detector.detect(points, r)
        seconds = time.perf_counter() - start
        s = bp.confusion(labels, exact)
        results[detector.method] = labels
        print(
            f"{detector.method:>7}: tp {s['tp']:5d}  fp {s['fp']:4d}  fn {s['fn']:4d}  "
            f"recall {s['recall']:.3f}  fpr {s['fpr']:.3f}  M {s['m']:.3f}  "
            f"({seconds * 1e3:.0f} ms)"
        )

    if args.no_plot:
        return
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib is not installed (pip install matplotlib): plot skipped")
        return
    panels = [("exact", exact)] + list(results.items())
    fig, axes = plt.subplots(1, len(panels), figsize=(4 * len(panels), 3.4), sharey=True)
    for ax, (name, labels) in zip(axes, panels):
        colours = np.where(labels, "tab:red", "lightgrey")
        ax.scatter(points[:, 0], points[:, 1], c=colours, s=2, linewidths=0)
        ax.set_title(f"{name}: {labels.sum()} boundary")
        ax.set_aspect("equal")
    fig.tight_layout()
    fig.savefig(args.plot, dpi=120)
    print(f"plot written to {args.plot}")


if __name__ == "__main__":
    main()

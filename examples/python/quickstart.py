"""Quick start of the Python package `boundary`: read a frame, detect its boundary particles
with three methods, print their scores against the exact labels, and plot the labels.

    pip install ./crates/boundary-py         # once (maturin builds the Rust extension)
    python examples/python/quickstart.py     # [--data DIR] [--plot quickstart.png] [--no-plot]

Reads frame 100 of the vortex of Sandim et al. from the public data (`../shared/data`, or
`$BOUNDARY_DATA_DIR`). The plot needs matplotlib (`pip install matplotlib`); without it the
script says so and skips the plot. `cargo xtask test` runs this script.
"""

import argparse
import os
import time
from pathlib import Path

import numpy as np

import boundary

REPO = Path(__file__).resolve().parents[2]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--data",
        type=Path,
        default=Path(os.environ.get("BOUNDARY_DATA_DIR", REPO.parent / "shared" / "data")),
    )
    parser.add_argument("--plot", type=Path, default=Path("quickstart.png"))
    parser.add_argument("--no-plot", action="store_true")
    args = parser.parse_args()

    # A frame and its particle resolution r (fixtures/scenes.toml).
    frame = args.data / "particles2d" / "sandim_vortex_spin_frame_100_1698.csv"
    r = 0.022105
    points, attributes = boundary.read(frame)
    print(f"{frame.name}: {len(points)} particles, {points.shape[1]}D, r = {r}")

    exact = boundary.detect(points, r)  # the reference labels (JCP 2020)
    print(f"exact: {exact.sum()} boundary particles")
    results = {}
    for method, params in [("ge", {"depth": 4}), ("muller", {}), ("hpr", {})]:
        start = time.perf_counter()
        labels = boundary.detect(points, r, method, **params)
        seconds = time.perf_counter() - start
        s = boundary.score(points, r, method, truth=exact, **params)
        results[method] = labels
        print(
            f"{method:>7}: TP {s['TP']:5d}  FP {s['FP']:4d}  FN {s['FN']:4d}  "
            f"Rec {s['Rec']:.3f}  FPR {s['FPR']:.3f}  M {s['M']:.3f}  ({seconds * 1e3:.0f} ms)"
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

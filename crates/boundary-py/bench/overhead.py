"""What a Python call adds to the Rust detection, on a million particles.

    python crates/boundary-py/bench/overhead.py [--side 100] [--methods exact,muller] [--repeat 3]

A jittered cubic lattice of side**3 particles (1M by default), r = 1 (spacing 1). For each
method, `Detector._detect_timed` of the compiled module returns the labels and the seconds
the Rust call `detector.detect(set, r)` took inside the extension; the wall time of the whole
Python call minus that is the overhead of the binding (array checks, building the particle set from the
NumPy buffer, the worker pool, the label array). Prints the median over the repeats. A
report, not a test: numbers depend on the machine and its load.
"""

import argparse
import statistics
import time

import numpy as np

from boundary_particles import _native


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--side", type=int, default=100)
    parser.add_argument("--methods", default="exact,muller")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--threads", type=int, default=None)
    args = parser.parse_args()
    rng = np.random.default_rng(1)
    axis = np.arange(args.side, dtype=np.float64)
    points = np.stack(np.meshgrid(axis, axis, axis, indexing="ij"), -1).reshape(-1, 3)
    points += rng.uniform(-0.1, 0.1, points.shape)
    print(f"{len(points)} particles, 3D, r = 1, threads = {args.threads or 'all'}")
    for method in args.methods.split(","):
        overheads, walls, rusts = [], [], []
        for _ in range(args.repeat):
            start = time.perf_counter()
            detector = _native.Detector(method, args.threads)
            labels, rust = detector._detect_timed(points, 1.0)
            wall = time.perf_counter() - start
            walls.append(wall)
            rusts.append(rust)
            overheads.append((wall - rust) / rust)
        print(
            f"{method:>7}: Python call {statistics.median(walls):.3f} s, Rust call "
            f"{statistics.median(rusts):.3f} s, overhead {100 * statistics.median(overheads):.2f} % "
            f"(median of {args.repeat}; {labels.sum()} boundary)"
        )


if __name__ == "__main__":
    main()

"""Labels particle files in ParaView with the Boundary Particles filter, and writes the labels.

Run with ParaView's Python (the `boundary` command line on PATH, or named by BOUNDARY_CLI):

    pvpython examples/paraview/label.py IN OUT.csv --smoothing-length H [--walls W]
    pvpython examples/paraview/label.py FRAME1 FRAME2 ... OUTDIR --smoothing-length H

It loads the plugin `BoundaryParticles.py` beside this script, opens IN with ParaView's own
readers (CSV with columns x, y[, z] through Table To Points; VTK, VTU, VTP and the other
formats ParaView reads), applies the filter and writes OUT.csv: the coordinates as ParaView
read them, then `boundary` (and `interface` or `wall` when asked for), one row per particle
in the input's order. Several inputs are opened as one time series and labelled time step
by time step as ParaView's animation steps through them, one OUTDIR/<name>.csv per frame.
"""

import argparse
import inspect
import os
import sys

from paraview import simple


def parse():
    parser = argparse.ArgumentParser(
        description="Label boundary particles with the ParaView filter of boundary."
    )
    parser.add_argument("inputs", nargs="+", metavar="IN", help="particle file(s)")
    parser.add_argument("output", metavar="OUT", help="OUT.csv, or a folder for a series")
    given = parser.add_mutually_exclusive_group(required=True)
    given.add_argument("--smoothing-length", type=float, metavar="H", help="r = h")
    given.add_argument("--spacing", type=float, metavar="DP", help="r = 1.45 dp")
    given.add_argument("--radius", metavar="R", help="r itself, or auto")
    parser.add_argument("--walls", metavar="W", help="a file of wall particles")
    parser.add_argument("--wall-attribute", metavar="NAME=V[,V...]")
    parser.add_argument("--phase-attribute", metavar="NAME")
    parser.add_argument("--method", default="exact")
    parser.add_argument("--set", dest="parameters", default="", metavar="KEY=VALUE ...")
    parser.add_argument("--band", type=int, default=0)
    parser.add_argument("--dim", type=int, choices=(2, 3))
    return parser.parse_args()


def csv_columns(path):
    """The x, y and z columns of a CSV's header (z None for a 2D file)."""
    with open(path, encoding="utf-8") as f:
        header = [c.strip().strip('"') for c in f.readline().split(",")]
    by_lower = {c.lower(): c for c in header}
    if "x" not in by_lower or "y" not in by_lower:
        sys.exit("{0}: the header has no x and y columns: {1}".format(path, header))
    return by_lower["x"], by_lower["y"], by_lower.get("z")


def open_points(paths):
    """The reader of files of one kind, the point set it gives, and whether that is 2D (a CSV
    without z)."""
    if all(p.lower().endswith(".csv") for p in paths):
        x, y, z = csv_columns(paths[0])
        table = simple.CSVReader(FileName=paths)
        points = simple.TableToPoints(Input=table, XColumn=x, YColumn=y)
        if z is None:
            points.a2DPoints = 1
        else:
            points.ZColumn = z
        return table, points, z is None
    reader = simple.OpenDataFile(paths if len(paths) > 1 else paths[0])
    if reader is None:
        sys.exit("ParaView has no reader for {0}".format(paths[0]))
    return reader, reader, False


def write_csv(path, data, flat):
    """The coordinates of `data` and its label arrays, one row per point."""
    names = [n for n in ("boundary", "interface", "wall") if data.GetPointData().GetArray(n)]
    if "boundary" not in names:
        sys.exit("the filter gave no boundary array (its error is printed above)")
    arrays = [data.GetPointData().GetArray(n) for n in names]
    axes = ("x", "y") if flat else ("x", "y", "z")
    with open(path, "w", encoding="utf-8") as out:
        out.write(",".join(list(axes) + names) + "\n")
        for i in range(data.GetNumberOfPoints()):
            p = data.GetPoint(i)
            row = [repr(p[k]) for k in range(len(axes))]
            row += [str(int(a.GetTuple1(i))) for a in arrays]
            out.write(",".join(row) + "\n")


def main():
    args = parse()
    here = os.path.dirname(os.path.abspath(__file__))
    if not hasattr(inspect, "getargspec"):
        # ParaView 5.11's plugin decorators call inspect.getargspec, which Python 3.11
        # removed (Debian 12's ParaView 5.11 runs on Python 3.11); its successor answers the
        # one field they read, the argument names.
        inspect.getargspec = inspect.getfullargspec
    simple.LoadPlugin(os.path.join(here, "BoundaryParticles.py"), ns=globals())
    reader, points, flat = open_points(args.inputs)
    options = {"Method": args.method, "Parameters": args.parameters, "Band": args.band}
    if args.smoothing_length is not None:
        options.update(ResolutionFrom=0, Value=args.smoothing_length)
    elif args.spacing is not None:
        options.update(ResolutionFrom=1, Value=args.spacing)
    elif args.radius == "auto":
        options.update(ResolutionFrom=3)
    else:
        options.update(ResolutionFrom=2, Value=float(args.radius))
    dim = args.dim or (2 if flat else 0)
    options["Dimension"] = dim
    if args.walls:
        _, walls, _ = open_points([args.walls])
        options["Walls"] = walls
    if args.wall_attribute:
        name, _, values = args.wall_attribute.partition("=")
        options.update(WallArray=name, WallValues=values)
    if args.phase_attribute:
        options["PhaseArray"] = args.phase_attribute
    labelled = BoundaryParticles(Input=points, **options)  # noqa: F821 (from the plugin)

    if len(args.inputs) == 1:
        labelled.UpdatePipeline()
        data = labelled.GetClientSideObject().GetOutputDataObject(0)
        write_csv(args.output, data, dim == 2)
        return
    # A series: step the animation through the input's time steps, as the GUI does.
    os.makedirs(args.output, exist_ok=True)
    scene = simple.GetAnimationScene()
    scene.UpdateAnimationUsingDataTimeSteps()
    times = list(reader.TimestepValues)
    if len(times) != len(args.inputs):
        sys.exit("ParaView read {0} time steps from {1} files".format(len(times), len(args.inputs)))
    for path, time in zip(args.inputs, times):
        scene.AnimationTime = time
        labelled.UpdatePipeline(time)
        data = labelled.GetClientSideObject().GetOutputDataObject(0)
        stem = os.path.splitext(os.path.basename(path))[0]
        write_csv(os.path.join(args.output, stem + ".csv"), data, dim == 2)


if __name__ == "__main__":
    main()

"""Draws a fluid with its walls and the boundary particles the ParaView filter finds.

    pvpython --force-offscreen-rendering examples/paraview/picture.py FLUID.csv WALLS.csv \\
        OUT.png --smoothing-length H

The fluid's boundary particles are blue, its interior particles grey, and the walls dark,
small and faint; the view looks down on the tank from the front. docs/PARAVIEW.md shows the
picture this draws of the DualSPHysics dam break of the shared data. Without a display (CI,
a server), Debian's ParaView still needs an X server: run it under `xvfb-run -a`.
"""

import argparse
import inspect
import os

from paraview import simple


def points_of(path):
    """Table To Points of a CSV with columns x, y, z."""
    table = simple.CSVReader(FileName=[path])
    return simple.TableToPoints(Input=table, XColumn="x", YColumn="y", ZColumn="z")


def show_points(source, view, colour, size, opacity=1.0):
    """`source` as points of one colour."""
    display = simple.Show(source, view)
    display.SetRepresentationType("Points")
    display.PointSize = size
    display.ColorArrayName = ["POINTS", ""]
    display.AmbientColor = colour
    display.DiffuseColor = colour
    display.Opacity = opacity
    return display


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("fluid")
    parser.add_argument("walls")
    parser.add_argument("output")
    parser.add_argument("--smoothing-length", type=float, required=True, metavar="H")
    parser.add_argument("--size", type=int, nargs=2, default=(720, 400), metavar=("W", "H"))
    args = parser.parse_args()
    if not hasattr(inspect, "getargspec"):
        # As in label.py: ParaView 5.11's plugin decorators on Python 3.11.
        inspect.getargspec = inspect.getfullargspec
    here = os.path.dirname(os.path.abspath(__file__))
    simple.LoadPlugin(os.path.join(here, "BoundaryParticles.py"), ns=globals())

    fluid, walls = points_of(args.fluid), points_of(args.walls)
    labelled = BoundaryParticles(  # noqa: F821 (from the plugin)
        Input=fluid, Walls=walls, ResolutionFrom=0, Value=args.smoothing_length
    )
    view = simple.CreateView("RenderView")
    view.ViewSize = list(args.size)
    view.OrientationAxesVisibility = 0
    view.Background = [1.0, 1.0, 1.0]
    if hasattr(view, "UseColorPaletteForBackground"):
        view.UseColorPaletteForBackground = 0
    show_points(walls, view, [0.25, 0.25, 0.25], 1.5, opacity=0.25)
    fluid_display = show_points(labelled, view, [0.78, 0.78, 0.78], 3.0)
    # Two colours, one per label.
    simple.ColorBy(fluid_display, ("POINTS", "boundary"))
    colours = simple.GetColorTransferFunction("boundary")
    colours.InterpretValuesAsCategories = 1
    colours.Annotations = ["0", "interior", "1", "boundary"]
    colours.IndexedColors = [0.78, 0.78, 0.78, 0.12, 0.35, 0.85]
    fluid_display.SetScalarBarVisibility(view, False)

    # DualSPHysics' z is up.
    view.CameraFocalPoint = [0.0, 0.0, 0.0]
    view.CameraPosition = [-0.8, -1.6, 1.0]
    view.CameraViewUp = [0.0, 0.0, 1.0]
    view.ResetCamera()
    view.GetActiveCamera().Zoom(1.55)
    simple.SaveScreenshot(args.output, view, ImageResolution=list(args.size))


if __name__ == "__main__":
    main()

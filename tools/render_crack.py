"""Renders a cracked body's particles from the side, moved by their displacement magnified, and
coloured by a point field: how the two parts of a body cut by a `[[precrack]]` moved against
each other, as docs/fracture_crack_tilted.png shows the block of "Contact on new surfaces"
(docs/FRACTURE.md).

    xvfb-run -a -s "-noreset" pvpython tools/render_crack.py PARTICLES.vtu OUT.png \
        [--field displacement] [--scale 100] [--axis y]

PARTICLES.vtu is a frame's `<body>_particles.vtu`; the view looks along --axis (default y) at
the particles moved by --scale times their displacement.
"""
import argparse

from paraview.simple import (ColorBy, GetActiveViewOrCreate, GetColorTransferFunction,
                             ResetCamera, SaveScreenshot, Show, WarpByVector,
                             XMLUnstructuredGridReader)

ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
ap.add_argument("particles")
ap.add_argument("out")
ap.add_argument("--field", default="displacement")
ap.add_argument("--scale", type=float, default=100.0)
ap.add_argument("--axis", default="y", choices=["x", "y", "z"])
args = ap.parse_args()

reader = XMLUnstructuredGridReader(FileName=[args.particles])
warp = WarpByVector(Input=reader)
warp.Vectors = ["POINTS", "displacement"]
warp.ScaleFactor = args.scale
view = GetActiveViewOrCreate("RenderView")
view.ViewSize = [900, 900]
shown = Show(warp, view)
shown.SetRepresentationType("Points")
shown.PointSize = 7
shown.RenderPointsAsSpheres = 1
ColorBy(shown, ("POINTS", args.field, "Magnitude"))
GetColorTransferFunction(args.field).ApplyPreset("Viridis (matplotlib)", True)
shown.SetScalarBarVisibility(view, True)
look = {"x": [1, 0, 0], "y": [0, 1, 0], "z": [0, 0, 1]}[args.axis]
view.CameraPosition = [-5 * c for c in look]
view.CameraFocalPoint = [0, 0, 0]
view.CameraViewUp = [0, 0, 1] if args.axis != "z" else [0, 1, 0]
view.CameraParallelProjection = 1
ResetCamera(view)
SaveScreenshot(args.out, view)

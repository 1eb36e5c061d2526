"""Renders a sphere's contact face seen from below, its particles coloured by `stick` (1
sticking, 0 slipping, -1 out of contact) or by another point field, as
docs/friction_stick.png shows the Cattaneo-Mindlin sphere of `pdcontact friction`.

    xvfb-run -a -s "-noreset" pvpython tools/render_stick.py PARTICLES.vtu OUT.png \
        [--field stick] [--centre X Y Z] [--half-width W] [--depth D]

PARTICLES.vtu is a frame's `<body>_particles.vtu`; shown are its surface particles within D
(default 0.05 m) of the lowest point's height, seen along +z, W wide around the centre
(default 0.22 m about (0, 0.1, -1)).
"""
import argparse

from paraview.simple import (Clip, ColorBy, GetActiveViewOrCreate, GetColorTransferFunction,
                             SaveScreenshot, Show, Threshold, XMLUnstructuredGridReader)

ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
ap.add_argument("particles")
ap.add_argument("out")
ap.add_argument("--field", default="stick")
ap.add_argument("--centre", type=float, nargs=3, default=[0.0, 0.1, -1.0])
ap.add_argument("--half-width", type=float, default=0.22)
ap.add_argument("--depth", type=float, default=0.05)
args = ap.parse_args()

x, y, z = args.centre
reader = XMLUnstructuredGridReader(FileName=[args.particles])
surface = Threshold(Input=reader)
surface.Scalars = ["POINTS", "surface"]
surface.LowerThreshold = 1
surface.UpperThreshold = 1
low = Clip(Input=surface)
low.ClipType = "Plane"
low.ClipType.Origin = [0, 0, z + args.depth]
low.ClipType.Normal = [0, 0, 1]
view = GetActiveViewOrCreate("RenderView")
view.ViewSize = [1000, 800]
shown = Show(low, view)
shown.SetRepresentationType("Points")
shown.PointSize = 9
shown.RenderPointsAsSpheres = 1
ColorBy(shown, ("POINTS", args.field))
lut = GetColorTransferFunction(args.field)
if args.field == "stick":
    lut.ApplyPreset("Rainbow Uniform", True)
    lut.RescaleTransferFunction(-1.0, 1.0)
shown.SetScalarBarVisibility(view, True)
view.CameraPosition = [x, y, z - 3.0]
view.CameraFocalPoint = [x, y, z]
view.CameraViewUp = [0, 1, 0]
view.CameraParallelProjection = 1
view.CameraParallelScale = args.half_width
SaveScreenshot(args.out, view)

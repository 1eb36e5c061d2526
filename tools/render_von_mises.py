"""Renders the von Mises stress of the particles in a slab through a contact, as
docs/guide/stress_below_contact.png shows it.

    xvfb-run -a -s "-noreset" pvpython tools/render_von_mises.py PARTICLES.vtu OUT.png \
        [--centre X Y Z] [--half-width W] [--slab T] [--max VM]

PARTICLES.vtu is a frame's `<body>_particles.vtu`; the slab is the particles within T of the
plane y = Y (default 0.004 m), seen along y, W wide around the centre (default 0.2 m), the
colours from 0 to VM Pa (default: the data's range).
"""
import argparse

from paraview.simple import (Clip, ColorBy, GetActiveViewOrCreate, GetColorTransferFunction,
                             SaveScreenshot, Show, XMLUnstructuredGridReader)

ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
ap.add_argument("particles")
ap.add_argument("out")
ap.add_argument("--centre", type=float, nargs=3, default=[0.0, 0.0, -0.85])
ap.add_argument("--half-width", type=float, default=0.2)
ap.add_argument("--slab", type=float, default=0.004)
ap.add_argument("--max", type=float)
args = ap.parse_args()

x, y, z = args.centre
reader = XMLUnstructuredGridReader(FileName=[args.particles])
front = Clip(Input=reader)
front.ClipType = "Plane"
front.ClipType.Origin = [0, y + args.slab, 0]
front.ClipType.Normal = [0, 1, 0]
front.Invert = 1
slab = Clip(Input=front)
slab.ClipType = "Plane"
slab.ClipType.Origin = [0, y - args.slab, 0]
slab.ClipType.Normal = [0, -1, 0]
slab.Invert = 1
view = GetActiveViewOrCreate("RenderView")
view.ViewSize = [1200, 700]
shown = Show(slab, view)
shown.SetRepresentationType("Points")
shown.PointSize = 6
shown.RenderPointsAsSpheres = 1
ColorBy(shown, ("POINTS", "von_mises"))
if args.max:
    GetColorTransferFunction("von_mises").RescaleTransferFunction(0.0, args.max)
shown.SetScalarBarVisibility(view, True)
view.CameraPosition = [x, y - 2.0, z]
view.CameraFocalPoint = [x, y, z]
view.CameraViewUp = [0, 0, 1]
view.CameraParallelProjection = 1
view.CameraParallelScale = args.half_width
SaveScreenshot(args.out, view)

"""Renders a perforated plate and its projectile at one frame: the plate's particles coloured
by `damage` (or another point field: `--colour new_surface`, the surfaces its cracks opened;
`--colour fragment --max 20`, the pieces, 0 the largest),
the projectile's grey, seen from below at an angle, where the hole and the fragments it throws
out show (docs/FRACTURE.md, "Fragments").

    xvfb-run -a -s "-noreset" pvpython tools/render_fragments.py FRAME_FOLDER OUT.png \
        [--plate plate] [--projectile ball] [--colour damage] [--max 1]

FRAME_FOLDER is one frame's folder (`out/frame_004733`), holding `<body>_particles.vtu`.
"""
import argparse
import os

from paraview.simple import (ColorBy, GetActiveViewOrCreate, GetColorTransferFunction,
                             ResetCamera, SaveScreenshot, Show, WarpByVector,
                             XMLUnstructuredGridReader)

ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
ap.add_argument("frame")
ap.add_argument("out")
ap.add_argument("--plate", default="plate")
ap.add_argument("--projectile", default="ball")
ap.add_argument("--colour", default="damage", help="the plate's point field to colour by")
ap.add_argument("--max", type=float, default=1.0, help="the top of the colour range (from 0)")
args = ap.parse_args()

view = GetActiveViewOrCreate("RenderView")
view.ViewSize = [1000, 800]
for name, colour in [(args.plate, args.colour), (args.projectile, None)]:
    path = os.path.join(args.frame, f"{name}_particles.vtu")
    warp = WarpByVector(Input=XMLUnstructuredGridReader(FileName=[path]))
    warp.Vectors = ["POINTS", "displacement"]
    warp.ScaleFactor = 1.0
    shown = Show(warp, view)
    shown.SetRepresentationType("Points")
    shown.PointSize = 5
    shown.RenderPointsAsSpheres = 1
    if colour:
        ColorBy(shown, ("POINTS", colour))
        lut = GetColorTransferFunction(colour)
        lut.ApplyPreset("Inferno (matplotlib)", True)
        lut.RescaleTransferFunction(0.0, args.max)
        shown.SetScalarBarVisibility(view, True)
    else:
        ColorBy(shown, None)
        shown.AmbientColor = shown.DiffuseColor = [0.6, 0.6, 0.65]
view.CameraPosition = [0.6, -1.0, -0.8]
view.CameraFocalPoint = [0, 0, 0]
view.CameraViewUp = [0, 0, 1]
ResetCamera(view)
SaveScreenshot(args.out, view)

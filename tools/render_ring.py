"""Renders a Hertz indentation block at one frame, its particles coloured by `damage`, twice:
OUT_top.png, the surface layer (the particles within SLAB of the top face) seen from above,
where a ring crack shows as a band about the contact; OUT_section.png, the layer within SLAB
of the symmetry plane y = 0 seen across it, the section through the contact's axis, where
how deep and which way the crack runs shows (docs/FRACTURE.md, "Hertzian cone fracture").
Only the particles within REACH of the axis and DEPTH of the surface are drawn.

    xvfb-run -a -s "-noreset" pvpython tools/render_ring.py FRAME_FOLDER OUT \
        --reach R --depth D --slab S [--block block] [--max 0.15]

FRAME_FOLDER is one frame's folder (`out/frame_000260`), holding `<body>_particles.vtu`.
"""
import argparse
import os

from paraview.simple import (Clip, ColorBy, CreateView, GetColorTransferFunction, GetScalarBar,
                             SaveScreenshot, Show, XMLUnstructuredGridReader)

ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
ap.add_argument("frame")
ap.add_argument("out", help="the PNGs' names without _top.png, _section.png")
ap.add_argument("--block", default="block")
ap.add_argument("--max", type=float, default=0.15, help="the top of the colour range (from 0)")
ap.add_argument("--reach", type=float, required=True, help="radius about the axis drawn")
ap.add_argument("--depth", type=float, required=True, help="depth below the surface drawn")
ap.add_argument("--slab", type=float, required=True, help="thickness of each layer drawn (about 1.5 spacings)")
args = ap.parse_args()

reader = XMLUnstructuredGridReader(FileName=[os.path.join(args.frame, f"{args.block}_particles.vtu")])
near = Clip(Input=reader)
near.ClipType = "Cylinder"
near.ClipType.Axis = [0.0, 0.0, 1.0]
near.ClipType.Radius = args.reach
near.Invert = 1
shallow = Clip(Input=near)
shallow.ClipType = "Plane"
shallow.ClipType.Origin = [0.0, 0.0, -args.depth]
shallow.ClipType.Normal = [0.0, 0.0, 1.0]
shallow.Invert = 0


def layer(origin, normal):
    """The particles within SLAB of a plane through `origin`, on the side `normal` points away from."""
    cut = Clip(Input=shallow)
    cut.ClipType = "Plane"
    cut.ClipType.Origin = origin
    cut.ClipType.Normal = normal
    cut.Invert = 1
    return cut


r, d = args.reach, args.depth
for name, source, focal, position, up in [
    ("top", layer([0.0, 0.0, -args.slab], [0.0, 0.0, -1.0]), [0.5 * r, 0.5 * r, 0.0],
     [0.5 * r, 0.5 * r, 2.5 * r], [0.0, 1.0, 0.0]),
    ("section", layer([0.0, args.slab, 0.0], [0.0, 1.0, 0.0]), [0.5 * r, 0.0, -0.5 * d],
     [0.5 * r, -2.5 * r, -0.5 * d], [0.0, 0.0, 1.0]),
]:
    view = CreateView("RenderView")
    view.ViewSize = [1200, 900]
    view.OrientationAxesVisibility = 1
    shown = Show(source, view)
    shown.SetRepresentationType("Points")
    shown.PointSize = 6
    shown.RenderPointsAsSpheres = 1
    ColorBy(shown, ("POINTS", "damage"))
    lut = GetColorTransferFunction("damage")
    lut.ApplyPreset("Inferno (matplotlib)", True)
    lut.RescaleTransferFunction(0.0, args.max)
    bar = GetScalarBar(lut, view)
    bar.Title = "damage"
    bar.ComponentTitle = ""
    bar.Visibility = 1
    view.CameraFocalPoint = focal
    view.CameraPosition = position
    view.CameraViewUp = up
    view.CameraParallelProjection = 1
    view.CameraParallelScale = 0.6 * max(r, d)
    out = f"{args.out}_{name}.png"
    SaveScreenshot(out, view, ImageResolution=[1200, 900])
    print(f"saved {out}")

"""Renders the lower face of the block of `pdcontact fracture --case closing` (a quarter of a
1 x 1 x 2 m block cut across at z = 0.525 m, Δ = 0.05 m), seen along the load, each face
particle coloured by the load it carries across the crack over its share of the section
(its cell Δ², halved on each edge of the quarter it lies on): how evenly the face carries the
load, as docs/fracture_crack_mouth.png shows (docs/FRACTURE.md, "The crack's mouth").

    xvfb-run -a -s "-noreset" pvpython tools/render_crack_face.py \
        DIR/cut/frame_*/block_particles.vtu OUT.png "TITLE" [--spacing 0.05]
"""
import argparse

from paraview.simple import (ColorBy, GetActiveViewOrCreate, GetColorTransferFunction,
                             GetScalarBar, PythonCalculator, ResetCamera, SaveScreenshot, Show,
                             Text, Threshold, XMLUnstructuredGridReader)

ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
ap.add_argument("particles")
ap.add_argument("out")
ap.add_argument("title")
ap.add_argument("--spacing", type=float, default=0.05)
ap.add_argument("--stress", type=float, default=1e6, help="the applied stress, Pa")
args = ap.parse_args()

reader = XMLUnstructuredGridReader(FileName=[args.particles])
# The particles in contact; of them, the lower face's (below the cut).
touching = Threshold(Input=reader)
touching.Scalars = ["POINTS", "contact_pressure"]
touching.LowerThreshold, touching.UpperThreshold = 1.0, 1e30
edge = "where((inputs[0].Points[:,{a}]<1e-9)|(inputs[0].Points[:,{a}]>0.5-1e-9),0.5,1.0)"
share = PythonCalculator(Input=touching)
share.Expression = (
    f"abs(inputs[0].PointData['contact_force'][:,2]) / ({args.stress}*{args.spacing}**2"
    f"*{edge.format(a=0)}*{edge.format(a=1)}) * where(inputs[0].Points[:,2]<0.525,1.0,-1.0)"
)
share.ArrayName = "share"
lower = Threshold(Input=share)
lower.Scalars = ["POINTS", "share"]
lower.LowerThreshold, lower.UpperThreshold = 0.0, 1e30

view = GetActiveViewOrCreate("RenderView")
view.ViewSize = [820, 620]
view.OrientationAxesVisibility = 0
shown = Show(lower, view)
shown.SetRepresentationType("Points")
shown.PointSize = 22
shown.RenderPointsAsSpheres = 1
ColorBy(shown, ("POINTS", "share"))
lut = GetColorTransferFunction("share")
lut.ApplyPreset("Cool to Warm", True)
lut.RescaleTransferFunction(0.6, 1.6)
bar = GetScalarBar(lut, view)
bar.Title = "load / its share of the section"
bar.ComponentTitle = ""
bar.Visibility = 1
label = Show(Text(Text=args.title), view)
label.FontSize = 14
label.WindowLocation = "Upper Center"
view.CameraParallelProjection = 1
ResetCamera(view)
view.CameraPosition = [0.32, 0.25, 3.0]
view.CameraFocalPoint = [0.32, 0.25, 0.5]
view.CameraViewUp = [0, 1, 0]
view.CameraParallelScale = 0.33
SaveScreenshot(args.out, view, ImageResolution=[820, 620])

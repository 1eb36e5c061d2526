"""Show the last frame of this run in ParaView, coloured by contact pressure (or by damage
where bonds broke).

    pvpython view.py                # render the last frame
    pvpython view.py contact.png    # ... and save it as a PNG
    pvpython view.py --pressure     # the contact pressure even where bonds broke
    python3 view.py --focus         # print the camera it would use (Python's vtk, no ParaView)

In ParaView's Python shell: `import os; os.chdir("RUN_FOLDER"); exec(open("view.py").read())`.

It opens run.pvd beside this file at its last timestep, warps every block by `displacement`
(the points are the reference positions, so scale 1 gives the deformed shape), shows each
slave's `<body>/surface` coloured by `contact_pressure` and each master translucent, and puts
the camera on the contact: looking through the master at the pressure-weighted centre of the
loaded surface nodes, along their mean outward normal. A body pressed on itself (the faces of
its pre-cracks, the pieces of one mesh) shows the faces in contact alone, coloured, inside the
body drawn faintly (its outer faces would hide a crack's). The legend, in the lower right corner,
gives the pressure in the unit that suits the frame (Pa, kPa, MPa or GPa; every label in one
format) from 0 to its largest value; the upper left corner names the contact pairs and the
frame: its load factor and iteration (ADR or the static solver) or its time (s) and step (explicit). Where bonds
broke (a `damage` field above 0), the damaged particles are shown coloured by damage, from 0
to 1, inside their bodies drawn faintly (the undamaged particles would hide them), seen along
the axis in which the bodies are thinnest, from the side the damage lies on, centred on it;
not in a body pressed on its own pre-cracks whose bonds cannot break (its damage is the cut,
and the faces found again show their pressure).

Offscreen, without a display, under a virtual X server that outlives pvpython's first client:

    xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" pvpython view.py contact.png
"""
import os
import sys
import xml.etree.ElementTree as ET

# (slave, master) body names of the contact pairs, and the deformable bodies: written by
# pdcontact for this run.
PAIRS = []
DEFORMABLE = []
# The deformable bodies whose damage is shown: all but those pressed on their own pre-cracks
# whose bonds cannot break (their damage is the cut, which the contact's pressure shows).
DAMAGE = []
# What a quasi-static frame's iteration counts: "ADR iteration" or "Newton iteration".
ITERATION = "ADR iteration"

# Size of the saved picture (pixels); the legend's and the caption's fonts are sized for it.
RESOLUTION = [1600, 1000]
# One format for every number on the legend, its range ends included.
LABEL_FORMAT = "%.3g"

try:
    HERE = os.path.dirname(os.path.abspath(__file__))
except NameError:  # run from ParaView's Python shell: the current folder
    HERE = os.getcwd()


def last_frame():
    """The .vtm file of the last timestep of run.pvd, and that timestep."""
    root = ET.parse(os.path.join(HERE, "run.pvd")).getroot()
    entries = [(float(e.get("timestep")), e.get("file")) for e in root.iter("DataSet")]
    if not entries:
        raise SystemExit("run.pvd lists no frames")
    t, f = max(entries)
    return os.path.join(HERE, f), t


def read_blocks(vtm):
    """{block path: dataset} of a frame, e.g. {"ball/surface": ..., "plane": ...}."""
    from vtkmodules.vtkCommonDataModel import vtkCompositeDataSet
    from vtkmodules.vtkIOXML import vtkXMLMultiBlockDataReader

    r = vtkXMLMultiBlockDataReader()
    r.SetFileName(vtm)
    r.Update()
    out = {}

    def walk(mb, prefix):
        for k in range(mb.GetNumberOfBlocks()):
            name = mb.GetMetaData(k).Get(vtkCompositeDataSet.NAME())
            b = mb.GetBlock(k)
            if b is None:
                continue
            if b.IsA("vtkMultiBlockDataSet"):
                walk(b, prefix + name + "/")
            elif b.IsA("vtkMultiPieceDataSet"):
                out[prefix + name] = merged(b)
            else:
                out[prefix + name] = b

    walk(r.GetOutput(), "")
    return out


def merged(pieces):
    """One grid of the pieces a decomposed run writes (a rank's particles each), in rank
    order, with the first piece's field data (the frame's load factor or time)."""
    from vtkmodules.vtkCommonDataModel import vtkUnstructuredGrid
    from vtkmodules.vtkFiltersCore import vtkAppendFilter

    parts = [pieces.GetPiece(k) for k in range(pieces.GetNumberOfPieces())]
    parts = [p for p in parts if p is not None and p.GetNumberOfPoints() > 0]
    if not parts:
        return vtkUnstructuredGrid()
    append = vtkAppendFilter()
    for p in parts:
        append.AddInputData(p)
    append.Update()
    grid = append.GetOutput()
    grid.GetFieldData().ShallowCopy(parts[0].GetFieldData())
    return grid


def focus(blocks, slaves, inner=()):
    """Camera target from the slaves' surfaces: (centre, outward normal, radius) of the loaded
    nodes (deformed positions, weighted by pressure); the surfaces' bounds when none is loaded.
    On the slaves in `inner` (a body its own master: a crack's two faces, facing each other)
    each normal counts along the first loaded node's, so that the two faces' do not cancel."""
    sw, c, n, pts, first = 0.0, [0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [], None
    lo, hi = [float("inf")] * 3, [float("-inf")] * 3
    for s in slaves:
        g = blocks.get(s + "/surface")
        if g is None:
            continue
        pd = g.GetPointData()
        p, u, nrm = pd.GetArray("contact_pressure"), pd.GetArray("displacement"), pd.GetArray("normal")
        for i in range(g.GetNumberOfPoints()):
            x = [a + b for a, b in zip(g.GetPoint(i), u.GetTuple3(i))]
            lo = [min(a, b) for a, b in zip(lo, x)]
            hi = [max(a, b) for a, b in zip(hi, x)]
            w = p.GetValue(i)
            if w > 0.0:
                sw += w
                c = [a + w * b for a, b in zip(c, x)]
                ni = nrm.GetTuple3(i)
                if s in inner:
                    first = first or ni
                    if sum(a * b for a, b in zip(ni, first)) < 0.0:
                        ni = [-a for a in ni]
                n = [a + w * b for a, b in zip(n, ni)]
                pts.append(x)
    if sw == 0.0:
        if lo[0] == float("inf"):
            raise SystemExit("no slave surface in the frame")
        centre = [(a + b) / 2 for a, b in zip(lo, hi)]
        radius = max(b - a for a, b in zip(lo, hi)) / 2
        return centre, [0.0, 0.0, -1.0], radius, 0
    centre = [a / sw for a in c]
    ln = sum(a * a for a in n) ** 0.5 or 1.0
    normal = [a / ln for a in n]
    radius = max(sum((a - b) ** 2 for a, b in zip(x, centre)) ** 0.5 for x in pts)
    # At least a tenth of the body, so that a one-node contact is not a close-up of nothing.
    radius = max(radius, max(b - a for a, b in zip(lo, hi)) / 10)
    return centre, normal, radius, len(pts)


def frame_info(blocks, slaves):
    """The field data pdcontact writes into every dataset of a frame: {"load_factor",
    "iteration"} (ADR, static) or {"time", "step"} (explicit); empty if the frame has none."""
    names = [s + "/surface" for s in slaves] + sorted(blocks)
    for name in names:
        g = blocks.get(name)
        if g is None:
            continue
        fd = g.GetFieldData()
        info = {}
        for key in ("load_factor", "iteration", "time", "step"):
            a = fd.GetArray(key)
            if a is not None and a.GetNumberOfTuples() > 0:
                info[key] = a.GetTuple1(0)
        if info:
            return info
    return {}


def caption(slaves, info, timestep):
    """The corner text: the bodies in contact, then what the frame is."""
    pairs = [s + " on " + m for s, m in PAIRS]
    bodies = ", ".join(pairs or slaves)
    if "load_factor" in info:
        when = "load factor %.4g" % info["load_factor"]
        if "iteration" in info:
            when += " (%s %d)" % (ITERATION, info["iteration"])
    elif "time" in info:
        when = "t = %.4g s" % info["time"]
        if "step" in info:
            when += " (step %d)" % info["step"]
    else:
        when = "timestep %.4g" % timestep
    return bodies + "\n" + when


def pressure_scale(blocks, slaves):
    """The largest contact pressure on the slaves' surfaces (Pa), and the unit to show it in:
    (its size in Pa, its name), so that the largest value reads between 1 and 1000."""
    pmax = 0.0
    for s in slaves:
        g = blocks.get(s + "/surface")
        a = g.GetPointData().GetArray("contact_pressure") if g is not None else None
        if a is not None and a.GetNumberOfTuples() > 0:
            pmax = max(pmax, a.GetRange(0)[1])
    for size, unit in ((1e9, "GPa"), (1e6, "MPa"), (1e3, "kPa")):
        if pmax >= size:
            return pmax, size, unit
    return pmax, 1.0, "Pa"


def damage_focus(blocks):
    """Where bonds broke: (centre, view direction, radius, damaged particles, largest damage)
    of the deformable bodies' damaged particles (reference positions), looking along the axis
    in which the damaged bodies are thinnest; None without damage."""
    lo, hi, blo, bhi, count, dmax = [float("inf")] * 3, [float("-inf")] * 3, [float("inf")] * 3, [float("-inf")] * 3, 0, 0.0
    for name, g in blocks.items():
        if name.split("/")[0] not in DAMAGE or "/particles" not in name:
            continue
        a = g.GetPointData().GetArray("damage")
        if a is None:
            continue
        for i in range(g.GetNumberOfPoints()):
            x = g.GetPoint(i)
            blo = [min(p, q) for p, q in zip(blo, x)]
            bhi = [max(p, q) for p, q in zip(bhi, x)]
            d = a.GetValue(i)
            if d > 0.0:
                count += 1
                dmax = max(dmax, d)
                lo = [min(p, q) for p, q in zip(lo, x)]
                hi = [max(p, q) for p, q in zip(hi, x)]
    if count == 0:
        return None
    extent = [b - a for a, b in zip(blo, bhi)]
    order = sorted(range(3), key=lambda k: extent[k])
    # From the side of the bodies' middle that the damage lies on (a ring under a contact:
    # from the contact's side; a crack through a beam's thickness: either).
    k = order[0]
    side = 1.0 if (lo[k] + hi[k]) >= (blo[k] + bhi[k]) else -1.0
    normal = [side if j == k else 0.0 for j in range(3)]
    # Up along the bodies' middle extent: a beam's height, a plate's shorter side.
    up = [1.0 if k == order[1] else 0.0 for k in range(3)]
    centre = [(a + b) / 2 for a, b in zip(lo, hi)]
    radius = max(max(b - a for a, b in zip(lo, hi)) / 2, extent[order[1]] / 2)
    return centre, normal, up, radius, count, dmax


def camera(centre, normal, radius):
    """Position, focal point and view-up: on the master's side of the contact, along the normal."""
    dist = 8.0 * radius
    position = [c + dist * n for c, n in zip(centre, normal)]
    # View-up: the axis least aligned with the normal, made orthogonal to it.
    axis = min(range(3), key=lambda k: abs(normal[k]))
    up = [1.0 if k == axis else 0.0 for k in range(3)]
    d = sum(a * b for a, b in zip(up, normal))
    up = [a - d * b for a, b in zip(up, normal)]
    return position, centre, up


def main(argv):
    slaves = sorted({s for s, _ in PAIRS}) or list(DEFORMABLE)
    masters = sorted({m for _, m in PAIRS} - set(slaves))
    # Bodies pressed on themselves (a pre-crack's faces, pieces of one mesh): their contact
    # may lie inside them, behind their outer faces; the faces in contact are drawn alone,
    # the body faintly about them.
    inner = sorted({s for s, m in PAIRS if s == m})
    vtm, t = last_frame()
    blocks = read_blocks(vtm)
    centre, normal, radius, loaded = focus(blocks, slaves, inner)
    position, focal, up = camera(centre, normal, radius)
    text = caption(slaves, frame_info(blocks, slaves), t)
    pmax, size, unit = pressure_scale(blocks, slaves)
    # Where bonds broke, the particles coloured by damage instead (--pressure keeps the
    # pressure).
    damage = None if "--pressure" in argv else damage_focus(blocks)
    if damage is not None:
        centre, normal, up, radius, count, dmax = damage
        position, focal, _ = camera(centre, normal, 0.6 * radius)
        text += "\n%d particles damaged (largest damage %.2f)" % (count, dmax)
    elif pmax == 0.0:
        text += "\nno contact pressure in this frame"
    elif inner:
        text += "\nthe faces in contact, the body drawn faintly"
    title = "contact pressure (%s)" % unit
    if "--focus" in argv:
        import json

        print(json.dumps({"frame": os.path.basename(vtm), "timestep": t, "centre": centre,
                          "normal": normal, "radius": radius, "loaded": loaded,
                          "position": position, "up": up, "slaves": slaves, "masters": masters,
                          "caption": text, "legend": title, "pressure_max": pmax,
                          "damaged": damage[4] if damage else 0}))
        return
    png = next((a for a in argv[1:] if not a.startswith("-")), None)

    from paraview import simple as pv

    reader = pv.PVDReader(FileName=os.path.join(HERE, "run.pvd"))
    scene = pv.GetAnimationScene()
    scene.UpdateAnimationUsingDataTimeSteps()
    scene.AnimationTime = t
    warp = pv.WarpByVector(Input=reader)
    warp.Vectors = ["POINTS", "displacement"]
    warp.ScaleFactor = 1.0
    view = pv.GetActiveViewOrCreate("RenderView")

    def block(path):
        e = pv.ExtractBlock(Input=warp)
        e.Selectors = ["/Root/" + path]
        return e

    # The pressure in the legend's unit; its colour range from 0 to the frame's largest value.
    shown = "contact_pressure" if size == 1.0 else "contact_pressure_" + unit
    if damage is not None:
        shown, title, pmax, size, slaves = "damage", "damage", 1.0, 1.0, []
        for b in DEFORMABLE:
            # The body faintly, for where the damage lies: its surface where the frame has
            # one, else its particles.
            has_surface = b + "/surface" in blocks
            d = pv.Show(block(b + ("/surface" if has_surface else "/particles")), view)
            pv.ColorBy(d, None)
            d.Representation = "Surface" if has_surface else "Points"
            d.AmbientColor = d.DiffuseColor = [0.75, 0.75, 0.8]
            d.Opacity = 0.15
            # The damaged particles alone: the undamaged ones in front would hide them.
            damaged = pv.Threshold(Input=block(b + "/particles"))
            damaged.Scalars = ["POINTS", "damage"]
            if hasattr(damaged, "ThresholdMethod"):  # ParaView 5.10 and later
                damaged.LowerThreshold, damaged.UpperThreshold = 1e-9, 1.0
                damaged.ThresholdMethod = "Between"
            else:
                damaged.ThresholdRange = [1e-9, 1.0]
            d = pv.Show(damaged, view)
            d.Representation = "Points"
            d.PointSize = 6
            d.RenderPointsAsSpheres = 1
            pv.ColorBy(d, ("POINTS", "damage"))
            d.SetScalarBarVisibility(view, True)
        # Bright from its low end: a damage of 0.1 must show against the faint body.
        pv.GetColorTransferFunction("damage").ApplyPreset("Turbo", True)
        # The damage alone: a master drawn over it would dim it.
        masters = []
    for s in slaves:
        src = block(s + "/surface")
        if s in inner and pmax > 0.0:
            d = pv.Show(src, view)
            pv.ColorBy(d, None)
            d.AmbientColor = d.DiffuseColor = [0.75, 0.75, 0.8]
            d.Opacity = 0.15
            # The surface's cells with every corner pressed: a crack's faces where they touch.
            src = pv.Threshold(Input=src)
            src.Scalars = ["POINTS", "contact_pressure"]
            if hasattr(src, "ThresholdMethod"):  # ParaView 5.10 and later
                src.LowerThreshold, src.UpperThreshold = 1e-12 * pmax, pmax
                src.ThresholdMethod = "Between"
            else:
                src.ThresholdRange = [1e-12 * pmax, pmax]
        if size != 1.0:
            src = pv.Calculator(Input=src)
            src.AttributeType = "Point Data"
            src.ResultArrayName = shown
            src.Function = "contact_pressure/%r" % size
        d = pv.Show(src, view)
        d.Representation = "Surface"
        pv.ColorBy(d, ("POINTS", shown))
        d.SetScalarBarVisibility(view, True)
    lut = pv.GetColorTransferFunction(shown)
    lut.AutomaticRescaleRangeMode = "Never"
    lut.RescaleTransferFunction(0.0, pmax / size if pmax > 0.0 else 1.0)
    bar = pv.GetScalarBar(lut, view)
    bar.Title = title
    bar.ComponentTitle = ""
    bar.HorizontalTitle = 1
    bar.WindowLocation = "Lower Right Corner"
    bar.ScalarBarLength = 0.3
    bar.ScalarBarThickness = 16
    bar.TitleFontSize = 18
    bar.LabelFontSize = 16
    bar.AutomaticLabelFormat = 0
    bar.LabelFormat = LABEL_FORMAT
    bar.AddRangeLabels = 1
    bar.RangeLabelFormat = LABEL_FORMAT
    bar.UseCustomLabels = 0
    label = pv.Text(Text=text)
    ld = pv.Show(label, view)
    ld.WindowLocation = "Upper Left Corner"
    ld.Justification = "Left"
    ld.FontSize = 18
    for m in masters:
        d = pv.Show(block(m + "/surface" if m in DEFORMABLE else m), view)
        pv.ColorBy(d, None)
        d.AmbientColor = d.DiffuseColor = [0.7, 0.7, 0.75]
        d.Opacity = 0.3
    # pvpython resets the camera to the whole scene on its first render unless told not to.
    if hasattr(pv, "_DisableFirstRenderCameraReset"):
        pv._DisableFirstRenderCameraReset()
    view.CameraPosition = position
    view.CameraFocalPoint = focal
    view.CameraViewUp = up
    if damage is not None:
        # Parallel: the particles of a lattice line up, where perspective draws them as rods.
        view.CameraParallelProjection = 1
        view.CameraParallelScale = 1.15 * damage[3]
    view.OrientationAxesVisibility = 1
    if png:
        # Rendered at the picture's size: saved at another, ParaView scales the fonts with it.
        view.ViewSize = RESOLUTION
    pv.Render(view)
    if png:
        pv.SaveScreenshot(png, view, ImageResolution=RESOLUTION)
        print("saved " + png)


if __name__ != "view":  # run as a script or through exec(), not imported
    main(getattr(sys, "argv", None) or [""])

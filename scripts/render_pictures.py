# Renders one prepared specimen from its XDMF sidecar (docs/pictures.md), run by
# scripts/render_pictures.sh with ParaView's pvbatch:
#   pvbatch render_pictures.py RESULT.xdmf OUT.png TITLE WIRE_RADIUS_M
# ParaView's own "XDMF Reader" opens the file (so the picture also shows that the
# export is readable); the first snapshot of the first test is drawn: the specimen
# after the confining ramp, with its wire strains. Grains and membrane in front of
# the axis are clipped away so that the wire shows; the grains left are spheres of
# their own radius, the wire is a tube coloured by segment strain.
import sys

from paraview import servermanager as sm
from paraview.simple import *

xdmf, png, title, wire_radius_m = sys.argv[1], sys.argv[2], sys.argv[3], float(sys.argv[4])

reader = XDMFReader(FileNames=[xdmf])
times = list(reader.TimestepValues) if reader.TimestepValues else [0.0]
reader.UpdatePipeline(times[0])
root = sm.Fetch(reader)


def leaves(block, name=""):
    """(collection name, grid name, data set) for every uniform grid."""
    if block is None:
        return
    if block.IsA("vtkMultiBlockDataSet"):
        for i in range(block.GetNumberOfBlocks()):
            meta = block.GetMetaData(i) if block.HasMetaData(i) else None
            child = meta.Get(block.NAME()) if meta is not None and meta.Has(block.NAME()) else ""
            for leaf in leaves(block.GetBlock(i), child if block.GetBlock(i) is not None
                               and block.GetBlock(i).IsA("vtkMultiBlockDataSet") else name):
                yield leaf
            if block.GetBlock(i) is not None and not block.GetBlock(i).IsA("vtkMultiBlockDataSet"):
                yield (name, child.split("[")[0], block.GetBlock(i))
    elif block.IsA("vtkMultiPieceDataSet"):
        for i in range(block.GetNumberOfPieces()):
            for leaf in leaves(block.GetPiece(i), name):
                yield leaf


grids = {}
for collection, grid, data in leaves(root):
    # the first test's snapshot when there is one, else the specimen
    if collection != "specimen" or grid not in grids:
        grids.setdefault(grid, data) if collection == "specimen" else grids.__setitem__(grid, data)
print("grids:", {k: (v.GetNumberOfPoints(), v.GetNumberOfCells()) for k, v in grids.items()})


def source(data):
    p = TrivialProducer()
    p.GetClientSideObject().SetOutput(data)
    p.UpdatePipeline()
    return p


view = CreateView("RenderView")
view.ViewSize = [720, 1000]
view.Background = [1.0, 1.0, 1.0]
view.OrientationAxesVisibility = 0
view.EnableRenderOnInteraction = 0
view.UseColorPaletteForBackground = 0

front = dict(ClipType="Plane", Crinkleclip=1)  # keep whole cells behind the plane y = 0


def behind(src):
    c = Clip(Input=src, **front)
    c.ClipType.Origin = [0.0, 0.0, 0.0]
    c.ClipType.Normal = [0.0, -1.0, 0.0]
    c.Invert = 1  # keep the side the normal points away from: y > 0, away from the camera
    return c


if "membrane" in grids:
    m = Show(behind(source(grids["membrane"])), view)
    m.SetRepresentationType("Surface")
    m.ColorArrayName = ["POINTS", ""]
    m.AmbientColor = m.DiffuseColor = [0.75, 0.78, 0.85]
    m.Opacity = 0.35

if "grains" in grids:
    g = Glyph(Input=behind(source(grids["grains"])), GlyphType="Sphere")
    g.ScaleArray = ["POINTS", "radius_m"]
    g.ScaleFactor = 2.0  # the glyph sphere has radius 0.5
    g.GlyphMode = "All Points"
    g.GlyphType.ThetaResolution = 24
    g.GlyphType.PhiResolution = 16
    gd = Show(g, view)
    gd.ColorArrayName = ["POINTS", ""]
    gd.AmbientColor = gd.DiffuseColor = [0.80, 0.68, 0.50]
    gd.Opacity = 0.55

if "wire" in grids:
    wire = source(grids["wire"])
    tube = Tube(Input=ExtractSurface(Input=wire))  # Tube needs polydata
    tube.Radius = wire_radius_m
    tube.NumberofSides = 16
    tube.Capping = 1
    td = Show(tube, view)
    ColorBy(td, ("CELLS", "segment_strain"))
    lut = GetColorTransferFunction("segment_strain")
    lut.ApplyPreset("Cool to Warm", True)
    rng = grids["wire"].GetCellData().GetArray("segment_strain").GetRange()
    m_abs = max(abs(rng[0]), abs(rng[1]), 1e-9)
    lut.RescaleTransferFunction(-m_abs, m_abs)
    bar = GetScalarBar(lut, view)
    bar.Title = "wire segment strain"
    bar.ComponentTitle = ""
    bar.TitleColor = bar.LabelColor = [0.1, 0.1, 0.1]
    bar.RangeLabelFormat = "%-#6.1e"
    bar.WindowLocation = "Any Location"
    bar.Position = [0.82, 0.25]
    bar.ScalarBarLength = 0.5
    td.SetScalarBarVisibility(view, True)

text = Text(Text=title)
tdisp = Show(text, view)
tdisp.Color = [0.1, 0.1, 0.1]
tdisp.FontSize = 14
tdisp.WindowLocation = "Upper Center"

# Frame the membrane (a grain that escaped the column must not shrink the picture).
bounds = (grids["membrane"] if "membrane" in grids else grids["grains"]).GetBounds()
height = bounds[5] - bounds[4]
cz = 0.5 * (bounds[4] + bounds[5])
view.CameraFocalPoint = [0.0, 0.0, cz]
view.CameraPosition = [0.0, -3.4 * height, cz + 1.0 * height]
view.CameraViewUp = [0.0, 0.0, 1.0]
view.CameraViewAngle = 30.0
view.CameraParallelProjection = 0
Render(view)  # the first render resets the camera to everything shown: frame it again
view.CameraFocalPoint = [0.0, 0.0, cz]
view.CameraPosition = [0.0, -3.4 * height, cz + 1.0 * height]
view.CameraViewUp = [0.0, 0.0, 1.0]
Render(view)
SaveScreenshot(png, view, ImageResolution=[720, 1000], TransparentBackground=0)
print("wrote", png)

# What a user sees of a run's animation, checked with ParaView itself (run with
#   xvfb-run -a pvbatch check_animation.py RESULTS_FOLDER SCREENSHOT.png
# on the output of arm_and_bead.prm; tests/animation.cmake).
#
# 1. A screenshot of frame 0, from above in parallel projection (800 px per 1.1 m): the arm tube
#    is drawn with its section size (50 mm across: 36.4 px, to 2 px: the width of an edge's
#    anti-aliasing on each side), the tip point mass and the bead as cubes of 100 mm (the smallest
#    side the writer draws for this scene: twice the 50 mm section), and the background between
#    them stays background.
# 2. The data of the last frame (t = 0.02 s): the bead's velocity field is rigid-body motion,
#    v + w x (x - c) with v = (0.1, 0, 0) m/s, w = (0, 0, 2) rad/s and its centre c = (0.5 + 0.1 t,
#    0.3, 0) m (no force: closed form), to 1e-6 m/s; the arm, bent by then, moves its tube's last
#    ring and its tip cube together: their centroids' displacements (the tip node's translation:
#    a ring and a cube are symmetric about it, so the rotation terms cancel) agree to 1e-9 of
#    their size, drawn from two sources (the arm's mode fields, the tip interface's modes), and
#    the bend is not zero (> 1e-6 m); the header comment names the bodies; field data the time.
import os
import sys

from paraview import servermanager as sm
from paraview.simple import (ColorBy, GetActiveViewOrCreate, PVDReader, SaveScreenshot, Show,
                             XMLUnstructuredGridReader)
from vtkmodules.vtkIOImage import vtkPNGReader

folder, screenshot = sys.argv[1], sys.argv[2]
failures = []


def check(ok, text):
    print(("ok:     " if ok else "FAILED: ") + text)
    if not ok:
        failures.append(text)


# --- 1. the screenshot --------------------------------------------------------------------------
W = H = 800
centre = (0.55, 0.15)
half_height = 0.55  # m: ParallelScale
pixels_per_metre = H / (2 * half_height)

reader = PVDReader(FileName=folder + "/animation.pvd")
view = GetActiveViewOrCreate("RenderView")
view.ViewSize = [W, H]
view.OrientationAxesVisibility = 0
try:
    view.UseColorPaletteForBackground = 0
except AttributeError:
    pass
view.Background = [1, 1, 1]
display = Show(reader, view)
ColorBy(display, None)
display.AmbientColor = display.DiffuseColor = [0.2, 0.3, 0.8]
view.ViewTime = 0.0
view.CameraParallelProjection = 1
view.CameraPosition = [centre[0], centre[1], 10]
view.CameraFocalPoint = [centre[0], centre[1], 0]
view.CameraViewUp = [0, 1, 0]
view.CameraParallelScale = half_height
SaveScreenshot(screenshot, view, ImageResolution=[W, H], TransparentBackground=0)

png = vtkPNGReader()
png.SetFileName(screenshot)
png.Update()
image = png.GetOutput()
dims = image.GetDimensions()
scalars = image.GetPointData().GetScalars()
check(dims[0] == W and dims[1] == H, "screenshot is %d x %d px" % (dims[0], dims[1]))


def drawn(x, y):
    """True if the pixel at world point (x, y) is not white background."""
    col = int(round(W / 2 + (x - centre[0]) * pixels_per_metre))
    row = int(round(H / 2 + (y - centre[1]) * pixels_per_metre))  # VTK images count rows from the bottom
    rgb = [scalars.GetComponent(row * dims[0] + col, c) for c in range(3)]
    return min(rgb) < 225


def width_along(fixed, along_x, lo, hi):
    """Drawn length [m] of the line x = fixed (along_x False) or y = fixed, from lo to hi."""
    n = int((hi - lo) * pixels_per_metre)
    hits = sum(drawn(fixed, lo + (k + 0.5) / pixels_per_metre) if not along_x
               else drawn(lo + (k + 0.5) / pixels_per_metre, fixed) for k in range(n))
    return hits / pixels_per_metre


tube = width_along(0.3, False, -0.1, 0.1)
check(abs(tube - 0.05) <= 2 / pixels_per_metre, "arm tube across at x = 0.3 m: %.4f m (section 0.05 m)" % tube)
tip = width_along(1.0, False, -0.1, 0.1)
check(abs(tip - 0.1) <= 2 / pixels_per_metre, "tip mass cube across at x = 1 m: %.4f m (0.1 m)" % tip)
bead = width_along(0.5, False, 0.2, 0.4)
check(abs(bead - 0.1) <= 2 / pixels_per_metre, "bead cube across at x = 0.5 m: %.4f m (0.1 m)" % bead)
check(not drawn(0.5, 0.15) and not drawn(0.2, 0.3), "background between the arm and the bead")

# --- 2. fields of the last frame ----------------------------------------------------------------
last = XMLUnstructuredGridReader(FileName=[folder + "/animation_00002.vtu"])
last.UpdatePipeline()
grid = sm.Fetch(last)
field = grid.GetFieldData()
t = field.GetArray("TimeValue").GetValue(0)
check(abs(t - 0.02) < 1e-12, "TimeValue %g s (0.02 s)" % t)
with open(folder + "/animation_00002.vtu") as f:
    head = f.read(400)
check("cell data 'body': 1 = arm, 2 = bead" in head, "the file names the bodies: " + head.split("\n")[1])
body = grid.GetCellData().GetArray("body")
velocity = grid.GetPointData().GetArray("velocity")
displacement = grid.GetPointData().GetArray("displacement")
bead_points, arm_points = set(), set()
for c in range(grid.GetNumberOfCells()):
    ids = grid.GetCell(c).GetPointIds()
    (bead_points if body.GetValue(c) == 2 else arm_points).update(ids.GetId(k) for k in range(ids.GetNumberOfIds()))
c = (0.5 + 0.1 * t, 0.3, 0.0)
worst = 0.0
for p in bead_points:
    x = grid.GetPoint(p)
    expected = (0.1 - 2 * (x[1] - c[1]), 2 * (x[0] - c[0]), 0.0)  # v + (0, 0, 2) x (x - c)
    worst = max(worst, max(abs(a - b) for a, b in zip(velocity.GetTuple3(p), expected)))
check(len(bead_points) == 8 and worst <= 1e-6,
      "bead velocity field = v + w x (x - c) at its %d corners: largest difference %.2e m/s" % (len(bead_points), worst))
# Point order (animation_writer.cc): the arm's drawing (its centre-line points, then the tube's
# rings of 16, then the tip cube's 8 corners), then the bead's 8 corners.
n_arm = grid.GetNumberOfPoints() - 8
cube = range(n_arm - 8, n_arm)
ring = range(n_arm - 8 - 16, n_arm - 8)


def centroid(points):
    return [sum(displacement.GetTuple3(p)[a] for p in points) / len(points) for a in range(3)]


u_cube, u_ring = centroid(cube), centroid(ring)
size = max(abs(c) for c in u_cube)
apart = max(abs(a - b) for a, b in zip(u_cube, u_ring))
check(size > 1e-6 and apart <= 1e-9 * size,
      "tip cube and last tube ring move together: displacement %s m, %.1e apart" % (["%.3e" % c for c in u_cube], apart))

sys.stdout.flush()
os._exit(1 if failures else 0)  # not sys.exit: ParaView's teardown under Xvfb can raise an X error

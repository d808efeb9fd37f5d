"""The image scripts' lighting keeps a colour map readable on every face of a
closed surface (pipelines/canopy_catalyst.py: one headlight, ambient 0.45): a box
colored by a field is rendered from several directions lit as the scripts light
3D surfaces and unlit (exactly the colour map); every covered pixel's lit colour
must lie between 0.45 and 1 times its unlit colour (within 2 levels: the floor
docs/insitu.md promises, stated here, not read from the module), and some faces
must be darker than unlit (the light is at work).

Run: tests/support/with_xvfb.sh -- pvbatch lit_surface_check.py <pipelines dir> <output dir>
"""
import os
import sys

pipelines, output = sys.argv[1], sys.argv[2]
sys.path.insert(0, pipelines)
os.makedirs(output, exist_ok=True)

import canopy_catalyst as canopy  # noqa: E402
from paraview.simple import Box, ColorBy, Elevation, Render, SaveScreenshot, Show  # noqa: E402
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
from output_checks import expect, finish, read_png  # noqa: E402

FLOOR = 0.45  # the darkest a face may get, times its colour (docs/insitu.md)

settings = canopy.Settings(canopy.COMMON_DEFAULTS, image_size="320x320")
view = canopy.render_view(settings)
canopy.light_from_camera(view)
box = Elevation(Input=Box(XLength=1.0, YLength=1.0, ZLength=1.0), LowPoint=[-0.5, -0.5, -0.5],
                HighPoint=[0.5, 0.5, 0.5])
display = Show(box, view)
ColorBy(display, ("POINTS", "Elevation"))
darker = 0
for k, position in enumerate([(3, 2, 4), (-3, 1, 2), (1, -4, 0.5), (0.2, 0.3, 5), (-2, -2, -2)]):
    view.CameraPosition = list(position)
    view.CameraFocalPoint = [0, 0, 0]
    view.CameraViewUp = [0, 0, 1] if abs(position[2]) < 4 else [0, 1, 0]
    view.ResetCamera()
    images = {}
    for name, flat in (("lit", False), ("unlit", True)):
        canopy.shade(display, flat)
        Render(view)
        path = os.path.join(output, "box_%d_%s.png" % (k, name))
        SaveScreenshot(path, view, ImageResolution=[320, 320])
        images[name] = read_png(path).astype(int)
    lit, unlit = images["lit"], images["unlit"]
    covered = (unlit != 255).any(axis=2)
    low = FLOOR * unlit - 2
    inside = ((lit >= low) & (lit <= unlit + 2)).all(axis=2)
    expect(covered.sum() > 5000, "view %d: the box covers %d pixels" % (k, covered.sum()))
    expect(bool(inside[covered].all()), "view %d: every face keeps between %.2f and 1 times its "
          "colour (%d pixels outside)" % (k, FLOOR, int((~inside & covered).sum())))
    darker += int((lit[covered].sum(axis=1) < 0.95 * unlit[covered].sum(axis=1)).sum())
expect(darker > 1000, "the headlight shades faces turned from it (%d darker pixels)" % darker)
finish(exit_on_success=False)

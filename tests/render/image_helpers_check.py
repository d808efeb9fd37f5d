"""The image scripts' helpers that make an image read (pipelines/canopy_catalyst.py):

- legend ends: a range end that is zero to rounding prints as 0, labels tell the
  ends apart (zero_to_rounding, label_format);
- mesh lines (edge_overlay): on a 2D grid with one root refined to cells of
  about 2.3 pixels, the overlay's lines leave most of the refined region its
  colour (under 30% dark pixels) where drawing every cell's edges paints it
  dark (checked in the same run: over 50%, or this check could not tell), the
  refinement still shows (the refined root has more lines than a coarse one),
  and a coarse root's edges are drawn.

Run: tests/support/with_xvfb.sh -- pvbatch image_helpers_check.py <pipelines dir> <output dir>
with CANOPY_PLUGIN set to the plugin library.
"""
import os
import sys

pipelines, output = sys.argv[1], sys.argv[2]
sys.path.insert(0, pipelines)
os.makedirs(output, exist_ok=True)

import canopy_catalyst as canopy  # noqa: E402
from paraview import simple  # noqa: E402
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
from output_checks import expect, finish, read_png  # noqa: E402

# ---- legend ends ----
expect(canopy.zero_to_rounding(1.2e-21, 1.0) == (0.0, 1.0), "1.2e-21 next to 1 is 0")
expect(canopy.zero_to_rounding(-3e-19, 2.5) == (0.0, 2.5), "-3e-19 next to 2.5 is 0")
expect(canopy.zero_to_rounding(1e-3, 1.0) == (1e-3, 1.0), "1e-3 next to 1 is kept")
expect(canopy.zero_to_rounding(1e-21, 2e-21) == (1e-21, 2e-21), "a range of tiny values is kept")
for low, high in ((0.0, 1.0), (1.2341, 1.2343), (0.0, 0.99), (-5e4, 3e5), (1e-6, 3e-6)):
    form = canopy.label_format(low, high)
    expect(form % low != form % high, "%s tells %r and %r apart: %s, %s"
          % (form, low, high, form % low, form % high))
expect(canopy.label_format(0.0, 1.0) % 0.0 == "0", "0 prints as 0")

# ---- mesh lines ----
canopy.load_canopy_plugin()
levels = 7  # root 0 refined to 128 x 128 cells, the other three roots leaves
descriptor = ["R..."] + ["R" * 4 ** level for level in range(1, levels)] + ["." * 4 ** levels]
grid = simple.HyperTreeGrid(Dimensions=[3, 3, 1], GridScale=[1, 1, 1], BranchFactor=2,
                            MaxDepth=levels + 1, Descriptor=" | ".join(descriptor))
size = 600
settings = canopy.Settings(canopy.COMMON_DEFAULTS, **canopy.IMAGE_DEFAULTS)
settings["image_size"] = "%dx%d" % (size, size)
view = canopy.render_view(settings)
simple._DisableFirstRenderCameraReset()  # the camera is ours


def top_view():
    """The 2 x 2 domain fills the image: a fine cell is 2.3 px. (Set after Show:
    showing the first source in a view resets its camera.)"""
    view.CameraParallelProjection = 1
    view.CameraPosition, view.CameraFocalPoint = [1, 1, 10], [1, 1, 0]
    view.CameraViewUp = [0, 1, 0]
    view.CameraParallelScale = 1.0


def dark_shares(name, with_overlay):
    surface = simple.CanopyAdaptiveSurface(Input=grid, Fields=["Depth"])
    display = simple.Show(surface, view)
    top_view()
    canopy.follow_view(surface, view)
    display.ColorArrayName = [None, ""]
    display.AmbientColor = display.DiffuseColor = [0.85, 0.85, 0.85]
    canopy.shade(display, True)
    shown = [(surface, display)]
    if with_overlay:
        overlay, lines = canopy.edge_overlay(surface, view, settings)
        canopy.follow_view(overlay, view)
        shown.append((overlay, lines))
    else:
        display.SetRepresentationType("Surface With Edges")
        display.EdgeColor = canopy.EDGE_COLOR
    simple.Render(view)
    path = os.path.join(output, name + ".png")
    simple.SaveScreenshot(path, view, ImageResolution=[size, size])
    for source, shown_display in shown:
        simple.Hide(source, view)
    image = read_png(path).astype(int)  # row 0 is the bottom (VTK's origin), as y
    dark = (image < 128).all(axis=2)
    half, margin = size // 2, 8
    fine = dark[margin:half - margin, margin:half - margin].mean()
    coarse = dark[half + margin:size - margin, half + margin:size - margin].mean()
    # The vertical edge between the two coarse roots at the top, x = 1.
    boundary = dark[half + margin:size - margin, half - 2:half + 2].any(axis=1).mean()
    return fine, coarse, boundary


fine, coarse, boundary = dark_shares("edges_overlay", True)
every_fine, _, _ = dark_shares("edges_every_cell", False)
expect(every_fine > 0.5, "every cell's edges paint the refined root dark: %.0f%% of its pixels"
      % (100 * every_fine))
expect(fine < 0.3, "the overlay leaves the refined root its colour: %.0f%% dark" % (100 * fine))
expect(fine > coarse, "the refined root shows more lines (%.1f%% dark) than a coarse one (%.1f%%)"
      % (100 * fine, 100 * coarse))
expect(boundary > 0.95, "the edge between two coarse roots is drawn along %.0f%% of its length"
      % (100 * boundary))
finish(exit_on_success=False)

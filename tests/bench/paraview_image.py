# script-version: 2
# canopy-renders: yes
"""Benchmark baseline (canopy_bench_image_step): ParaView's own route to the
image surface_image.py makes, on the same grid, in the same run.

No Canopy filter and no plugin: the hypertree grid goes straight into a render
view with ParaView 5.11's own representation for hypertree grids, colored by the
same field, with the same camera (canopy_catalyst.frame_grid), image size,
background, edges and PNG extractor as surface_image.py.

Settings (defaults; environment CANOPY_<NAME>; script arguments --name=value):
  frequency, start    run at steps start, start + frequency, ... (1, 0)
  image_size          WIDTHxHEIGHT (800x600)
  color_by            cell field to color by ('' : solid color)
  fields              fields Canopy wraps for this script ('' : every field)
  show_edges          draw the cells' edges (false)
  representation      'Surface': ParaView's default for a hypertree grid
                      (vtkPVGeometryFilter, which runs vtkHyperTreeGridGeometry);
                      'HTG Surface': its 2D adaptive-decimation representation
                      (vtkAdaptiveDataSetSurfaceFilter in the HTG mapper)
  png_compression     zlib level of the PNG files (3, as surface_image.py)
  legend, time_label  the colour legend and the time, as surface_image.py shows them (true)
  file_prefix         the files' names ("paraview")

Writes, in the output directory:
  <prefix>_<step>.png   the image
"""
import canopy_catalyst as canopy
from paraview.simple import Show

# surface_image.py's defaults (IMAGE_DEFAULTS) for the settings this route shares
# with it, and only those: another of its settings would do nothing here (an error).
SHARED = ("image_size", "color_by", "show_edges", "camera_position", "camera_focal_point",
          "camera_view_up", "parallel_scale", "png_compression", "legend", "time_label")
settings = canopy.settings(**{name: canopy.IMAGE_DEFAULTS[name] for name in SHARED},
                           representation="Surface", file_prefix="paraview")
options = canopy.catalyst_options(settings)

grid = canopy.simulation_grid(settings)
view = canopy.render_view(settings)
display = Show(grid, view)
display.SetRepresentationType(settings.representation +
                              (" With Edges" if settings.show_edges else ""))
if settings.show_edges:
    display.EdgeColor = canopy.EDGE_COLOR

image = canopy.png_extractor(view, settings)


def RequestDataDescription(datadescription):
    canopy.request_fields(datadescription, settings, extra=[settings.color_by],
                          every_field_when_empty=False)


legend = canopy.color_legend(view, settings.color_by) if settings.legend else None
time_label = canopy.time_label(view) if settings.time_label else None


def catalyst_execute(info):
    # The same camera and color range as surface_image.py (collectives: every rank).
    canopy.frame_grid(view, grid, settings)
    canopy.color_by(display, view, grid, settings.color_by)
    if time_label is not None:
        time_label.Text = canopy.time_text(info.time)

# script-version: 2
"""Canopy pipeline: an image of the adaptive surface, colored by a field.

The surface follows the render view: before each image it takes the view's
camera and viewport size, so only what the camera sees is built, and nothing
finer than a pixel (change the camera settings and the culling changes).

Settings (defaults; environment CANOPY_<NAME>; script arguments --name=value):
  output_directory  where images go (the driver sets it from its options)
  frequency         run every N steps (1)
  image_size        WIDTHxHEIGHT (800x600)
  color_by          cell field to color by ('' : solid color)
  fields            fields Canopy wraps for this script, besides color_by ('' : color_by
                    alone; the surface extract carries these)
  pixel_threshold   stop refining below this many pixels (1.0)
  show_edges        draw the cells' edges: the mesh the camera sees (false)
  camera_position, camera_focal_point, camera_view_up   'x,y,z' ('' : frame the grid)
  parallel_scale    > 0: parallel projection with this scale (with camera_position)
  surface_extract   also write the surface the camera saw (.pvtp and pieces) (false)
  cinema            write into a Cinema database instead: surface.cdb/ in the output
                    directory, indexed by data.csv at the end (false)
  png_compression   zlib level of the PNG files, 0-9 (3: about 35% less time than
                    ParaView's default 5 for files about 13% larger, docs/benchmarks.md)
  file_prefix       the files' names: <prefix>_<step>.png, ... ("surface")
  legend            a colour legend (the field's name and range) when color_by is set (true)
  time_label        the simulation time in the upper left corner (true)
  color_range       '' : each step's range over all ranks; 'low,high': that range for the
                    whole run; 'first': the first image's range, kept for the run (a time
                    series then does not flicker)

Writes, in the output directory (<step>: the time step, 6 digits; <rank>: an MPI rank):
  <prefix>_<step>.png                           the image
  <prefix>_<step>.pvtp                          surface_extract: the surface the camera saw,
  <prefix>_<step>/<prefix>_<step>_<rank>.vtp      listing its pieces, one per rank with quads
  surface.cdb/data.csv                          cinema: the same files in surface.cdb/ instead,
  surface.cdb/<prefix>_<step>.png                 indexed by data.csv (a row per file)
  surface.cdb/<prefix>_<step>.pvtp
  surface.cdb/<prefix>_<step>/<prefix>_<step>_<rank>.vtp
Reports "<prefix> quads" (the quads drawn, all ranks) in the step's StepReport::measures.
"""
import canopy_catalyst as canopy
from paraview import simple
from paraview.simple import CreateExtractor, Show

settings = canopy.settings(image_size="800x600", color_by="", pixel_threshold=1.0,
                           camera_position="", camera_focal_point="", camera_view_up="",
                           parallel_scale=0.0, surface_extract=False, cinema=False,
                           show_edges=False, legend=True, time_label=True, color_range="",
                           png_compression=3,
                           file_prefix="surface")
fixed_range = settings.list("color_range", float) if settings.color_range not in ("", "first") \
    else None
if fixed_range is not None and (len(fixed_range) != 2 or not fixed_range[0] < fixed_range[1]):
    raise ValueError("color_range: 'low,high' with low < high, 'first' or '' (got %r)"
                     % settings.color_range)
options = canopy.catalyst_options(settings, cinema="surface.cdb" if settings.cinema else None)
# The plugin's filters go into paraview.simple (see load_canopy_plugin).
canopy.load_canopy_plugin()

grid = canopy.simulation_grid(settings)
view = canopy.render_view(settings)
surface = simple.CanopyAdaptiveSurface(Input=grid, PixelThreshold=settings.pixel_threshold,
                                       Fields=settings.list("fields"))
display = Show(surface, view)
if settings.show_edges:
    display.SetRepresentationType("Surface With Edges")
    display.EdgeColor = [0.15, 0.15, 0.15]

image = CreateExtractor("PNG", view, registrationName="surface_image")
image.Writer.FileName = settings.file_prefix + "_{timestep:06d}.png"
image.Writer.ImageResolution = canopy.image_size(settings)
image.Writer.Format.CompressionLevel = str(settings.png_compression)
canopy.set_trigger(image, settings)

if settings.surface_extract:
    canopy.data_extractor("VTP", surface, "surface_data",
                          settings.file_prefix + "_{timestep:06d}.pvtp", settings)


def RequestDataDescription(datadescription):
    canopy.request_fields(datadescription, settings, extra=[settings.color_by],
                          every_field_when_empty=False)


legend = canopy.color_legend(view, settings.color_by) if settings.legend else None
time_label = canopy.time_label(view) if settings.time_label else None


def catalyst_execute(info):
    global fixed_range
    # frame_grid and color_by agree over ranks (collectives): every rank calls them.
    canopy.frame_grid(view, grid, settings)
    canopy.follow_view(surface, view)
    used = canopy.color_by(display, view, grid, settings.color_by, fixed_range)
    if settings.color_range == "first" and fixed_range is None and used is not None:
        fixed_range = used
    if time_label is not None:
        time_label.Text = canopy.time_text(info.time)
    canopy.report(settings.file_prefix + " quads", canopy.output_cells(surface))

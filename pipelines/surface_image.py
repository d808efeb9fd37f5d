# script-version: 2
# canopy-renders: yes
"""Canopy pipeline: an image of the adaptive surface, colored by a field; in 3D
optionally of a selected region only (a value range, an octant or a box cut away),
drawn as the surface of the cells it keeps.

The surface follows the render view: before each image it takes the view's
camera and viewport size, so only what the camera sees is built, and nothing
finer than a pixel (change the camera settings and the culling changes).

Settings (defaults; environment CANOPY_<NAME>; script arguments --name=value):
  output_directory  where images go (the driver sets it from its options)
  frequency, start  run at steps start, start + frequency, ... (1, 0)
  image_size        WIDTHxHEIGHT (800x600)
  color_by          cell field to color by ('' : solid color)
  fields            fields Canopy wraps for this script, besides color_by and select_field
                    ('' : those alone; the surface extract carries these)
  pixel_threshold   stop refining below this many pixels (1.0)
  show_edges        draw the mesh (false): on flat pieces (a 2D grid, slices) cells at least
                    edge_spacing pixels wide show their own edges, finer regions their
                    ancestors' (edge_spacing to twice that apart); in 3D each drawn cell's edges
  edge_spacing      the fewest pixels between mesh lines on flat pieces (8; 0: every cell's edges)
  average_colors    draw the colours the filter computes: a coarse quad its leaves' average
                    colour, face-on a quad covering one pixel that pixel's average (true)
  camera_position, camera_focal_point, camera_view_up   'x,y,z' ('' : frame the grid)
  parallel_scale    > 0: parallel projection with this scale (with camera_position)
  select_field, select_range   draw only the cells whose field lies in 'low,high'
                    (inclusive): in 3D the blocky shell around that region ('' : all)
  cut_away          '' (none), 'octant' (the octant of the domain towards the camera,
                    to look inside) or 'xmin,xmax,ymin,ymax,zmin,zmax': cells overlapping
                    that box are not drawn
  skip_back_faces   3D: leave out the faces turned away from the camera, about half of
                    them (false: a camera inside the domain sees only back faces)
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

Lighting: one light from the camera; a face shows its colour times 0.45 + 0.55 cos(angle
to the view), so no face is darker than 45% of the colour map (canopy_catalyst.SURFACE_AMBIENT).

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

settings = canopy.settings(**dict(canopy.SURFACE_DEFAULTS, file_prefix="surface"))
# The pipeline is canopy_catalyst.SurfaceImage, which surface_image_second_view.py shares.
image = canopy.SurfaceImage(settings)
options = image.options


def RequestDataDescription(datadescription):
    image.request_fields(datadescription)


def catalyst_execute(info):
    # Collective (bounds and colour ranges agree over ranks): every rank calls it.
    image.execute(info)

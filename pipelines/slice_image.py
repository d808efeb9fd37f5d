# script-version: 2
# canopy-renders: yes
"""Canopy pipeline: an image of adaptive slices through a 3D grid (up to three
axis-aligned planes), with the domain's outline and, optionally, the surface of a
selected region, colored by a field.

The slices and the surface follow the render view: only what the camera sees is
built, nothing finer than a pixel; a slice enters only the cells its plane cuts.
A plane on a face between two cells cuts the cell on its upper side.

Settings (defaults; environment CANOPY_<NAME>; script arguments --name=value):
  slices            'center' (x, y and z through the domain's centre) or a list such
                    as 'x=0.5,z=0.25' (at most three planes; positions in the grid's
                    coordinates) ("center")
  outline           draw the domain's outline (true)
  select_field, select_range, cut_away   also draw the surface of a selected region
                    (as surface_image.py; '' : no surface)
  contour_field     also draw the isosurfaces of this cell field (CanopyContour:
                    crack-free across levels and trees, up to the domain's boundary;
                    '' : none) ("")
  contour_values    their values, e.g. '0.5' or '0.2,0.5' ("")
  contour_count     without contour_values: this many values spread evenly inside the
                    field's range this step (agreed over ranks) (1)
  contour_opacity   the isosurfaces' opacity, in (0, 1] (1.0; below 1 on several ranks
                    ParaView 5.11 redistributes the geometry for ordered compositing, and
                    the slices' mesh lines then show the triangles it cuts quads into)
  contour_level_of_detail   the isosurfaces follow the view as the slices do: nothing
                    finer than pixel_threshold pixels (a node that small is contoured
                    as a leaf holding its own value, crack-free alike), nothing outside
                    the view; false: the full-resolution isosurfaces (true)
  slice_extract     also write what was drawn: the slices, the region's surface and
                    the isosurfaces, as .pvtp with their fields (false)
  file_prefix       the files' names: <prefix>_<step>.png, ... ("slices")
  frequency, start, image_size, color_by, fields, pixel_threshold, show_edges, edge_spacing,
  average_colors, camera_position, camera_focal_point, camera_view_up, parallel_scale, legend,
  time_label, color_range, png_compression, skip_back_faces   as surface_image.py

Lighting: the slices are unlit (exactly the colour map); the region's surface and the
isosurfaces as surface_image.py's surface. The isosurfaces are coloured by color_by
interpolated onto them (white without color_by). On several ranks each rank draws the
isosurfaces of its own part: they do not yet meet across the parts' borders
(docs/filters.md).

Writes, in the output directory (<step>: the time step, 6 digits; <rank>: an MPI rank):
  <prefix>_<step>.png                           the image
  <prefix>_<step>.pvtp                          slice_extract: the slices as drawn,
  <prefix>_<step>/<prefix>_<step>_<rank>.vtp      one piece per rank
  <prefix>_region_<step>.pvtp                   slice_extract with a region: its surface
  <prefix>_region_<step>/<prefix>_region_<step>_<rank>.vtp
  <prefix>_contour_<step>.pvtp                  slice_extract with contour_field: the
  <prefix>_contour_<step>/<prefix>_contour_<step>_<rank>.vtp  isosurfaces
Reports "<prefix> quads" (slice quads drawn, all ranks), with a region "<prefix> region
quads", with contour_field "<prefix> contour triangles" in the step's StepReport::measures.
"""
import canopy_catalyst as canopy
from paraview import simple

settings = canopy.settings(**dict(canopy.IMAGE_DEFAULTS, file_prefix="slices"),
                           slices="center", outline=True, slice_extract=False,
                           contour_field="", contour_values="", contour_count=1,
                           contour_opacity=1.0, contour_level_of_detail=True)


def planes(text):
    """'center' -> None (the centre, known once the grid is); else [(axis, position)]."""
    if text == "center":
        return None
    found = []
    for item in (part.strip() for part in text.split(",") if part.strip()):
        name, _, value = item.partition("=")
        if name.strip().lower() not in ("x", "y", "z") or not value:
            raise ValueError("slices: 'center' or a list such as 'x=0.5,z=0.25' (got %r)" % text)
        found.append(("xyz".index(name.strip().lower()), float(value)))
    if not 1 <= len(found) <= 3:
        raise ValueError("slices: one to three planes (got %d)" % len(found))
    return found


def contour_values(values):
    """The contour settings, checked: the values given (a list of finite numbers, [] for
    contour_count values spread inside the range). Raises ValueError naming the setting."""
    import math
    text = str(values.contour_values)
    try:
        given = values.list("contour_values", float)
    except ValueError:
        raise ValueError("contour_values: numbers separated by commas, e.g. '0.5' or "
                         "'0.2,0.5' (got %r)" % text) from None
    if not all(math.isfinite(value) for value in given):
        raise ValueError("contour_values: finite numbers (got %r)" % text)
    if given and not values.contour_field:
        raise ValueError("contour_values=%r needs contour_field (the cell field to contour)" % text)
    if values.contour_field and not given and values.contour_count < 1:
        raise ValueError("contour_count: at least 1 (got %d)" % values.contour_count)
    if not 0.0 < values.contour_opacity <= 1.0:
        raise ValueError("contour_opacity: greater than 0, at most 1 (got %r)"
                         % values.contour_opacity)
    return given


given = planes(settings.slices)
given_contour_values = contour_values(settings)
image = canopy.ImageScript(settings)
options = image.options

slices = simple.CanopyAdaptiveSlice(Input=image.grid, PixelThreshold=settings.pixel_threshold,
                                    Fields=settings.list("fields"))
image.show(slices, flat=True)
region_surface = None
if image.region is not image.grid:
    region_surface = simple.CanopyAdaptiveSurface(
        Input=image.region, PixelThreshold=settings.pixel_threshold, Fields=settings.list("fields"),
        SkipBackFaces=int(settings.skip_back_faces))
    image.show(region_surface)
contour = None
contour_display = None
if settings.contour_field:
    interpolated = [settings.color_by] if settings.color_by not in ("", settings.contour_field) \
        else []
    follows = bool(settings.contour_level_of_detail)
    # With level of detail the contour takes the view each step (ImageScript.execute) and
    # stops at nodes of pixel_threshold pixels, as the slices do; without, the filter's
    # own default: the full-resolution contour whatever the camera.
    contour = simple.CanopyContour(Input=image.grid, ContourBy=["CELLS", settings.contour_field],
                                   ContourValues=given_contour_values,
                                   InterpolatedFields=interpolated, ViewDependent=int(follows),
                                   LevelOfDetail=1, ViewCulling=1,
                                   PixelThreshold=settings.pixel_threshold)
    contour_display = image.show(contour, follows_view=follows, colored=False, edges=False)
    contour_display.Opacity = settings.contour_opacity
outline = None
if settings.outline:
    outline = simple.Box()
    shown = image.show(outline, flat=True, follows_view=False, colored=False)
    shown.SetRepresentationType("Outline")
    shown.AmbientColor = shown.DiffuseColor = [0.2, 0.2, 0.2]

if settings.slice_extract:
    canopy.data_extractor("VTP", slices, "slices_data",
                          settings.file_prefix + "_{timestep:06d}.pvtp", settings)
    if region_surface is not None:
        canopy.data_extractor("VTP", region_surface, "slices_region_data",
                              settings.file_prefix + "_region_{timestep:06d}.pvtp", settings)
    if contour is not None:
        canopy.data_extractor("VTP", contour, "slices_contour_data",
                              settings.file_prefix + "_contour_{timestep:06d}.pvtp", settings)


def RequestDataDescription(datadescription):
    canopy.request_fields(datadescription, settings,
                          extra=image.fields() + [settings.contour_field],
                          every_field_when_empty=False)


def contour_step():
    """This step's contour values (contour_count spread inside the field's range,
    agreed over ranks) and colours. Collective."""
    from paraview.simple import GetColorTransferFunction
    if not given_contour_values:
        low, high = canopy.field_range(image.grid, settings.contour_field)
        count = settings.contour_count
        contour.ContourValues = ([low + (high - low) * (i + 1) / (count + 1) for i in range(count)]
                                 if low <= high else [])
    if settings.color_by:
        # Point data (interpolated onto the isosurfaces), the slices' colour map.
        contour_display.ColorArrayName = ["POINTS", settings.color_by]
        contour_display.LookupTable = GetColorTransferFunction(settings.color_by)
    else:
        contour_display.ColorArrayName = ["POINTS", ""]
        contour_display.AmbientColor = contour_display.DiffuseColor = [1.0, 1.0, 1.0]


def place(bounds):
    """Planes and outline from the grid's bounds (the same on every rank)."""
    chosen = given or [(axis, 0.5 * (bounds[2 * axis] + bounds[2 * axis + 1]))
                       for axis in range(3)]
    for axis, name in enumerate(("XPlanes", "YPlanes", "ZPlanes")):
        setattr(slices, name, [position for a, position in chosen if a == axis])
    if outline is not None:
        outline.XLength, outline.YLength, outline.ZLength = (
            bounds[1] - bounds[0], bounds[3] - bounds[2], bounds[5] - bounds[4])
        outline.Center = [0.5 * (bounds[2 * a] + bounds[2 * a + 1]) for a in range(3)]


def catalyst_execute(info):
    # Collective (bounds and colour ranges agree over ranks): every rank calls it.
    if contour is not None and not canopy.has_cell_field(image.grid, settings.contour_field):
        raise ValueError("contour_field %r: no rank's grid has a cell field of that name"
                         % settings.contour_field)
    place(canopy.grid_bounds(image.grid))
    if contour is not None:
        contour_step()
    image.execute(info)
    canopy.report(settings.file_prefix + " quads", canopy.output_cells(slices))
    if region_surface is not None:
        canopy.report(settings.file_prefix + " region quads", canopy.output_cells(region_surface))
    if contour is not None:
        canopy.report(settings.file_prefix + " contour triangles", canopy.output_cells(contour))

# script-version: 2
"""Canopy pipeline: cells selected by location, id, value range, box or frustum,
written as an unstructured grid of lines/quads/hexahedra with the cell fields and
original ids (.pvtu), or, with preserve_topology, as the grid itself with every
cell that is not selected masked (the grid extracts of data_extracts.py: VTKHDF
and/or ParaView 5.11's .pvd series of .htg pieces).

Settings (defaults; environment CANOPY_<NAME>; script arguments --name=value):
  frequency, start   run at steps start, start + frequency, ... (1, 0)
  selection          points | ids | range | box | frustum ("points")
  points             'x,y,z,x,y,z,...' for 'points'
  ids                'i,j,...' global cell ids for 'ids' (a coarse id selects that cell)
  value_field        field for 'range'; value_component: component (-1: magnitude)
  value_range        'low,high' for 'range' (inclusive)
  box                'xmin,xmax,ymin,ymax,zmin,zmax' for 'box': the leaves overlapping it
                     with positive volume (area, length; flat axes of 2D/1D grids ignored)
  frustum            for 'frustum': 8 corners 'x,y,z,...' in vtkSelectionNode's FRUSTUM order
                     (near/far lower left, near/far upper left, near/far lower right,
                     near/far upper right); or, when empty, the camera's view:
  camera_position, camera_focal_point, camera_view_up   'x,y,z', as surface_image.py's
  parallel_scale     > 0: parallel projection with this scale (else perspective)
  view_angle         perspective: the vertical view angle in degrees (30)
  image_size         WIDTHxHEIGHT: the view's aspect ratio (800x600)
  clipping_range     'near,far' distances from the camera ('' : everything of the grid
                     in front of the camera, as a render view resets its clipping range)
  allow_masked       masked cells may be selected (false)
  preserve_topology  write a masked hypertree grid instead of cells (false)
  format             preserve_topology's grid: vtkhdf, htg or both (both)
  fields             fields Canopy wraps for this script ('' : every field)
  file_prefix        the files' names: <prefix>_<step>.pvtu, <prefix>.pvd, ... ("selection")

Writes, in the output directory (<step>: the time step, 6 digits; <rank>: an MPI rank):
  <prefix>_<step>.pvtu                          the selected cells, listing its pieces,
  <prefix>_<step>/<prefix>_<step>_<rank>.vtu      one per rank that selected cells
  <prefix>.vtkhdf                               preserve_topology, instead (format vtkhdf):
                                                  the masked grid, every step in one file
                                                  (VTK 9.5+: ParaView 6.0 and later)
  <prefix>.pvd                                  preserve_topology (format htg): the masked
                                                  grid's steps (ParaView 5.11: open this),
  <prefix>_<step>.vtm                             one step, listing its pieces,
  <prefix>_<step>/<prefix>_<step>_<rank>.htg      one per rank
"""
import canopy_catalyst as canopy

settings = canopy.settings(selection="points", points="", ids="", value_field="",
                           value_component=0, value_range="", box="", frustum="",
                           camera_position="", camera_focal_point="", camera_view_up="",
                           parallel_scale=0.0, view_angle=30.0, image_size="800x600",
                           clipping_range="", allow_masked=False, preserve_topology=False,
                           format="both", file_prefix="selection")
options = canopy.catalyst_options(settings)
canopy.load_canopy_plugin(globals())

MODES = {"points": "Locations", "ids": "Ids", "range": "Value Range", "box": "Box",
         "frustum": "Frustum"}
if settings.selection not in MODES:
    raise ValueError("selection must be one of %s, not %r" % (", ".join(MODES), settings.selection))
points = settings.list("points", float)
if len(points) % 3 != 0:
    raise ValueError("points must be x,y,z triples; got %d numbers" % len(points))
value_range = settings.list("value_range", float)
if settings.selection == "range" and (len(value_range) != 2 or not settings.value_field):
    raise ValueError("selection=range needs value_field and value_range=low,high")
box = settings.list("box", float)
if settings.selection == "box" and len(box) != 6:
    raise ValueError("selection=box needs box=xmin,xmax,ymin,ymax,zmin,zmax; got %d numbers"
                     % len(box))
corners = settings.list("frustum", float)
camera_given = bool(settings.list("camera_position", float))
if settings.selection == "frustum":
    if corners and len(corners) != 24:
        raise ValueError("frustum must be 8 corners x,y,z; got %d numbers" % len(corners))
    if not corners and (not camera_given or len(settings.list("camera_focal_point", float)) != 3):
        raise ValueError("selection=frustum needs frustum=<8 corners> or a camera "
                         "(camera_position and camera_focal_point)")
clipping_range = settings.list("clipping_range", float)
if clipping_range and len(clipping_range) != 2:
    raise ValueError("clipping_range must be near,far; got %d numbers" % len(clipping_range))

grid = canopy.simulation_grid(settings)
selection = CanopyExtractSelection(  # noqa: F821
    Input=grid, SelectionMode=MODES[settings.selection], Locations=points,
    Ids=settings.list("ids", int), ValueArrayName=settings.value_field,
    ValueComponent=settings.value_component, ValueRange=value_range or [0.0, 0.0],
    Box=box or [0.0] * 6, FrustumCorners=corners if settings.selection == "frustum" else [],
    AllowMasked=int(settings.allow_masked), PreserveTopology=int(settings.preserve_topology))


def camera_frustum_planes(grid_bounds):
    """The six planes of the camera the settings give (vtkCamera::GetFrustumPlanes).
    Without a clipping range, near and far enclose this rank's part of the grid:
    everything in front of the camera can be selected."""
    from vtkmodules.vtkRenderingCore import vtkCamera
    camera = vtkCamera()
    camera.SetPosition(settings.list("camera_position", float))
    camera.SetFocalPoint(settings.list("camera_focal_point", float))
    camera.SetViewUp(settings.list("camera_view_up", float) or [0.0, 1.0, 0.0])
    if settings.parallel_scale > 0.0:
        camera.SetParallelProjection(1)
        camera.SetParallelScale(settings.parallel_scale)
    else:
        camera.SetViewAngle(settings.view_angle)
    if clipping_range:
        camera.SetClippingRange(*clipping_range)
    else:
        position = camera.GetPosition()
        forward = camera.GetDirectionOfProjection()
        depths = [sum((corner[a] - position[a]) * forward[a] for a in range(3))
                  for corner in ([grid_bounds[i], grid_bounds[2 + j], grid_bounds[4 + k]]
                                 for i in (0, 1) for j in (0, 1) for k in (0, 1))]
        far = max(depths)
        if far <= 0.0:
            far = 1.0  # the grid is behind the camera: nothing to select anyway
        span = far - max(min(depths), 0.0)
        near = max(min(depths) - 0.01 * span, 1e-6 * far)
        camera.SetClippingRange(near, far + 0.01 * span + 1e-6 * far)
    width, height = canopy.image_size(settings)
    planes = [0.0] * 24
    camera.GetFrustumPlanes(width / height, planes)
    return planes


camera_frustum = settings.selection == "frustum" and not corners
writers = []
if settings.preserve_topology:
    # Canopy's grid writers: ParaView's own HTG extractor writes a .phtg whose
    # reader crashes ParaView 5.11 (docs/insitu.md).
    writers = canopy.grid_writers(selection, settings)
else:
    canopy.data_extractor("VTU", selection, "selection_data",
                          settings.file_prefix + "_{timestep:06d}.pvtu", settings)


@canopy.collective
def update_camera_frustum():
    # Each step: near and far follow the grid (local bounds, no collective call).
    bounds = grid.GetClientSideObject().GetOutputDataObject(0).GetBounds()
    if bounds[0] > bounds[1]:
        bounds = [0.0, 1.0, 0.0, 1.0, 0.0, 1.0]  # a rank without trees
    selection.FrustumPlanes = camera_frustum_planes(bounds)


def catalyst_execute(info):
    if camera_frustum:
        update_camera_frustum()
    # Collective: every rank writes its piece; a failure raises on every rank.
    canopy.write_grid(writers, info)


def RequestDataDescription(datadescription):
    canopy.request_fields(datadescription, settings, extra=[settings.value_field])

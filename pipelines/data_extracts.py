# script-version: 2
"""Canopy pipeline: data extracts of the whole grid: the hypertree grid itself,
in the form current ParaView reads (VTKHDF, one file for the run) and/or the
form ParaView 5.11 reads (a .pvd series of .htg pieces), and the
view-independent adaptive surface (.pvtp, with .vtp pieces: the grid's exposed
boundary at full resolution, 2D: every visible leaf).

Settings (defaults; environment CANOPY_<NAME>; script arguments --name=value):
  frequency, start
               run at steps start, start + frequency, ... (1, 0)
  grid         write the grid (true)
  format       the grid's form: vtkhdf, htg or both (both)
  surface      write the surface (true)
  fields       fields Canopy wraps for this script, and the grid's fields ('' : every field)
  file_prefix  the files' names: <prefix>.vtkhdf, <prefix>.pvd, <prefix>_surface_<step>.pvtp ("grid")

Writes, in the output directory (<step>: the time step, 6 digits; <rank>: an MPI rank):
  <prefix>.vtkhdf                               vtkhdf: the grid, every step in one file
                                                  (VTK 9.5+: ParaView 6.0 and later)
  <prefix>.pvd                                  htg: the grid's steps as one time series
                                                  (ParaView 5.11: open this),
  <prefix>_<step>.vtm                             one step, listing its pieces,
  <prefix>_<step>/<prefix>_<step>_<rank>.htg      one per rank, vectors included
  <prefix>_surface_<step>.pvtp                  surface: the surface, listing its pieces,
  <prefix>_surface_<step>/<prefix>_surface_<step>_<rank>.vtp
                                                  one per rank with faces

A grid write that fails on any rank (disk full, unwritable folder, HDF5 error)
raises on every rank, naming each rank's problem and the step: the driver
reports it and every rank skips the step; the VTKHDF file keeps its earlier steps.
"""
import canopy_catalyst as canopy

settings = canopy.settings(grid=True, format="both", surface=True, file_prefix="grid")
options = canopy.catalyst_options(settings)
canopy.load_canopy_plugin(globals())

grid = canopy.simulation_grid(settings)

writers = canopy.grid_writers(grid, settings) if settings.grid else []

if settings.surface:
    surface = CanopyAdaptiveSurface(Input=grid, ViewDependent=0,  # noqa: F821
                                    Fields=settings.list("fields"))
    canopy.data_extractor("VTP", surface, "grid_surface",
                          settings.file_prefix + "_surface_{timestep:06d}.pvtp", settings)


def RequestDataDescription(datadescription):
    canopy.request_fields(datadescription, settings)


def catalyst_execute(info):
    # Collective: every rank writes its piece; a failure raises on every rank.
    canopy.write_grid(writers, info)

# script-version: 2
"""Canopy pipeline: data extracts of the whole grid: the hypertree grid itself
(.phtg, with one .htg piece per rank) and the view-independent adaptive surface
(.pvtp, with .vtp pieces: the grid's exposed boundary at full resolution, 2D:
every visible leaf).

Settings (defaults; environment CANOPY_<NAME>; script arguments --name=value):
  frequency    run every N steps (1)
  htg          write the grid (true)
  surface      write the surface (true)
  fields       fields Canopy wraps for this script ('' : every field)
  file_prefix  the files' names: <prefix>_<step>.phtg, <prefix>_surface_<step>.pvtp ("grid")

Writes, in the output directory (<step>: the time step, 6 digits; <rank>: an MPI rank):
  <prefix>_<step>.phtg                          htg: the grid, listing its pieces,
  <prefix>_<step>/<prefix>_<step>_<rank>.htg      one per rank (open these: ParaView 5.11
                                                  crashes on the .phtg)
  <prefix>_surface_<step>.pvtp                  surface: the surface, listing its pieces,
  <prefix>_surface_<step>/<prefix>_surface_<step>_<rank>.vtp
                                                  one per rank with faces

VTK 9.2's hypertree-grid writer corrupts arrays of more than one component, so
the .htg pieces hold the scalar fields only (vectors are in the surface).
"""
import canopy_catalyst as canopy
from paraview.simple import PassArrays

settings = canopy.settings(htg=True, surface=True, file_prefix="grid")
options = canopy.catalyst_options(settings)
canopy.load_canopy_plugin(globals())

grid = canopy.simulation_grid(settings)

if settings.htg:
    cell_data = grid.GetCellDataInformation()
    scalars = [cell_data.GetArray(i).GetName() for i in range(cell_data.GetNumberOfArrays())
               if cell_data.GetArray(i).GetNumberOfComponents() == 1]
    scalar_grid = PassArrays(Input=grid, CellDataArrays=scalars, PointDataArrays=[],
                             FieldDataArrays=[])
    canopy.data_extractor("HTG", scalar_grid, "grid_htg",
                          settings.file_prefix + "_{timestep:06d}.phtg", settings)

if settings.surface:
    surface = CanopyAdaptiveSurface(Input=grid, ViewDependent=0,  # noqa: F821
                                    Fields=settings.list("fields"))
    canopy.data_extractor("VTP", surface, "grid_surface",
                          settings.file_prefix + "_surface_{timestep:06d}.pvtp", settings)


def RequestDataDescription(datadescription):
    canopy.request_fields(datadescription, settings)

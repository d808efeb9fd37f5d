# script-version: 2
"""Canopy pipeline: cells selected by location, id or value range, written as an
unstructured grid of quads/hexahedra with the cell fields and original ids
(.pvtu), or as a masked hypertree grid (.phtg) with preserve_topology.

Settings (defaults; environment CANOPY_<NAME>; script arguments --name=value):
  frequency          run every N steps (1)
  selection          points | ids | range ("points")
  points             'x,y,z,x,y,z,...' for 'points'
  ids                'i,j,...' global cell ids for 'ids' (a coarse id selects that cell)
  value_field        field for 'range'; value_component: component (-1: magnitude)
  value_range        'low,high' for 'range' (inclusive)
  allow_masked       masked cells may be selected (false)
  preserve_topology  write a masked hypertree grid instead of cells (false)
  fields             fields Canopy wraps for this script ('' : every field)
  file_prefix        the files' names: <prefix>_<step>.pvtu, ... ("selection")

Writes, in the output directory (<step>: the time step, 6 digits; <rank>: an MPI rank):
  <prefix>_<step>.pvtu                          the selected cells, listing its pieces,
  <prefix>_<step>/<prefix>_<step>_<rank>.vtu      one per rank that selected cells
  <prefix>_<step>.phtg                          preserve_topology, instead: the masked grid,
  <prefix>_<step>/<prefix>_<step>_<rank>.htg      one piece per rank (open these: ParaView
                                                  5.11 crashes on the .phtg)
"""
import canopy_catalyst as canopy

settings = canopy.settings(selection="points", points="", ids="", value_field="",
                           value_component=0, value_range="", allow_masked=False,
                           preserve_topology=False, file_prefix="selection")
options = canopy.catalyst_options(settings)
canopy.load_canopy_plugin(globals())

MODES = {"points": "Locations", "ids": "Ids", "range": "Value Range"}
if settings.selection not in MODES:
    raise ValueError("selection must be one of %s, not %r" % (", ".join(MODES), settings.selection))
points = settings.list("points", float)
if len(points) % 3 != 0:
    raise ValueError("points must be x,y,z triples; got %d numbers" % len(points))
value_range = settings.list("value_range", float)
if settings.selection == "range" and (len(value_range) != 2 or not settings.value_field):
    raise ValueError("selection=range needs value_field and value_range=low,high")

grid = canopy.simulation_grid(settings)
selection = CanopyExtractSelection(  # noqa: F821
    Input=grid, SelectionMode=MODES[settings.selection], Locations=points,
    Ids=settings.list("ids", int), ValueArrayName=settings.value_field,
    ValueComponent=settings.value_component, ValueRange=value_range or [0.0, 0.0],
    AllowMasked=int(settings.allow_masked), PreserveTopology=int(settings.preserve_topology))

if settings.preserve_topology:
    canopy.data_extractor("HTG", selection, "selection_data",
                          settings.file_prefix + "_{timestep:06d}.phtg", settings)
else:
    canopy.data_extractor("VTU", selection, "selection_data",
                          settings.file_prefix + "_{timestep:06d}.pvtu", settings)


def RequestDataDescription(datadescription):
    canopy.request_fields(datadescription, settings, extra=[settings.value_field])

# script-version: 2
"""Test pipeline: records each step it runs (ran_<step>.txt and an .htg extract
of the grid), raises at the steps in --fail-steps on the ranks in --fail-ranks
(all, or a rank number), raises at import on --fail-import-rank, and writes
finalized.txt from catalyst_finalize."""
import os

import canopy_catalyst as canopy
from paraview.simple import PassArrays


def my_rank():
    from paraview.modules.vtkRemotingCore import vtkProcessModule
    return vtkProcessModule.GetProcessModule().GetPartitionId()


settings = canopy.settings(fail_steps="", fail_ranks="all", fail_import_rank=-1)
if settings.fail_import_rank == my_rank():
    raise RuntimeError("failing on purpose at import on rank %d" % my_rank())
options = canopy.catalyst_options(settings)
grid = canopy.simulation_grid(settings)
canopy.data_extractor("HTG", PassArrays(Input=grid), "grid_htg", "grid_{timestep:06d}.phtg",
                      settings)




@canopy.collective
def catalyst_execute(info):
    failing_rank = settings.fail_ranks == "all" or int(settings.fail_ranks) == my_rank()
    if info.timestep in settings.list("fail_steps", int) and failing_rank:
        raise RuntimeError("failing on purpose at step %d" % info.timestep)
    with open(os.path.join(settings.output_directory, "ran_%06d.txt" % info.timestep), "w") as out:
        out.write("rank %d\n" % my_rank())


def catalyst_finalize():
    if my_rank() == 0:
        with open(os.path.join(settings.output_directory, "finalized.txt"), "w") as out:
            out.write("finalized\n")

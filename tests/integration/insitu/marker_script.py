# script-version: 2
"""Test pipeline: records each step it runs (ran_<step>.txt and an .htg extract
of the grid) and misbehaves on request, on the ranks in --fail-ranks (all, or a
rank number):
  --fail-steps=S,...     raise in catalyst_execute at these steps
  --exit-steps=S,...     call sys.exit(3) in catalyst_execute at these steps
  --exit-at=import|initialize|finalize   call sys.exit(4) there
  --fail-import-rank=R   raise at import on rank R
catalyst_finalize writes finalized.txt (rank 0)."""
import os
import sys

import canopy_catalyst as canopy
from paraview.simple import PassArrays


def my_rank():
    from paraview.modules.vtkRemotingCore import vtkProcessModule
    return vtkProcessModule.GetProcessModule().GetPartitionId()


settings = canopy.settings(fail_steps="", exit_steps="", exit_at="", fail_ranks="all",
                           fail_import_rank=-1)


def failing_rank():
    return settings.fail_ranks == "all" or int(settings.fail_ranks) == my_rank()


if settings.fail_import_rank == my_rank():
    raise RuntimeError("failing on purpose at import on rank %d" % my_rank())
if settings.exit_at == "import" and failing_rank():
    sys.exit(4)
options = canopy.catalyst_options(settings)
grid = canopy.simulation_grid(settings)
canopy.data_extractor("HTG", PassArrays(Input=grid), "grid_htg", "grid_{timestep:06d}.phtg",
                      settings)


def catalyst_initialize():
    if settings.exit_at == "initialize" and failing_rank():
        sys.exit(4)


@canopy.collective
def catalyst_execute(info):
    if info.timestep in settings.list("fail_steps", int) and failing_rank():
        raise RuntimeError("failing on purpose at step %d" % info.timestep)
    if info.timestep in settings.list("exit_steps", int) and failing_rank():
        sys.exit(3)
    with open(os.path.join(settings.output_directory, "ran_%06d.txt" % info.timestep), "w") as out:
        out.write("rank %d\n" % my_rank())


def catalyst_finalize():
    if settings.exit_at == "finalize" and failing_rank():
        sys.exit(4)
    if my_rank() == 0:
        with open(os.path.join(settings.output_directory, "finalized.txt"), "w") as out:
            out.write("finalized\n")

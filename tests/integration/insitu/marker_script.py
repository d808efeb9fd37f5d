# script-version: 2
"""Test pipeline: records each step it runs (ran_<step>.txt and an .htg extract
of the grid) and misbehaves on request, on the ranks in --fail-ranks (all, or a
rank number):
  --fail-steps=S,...     raise in catalyst_execute at these steps (--fail-message: with
                         this text instead of the default)
  --exit-steps=S,...     call sys.exit(3) in catalyst_execute at these steps
  --exit-at=import|initialize|finalize   call sys.exit(4) there
  --fail-import-rank=R   raise at import on rank R
  --loop-steps=S,...     loop forever in catalyst_execute at these steps
  --loop-at=finalize     loop forever in catalyst_finalize
  --collective=0         catalyst_execute without @canopy.collective
  --collective-call=1    catalyst_execute ends with a collective (a reduction over ranks)
  --record-queries=1     write canopy_catalyst.query_values() to queries_<step>_<rank>.json
catalyst_finalize writes finalized.txt (rank 0)."""
import os
import sys

import canopy_catalyst as canopy
from paraview.simple import PassArrays


def my_rank():
    from paraview.modules.vtkRemotingCore import vtkProcessModule
    return vtkProcessModule.GetProcessModule().GetPartitionId()


settings = canopy.settings(fail_steps="", exit_steps="", exit_at="", fail_ranks="all",
                           fail_import_rank=-1, loop_steps="", loop_at="", collective=True,
                           collective_call=False, fail_message="",
                           record_queries=False)


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


def loop_forever():
    spins = 0
    while True:
        spins += 1


def execute(info):
    if info.timestep in settings.list("fail_steps", int) and failing_rank():
        raise RuntimeError(settings.fail_message or
                           "failing on purpose at step %d on rank %d" % (info.timestep, my_rank()))
    if info.timestep in settings.list("exit_steps", int) and failing_rank():
        sys.exit(3)
    if info.timestep in settings.list("loop_steps", int) and failing_rank():
        loop_forever()
    with open(os.path.join(settings.output_directory, "ran_%06d.txt" % info.timestep), "w") as out:
        out.write("rank %d\n" % my_rank())
    if settings.record_queries:
        import json
        name = "queries_%06d_%d.json" % (info.timestep, my_rank())
        with open(os.path.join(settings.output_directory, name), "w") as out:
            json.dump(canopy.query_values(), out)


if settings.collective:
    execute = canopy.collective(execute)


def catalyst_execute(info):
    execute(info)
    if settings.collective_call:
        canopy._reduce([1.0], "SUM_OP")  # every rank must come: an MPI_Allreduce


def catalyst_finalize():
    if settings.exit_at == "finalize" and failing_rank():
        sys.exit(4)
    if settings.loop_at == "finalize" and failing_rank():
        loop_forever()
    if my_rank() == 0:
        with open(os.path.join(settings.output_directory, "finalized.txt"), "w") as out:
            out.write("finalized\n")

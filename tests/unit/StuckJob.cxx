// Jobs that Canopy must end, run by the in-situ component tests as jobs of their
// own (tests/support/SeparateJob.h), since ending a job ends every rank of it:
//
//   canopy_stuck_job watched-call   one rank whose watched script call never
//                                   returns: StepWatchdog (limit 0.2 s) ends it
//   canopy_stuck_job agreement      two ranks (under mpirun); rank 1 never comes
//                                   to the agreement after a script call:
//                                   CollectiveAgreement (limit 0.2 s, grace 1 s)
//                                   on rank 0 ends it
//
// Either way the job should end with exit code 124 (canopy::stuckJobExitCode)
// and a message naming the rank, the step and the call; exit code 0 means
// nothing ended it within 30 s.
#include "CollectiveAgreement.h"
#include "JobOutput.h"
#include "StepWatchdog.h"

#include <mpi.h>

#include <chrono>
#include <cstdio>
#include <string>
#include <thread>

int main(int argc, char** argv)
{
  MPI_Init(&argc, &argv);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  const std::string scenario = argc > 1 ? argv[1] : "";
  const canopy::JobOutput output;
  const auto forever = std::chrono::seconds(30);
  if (scenario == "watched-call")
  {
    canopy::StepWatchdog watchdog(0.2, rank, MPI_COMM_WORLD, output);
    // No Python here to take a pending call: the interrupt is a signal, which
    // nothing handles (SIGURG is ignored by default).
    watchdog.useSignal(true);
    const auto watch = watchdog.watch("/scripts/stuck.py", "catalyst_execute", "step 4");
    std::this_thread::sleep_for(forever); // in C code, where no interrupt reaches
  }
  else if (scenario == "agreement")
  {
    const canopy::CollectiveAgreement agreement(MPI_COMM_WORLD, output, 0.2, 1.0);
    const canopy::CollectiveAgreement::After after{
        "the script '/scripts/a.py' (catalyst_execute) at step 7", std::chrono::steady_clock::now(),
        0.0};
    if (rank == 1)
    {
      std::this_thread::sleep_for(forever); // never arrives
    }
    agreement.gatherFailures("", &after);
  }
  else
  {
    std::fprintf(stderr, "usage: canopy_stuck_job watched-call|agreement\n");
    MPI_Finalize();
    return 2;
  }
  std::fprintf(stderr, "nothing ended the job\n");
  MPI_Finalize();
  return 0;
}

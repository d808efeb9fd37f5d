// GoogleTest on real MPI ranks: vtkMPIController as VTK's global controller,
// as Catalyst sets it; one report (rank 0's), a failure on any rank fails all.
#include <gtest/gtest.h>
#include <vtkMPIController.h>
#include <vtkMultiProcessController.h>
#include <vtkNew.h>

int main(int argc, char** argv)
{
  vtkNew<vtkMPIController> controller;
  controller->Initialize(&argc, &argv);
  vtkMultiProcessController::SetGlobalController(controller);
  ::testing::InitGoogleTest(&argc, argv);
  if (controller->GetLocalProcessId() != 0)
  {
    // One report: rank 0's (it checks; the others only take part).
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
  }
  const int failed = RUN_ALL_TESTS();
  int anyFailed = failed;
  controller->AllReduce(&failed, &anyFailed, 1, vtkCommunicator::MAX_OP);
  vtkMultiProcessController::SetGlobalController(nullptr);
  controller->Finalize();
  return anyFailed;
}

// Runs a ParaView 5.9+ (V2) Catalyst Python script through ParaView 5.11's
// legacy Catalyst API on paper case A built by Canopy; the script loads the
// Canopy plugin with LoadPlugin and runs both filters. It writes what it saw to
// a file, which this program checks. Usage: canopy_catalyst_plugin SCRIPT RESULT
#include "DescriptorForest.h"
#include "PaperCaseDefinitions.h"

#include <canopy/HtgBuilder.h>

#include <mpi.h>
#include <vtkCPDataDescription.h>
#include <vtkCPInputDataDescription.h>
#include <vtkCPProcessor.h>
#include <vtkCPPythonScriptV2Pipeline.h>
#include <vtkHyperTreeGrid.h>
#include <vtkNew.h>

#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>

int main(int argc, char** argv)
{
  if (argc != 3)
  {
    std::cerr << "usage: canopy_catalyst_plugin SCRIPT RESULT\n";
    return 2;
  }
  MPI_Init(&argc, &argv);
  std::remove(argv[2]); // a result left by an earlier run must not count
  int status = 1;
  {
    canopy::testing::DescriptorForest forest(canopy::testing::paperCaseA(false));
    auto htg = canopy::buildHyperTreeGrid(forest.description());

    // The processor is destroyed (end of scope) before MPI_Finalize.
    vtkNew<vtkCPProcessor> processor;
    processor->Initialize();
    vtkNew<vtkCPPythonScriptV2Pipeline> pipeline;
    if (!pipeline->Initialize(argv[1]))
    {
      std::cerr << "cannot load the Catalyst script " << argv[1] << "\n";
    }
    else
    {
      processor->AddPipeline(pipeline);
      vtkNew<vtkCPDataDescription> description;
      description->AddInput("input");
      description->SetTimeData(0.0, 0);
      description->ForceOutputOn();
      if (processor->RequestDataDescription(description) != 0)
      {
        description->GetInputDescriptionByName("input")->SetGrid(htg);
        processor->CoProcess(description);
      }
      std::ifstream result(argv[2]);
      std::string line;
      std::getline(result, line);
      std::cout << "Catalyst script reported: " << line << "\n";
      status = line == "surface 75 selection 3" ? 0 : 1;
    }
    processor->Finalize();
  }
  MPI_Finalize();
  return status;
}

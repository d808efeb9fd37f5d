// Selection by location and by id: Canopy's filter against the best route
// ParaView 5.11's VTK offers (vtkHyperTreeGridToUnstructuredGrid, then
// vtkExtractSelection), in one run, on 2D forests of 1e5 to 1e7 cells.
//
// Usage: canopy_bench_selection [--max-level L] [--csv FILE]
#include "ForestFingerprint.h"
#include "SyntheticForest.h"

#include <canopy/HtgBuilder.h>
#include <canopy/filters/vtkCanopyExtractSelection.h>

#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkExtractSelection.h>
#include <vtkHyperTreeGrid.h>
#include <vtkHyperTreeGridToUnstructuredGrid.h>
#include <vtkIdTypeArray.h>
#include <vtkSelection.h>
#include <vtkSelectionNode.h>
#include <vtkUnstructuredGrid.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <random>

namespace
{

using Clock = std::chrono::steady_clock;

double since(Clock::time_point t)
{
  return std::chrono::duration<double>(Clock::now() - t).count();
}

vtkIdType cellsOf(vtkDataObject* o)
{
  auto* ug = vtkUnstructuredGrid::SafeDownCast(o);
  return ug ? ug->GetNumberOfCells() : -1;
}

} // namespace

int main(int argc, char** argv)
{
  int maxLevel = 10;
  std::string csvPath;
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    if (arg == "--max-level" && i + 1 < argc)
      maxLevel = std::atoi(argv[++i]);
    else if (arg == "--csv" && i + 1 < argc)
      csvPath = argv[++i];
    else
    {
      std::cerr << "usage: canopy_bench_selection [--max-level L] [--csv FILE]\n";
      return 2;
    }
  }
  std::ofstream csv;
  if (!csvPath.empty())
  {
    csv.open(csvPath);
    csv << "cells,mode,k,canopy_s,upstream_convert_s,upstream_extract_s,speedup,canopy_selected,"
           "upstream_selected\n";
  }
  std::cout << "| cells | selection | k | Canopy s | upstream: to unstructured s | upstream: "
               "extract s | speedup | selected (Canopy / upstream) |\n"
            << "|---:|---|---:|---:|---:|---:|---:|---:|\n";
  for (int levels = 6; levels <= maxLevel; levels += 2)
  {
    canopy::tools::SyntheticForestOptions o;
    o.dimension = 2;
    o.rootsPerAxis = 16;
    o.maxLevels = levels;
    o.cutaway = false;
    canopy::tools::SyntheticForest forest(o);
    std::cout << canopy::tools::describeInput("synthetic 2D, 16 roots per axis, " +
                                                  std::to_string(levels) + " levels",
                                              forest.description())
              << std::endl;
    auto htg = canopy::buildHyperTreeGrid(forest.description());
    const vtkIdType cells = htg->GetNumberOfCells();

    auto start = Clock::now();
    vtkNew<vtkHyperTreeGridToUnstructuredGrid> convert;
    convert->SetInputData(htg);
    convert->Update();
    const double convertSeconds = since(start);

    std::mt19937_64 random(levels);
    std::uniform_real_distribution<double> coordinate(-0.97, 0.97);
    for (int k : {100, 10000})
    {
      for (int mode : {0, 1})
      {
        vtkNew<vtkCanopyExtractSelection> canopy;
        canopy->SetInputData(htg);
        vtkNew<vtkSelectionNode> node;
        node->SetFieldType(vtkSelectionNode::CELL);
        if (mode == 0)
        {
          canopy->SetSelectionMode(vtkCanopyExtractSelection::LOCATIONS);
          vtkNew<vtkDoubleArray> points;
          points->SetNumberOfComponents(3);
          for (int i = 0; i < k; ++i)
          {
            const double x = coordinate(random);
            const double y = coordinate(random);
            canopy->AddLocation(x, y, 0);
            points->InsertNextTuple3(x, y, 0);
          }
          node->SetContentType(vtkSelectionNode::LOCATIONS);
          node->SetSelectionList(points);
        }
        else
        {
          canopy->SetSelectionMode(vtkCanopyExtractSelection::IDS);
          vtkNew<vtkIdTypeArray> ids;
          std::uniform_int_distribution<vtkIdType> id(0, cells - 1);
          for (int i = 0; i < k; ++i)
          {
            const vtkIdType v = id(random);
            canopy->AddId(v);
            ids->InsertNextValue(v);
          }
          // The unstructured grid has no hypertree global ids: its cells are the
          // leaves in traversal order, so upstream selects by its own indices.
          node->SetContentType(vtkSelectionNode::INDICES);
          node->SetSelectionList(ids);
        }
        start = Clock::now();
        canopy->Update();
        const double canopySeconds = since(start);

        vtkNew<vtkSelection> selection;
        selection->AddNode(node);
        vtkNew<vtkExtractSelection> extract;
        extract->SetInputConnection(0, convert->GetOutputPort());
        extract->SetInputData(1, selection);
        start = Clock::now();
        extract->Update();
        const double extractSeconds = since(start);

        const double upstream = convertSeconds + extractSeconds;
        const char* name = mode == 0 ? "location" : "id";
        std::cout << std::fixed << std::setprecision(4) << "| " << cells << " | " << name << " | "
                  << k << " | " << canopySeconds << " | " << convertSeconds << " | "
                  << extractSeconds << " | " << std::setprecision(0) << upstream / canopySeconds
                  << "x | " << cellsOf(canopy->GetOutput()) << " / "
                  << cellsOf(extract->GetOutput()) << " |" << std::endl;
        if (csv)
        {
          csv << cells << "," << name << "," << k << "," << canopySeconds << "," << convertSeconds
              << "," << extractSeconds << "," << upstream / canopySeconds << ","
              << cellsOf(canopy->GetOutput()) << "," << cellsOf(extract->GetOutput()) << "\n";
        }
      }
    }
  }
  return 0;
}

// Builds a 2 x 1 forest through the installed headers and library and checks
// the grid it gets back. Exit code 0 on success.
#include <canopy/HtgBuilder.h>

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkHyperTreeGrid.h>

#include <cstdint>
#include <iostream>
#include <vector>

int main()
{
  const std::vector<double> x{0.0, 1.0, 2.0}, y{0.0, 1.0}, z{0.0};
  // Tree 0 refined once (5 nodes), tree 1 a single leaf.
  const std::vector<std::uint8_t> refined0{1, 0, 0, 0, 0}, refined1{0};
  const std::vector<double> density{1.0, 2.0, 3.0, 4.0, 5.0, 6.0};

  canopy::ForestDescription forest;
  forest.dimension = 2;
  forest.branchFactor = 2;
  forest.maxLevels = 2;
  forest.rootGrid = {x.data(), y.data(), z.data(), x.size(), y.size(), z.size()};
  forest.trees.push_back({0, refined0.data(), refined0.size(), nullptr, nullptr});
  forest.trees.push_back({1, refined1.data(), refined1.size(), nullptr, nullptr});
  forest.fields.push_back(canopy::FieldDescription::aos("density", density.data(), density.size()));

  vtkSmartPointer<vtkHyperTreeGrid> htg = canopy::buildHyperTreeGrid(forest);
  vtkDataArray* array = htg->GetCellData()->GetArray("density");
  const bool ok = htg->GetNumberOfCells() == 6 && array != nullptr &&
                  array->GetVoidPointer(0) == static_cast<const void*>(density.data());
  std::cout << (ok ? "consumer: ok" : "consumer: FAILED") << std::endl;
  return ok ? 0 : 1;
}

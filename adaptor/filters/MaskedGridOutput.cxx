#include "MaskedGridOutput.h"

#include "PureMask.h"

#include <vtkBitArray.h>
#include <vtkCellData.h>
#include <vtkFieldData.h>
#include <vtkHyperTree.h>
#include <vtkHyperTreeGrid.h>

namespace canopy
{

void shareWithMask(vtkHyperTreeGrid* input, vtkHyperTreeGrid* output, vtkBitArray* mask,
                   vtkBitArray* pure)
{
  output->Initialize();
  output->CopyEmptyStructure(input);
  vtkHyperTreeGrid::vtkHyperTreeGridIterator it;
  input->InitializeTreeIterator(it);
  vtkIdType index = 0;
  while (vtkHyperTree* tree = it.GetNextTree(index))
  {
    output->SetTree(index, tree); // the same tree, shared
  }
  output->GetCellData()->ShallowCopy(input->GetCellData());
  output->GetFieldData()->ShallowCopy(input->GetFieldData());
  output->SetMask(mask);
  if (!output->GetHasInterface())
  {
    setPureMask(output, pure); // what ShallowCopy and ParaView would ask VTK to compute
  }
}

} // namespace canopy

#include "GatherTuples.h"

#include <vtkAOSDataArrayTemplate.h>
#include <vtkDataArray.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkSMPTools.h>

#include <cstring>

namespace canopy
{

vtkSmartPointer<vtkDataArray> gatherTuples(vtkDataArray* source, const vtkIdType* ids,
                                           vtkIdType count, vtkSmartPointer<vtkDataArray> out)
{
  if (!out)
  {
    out = vtkSmartPointer<vtkDataArray>::Take(vtkDataArray::CreateDataArray(source->GetDataType()));
  }
  const int nc = source->GetNumberOfComponents();
  out->SetName(source->GetName());
  out->SetNumberOfComponents(nc);
  out->SetNumberOfTuples(count);
  switch (source->GetDataType())
  {
    vtkTemplateMacro({
      auto* to = static_cast<VTK_TT*>(out->GetVoidPointer(0));
      if (auto* aos = vtkAOSDataArrayTemplate<VTK_TT>::FastDownCast(source))
      {
        const VTK_TT* from = aos->GetPointer(0);
        const std::size_t tupleBytes = sizeof(VTK_TT) * static_cast<std::size_t>(nc);
        vtkSMPTools::For(0, count,
                         [&](vtkIdType begin, vtkIdType end)
                         {
                           for (vtkIdType i = begin; i < end; ++i)
                           {
                             std::memcpy(to + i * nc, from + ids[i] * nc, tupleBytes);
                           }
                         });
      }
      else
      {
        // Through the source's own GetTuples: typed for VTK's array classes (its
        // dispatch) and for Canopy's simulation arrays (their override), a
        // virtual call per value only for arrays neither knows.
        vtkNew<vtkIdList> list;
        list->SetArray(const_cast<vtkIdType*>(ids), count, /*save=*/true);
        source->GetTuples(list, out);
        list->Release(); // the ids stay the caller's
      }
    });
  default:
    for (vtkIdType i = 0; i < count; ++i)
    {
      for (int c = 0; c < nc; ++c)
      {
        out->SetComponent(i, c, source->GetComponent(ids[i], c));
      }
    }
  }
  return out;
}

} // namespace canopy

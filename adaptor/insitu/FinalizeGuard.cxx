#include "FinalizeGuard.h"

namespace canopy
{

FinalizeGuard::FinalizeGuard(std::function<void()> onFinalize) : OnFinalize(std::move(onFinalize))
{
  if (MPI_Comm_create_keyval(MPI_COMM_NULL_COPY_FN, &FinalizeGuard::onDelete, &this->Keyval,
                             nullptr) == MPI_SUCCESS &&
      MPI_Comm_set_attr(MPI_COMM_SELF, this->Keyval, this) == MPI_SUCCESS)
  {
    this->Armed = true;
  }
}

FinalizeGuard::~FinalizeGuard()
{
  this->disarm();
}

void FinalizeGuard::disarm()
{
  if (!this->Armed)
  {
    return;
  }
  this->Armed = false;
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (!finalized)
  {
    // Deleting the attribute calls onDelete, which sees the guard disarmed.
    MPI_Comm_delete_attr(MPI_COMM_SELF, this->Keyval);
    MPI_Comm_free_keyval(&this->Keyval);
  }
}

int FinalizeGuard::onDelete(MPI_Comm, int keyval, void* attribute, void*)
{
  auto* guard = static_cast<FinalizeGuard*>(attribute);
  if (guard->Armed)
  {
    guard->Armed = false;
    guard->OnFinalize();
    // Inside MPI_Finalize: disarm() will not free the keyval once MPI is gone, so
    // free it here (MPI frees it when this deletion ends). Found by LeakSanitizer
    // (insitu.sanitizers.planted_leak_at_finalize_reported).
    MPI_Comm_free_keyval(&keyval);
  }
  return MPI_SUCCESS;
}

} // namespace canopy

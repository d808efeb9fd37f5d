// Closes an in-situ driver from inside MPI_Finalize if the simulation forgot
// to: MPI deletes the attributes of MPI_COMM_SELF first thing in MPI_Finalize,
// while MPI still works, and Catalyst must be finalized before MPI is gone.
#pragma once

#include <mpi.h>

#include <functional>

namespace canopy
{

class FinalizeGuard
{
public:
  /// Arms the guard: `onFinalize` runs at MPI_Finalize unless disarmed first.
  explicit FinalizeGuard(std::function<void()> onFinalize);
  /// Disarms (if MPI is still initialized).
  ~FinalizeGuard();
  FinalizeGuard(const FinalizeGuard&) = delete;
  FinalizeGuard& operator=(const FinalizeGuard&) = delete;

  /// Disarms without running the callback. Safe to call twice.
  void disarm();

private:
  static int onDelete(MPI_Comm comm, int keyval, void* attribute, void* extra);
  std::function<void()> OnFinalize;
  int Keyval = -1;
  bool Armed = false;
};

} // namespace canopy

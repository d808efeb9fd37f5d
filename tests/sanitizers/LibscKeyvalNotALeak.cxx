// Sanitizer builds only (CANOPY_SANITIZE, see adaptor/p4est/CMakeLists.txt):
// libsc's sc_init makes an MPI keyval (sc_mpi_comm_attach_node_comms ->
// MPI_Comm_create_keyval) and never frees it. Under the fast unwinder its
// allocation stack stops inside libmpi at a frame without a symbol
// (libmpi.so.40+0x2ca14), which no suppression can name without naming libmpi
// as a whole, and that would also hide a leak in Canopy's code run from
// MPI_Finalize (docs/testing.md, "Suppressions"). So this MPI_Comm_create_keyval
// takes the place of OpenMPI's for the process (libcanopy_p4est is loaded
// before libmpi by every program that runs p4est) and tells LeakSanitizer to
// ignore what it allocates, only when libsc is the caller: Canopy's own keyval
// (FinalizeGuard) stays checked.
#include <mpi.h>

#include <dlfcn.h>
#include <sanitizer/lsan_interface.h>

#include <cstring>

namespace
{

bool calledFromLibsc(void* returnAddress)
{
  Dl_info info{};
  if (dladdr(returnAddress, &info) == 0 || info.dli_fname == nullptr)
  {
    return false;
  }
  const char* slash = std::strrchr(info.dli_fname, '/');
  const char* name = slash ? slash + 1 : info.dli_fname;
  return std::strncmp(name, "libsc-", 6) == 0 || std::strncmp(name, "libsc.", 6) == 0;
}

} // namespace

extern "C" int MPI_Comm_create_keyval(MPI_Comm_copy_attr_function* copy,
                                      MPI_Comm_delete_attr_function* remove, int* keyval,
                                      void* extraState)
{
  if (!calledFromLibsc(__builtin_return_address(0)))
  {
    return PMPI_Comm_create_keyval(copy, remove, keyval, extraState);
  }
  __lsan::ScopedDisabler libscKeepsItForTheProcess;
  return PMPI_Comm_create_keyval(copy, remove, keyval, extraState);
}

// A communicator of Canopy's own: a duplicate of the simulation's, freed with
// this object (unless MPI is already finalized).
#pragma once

#include <mpi.h>

namespace canopy
{

class OwnCommunicator
{
public:
  explicit OwnCommunicator(MPI_Comm parent) { MPI_Comm_dup(parent, &this->Handle); }
  ~OwnCommunicator()
  {
    int finalized = 0;
    MPI_Finalized(&finalized);
    if (!finalized)
    {
      MPI_Comm_free(&this->Handle);
    }
  }
  OwnCommunicator(const OwnCommunicator&) = delete;
  OwnCommunicator& operator=(const OwnCommunicator&) = delete;

  MPI_Comm get() const { return Handle; }

private:
  MPI_Comm Handle = MPI_COMM_NULL;
};

} // namespace canopy

// Every MPI call that communicates goes through here first (the executable's
// definitions win over libmpi's for the whole process, libcanopy_queries included)
// and is counted, then made through its PMPI_ name.
#include "CountedCollectives.h"

#include <mpi.h>

#include <atomic>

namespace
{
std::atomic<long long> calls{0};
}

long long canopy::testing::mpiCallsMade()
{
  return calls.load();
}

extern "C"
{

  int MPI_Allgather(const void* sendbuf, int sendcount, MPI_Datatype sendtype, void* recvbuf,
                    int recvcount, MPI_Datatype recvtype, MPI_Comm comm)
  {
    ++calls;
    return PMPI_Allgather(sendbuf, sendcount, sendtype, recvbuf, recvcount, recvtype, comm);
  }

  int MPI_Allgatherv(const void* sendbuf, int sendcount, MPI_Datatype sendtype, void* recvbuf,
                     const int recvcounts[], const int displs[], MPI_Datatype recvtype,
                     MPI_Comm comm)
  {
    ++calls;
    return PMPI_Allgatherv(sendbuf, sendcount, sendtype, recvbuf, recvcounts, displs, recvtype,
                           comm);
  }

  int MPI_Allreduce(const void* sendbuf, void* recvbuf, int count, MPI_Datatype datatype, MPI_Op op,
                    MPI_Comm comm)
  {
    ++calls;
    return PMPI_Allreduce(sendbuf, recvbuf, count, datatype, op, comm);
  }

  int MPI_Reduce(const void* sendbuf, void* recvbuf, int count, MPI_Datatype datatype, MPI_Op op,
                 int root, MPI_Comm comm)
  {
    ++calls;
    return PMPI_Reduce(sendbuf, recvbuf, count, datatype, op, root, comm);
  }

  int MPI_Bcast(void* buffer, int count, MPI_Datatype datatype, int root, MPI_Comm comm)
  {
    ++calls;
    return PMPI_Bcast(buffer, count, datatype, root, comm);
  }

  int MPI_Gather(const void* sendbuf, int sendcount, MPI_Datatype sendtype, void* recvbuf,
                 int recvcount, MPI_Datatype recvtype, int root, MPI_Comm comm)
  {
    ++calls;
    return PMPI_Gather(sendbuf, sendcount, sendtype, recvbuf, recvcount, recvtype, root, comm);
  }

  int MPI_Barrier(MPI_Comm comm)
  {
    ++calls;
    return PMPI_Barrier(comm);
  }

  int MPI_Alltoall(const void* sendbuf, int sendcount, MPI_Datatype sendtype, void* recvbuf,
                   int recvcount, MPI_Datatype recvtype, MPI_Comm comm)
  {
    ++calls;
    return PMPI_Alltoall(sendbuf, sendcount, sendtype, recvbuf, recvcount, recvtype, comm);
  }

  int MPI_Send(const void* buf, int count, MPI_Datatype datatype, int dest, int tag, MPI_Comm comm)
  {
    ++calls;
    return PMPI_Send(buf, count, datatype, dest, tag, comm);
  }

  int MPI_Recv(void* buf, int count, MPI_Datatype datatype, int source, int tag, MPI_Comm comm,
               MPI_Status* status)
  {
    ++calls;
    return PMPI_Recv(buf, count, datatype, source, tag, comm, status);
  }

  int MPI_Iallreduce(const void* sendbuf, void* recvbuf, int count, MPI_Datatype datatype,
                     MPI_Op op, MPI_Comm comm, MPI_Request* request)
  {
    ++calls;
    return PMPI_Iallreduce(sendbuf, recvbuf, count, datatype, op, comm, request);
  }

} // extern "C"

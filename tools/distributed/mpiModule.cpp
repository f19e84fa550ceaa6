// SPDX-License-Identifier: Apache-2.0
// libprincipled_mpi.so: the MPI calls of tools/distributed/comm.cpp (see mpiModule.h).
#define OMPI_SKIP_MPICXX 1  // the C API only
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>

#include "tools/distributed/mpiModule.h"

namespace {

void init(int* rank, int* size) {
    MPI_Init(nullptr, nullptr);
    MPI_Comm_rank(MPI_COMM_WORLD, rank);
    MPI_Comm_size(MPI_COMM_WORLD, size);
    // Errors end the job with a message instead of returning codes we would ignore.
    MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_ARE_FATAL);
}

void finalize() { MPI_Finalize(); }

void sendBytes(const void* data, int count, int dest, int tag) {
    MPI_Send(data, count, MPI_BYTE, dest, tag, MPI_COMM_WORLD);
}

void recvBytes(void* data, int count, int src, int tag) {
    MPI_Recv(data, count, MPI_BYTE, src, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
}

void sendInt64(long long v, int dest, int tag) {
    MPI_Send(&v, 1, MPI_LONG_LONG, dest, tag, MPI_COMM_WORLD);
}

long long recvInt64(int src, int tag) {
    long long v = 0;
    MPI_Recv(&v, 1, MPI_LONG_LONG, src, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    return v;
}

int probe(int src, int tag) {
    int flag = 0;
    MPI_Status st;
    MPI_Iprobe(src < 0 ? MPI_ANY_SOURCE : src, tag, MPI_COMM_WORLD, &flag, &st);
    return flag ? st.MPI_SOURCE : -1;
}

void broadcastInt(int* v) { MPI_Bcast(v, 1, MPI_INT, 0, MPI_COMM_WORLD); }

void broadcastChars(char* data, int count) { MPI_Bcast(data, count, MPI_CHAR, 0, MPI_COMM_WORLD); }

void barrier() { MPI_Barrier(MPI_COMM_WORLD); }

void abortJob(int code) { MPI_Abort(MPI_COMM_WORLD, code); }

const PrincipledMpiApi kApi = {PRINCIPLED_MPI_MODULE_VERSION,
                               init,
                               finalize,
                               sendBytes,
                               recvBytes,
                               sendInt64,
                               recvInt64,
                               probe,
                               broadcastInt,
                               broadcastChars,
                               barrier,
                               abortJob};

}  // namespace

extern "C" __attribute__((visibility("default"))) const PrincipledMpiApi* principled_mpi_api() {
    return &kApi;
}

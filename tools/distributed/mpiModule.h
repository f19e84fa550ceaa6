// SPDX-License-Identifier: Apache-2.0
// The MPI calls distributed rendering makes, as a C function table exported by
// libprincipled_mpi.so (tools/distributed/mpiModule.cpp, the only module that links MPI).
// Comm (comm.cpp) dlopen()s it only when an MPI launcher started the process, so an ordinary
// `principled render` does not load Open MPI's libraries (~1 ms of every process start).
#pragma once

extern "C" {

#define PRINCIPLED_MPI_MODULE_VERSION 1

struct PrincipledMpiApi {
    int version;  ///< PRINCIPLED_MPI_MODULE_VERSION
    /// MPI_Init, rank and size of MPI_COMM_WORLD; errors end the job (MPI_ERRORS_ARE_FATAL).
    void (*init)(int* rank, int* size);
    void (*finalize)();
    void (*sendBytes)(const void* data, int count, int dest, int tag);
    void (*recvBytes)(void* data, int count, int src, int tag);
    void (*sendInt64)(long long v, int dest, int tag);
    long long (*recvInt64)(int src, int tag);
    int (*probe)(int src, int tag);  ///< src -1: any; returns the source or -1
    void (*broadcastInt)(int* v);
    void (*broadcastChars)(char* data, int count);
    void (*barrier)();
    void (*abort)(int code);
};

/// The module's entry point.
using PrincipledMpiApiFn = const PrincipledMpiApi* (*)();
}

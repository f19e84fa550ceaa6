// SPDX-License-Identifier: Apache-2.0
#include "tools/distributed/comm.h"

#include <algorithm>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <unistd.h>

#ifdef PRINCIPLED_HAVE_MPI
#define OMPI_SKIP_MPICXX 1  // the C API only
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>
#endif

namespace principled::tools::distributed {

namespace {

constexpr size_t kChunk = size_t(1) << 30;  // MPI counts are int

}  // namespace

// Launchers set these before exec: Open MPI's mpirun, MPICH/Hydra and Slurm PMI.
int Comm::launcherSize() {
    for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})
        if (const char* s = std::getenv(v)) return std::max(1, std::atoi(s));
    return 0;
}

Comm::Comm() {
    char name[256] = {};
    gethostname(name, sizeof name - 1);
    _host = name;
    int launched = launcherSize();
#ifdef PRINCIPLED_HAVE_MPI
    if (launched > 0) {
        MPI_Init(nullptr, nullptr);
        _initialized = true;
        MPI_Comm_rank(MPI_COMM_WORLD, &_rank);
        MPI_Comm_size(MPI_COMM_WORLD, &_size);
        // Errors end the job with a message instead of returning codes we would ignore.
        MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_ARE_FATAL);
    }
#else
    _unsupported = launched > 1;
#endif
}

Comm::~Comm() {
#ifdef PRINCIPLED_HAVE_MPI
    if (_initialized) MPI_Finalize();
#endif
}

#ifdef PRINCIPLED_HAVE_MPI
// Every call is a no-op for a single rank that never initialised MPI.
void Comm::send(int dest, int tag, const std::vector<char>& bytes) {
    if (!_initialized) return;
    for (size_t at = 0; at < bytes.size() || at == 0; at += kChunk) {
        int n = int(std::min(kChunk, bytes.size() - at));
        MPI_Send(bytes.data() + at, n, MPI_BYTE, dest, tag, MPI_COMM_WORLD);
        if (bytes.empty()) break;
    }
}

void Comm::recv(int src, int tag, std::vector<char>& bytes) {
    if (!_initialized) return;
    for (size_t at = 0; at < bytes.size() || at == 0; at += kChunk) {
        int n = int(std::min(kChunk, bytes.size() - at));
        MPI_Recv(bytes.data() + at, n, MPI_BYTE, src, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        if (bytes.empty()) break;
    }
}

void Comm::sendInt64(int dest, int tag, long long v) {
    if (!_initialized) return;
    MPI_Send(&v, 1, MPI_LONG_LONG, dest, tag, MPI_COMM_WORLD);
}

int Comm::probe(int src, int tag) {
    if (!_initialized) return -1;
    int flag = 0;
    MPI_Status st;
    MPI_Iprobe(src < 0 ? MPI_ANY_SOURCE : src, tag, MPI_COMM_WORLD, &flag, &st);
    return flag ? st.MPI_SOURCE : -1;
}

long long Comm::recvInt64(int src, int tag) {
    long long v = 0;
    if (!_initialized) return v;
    MPI_Recv(&v, 1, MPI_LONG_LONG, src, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    return v;
}

void Comm::broadcast(std::string& s) {
    if (!_initialized) return;
    int n = int(s.size());
    MPI_Bcast(&n, 1, MPI_INT, 0, MPI_COMM_WORLD);
    s.resize(size_t(n));
    MPI_Bcast(s.data(), n, MPI_CHAR, 0, MPI_COMM_WORLD);
}

void Comm::broadcast(int& v) {
    if (_initialized) MPI_Bcast(&v, 1, MPI_INT, 0, MPI_COMM_WORLD);
}

void Comm::barrier() {
    if (_initialized) MPI_Barrier(MPI_COMM_WORLD);
}

void Comm::abort(int code) {
    std::fflush(stderr);
    if (_initialized) MPI_Abort(MPI_COMM_WORLD, code);
    std::_Exit(code);
}
#else
// A single rank never sends or receives.
void Comm::send(int, int, const std::vector<char>&) {}
void Comm::recv(int, int, std::vector<char>&) {}
void Comm::sendInt64(int, int, long long) {}
int Comm::probe(int, int) { return -1; }
long long Comm::recvInt64(int, int) { return 0; }
void Comm::broadcast(std::string&) {}
void Comm::broadcast(int&) {}
void Comm::barrier() {}
void Comm::abort(int code) {
    std::fflush(stderr);
    std::_Exit(code);
}
#endif

}  // namespace principled::tools::distributed

// SPDX-License-Identifier: Apache-2.0
#include "tools/distributed/comm.h"

#include <algorithm>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <unistd.h>

#ifdef PRINCIPLED_HAVE_MPI
#include <dlfcn.h>

#include <filesystem>
#endif

#include "tools/distributed/mpiModule.h"

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

#ifdef PRINCIPLED_HAVE_MPI
namespace {

// libprincipled_mpi.so: $PRINCIPLED_MPI_MODULE, <exe>/../lib/, the build tree, the install
// prefix, then the default dlopen search. RTLD_GLOBAL: Open MPI's own components may expect
// libmpi's symbols to be global.
const PrincipledMpiApi* loadMpi(std::string* error) {
    namespace fs = std::filesystem;
    constexpr const char* kModule = "libprincipled_mpi.so";
    std::vector<std::string> names;
    if (const char* env = std::getenv("PRINCIPLED_MPI_MODULE"); env && *env) {
        names.push_back(env);
    } else {
        std::error_code ec;
        fs::path exe = fs::read_symlink("/proc/self/exe", ec);
        if (!ec) names.push_back((exe.parent_path() / ".." / "lib" / kModule).string());
#ifdef PRINCIPLED_MPI_BUILD_DIR
        names.push_back(std::string(PRINCIPLED_MPI_BUILD_DIR) + "/" + kModule);
#endif
#ifdef PRINCIPLED_MPI_INSTALL_DIR
        names.push_back(std::string(PRINCIPLED_MPI_INSTALL_DIR) + "/" + kModule);
#endif
        names.push_back(kModule);
    }
    std::string tried;
    for (const auto& n : names) {
        void* h = dlopen(n.c_str(), RTLD_NOW | RTLD_GLOBAL);
        if (!h) {
            const char* e = dlerror();
            tried += "\n  " + n + ": " + (e ? e : "cannot be loaded");
            continue;
        }
        auto entry = reinterpret_cast<PrincipledMpiApiFn>(dlsym(h, "principled_mpi_api"));
        const PrincipledMpiApi* api = entry ? entry() : nullptr;
        if (api && api->version == PRINCIPLED_MPI_MODULE_VERSION) return api;
        tried += "\n  " + n + ": not a principled MPI module of version " +
                 std::to_string(PRINCIPLED_MPI_MODULE_VERSION);
    }
    *error = std::string("started by an MPI launcher, but cannot load ") + kModule +
             " (set PRINCIPLED_MPI_MODULE to its path). Tried:" + tried;
    return nullptr;
}

}  // namespace
#endif

Comm::Comm() {
    char name[256] = {};
    gethostname(name, sizeof name - 1);
    _host = name;
    int launched = launcherSize();
#ifdef PRINCIPLED_HAVE_MPI
    if (launched > 0) {
        _mpi = loadMpi(&_loadError);
        if (_mpi) {
            _mpi->init(&_rank, &_size);
            _initialized = true;
        }
    }
#else
    _unsupported = launched > 1;
#endif
}

Comm::~Comm() {
    if (_initialized) _mpi->finalize();
}

// Every call is a no-op for a single rank that never initialised MPI.
void Comm::send(int dest, int tag, const std::vector<char>& bytes) {
    if (!_initialized) return;
    for (size_t at = 0; at < bytes.size() || at == 0; at += kChunk) {
        int n = int(std::min(kChunk, bytes.size() - at));
        _mpi->sendBytes(bytes.data() + at, n, dest, tag);
        if (bytes.empty()) break;
    }
}

void Comm::recv(int src, int tag, std::vector<char>& bytes) {
    if (!_initialized) return;
    for (size_t at = 0; at < bytes.size() || at == 0; at += kChunk) {
        int n = int(std::min(kChunk, bytes.size() - at));
        _mpi->recvBytes(bytes.data() + at, n, src, tag);
        if (bytes.empty()) break;
    }
}

void Comm::sendInt64(int dest, int tag, long long v) {
    if (_initialized) _mpi->sendInt64(v, dest, tag);
}

int Comm::probe(int src, int tag) {
    return _initialized ? _mpi->probe(src, tag) : -1;
}

long long Comm::recvInt64(int src, int tag) {
    return _initialized ? _mpi->recvInt64(src, tag) : 0;
}

void Comm::broadcast(std::string& s) {
    if (!_initialized) return;
    int n = int(s.size());
    _mpi->broadcastInt(&n);
    s.resize(size_t(n));
    _mpi->broadcastChars(s.data(), n);
}

void Comm::broadcast(int& v) {
    if (_initialized) _mpi->broadcastInt(&v);
}

void Comm::barrier() {
    if (_initialized) _mpi->barrier();
}

void Comm::abort(int code) {
    std::fflush(stderr);
    if (_initialized) _mpi->abort(code);
    std::_Exit(code);
}

}  // namespace principled::tools::distributed

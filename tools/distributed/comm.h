// SPDX-License-Identifier: Apache-2.0
// Comm: the few MPI operations distributed rendering needs, behind a class that is a single
// rank when the binary was built without MPI or was not started by mpirun (so the ordinary
// `principled render` never initialises MPI). MPI itself is in libprincipled_mpi.so, loaded
// only when a launcher started the process (tools/distributed/mpiModule.h).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

struct PrincipledMpiApi;  // tools/distributed/mpiModule.h

namespace principled::tools::distributed {

class Comm {
public:
    enum Tag { kProgress = 1, kData = 2, kDone = 3 };

    /// Initialises MPI only when a launcher (mpirun/srun) started this process.
    Comm();
    ~Comm();
    Comm(const Comm&) = delete;
    Comm& operator=(const Comm&) = delete;

    /// Ranks an MPI launcher announced in the environment (0: not launched by one).
    static int launcherSize();

    int rank() const { return _rank; }
    int size() const { return _size; }
    bool distributed() const { return _size > 1; }
    const std::string& host() const { return _host; }
    /// True when a launcher says there are several ranks but MPI support is not compiled in.
    bool launchedWithoutSupport() const { return _unsupported; }
    /// Why libprincipled_mpi.so could not be loaded for a launched process (empty: fine).
    const std::string& loadError() const { return _loadError; }

    void send(int dest, int tag, const std::vector<char>& bytes);
    /// Receives a message of known size (chunked like send).
    void recv(int src, int tag, std::vector<char>& bytes);
    void sendInt64(int dest, int tag, long long v);
    /// Non-blocking check for a message (src -1: any) with tag; returns its source or -1.
    int probe(int src, int tag);
    long long recvInt64(int src, int tag);
    /// Rank 0's value to everyone.
    void broadcast(std::string& s);
    void broadcast(int& v);
    void barrier();
    /// Ends every rank of the job with this exit code.
    [[noreturn]] void abort(int code);

private:
    int _rank = 0, _size = 1;
    bool _initialized = false, _unsupported = false;
    std::string _host, _loadError;
    const ::PrincipledMpiApi* _mpi = nullptr;  ///< set when MPI is initialised
};

}  // namespace principled::tools::distributed

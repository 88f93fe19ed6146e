#include "hexmesh/pipeline/ranks.h"

#include <algorithm>
#include <cstdlib>
#include <new>
#include <stdexcept>

#ifdef HEXMESH_MPI
#include <mpi.h>
#endif

namespace hexmesh::ranks {
namespace {

int rank_ = 0, size_ = 1;

// The process count the launcher announced (1 when none did).
int launched_size() {
    for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE"})
        if (const char* v = std::getenv(name)) return std::max(1, std::atoi(v));
    return 1;
}

}  // namespace

#ifdef HEXMESH_MPI

namespace {
bool started_ = false;

// MPI counts in int: longer messages go in pieces of 1 GiB.
constexpr size_t piece = size_t(1) << 30;

void send(const std::string& bytes, int to) {
    for (size_t at = 0; at < bytes.size(); at += piece)
        MPI_Send(bytes.data() + at, int(std::min(piece, bytes.size() - at)), MPI_BYTE, to, 0,
                 MPI_COMM_WORLD);
}

void receive(std::string& bytes, int from) {
    for (size_t at = 0; at < bytes.size(); at += piece)
        MPI_Recv(bytes.data() + at, int(std::min(piece, bytes.size() - at)), MPI_BYTE, from, 0,
                 MPI_COMM_WORLD, MPI_STATUS_IGNORE);
}
}  // namespace

Session::Session(int& argc, char**& argv) {
    if (launched_size() <= 1 && !std::getenv("PMIX_RANK")) return;
    int provided = 0;
    MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
    started_ = true;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

Session::~Session() {
    if (started_) MPI_Finalize();
}

std::vector<std::string> gather(const std::string& bytes) {
    if (!started_) return {bytes};
    const long long mine = static_cast<long long>(bytes.size());
    std::vector<long long> lengths(static_cast<size_t>(size_));
    MPI_Gather(&mine, 1, MPI_LONG_LONG, lengths.data(), 1, MPI_LONG_LONG, 0, MPI_COMM_WORLD);
    // Rank by rank, in pieces within MPI's int counts, not one MPI_Gatherv.
    std::vector<std::string> out;
    if (rank_ == 0) {
        out.resize(size_t(size_));
        out[0] = bytes;
        for (int r = 1; r < size_; ++r) {
            out[size_t(r)].resize(size_t(lengths[size_t(r)]));
            receive(out[size_t(r)], r);
        }
    } else {
        send(bytes, 0);
    }
    return out;
}

std::string broadcast(const std::string& bytes) {
    if (!started_) return bytes;
    long long length = static_cast<long long>(bytes.size());
    MPI_Bcast(&length, 1, MPI_LONG_LONG, 0, MPI_COMM_WORLD);
    std::string out = rank_ == 0 ? bytes : std::string(size_t(length), '\0');
    for (size_t at = 0; at < out.size(); at += piece)
        MPI_Bcast(out.data() + at, int(std::min(piece, out.size() - at)), MPI_BYTE, 0,
                  MPI_COMM_WORLD);
    return out;
}

std::vector<double> max(std::vector<double> values) {
    if (!started_) return values;
    std::vector<double> out(values.size());
    MPI_Allreduce(values.data(), out.data(), int(values.size()), MPI_DOUBLE, MPI_MAX,
                  MPI_COMM_WORLD);
    return out;
}

Id sum(Id n) {
    if (!started_) return n;
    long long mine = n, total = 0;
    MPI_Allreduce(&mine, &total, 1, MPI_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
    return Id(total);
}

#else  // without MPI: one process

Session::Session(int&, char**&) {
    if (launched_size() > 1)
        throw std::runtime_error(
            "this hexmesh was built without MPI, so it cannot run as one of several processes "
            "(mpirun -np N): install libopenmpi-dev and build again, or run it without mpirun");
}
Session::~Session() = default;
std::vector<std::string> gather(const std::string& bytes) {
    return {bytes};
}
std::string broadcast(const std::string& bytes) {
    return bytes;
}
Id sum(Id n) {
    return n;
}
std::vector<double> max(std::vector<double> values) {
    return values;
}

#endif

void rethrow_as_own(std::exception_ptr error) {
    try {
        std::rethrow_exception(error);
    } catch (const std::bad_alloc&) {
        throw;
    } catch (const std::exception& e) {
        throw std::runtime_error(e.what());
    }
    throw std::runtime_error("an unknown error");
}

int rank() {
    return rank_;
}
int size() {
    return size_;
}

}  // namespace hexmesh::ranks

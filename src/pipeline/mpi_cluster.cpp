// The cluster of an MPI run (Open MPI): rank 0 hands out work items from a
// thread of its own while it works on items itself; the other ranks ask it for
// their next item when they are ready for one, so a slow rank holds no one up.
#include "pipeline/cluster.h"

#include "core/error.h"
#include "core/interrupt.h"

// The C API only: Debian's Open MPI would otherwise pull in its deprecated
// C++ bindings, which need libmpi_cxx.
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <mutex>
#include <thread>

#include <sched.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <string>
#include <vector>

namespace yv {
namespace {

constexpr int kClaimTag = 1, kItemTag = 2;

/// A fault for the tests of a rank that dies, set only by them:
/// YARNVOX_TEST_KILL_RANK=R:K makes rank R kill itself (SIGKILL, as a crashed
/// node would end) when the hand-out gives it its (K+1)-th item (a region, or
/// a whole garment), so tests can check what the other ranks and --resume
/// make of it. Never set in real runs; unset, it never fires.
struct InjectedFault {
    int rank = -1;
    std::uint64_t dieAtClaim = 0; ///< 1-based claim that kills (0: none)
    static InjectedFault fromEnvironment() {
        InjectedFault fault;
        unsigned long long after = 0;
        if (const char* text = std::getenv("YARNVOX_TEST_KILL_RANK"); text && std::sscanf(text, "%d:%llu", &fault.rank, &after) == 2)
            fault.dieAtClaim = after + 1;
        else
            fault.rank = -1;
        return fault;
    }
};

/// Waits for `request` without spinning: Open MPI's blocking calls poll at
/// full speed, which would take a core from the ranks still rasterizing on
/// the same machine (tests run three ranks on two cores).
void waitPolitely(MPI_Request& request, MPI_Status* status = MPI_STATUS_IGNORE) {
    for (int done = 0;;) {
        MPI_Test(&request, &done, status);
        if (done) return;
        std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
}

/// Watches the ranks on this machine while the run needs them: a rank whose
/// process is gone (SIGKILL, a crash, the OOM killer) before the run ends
/// leaves the others waiting in a collective for ever wherever the launcher
/// does not end them (srun without --kill-on-bad-exit, an mpirun told to
/// keep going). The watcher ends this rank within kPeriod, saying which rank
/// is gone, what is kept and how to go on (core/interrupt.h, stopAtOnce); the
/// launcher then sees a rank fail and ends the rest. Ranks on other machines
/// are left to the launcher, which learns of a lost node from its daemons.
class PeerWatch {
  public:
    static constexpr std::chrono::milliseconds kPeriod{200};

    PeerWatch(MPI_Comm comm, int rank, int size) {
        struct Peer {
            char host[64];
            long pid;
        } mine{};
        ::gethostname(mine.host, sizeof mine.host - 1);
        mine.pid = long(::getpid());
        std::vector<Peer> all(std::size_t(size), Peer{});
        MPI_Allgather(&mine, sizeof mine, MPI_BYTE, all.data(), sizeof mine, MPI_BYTE, comm);
        for (int r = 0; r < size; ++r)
            if (r != rank && std::strncmp(all[std::size_t(r)].host, mine.host, sizeof mine.host) == 0)
                peers_.push_back({r, all[std::size_t(r)].pid});
        if (!peers_.empty()) thread_ = std::thread([this] { watch(); });
    }
    /// Call before MPI_Finalize: past it, a peer may end first and rightly.
    void stop() {
        stopping_ = true;
        if (thread_.joinable()) thread_.join();
    }
    ~PeerWatch() { stop(); }

  private:
    struct Peer {
        int rank;
        long pid;
    };
    void watch() {
        while (!stopping_) {
            for (const Peer& p : peers_)
                if (::kill(pid_t(p.pid), 0) != 0 && errno == ESRCH && !stopping_)
                    stopAtOnce("rank " + std::to_string(p.rank) + " (PID " + std::to_string(p.pid) +
                               ") ended before the run did: stopping");
            std::this_thread::sleep_for(kPeriod);
        }
    }

    std::vector<Peer> peers_;
    std::atomic<bool> stopping_{false};
    std::thread thread_;
};

class MpiCluster : public Cluster {
  public:
    MpiCluster() {
        MPI_Comm_dup(MPI_COMM_WORLD, &comm_);
        MPI_Comm_rank(comm_, &rank_);
        MPI_Comm_size(comm_, &size_);
        MPI_Comm node;
        MPI_Comm_split_type(comm_, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &node);
        MPI_Comm_rank(node, &localRank_);
        MPI_Comm_size(node, &localSize_);
        MPI_Comm_free(&node);
        if (size_ > 1) {
            answerSignalsAtOnce("rank " + std::to_string(rank_) + ": ");
            watch_ = std::make_unique<PeerWatch>(comm_, rank_, size_);
        }
    }
    ~MpiCluster() override {
        if (server_.joinable()) server_.join();
        if (watch_) watch_->stop();
        MPI_Comm_free(&comm_);
    }

    int rank() const override { return rank_; }
    int size() const override { return size_; }
    int localRank() const override { return localRank_; }
    int localSize() const override { return localSize_; }

    std::uint64_t broadcast(std::uint64_t value) override {
        MPI_Request request;
        MPI_Ibcast(&value, 1, MPI_UINT64_T, 0, comm_, &request);
        waitPolitely(request);
        return value;
    }

    void beginHandout(std::uint64_t count) override {
        count_ = count;
        next_ = 0;
        exhausted_ = false;
        if (rank_ == 0 && size_ > 1) server_ = std::thread([this] { serve(); });
    }

    std::optional<std::uint64_t> claim() override {
        const std::optional<std::uint64_t> item = next();
        if (item && ++claimed_ == faults_.dieAtClaim && rank_ == faults_.rank) std::raise(SIGKILL);
        return item;
    }

    std::vector<double> endHandout(const std::vector<double>& values) override {
        while (next()) {
        }
        if (server_.joinable()) server_.join();
        std::vector<double> sums(values.size());
        MPI_Request request;
        MPI_Ireduce(values.data(), sums.data(), static_cast<int>(values.size()), MPI_DOUBLE, MPI_SUM, 0, comm_,
                    &request);
        waitPolitely(request);
        return rank_ == 0 ? sums : values;
    }

    [[noreturn]] void abort(int exitCode) override {
        MPI_Abort(comm_, exitCode);
        std::_Exit(exitCode);
    }

  private:
    /// The next item of the hand-out for this rank, or nothing once all are out.
    std::optional<std::uint64_t> next() {
        if (exhausted_) return std::nullopt;
        std::int64_t item = -1;
        if (rank_ == 0) {
            item = take();
        } else {
            const int ask = 0;
            MPI_Send(&ask, 1, MPI_INT, 0, kClaimTag, comm_);
            MPI_Request request;
            MPI_Irecv(&item, 1, MPI_INT64_T, 0, kItemTag, comm_, &request);
            waitPolitely(request);
        }
        if (item < 0) {
            exhausted_ = true; // rank 0 says "none" to each rank once
            return std::nullopt;
        }
        return static_cast<std::uint64_t>(item);
    }

    /// The next item in order, or -1 once all are out.
    std::int64_t take() {
        const std::lock_guard lock(mutex_);
        return next_ < count_ ? static_cast<std::int64_t>(next_++) : -1;
    }

    /// Rank 0's server: answers every other rank's asks until each has been
    /// told there is nothing left.
    void serve() {
        for (int told = 0; told < size_ - 1;) {
            int ask = 0;
            MPI_Status status;
            MPI_Request request;
            MPI_Irecv(&ask, 1, MPI_INT, MPI_ANY_SOURCE, kClaimTag, comm_, &request);
            waitPolitely(request, &status);
            const std::int64_t item = take();
            MPI_Send(&item, 1, MPI_INT64_T, status.MPI_SOURCE, kItemTag, comm_);
            if (item < 0) ++told;
        }
    }

    MPI_Comm comm_ = MPI_COMM_NULL;
    int rank_ = 0, size_ = 1, localRank_ = 0, localSize_ = 1;
    std::mutex mutex_;
    std::uint64_t count_ = 0, next_ = 0;
    bool exhausted_ = false;
    std::uint64_t claimed_ = 0; ///< items this rank was given, over every hand-out
    InjectedFault faults_ = InjectedFault::fromEnvironment();
    std::thread server_;
    std::unique_ptr<PeerWatch> watch_;
};

std::unique_ptr<MpiCluster> gCluster;

/// Started by mpirun (or srun with PMIx)? Only then is MPI initialised, so a
/// plain run of an MPI build behaves as a build without it.
/// Cores this process may run on, and the machine's.
std::pair<long, long> usableCores() {
    cpu_set_t set;
    CPU_ZERO(&set);
    const long usable = sched_getaffinity(0, sizeof set, &set) == 0 ? CPU_COUNT(&set) : -1;
    return {usable, sysconf(_SC_NPROCESSORS_ONLN)};
}

bool startedByLauncher() {
    for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK"})
        if (std::getenv(name)) return true;
    return false;
}

} // namespace

Cluster* cluster() { return gCluster.get(); }

ClusterScope::ClusterScope(int& argc, char**& argv) {
    if (!startedByLauncher()) return;
    // Rank 0's server thread and its main thread take turns with MPI, never at once.
    int provided = 0;
    MPI_Init_thread(&argc, &argv, MPI_THREAD_SERIALIZED, &provided);
    if (provided < MPI_THREAD_SERIALIZED) {
        MPI_Finalize();
        throw Error("the MPI library offers no MPI_THREAD_SERIALIZED: rank 0 cannot hand out regions while it works");
    }
    gCluster = std::make_unique<MpiCluster>();
    // Open MPI binds each rank to one core when there are two ranks or fewer:
    // a rank's threads (readback, region files, the merge) then share that
    // core, measured 3 to 5 times slower on the H100 machine.
    if (const auto [usable, machine] = usableCores(); usable == 1 && machine > 1)
        std::fprintf(stderr,
                     "yarnvox: warning: rank %d may run on 1 of this machine's %ld cores, so its threads share it; "
                     "start it with mpirun --bind-to none (or --bind-to socket)\n",
                     gCluster->rank(), machine);
}

ClusterScope::~ClusterScope() {
    if (!gCluster) return;
    gCluster.reset();
    MPI_Finalize();
}

bool clusterSupport() { return true; }

} // namespace yv

// The processes of one run started by mpirun (Open MPI), as the pipeline
// needs them: who am I, rank 0's value, and a hand-out of work items in a
// fixed order to whichever rank asks first. Built only with -DYARNVOX_MPI=ON;
// without it, or outside mpirun, there is no cluster and a run is one process.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

namespace yv {

class Cluster {
  public:
    virtual ~Cluster() = default;
    virtual int rank() const = 0;
    virtual int size() const = 0;
    /// Rank among the processes on this node (picks the GPU).
    virtual int localRank() const = 0;
    /// Processes on this node (they share its cores).
    virtual int localSize() const = 0;
    /// Rank 0's `value`, on every rank (collective).
    virtual std::uint64_t broadcast(std::uint64_t value) = 0;
    /// Starts handing out the items 0..count-1, in that order, each to the
    /// first rank that asks (collective). Rank 0 serves from a thread of its
    /// own, so it rasterizes too.
    virtual void beginHandout(std::uint64_t count) = 0;
    /// This rank's next item, or nothing once every item is handed out.
    virtual std::optional<std::uint64_t> claim() = 0;
    /// Ends the hand-out (collective): items this rank would still get are
    /// drawn and left undone, then `values` are summed over the ranks; rank 0
    /// gets the sums, the others get their own values back.
    virtual std::vector<double> endHandout(const std::vector<double>& values) = 0;
    /// Ends every process of the run (after an error on this rank, already reported).
    [[noreturn]] virtual void abort(int exitCode) = 0;
};

/// The run's cluster: set while a ClusterScope lives in a process that
/// mpirun started; null otherwise (and always without MPI built in).
Cluster* cluster();

/// Joins the other processes when started by mpirun (MPI_Init), for the
/// lifetime of main; does nothing in a process started any other way.
class ClusterScope {
  public:
    ClusterScope(int& argc, char**& argv);
    ~ClusterScope();
    ClusterScope(const ClusterScope&) = delete;
    ClusterScope& operator=(const ClusterScope&) = delete;
};

/// Whether this binary was built with MPI (-DYARNVOX_MPI=ON).
bool clusterSupport();

} // namespace yv

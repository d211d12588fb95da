// The build without MPI: a run is always one process.
#include "pipeline/cluster.h"

namespace yv {

Cluster* cluster() { return nullptr; }
ClusterScope::ClusterScope(int&, char**&) {}
ClusterScope::~ClusterScope() = default;
bool clusterSupport() { return false; }

} // namespace yv

#include "app/simulation.hpp"

#include "comm/mpi_check.hpp"
#include "common/error.hpp"

namespace descent {

std::vector<int> partition_on_root(MPI_Comm comm, const Mesh& mesh) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  std::vector<int> part;
  // A METIS failure on rank 0 must end every rank, so its verdict travels
  // with the broadcast.
  std::string error;
  if (rank == 0) {
    try {
      part = partition_tets(mesh, size);
    } catch (const MetisError& e) {
      error = e.what();
    }
  }
  int error_length = static_cast<int>(error.size());
  DESCENT_MPI_CHECK(MPI_Bcast(&error_length, 1, MPI_INT, 0, comm));
  if (error_length > 0) {
    error.resize(error_length);
    DESCENT_MPI_CHECK(MPI_Bcast(error.data(), error_length, MPI_CHAR, 0, comm));
    throw MetisError(error);
  }
  part.resize(mesh.num_tets());
  DESCENT_MPI_CHECK(MPI_Bcast(part.data(), mesh.num_tets(), MPI_INT, 0, comm));
  return part;
}

namespace {
int comm_rank(MPI_Comm comm) {
  int r = 0;
  MPI_Comm_rank(comm, &r);
  return r;
}
int comm_size(MPI_Comm comm) {
  int s = 1;
  MPI_Comm_size(comm, &s);
  return s;
}
}  // namespace

template <class Real>
Simulation<Real>::Simulation(MPI_Comm comm, const Scene& scene, const Mesh& mesh)
    : tet_part_(partition_on_root(comm, mesh)),
      local_(build_local_mesh(mesh, tet_part_, comm_rank(comm), comm_size(comm))),
      halo_(comm, local_),
      reduction_(comm),
      problem_(local_, scene, halo_, reduction_),
      solver_(problem_, scene.solver),
      state_(rest_state<Real>(local_)) {}

template <class Real>
std::vector<double> Simulation<Real>::owned_positions() const {
  return std::vector<double>(state_.q.begin(), state_.q.begin() + 3 * local_.num_owned);
}

template class Simulation<double>;
template class Simulation<float>;

}  // namespace descent

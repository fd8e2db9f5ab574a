// Any mesh file as this rank's slice. The ASCII formats have no random access
// by row, so rank 0 parses the whole file with the serial reader (its full
// validation and file:line messages) and scatters each rank its blocks; the
// whole mesh lives on rank 0 only, and only until the scatter is done.
#include <mpi.h>

#include <exception>
#include <functional>
#include <vector>

#include "comm/collective_error.hpp"
#include "common/block_range.hpp"
#include "common/error.hpp"
#include "io/mesh_h5.hpp"
#include "io/mesh_io_detail.hpp"

namespace descent {
namespace {

// Scatters rows of `cols` values of type T (`mpi_type`) from rank 0's `all`
// by `blocks`; returns this rank's block. Counts are in rows, which a serial
// mesh's 32-bit indices keep below INT_MAX.
template <class T>
std::vector<T> scatter_rows(MPI_Comm comm, const std::vector<T>& all, int cols,
                            const BlockRange& blocks, MPI_Datatype mpi_type) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  std::vector<int> counts(blocks.parts()), offsets(blocks.parts());
  for (int r = 0; r < blocks.parts(); ++r) {
    counts[r] = static_cast<int>(blocks.size(r));
    offsets[r] = static_cast<int>(blocks.begin(r));
  }
  MPI_Datatype row;
  MPI_Type_contiguous(cols, mpi_type, &row);
  MPI_Type_commit(&row);
  std::vector<T> mine(static_cast<std::size_t>(cols) * counts[rank]);
  MPI_Scatterv(all.data(), counts.data(), offsets.data(), row, mine.data(), counts[rank], row, 0,
               comm);
  MPI_Type_free(&row);
  return mine;
}

}  // namespace

MeshSlice scatter_mesh_from_rank0(MPI_Comm comm, const std::function<Mesh()>& make_on_rank0,
                                  const std::string& source) {
  int rank = 0, size = 0;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  Mesh mesh;  // rank 0 only
  // What rank 0's read threw, thrown on every rank as the same kind of error.
  std::string input_error, other_error;
  if (rank == 0) {
    try {
      mesh = make_on_rank0();
    } catch (const InputError& error) {
      input_error = error.what();
    } catch (const std::exception& error) {
      other_error = detail::concat(source, ": ", error.what());
    }
  }
  throw_if_rank0_failed<InputError>(comm, input_error);
  throw_if_rank0_failed<Error>(comm, other_error);

  global_index_t totals[3] = {mesh.num_tets(), mesh.num_vertices(),
                              static_cast<global_index_t>(mesh.body_vertex_offsets.size())};
  MPI_Bcast(totals, 3, MPI_INT64_T, 0, comm);
  const BlockRange tet_blocks(totals[0], size), vertex_blocks(totals[1], size);
  MeshSlice slice;
  slice.source = source;
  slice.num_global_tets = totals[0];
  slice.num_global_vertices = totals[1];
  slice.first_tet = tet_blocks.begin(rank);
  slice.first_vertex = vertex_blocks.begin(rank);
  slice.body_vertex_offsets = std::move(mesh.body_vertex_offsets);
  slice.body_vertex_offsets.resize(totals[2]);
  MPI_Bcast(slice.body_vertex_offsets.data(), static_cast<int>(totals[2]), MPI_INT64_T, 0, comm);
  const std::vector<index_t> tets = scatter_rows(comm, mesh.tets, 4, tet_blocks, MPI_INT32_T);
  slice.positions = scatter_rows(comm, mesh.positions, 3, vertex_blocks, MPI_DOUBLE);
  mesh = Mesh{};  // frees rank 0's whole copy before the slice grows to 64-bit ids
  slice.tets.assign(tets.begin(), tets.end());
  return slice;
}

bool is_hdf5_mesh_path(const std::string& path) {
  const std::string extension = mesh_io_detail::lowercase_extension(path);
  return extension == ".h5" || extension == ".hdf5";
}

MeshSlice read_mesh_slice(MPI_Comm comm, const std::string& path, MeshReadReport* report) {
  if (report) *report = MeshReadReport{};
  if (is_hdf5_mesh_path(path)) return read_mesh_h5(comm, path);
  return scatter_mesh_from_rank0(
      comm, [&] { return read_mesh(path, report); }, path);
}

}  // namespace descent

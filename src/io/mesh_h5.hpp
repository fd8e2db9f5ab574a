#pragma once
// Meshes read and written by all ranks at once, so that no rank holds the
// whole mesh: each rank reads or writes its MeshSlice, the BlockRange block of
// tets and of vertices.
//
// File layout (FILE.h5), rows in the input's order:
//   /mesh/positions  float64 [V, 3]  xyz of each vertex, metres
//   /mesh/tets       int64   [T, 4]  0-based vertex ids of each tet
// Beside it FILE.xdmf (same stem) names the two datasets by relative path, so
// ParaView and meshio open the mesh directly (Topology Tetrahedron, Geometry
// XYZ).
//
// The reader accepts integer tets of any width and float32 or float64
// positions (converted to int64 and double) and checks what each rank reads:
// shapes, ids in [0, V), no tet using a vertex twice, finite coordinates, at
// least one tet. Orientation and duplicate tets are checked later, once tets
// meet their vertices. Messages name the file, the dataset and the row.
#include <mpi.h>

#include <functional>
#include <string>

#include "common/mesh_slice.hpp"
#include "io/mesh_io.hpp"

namespace descent {

// Collective over `comm`. Each rank writes its slice's tet block and vertex
// block as one contiguous hyperslab each; the slices must cover the mesh once
// (LogicError on every rank otherwise). Rank 0 writes FILE.xdmf.
void write_mesh_h5(MPI_Comm comm, const MeshSlice& slice, const std::string& path);

// Collective over `comm`: each rank reads only its BlockRange block of tets
// and of vertices, in contiguous hyperslabs read independently.
// Failures every rank sees alike (no file, not HDF5, a dataset missing or of
// the wrong shape or type) throw InputError on every rank; a read that fails
// on some rank throws Hdf5Error there and PeerFailure on the others; a bad row throws on
// the rank that read it, after every collective call, so that no rank is left
// waiting (the caller agrees across ranks, as the application's set-up does).
MeshSlice read_mesh_h5(MPI_Comm comm, const std::string& path);

// Collective: any mesh file as this rank's slice. .h5 and .hdf5 go to
// read_mesh_h5. Other formats (the ASCII ones read_mesh parses) are read and
// fully validated on rank 0 alone, which scatters each rank its blocks
// (MPI_Scatterv) and drops the whole mesh; an error there is thrown on every
// rank with rank 0's message. `report`, when not null, is reset on every rank
// and receives rank 0's reader warnings there.
MeshSlice read_mesh_slice(MPI_Comm comm, const std::string& path, MeshReadReport* report);

// Collective: a whole mesh that rank 0 alone makes (`make_on_rank0`, called
// there only: a serial reader, the bodies of a scene) as this rank's slice,
// scattered as read_mesh_slice scatters an ASCII file, with its body offsets
// sent to every rank. What make_on_rank0 throws is thrown on every rank
// (an InputError as one; anything else as an Error prefixed with `source`).
MeshSlice scatter_mesh_from_rank0(MPI_Comm comm, const std::function<Mesh()>& make_on_rank0,
                                  const std::string& source);

// Whether `path` names an HDF5 mesh (.h5 or .hdf5, any case).
bool is_hdf5_mesh_path(const std::string& path);

}  // namespace descent

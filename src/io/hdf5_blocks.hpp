#pragma once
// Files every rank opens together through MPI-IO, and the one access pattern
// descent uses on them: each rank moves its block of rows [first, first +
// count) of a 2-D dataset [rows, cols] as one contiguous hyperslab. One
// hyperslab per rank lets MPI-IO write large contiguous extents instead of
// one element at a time.
#include <hdf5.h>
#include <mpi.h>

#include <algorithm>
#include <string>

#include "common/mesh.hpp"
#include "io/hdf5_handle.hpp"

namespace descent::hdf5 {

// File access list for a file that every rank of `comm` opens. Every
// collective open goes through here, so HDF5's error printing is turned off
// here too (our errors say what failed, once).
inline Hid mpio_access(MPI_Comm comm, const std::string& where) {
  quiet_errors();
  Hid access = owned(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, "H5Pcreate", where);
  check(H5Pset_fapl_mpio(access.get(), comm, MPI_INFO_NULL), "H5Pset_fapl_mpio", where);
  return access;
}

// Transfer list for reads and writes of each rank's own contiguous block
// without MPI-IO's collective buffering: two-phase I/O gathers the data of
// a node on its aggregator (rank 0 on one node) in buffers of tens of MB,
// which made rank 0 the largest rank of a run by 17% (1M-tet helix on 8
// ranks), and a contiguous block per rank gains nothing from it (measured:
// the same time per frame within the noise). The readers use it for a
// second reason: a read that fails on one rank (a disk error, MPI-IO)
// leaves no other rank waiting inside a collective call, so the ranks can
// agree on the failure afterwards and end with one message.
inline Hid independent_transfer(const std::string& where) {
  Hid transfer = owned(H5Pcreate(H5P_DATASET_XFER), H5Pclose, "H5Pcreate", where);
  check(H5Pset_dxpl_mpio(transfer.get(), H5FD_MPIO_INDEPENDENT), "H5Pset_dxpl_mpio", where);
  return transfer;
}

// Transfer list for reads and writes that every rank joins.
inline Hid collective_transfer(const std::string& where) {
  Hid transfer = owned(H5Pcreate(H5P_DATASET_XFER), H5Pclose, "H5Pcreate", where);
  check(H5Pset_dxpl_mpio(transfer.get(), H5FD_MPIO_COLLECTIVE), "H5Pset_dxpl_mpio", where);
  return transfer;
}

// A [rows, cols] dataset in the default contiguous layout, never filled:
// every row is written by some rank, and filling first would write it twice.
inline Hid create_rows_dataset(hid_t parent, const char* name, hid_t file_type, global_index_t rows,
                               int cols, const std::string& where) {
  const hsize_t dims[2] = {static_cast<hsize_t>(rows), static_cast<hsize_t>(cols)};
  Hid space = owned(H5Screate_simple(2, dims, nullptr), H5Sclose, "H5Screate_simple", where);
  Hid creation = owned(H5Pcreate(H5P_DATASET_CREATE), H5Pclose, "H5Pcreate", where);
  check(H5Pset_fill_time(creation.get(), H5D_FILL_TIME_NEVER), "H5Pset_fill_time", where);
  return owned(
      H5Dcreate2(parent, name, file_type, space.get(), H5P_DEFAULT, creation.get(), H5P_DEFAULT),
      H5Dclose, "H5Dcreate2", where);
}

// The file and memory selections of rows [first, first + count) of `dataset`.
// A rank without rows selects nothing and still joins the collective call.
struct BlockSelection {
  Hid file_space;
  Hid memory_space;
};

inline BlockSelection select_block(hid_t dataset, global_index_t first, global_index_t count,
                                   int cols, const std::string& where) {
  BlockSelection selection;
  selection.file_space = owned(H5Dget_space(dataset), H5Sclose, "H5Dget_space", where);
  const hsize_t memory_dims[2] = {std::max<hsize_t>(static_cast<hsize_t>(count), 1),
                                  static_cast<hsize_t>(cols)};
  selection.memory_space =
      owned(H5Screate_simple(2, memory_dims, nullptr), H5Sclose, "H5Screate_simple", where);
  if (count == 0) {
    check(H5Sselect_none(selection.file_space.get()), "H5Sselect_none", where);
    check(H5Sselect_none(selection.memory_space.get()), "H5Sselect_none", where);
    return selection;
  }
  const hsize_t start[2] = {static_cast<hsize_t>(first), 0};
  const hsize_t block[2] = {static_cast<hsize_t>(count), static_cast<hsize_t>(cols)};
  check(H5Sselect_hyperslab(selection.file_space.get(), H5S_SELECT_SET, start, nullptr, block,
                            nullptr),
        "H5Sselect_hyperslab", where);
  return selection;
}

// Writes `count` rows of `cols` values at `data` (memory type `memory_type`,
// row-major) to rows [first, first + count) of `dataset`. Every rank calls
// it, one with no rows too; the transfer list says whether MPI-IO moves the
// data collectively.
inline void write_block(hid_t dataset, hid_t transfer, hid_t memory_type, global_index_t first,
                        global_index_t count, int cols, const void* data,
                        const std::string& where) {
  const BlockSelection selection = select_block(dataset, first, count, cols, where);
  const double unused = 0;  // HDF5 wants a buffer even when nothing is selected
  check(H5Dwrite(dataset, memory_type, selection.memory_space.get(), selection.file_space.get(),
                 transfer, count == 0 ? &unused : data),
        "H5Dwrite", where);
}

// Reads rows [first, first + count) of `dataset` into `data`, converted to
// `memory_type`; every rank calls it, as write_block.
inline void read_block(hid_t dataset, hid_t transfer, hid_t memory_type, global_index_t first,
                       global_index_t count, int cols, void* data, const std::string& where) {
  const BlockSelection selection = select_block(dataset, first, count, cols, where);
  double unused = 0;
  check(H5Dread(dataset, memory_type, selection.memory_space.get(), selection.file_space.get(),
                transfer, count == 0 ? &unused : data),
        "H5Dread", where);
}

}  // namespace descent::hdf5

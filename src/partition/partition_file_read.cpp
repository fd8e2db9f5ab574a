// Reading a partition file (layout in partition_file.hpp), checked as it is
// read, so that a damaged or hand-edited file ends every rank with one
// message naming the file, the dataset and the first bad row:
//  1. what every rank reads alike (the attributes, each dataset's shape and
//     type, the whole tet_offsets and part_stats tables), checked before any
//     rank reads its rows, so every rank throws alike and none is left in a
//     collective call;
//  2. the rows of this rank's part (ids, vertices, surface bits, its block of
//     positions), read once step 1 proved them in range (independent reads:
//     a rank whose read fails is agreed on, never waited for), then checked
//     by each rank, which agree on the outcome;
//  3. every tet of the mesh listed by exactly one part, collectively.
#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <utility>

#include "comm/collective_error.hpp"
#include "common/block_range.hpp"
#include "common/error.hpp"
#include "io/block_routing.hpp"
#include "io/hdf5_blocks.hpp"
#include "io/hdf5_rows.hpp"
#include "partition/partition_file.hpp"

namespace descent {
namespace {

using hdf5::check;
using hdf5::Hid;
using hdf5::owned;

constexpr int kFaceBits = 0xF;  // one bit per face of a tet

// An attribute of /partition: present, one value, of `type_class`.
Hid open_attribute(hid_t group, const char* name, H5T_class_t type_class, const char* kind,
                   const std::string& path) {
  const std::string what = detail::concat(path, ": /partition attribute ", name);
  if (H5Aexists(group, name) <= 0)
    throw InputError(what +
                     ": missing (a partition file's /partition has num_parts, "
                     "cut_faces, imbalance and method)");
  Hid attribute = owned(H5Aopen(group, name, H5P_DEFAULT), H5Aclose, "H5Aopen", what);
  Hid space = owned(H5Aget_space(attribute.get()), H5Sclose, "H5Aget_space", what);
  Hid type = owned(H5Aget_type(attribute.get()), H5Tclose, "H5Aget_type", what);
  const H5T_class_t found = H5Tget_class(type.get());
  if (found != type_class || (type_class != H5T_STRING && H5Tget_size(type.get()) > 8))
    throw InputError(detail::concat(what, ": not ", kind));
  if (H5Sget_simple_extent_npoints(space.get()) != 1)
    throw InputError(detail::concat(what, ": not a single value"));
  return attribute;
}

global_index_t read_integer_attribute(hid_t group, const char* name, const std::string& path) {
  Hid attribute = open_attribute(group, name, H5T_INTEGER, "an integer", path);
  global_index_t value = 0;
  check(H5Aread(attribute.get(), H5T_NATIVE_INT64, &value), "H5Aread",
        path + ": /partition attribute " + name);
  return value;
}

double read_float_attribute(hid_t group, const char* name, const std::string& path) {
  Hid attribute = open_attribute(group, name, H5T_FLOAT, "a float", path);
  double value = 0;
  check(H5Aread(attribute.get(), H5T_NATIVE_DOUBLE, &value), "H5Aread",
        path + ": /partition attribute " + name);
  return value;
}

// Fixed-length (as descent writes it) or variable-length (as h5py does) text.
std::string read_text_attribute(hid_t group, const char* name, const std::string& path) {
  const std::string where = path + ": /partition attribute " + name;
  Hid attribute = open_attribute(group, name, H5T_STRING, "text", path);
  Hid type = owned(H5Aget_type(attribute.get()), H5Tclose, "H5Aget_type", where);
  if (H5Tis_variable_str(type.get()) > 0) {
    char* text = nullptr;
    check(H5Aread(attribute.get(), type.get(), &text), "H5Aread", where);
    std::string value = text != nullptr ? text : "";
    H5free_memory(text);
    return value;
  }
  std::string text(H5Tget_size(type.get()), '\0');
  check(H5Aread(attribute.get(), type.get(), text.data()), "H5Aread", where);
  return text.substr(0, text.find('\0'));
}

// Step 1's checks of the offsets: they start at 0, never decrease and end at
// the rows of the per-tet datasets. Returns "" or the message.
std::string offsets_error(const std::vector<global_index_t>& offsets, global_index_t tet_rows,
                          const std::string& path) {
  const std::string where = path + ": dataset /partition/tet_offsets: row ";
  if (offsets[0] != 0)
    return detail::concat(where, 0, ": ", offsets[0], ", but part 0 starts at 0");
  for (std::size_t p = 1; p < offsets.size(); ++p) {
    if (offsets[p] < offsets[p - 1])
      return detail::concat(where, p, ": ", offsets[p], ", less than the row before (",
                            offsets[p - 1], "): offsets must not decrease");
    if (offsets[p] > tet_rows)
      return detail::concat(where, p, ": ", offsets[p], ", past the end of /partition/tet_ids (",
                            tet_rows, " rows)");
  }
  if (offsets.back() != tet_rows)
    return detail::concat(where, offsets.size() - 1, ": ", offsets.back(),
                          ", but /partition/tet_ids has ", tet_rows,
                          " rows: the parts must end where the table does");
  return "";
}

// Step 1's checks of part_stats against the offsets; "" or the message.
std::string stats_error(const std::vector<global_index_t>& stats,
                        const std::vector<global_index_t>& offsets, const std::string& path) {
  for (std::size_t p = 0; p + 1 < offsets.size(); ++p) {
    const global_index_t* row = &stats[kPartStatsColumns * p];
    const global_index_t tets = offsets[p + 1] - offsets[p];
    if (row[0] != tets)
      return detail::concat(path, ": dataset /partition/part_stats: row ", p, ": ", row[0],
                            " tets, but /partition/tet_offsets gives part ", p, " ", tets);
    for (int c = 1; c < kPartStatsColumns; ++c)
      if (row[c] < 0)
        return detail::concat(path, ": dataset /partition/part_stats: row ", p, ": column ", c,
                              " is negative (", row[c], ")");
  }
  return "";
}

// Step 2: the first bad row this rank read, as a message ("" for none).
std::string rows_error(const PartitionPiece& piece, const std::vector<global_index_t>& surface,
                       global_index_t first_row, const std::string& path) {
  const PartTets& tets = piece.tets;
  const std::string at = path + ": dataset /partition/";
  for (index_t k = 0; k < tets.num_tets(); ++k) {
    const global_index_t row = first_row + k, id = tets.ids[k];
    if (id < 0 || id >= piece.num_global_tets)
      return detail::concat(at, "tet_ids: row ", row, ": tet ", id, " is not a tet of /mesh/tets (",
                            piece.num_global_tets, " rows)");
    if (k > 0 && id <= tets.ids[k - 1])
      return detail::concat(at, "tet_ids: row ", row, ": tet ", id, " after tet ", tets.ids[k - 1],
                            ": the ids of a part must ascend");
  }
  for (index_t k = 0; k < tets.num_tets(); ++k) {
    const global_index_t row = first_row + k;
    const global_index_t* v = &tets.vertices[4 * static_cast<std::size_t>(k)];
    for (int a = 0; a < 4; ++a) {
      if (v[a] < 0 || v[a] >= piece.num_global_vertices)
        return detail::concat(at, "tets: row ", row, ": vertex ", v[a], ", but the mesh has ",
                              piece.num_global_vertices, " vertices");
      for (int b = 0; b < a; ++b)
        if (v[a] == v[b])
          return detail::concat(at, "tets: row ", row, ": vertex ", v[a], " twice (vertices ", v[0],
                                " ", v[1], " ", v[2], " ", v[3], ")");
    }
  }
  for (std::size_t k = 0; k < surface.size(); ++k)
    if (surface[k] < 0 || surface[k] > kFaceBits)
      return detail::concat(at, "surface_faces: row ", first_row + k, ": ", surface[k],
                            " is not a set of a tet's 4 face bits");
  for (std::size_t k = 0; 3 * k < piece.block_positions.size(); ++k) {
    const double* x = &piece.block_positions[3 * k];
    if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2]))
      return detail::concat(path, ": dataset /mesh/positions: row ", piece.first_vertex + k,
                            ": a non-finite coordinate (", x[0], " ", x[1], " ", x[2], ")");
  }
  return "";
}

// Step 3, collective: every tet of [0, T) is listed by exactly one row of
// tet_ids (the rows number T, so a tet listed twice leaves another unlisted).
// Each id's row number travels to the rank whose block holds the id, which
// names the second row of the first id it receives twice.
void verify_each_tet_once(MPI_Comm comm, const PartitionPiece& piece, global_index_t first_row,
                          const std::string& path) {
  int size = 1;
  MPI_Comm_size(comm, &size);
  BlockRouting routing(comm, BlockRange(piece.num_global_tets, size), piece.tets.ids);
  if (routing.covers_each_row_once()) return;
  std::vector<std::byte>& sent = routing.send_buffer();
  sent.resize(routing.num_sent() * sizeof(global_index_t));
  for (std::size_t k = 0; k < routing.num_sent(); ++k) {
    const global_index_t row = first_row + static_cast<global_index_t>(k);
    std::memcpy(&sent[routing.send_slot(k) * sizeof row], &row, sizeof row);
  }
  routing.exchange_rows(sizeof(global_index_t));
  std::vector<std::pair<std::size_t, global_index_t>> arrivals(routing.num_received());
  for (std::size_t j = 0; j < arrivals.size(); ++j) {
    arrivals[j].first = routing.block_row(j);
    std::memcpy(&arrivals[j].second, &routing.receive_buffer()[j * sizeof(global_index_t)],
                sizeof(global_index_t));
  }
  std::sort(arrivals.begin(), arrivals.end());
  std::string error;
  for (std::size_t j = 1; j < arrivals.size() && error.empty(); ++j)
    if (arrivals[j].first == arrivals[j - 1].first)
      error =
          detail::concat(path, ": dataset /partition/tet_ids: row ", arrivals[j].second, ": tet ",
                         routing.first_row() + arrivals[j].first, " again (listed first at row ",
                         arrivals[j - 1].second, "): each tet belongs to exactly one part");
  throw_if_any_failed(comm, error);
}

// The datasets of a partition file, each checked for presence, type and
// shape, and their row counts against num_parts and each other.
struct PartitionDatasets {
  hdf5::RowsDataset offsets, stats, ids, tets, surface, positions, mesh_tets;
};

void expect_rows(const hdf5::RowsDataset& set, const char* name, global_index_t rows,
                 const std::string& why, const std::string& path) {
  if (set.rows != rows)
    throw InputError(
        detail::concat(path, ": dataset ", name, " has ", set.rows, " rows, but ", why));
}

PartitionDatasets open_datasets(hid_t file, const std::string& path, global_index_t parts) {
  auto open = [&](const char* name, const hdf5::RowsShape& shape) {
    return hdf5::open_rows_dataset(file, path, name, shape);
  };
  const char* integers = "ids and counts are integers";
  PartitionDatasets sets;
  sets.offsets =
      open("/partition/tet_offsets", {1, H5T_INTEGER, "P + 1", "1 offset per row", integers});
  sets.stats =
      open("/partition/part_stats", {kPartStatsColumns, H5T_INTEGER, "P",
                                     "tets, shared vertices, neighbours, shared pairs", integers});
  sets.ids = open("/partition/tet_ids", {1, H5T_INTEGER, "T", "1 tet id per row", integers});
  sets.tets = open("/partition/tets", {4, H5T_INTEGER, "T", "4 vertex ids per tet", integers});
  sets.surface =
      open("/partition/surface_faces", {1, H5T_INTEGER, "T", "4 face bits per tet", integers});
  sets.positions = open("/mesh/positions", {3, H5T_FLOAT, "V", "3 coordinates per vertex",
                                            "coordinates must be one of these"});
  sets.mesh_tets = open("/mesh/tets", {4, H5T_INTEGER, "T", "4 vertex ids per tet", integers});
  const std::string parts_text = detail::concat("num_parts is ", parts);
  expect_rows(sets.offsets, "/partition/tet_offsets", parts + 1, parts_text + " (one more row)",
              path);
  expect_rows(sets.stats, "/partition/part_stats", parts, parts_text, path);
  const std::string tets_text =
      detail::concat("/partition/tet_ids has ", sets.ids.rows,
                     ": every tet is listed once, with its vertices and surface faces");
  expect_rows(sets.tets, "/partition/tets", sets.ids.rows, tets_text, path);
  expect_rows(sets.surface, "/partition/surface_faces", sets.ids.rows, tets_text, path);
  expect_rows(sets.mesh_tets, "/mesh/tets", sets.ids.rows, tets_text, path);
  return sets;
}

// The file is a regular HDF5 file with a /partition group; every rank asks
// (the answers are alike on a shared file system).
void verify_partition_file(const std::string& path) {
  std::error_code missing;
  if (!std::filesystem::is_regular_file(path, missing))
    throw InputError(detail::concat(path,
                                    ": no such file (--partition names a file that "
                                    "`descent partition` wrote)"));
  hdf5::quiet_errors();
  if (H5Fis_hdf5(path.c_str()) <= 0)
    throw InputError(detail::concat(path,
                                    ": not an HDF5 file (--partition names a file that "
                                    "`descent partition` wrote)"));
}

}  // namespace

PartitionPiece read_partition_piece(MPI_Comm comm, const std::string& path) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  verify_partition_file(path);
  const std::string where = path + ":/partition";
  PartitionPiece piece;
  global_index_t first_row = 0;  // of this rank's part in the per-tet datasets
  // Surface bits are read as int64 so that a value outside a byte shows as
  // itself, not clamped into one by the conversion.
  std::vector<global_index_t> surface;
  // Every collective call happens in this block, and every handle is closed
  // at its end, before any rank checks its rows and may throw.
  {
    Hid access = hdf5::mpio_access(comm, path);
    Hid file =
        owned(H5Fopen(path.c_str(), H5F_ACC_RDONLY, access.get()), H5Fclose, "H5Fopen", path);
    if (H5Lexists(file.get(), "/partition", H5P_DEFAULT) <= 0)
      throw InputError(detail::concat(
          path,
          ": no /partition group: a mesh file, not a partition (make one with descent "
          "partition SCENE -n P -o FILE.h5)"));
    Hid group = owned(H5Gopen2(file.get(), "/partition", H5P_DEFAULT), H5Gclose, "H5Gopen2", where);

    // 1. What every rank reads alike.
    const global_index_t parts = read_integer_attribute(group.get(), "num_parts", path);
    if (parts != size)
      throw InputError(
          detail::concat(path, " holds a partition into ", parts, " parts, for runs on ", parts,
                         " ranks; this run has ", size, " rank(s): run on ", parts,
                         " ranks, or partition again with descent partition -n ", size));
    piece.method = read_text_attribute(group.get(), "method", path);
    if (piece.method != "metis" && piece.method != "ptscotch" && piece.method != "rcb")
      throw InputError(detail::concat(path, ": /partition attribute method: '", piece.method,
                                      "', not metis, ptscotch or rcb"));
    piece.quality.cut_faces = read_integer_attribute(group.get(), "cut_faces", path);
    piece.quality.imbalance = read_float_attribute(group.get(), "imbalance", path);
    if (piece.quality.cut_faces < 0 || !std::isfinite(piece.quality.imbalance) ||
        piece.quality.imbalance < 0)
      throw InputError(detail::concat(path, ": /partition attributes cut_faces (",
                                      piece.quality.cut_faces, ") and imbalance (",
                                      piece.quality.imbalance, ") must be finite and >= 0"));

    const PartitionDatasets sets = open_datasets(file.get(), path, parts);
    piece.num_global_tets = sets.ids.rows;
    piece.num_global_vertices = sets.positions.rows;

    // Independent reads (io/hdf5_blocks.hpp says why); a rank's failed read
    // is agreed on by every rank before any goes on.
    Hid transfer = hdf5::independent_transfer(where);
    std::vector<global_index_t> offsets(size + 1), stats(kPartStatsColumns * size);
    std::string read_error;
    try {
      hdf5::read_block(sets.offsets.dataset.get(), transfer.get(), H5T_NATIVE_INT64, 0, size + 1, 1,
                       offsets.data(), where + "/tet_offsets");
      hdf5::read_block(sets.stats.dataset.get(), transfer.get(), H5T_NATIVE_INT64, 0, size,
                       kPartStatsColumns, stats.data(), where + "/part_stats");
    } catch (const Hdf5Error& e) {
      read_error = e.what();
    }
    throw_if_any_failed<Hdf5Error>(comm, read_error);
    if (std::string error = offsets_error(offsets, sets.ids.rows, path); !error.empty())
      throw InputError(error);
    if (std::string error = stats_error(stats, offsets, path); !error.empty())
      throw InputError(error);
    for (int p = 0; p < size; ++p) {
      const global_index_t* row = &stats[kPartStatsColumns * static_cast<std::size_t>(p)];
      piece.quality.tets_per_part.push_back(row[0]);
      piece.quality.shared_vertices_per_part.push_back(row[1]);
      piece.quality.neighbours_per_part.push_back(static_cast<int>(row[2]));
      piece.quality.shared_pairs_per_part.push_back(row[3]);
    }

    // 2. This rank's part and its block of vertex positions.
    first_row = offsets[rank];
    const global_index_t count = offsets[rank + 1] - offsets[rank];
    PartTets& tets = piece.tets;
    tets.part = rank;
    tets.ids.resize(count);
    tets.vertices.resize(4 * static_cast<std::size_t>(count));
    surface.resize(count);
    const BlockRange blocks(piece.num_global_vertices, size);
    piece.first_vertex = blocks.begin(rank);
    piece.block_positions.resize(3 * static_cast<std::size_t>(blocks.size(rank)));
    read_error.clear();
    try {
      hdf5::read_block(sets.ids.dataset.get(), transfer.get(), H5T_NATIVE_INT64, first_row, count,
                       1, tets.ids.data(), where + "/tet_ids");
      hdf5::read_block(sets.tets.dataset.get(), transfer.get(), H5T_NATIVE_INT64, first_row, count,
                       4, tets.vertices.data(), where + "/tets");
      hdf5::read_block(sets.surface.dataset.get(), transfer.get(), H5T_NATIVE_INT64, first_row,
                       count, 1, surface.data(), where + "/surface_faces");
      hdf5::read_block(sets.positions.dataset.get(), transfer.get(), H5T_NATIVE_DOUBLE,
                       piece.first_vertex, blocks.size(rank), 3, piece.block_positions.data(),
                       path + ":/mesh/positions");
    } catch (const Hdf5Error& e) {
      read_error = e.what();
    }
    throw_if_any_failed<Hdf5Error>(comm, read_error);
  }
  throw_if_any_failed(comm, rows_error(piece, surface, first_row, path));
  piece.tets.surface_faces.assign(surface.begin(), surface.end());
  // 3. Every tet once.
  verify_each_tet_once(comm, piece, first_row, path);
  return piece;
}

}  // namespace descent

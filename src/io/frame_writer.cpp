// Frames written by every rank into one HDF5 file through MPI-IO, and the XDMF
// index that rank 0 rewrites beside it after each frame. Each rank writes its
// own rows of the shared datasets in one collective call per dataset.
#include "io/frame_writer.hpp"

#include <hdf5.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <filesystem>
#include <numeric>
#include <sstream>
#include <system_error>
#include <type_traits>
#include <utility>
#include <vector>

#include "common/error.hpp"
#include "io/hdf5_handle.hpp"
#include "io/number_text.hpp"

namespace descent {
namespace {

namespace fs = std::filesystem;
using hdf5::check;
using hdf5::Hid;
using hdf5::owned;

constexpr const char* kH5Name = "frames.h5";
constexpr const char* kXdmfName = "frames.xdmf";
constexpr int kLastFrame = 999999;  // frame groups are named with 6 digits

// Rank 0 alone touched the file system and got `error_on_rank0` (an errno
// value, 0 for success). Every rank throws the same error, so that no rank is
// left waiting in a collective call for one that gave up.
void throw_on_every_rank_if_failed(MPI_Comm comm, int error_on_rank0, const std::string& what) {
  MPI_Bcast(&error_on_rank0, 1, MPI_INT, 0, comm);
  if (error_on_rank0 != 0)
    throw InputError(what + ": " + std::generic_category().message(error_on_rank0));
}

// A caller's mistake seen on any rank throws on every rank, for the same reason.
void verify_on_every_rank(MPI_Comm comm, bool ok_here, const std::string& what) {
  int ok_everywhere = ok_here ? 1 : 0;
  MPI_Allreduce(MPI_IN_PLACE, &ok_everywhere, 1, MPI_INT, MPI_MIN, comm);
  if (!ok_everywhere) throw LogicError(what);
}

std::string frame_name(int frame) {
  char name[16];
  std::snprintf(name, sizeof name, "%06d", frame);
  return name;
}

// Positions k of `ids` such that ids[order[0]] < ids[order[1]] < ...
std::vector<std::size_t> ascending_order(std::span<const global_index_t> ids) {
  std::vector<std::size_t> order(ids.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return ids[a] < ids[b]; });
  return order;
}

// Row order[k] of `rows` (`cols` values per row) becomes row k of the result.
template <class T>
std::vector<T> permute_rows(std::span<const T> rows, std::span<const std::size_t> order, int cols) {
  std::vector<T> permuted(rows.size());
  for (std::size_t k = 0; k < order.size(); ++k)
    std::copy_n(rows.begin() + order[k] * cols, cols, permuted.begin() + k * cols);
  return permuted;
}

bool all_below(std::span<const global_index_t> ids, global_index_t end) {
  return std::all_of(ids.begin(), ids.end(),
                     [&](global_index_t id) { return id >= 0 && id < end; });
}

bool has_duplicates(std::span<const global_index_t> sorted_ids) {
  return std::adjacent_find(sorted_ids.begin(), sorted_ids.end()) != sorted_ids.end();
}

template <class T>
hid_t native_type() {
  if constexpr (std::is_same_v<T, double>)
    return H5T_NATIVE_DOUBLE;
  else
    return H5T_NATIVE_INT64;
}

// A [rows, cols] dataset in the default contiguous layout.
Hid create_dataset(hid_t parent, const char* name, hid_t file_type, hsize_t rows, hsize_t cols,
                   const std::string& where) {
  const hsize_t dims[2] = {rows, cols};
  Hid space = owned(H5Screate_simple(2, dims, nullptr), H5Sclose, "H5Screate_simple", where);
  Hid creation = owned(H5Pcreate(H5P_DATASET_CREATE), H5Pclose, "H5Pcreate", where);
  // Every row is written by some rank: filling first would write the dataset twice.
  check(H5Pset_fill_time(creation.get(), H5D_FILL_TIME_NEVER), "H5Pset_fill_time", where);
  return owned(
      H5Dcreate2(parent, name, file_type, space.get(), H5P_DEFAULT, creation.get(), H5P_DEFAULT),
      H5Dclose, "H5Dcreate2", where);
}

// Collectively writes `rows` (`cols` values each) into the rows `sorted_ids` of
// `dataset`, row k of `rows` going to row sorted_ids[k]. The file selection is a
// point selection: HDF5 visits points in the order given, which here is memory
// order and ascending file order. (A union of hyperslabs, one per run of ids,
// takes time quadratic in the number of runs to build in HDF5 1.10.) It is
// built per call because HDF5 stores one node per selected element.
template <class T>
void write_rows(hid_t dataset, hid_t transfer, std::span<const global_index_t> sorted_ids, int cols,
                std::span<const T> rows, const std::string& where) {
  Hid file_space = owned(H5Dget_space(dataset), H5Sclose, "H5Dget_space", where);
  const hsize_t num_rows = sorted_ids.size();
  // A rank without rows still joins the collective write, selecting nothing.
  const hsize_t memory_dims[2] = {std::max<hsize_t>(num_rows, 1), static_cast<hsize_t>(cols)};
  Hid memory_space =
      owned(H5Screate_simple(2, memory_dims, nullptr), H5Sclose, "H5Screate_simple", where);
  if (num_rows == 0) {
    check(H5Sselect_none(file_space.get()), "H5Sselect_none", where);
    check(H5Sselect_none(memory_space.get()), "H5Sselect_none", where);
  } else {
    std::vector<hsize_t> coordinates;  // (row, col) of each element, memory order
    coordinates.reserve(2 * num_rows * cols);
    for (global_index_t row : sorted_ids) {
      for (int col = 0; col < cols; ++col) {
        coordinates.push_back(static_cast<hsize_t>(row));
        coordinates.push_back(static_cast<hsize_t>(col));
      }
    }
    check(H5Sselect_elements(file_space.get(), H5S_SELECT_SET, coordinates.size() / 2,
                             coordinates.data()),
          "H5Sselect_elements", where);
  }
  const T unused{};  // HDF5 wants a buffer even when nothing is selected
  check(H5Dwrite(dataset, native_type<T>(), memory_space.get(), file_space.get(), transfer,
                 rows.empty() ? &unused : rows.data()),
        "H5Dwrite", where);
}

// Writes `text` to `path` through a temporary file and a rename, so readers see
// either the old or the new text. Returns an errno value, 0 for success.
int write_file_atomically(const fs::path& path, const std::string& text) {
  const fs::path temporary = path.string() + ".tmp";
  std::FILE* file = std::fopen(temporary.c_str(), "w");
  if (file == nullptr) return errno != 0 ? errno : EIO;
  const bool written = std::fwrite(text.data(), 1, text.size(), file) == text.size();
  const bool closed = std::fclose(file) == 0;
  if (!written || !closed) return errno != 0 ? errno : EIO;
  std::error_code error;
  fs::rename(temporary, path, error);
  return error.value();
}

// A DataItem naming a float64 [num_vertices, 3] dataset of frames.h5.
std::string xdmf_vertex_item(global_index_t num_vertices, const std::string& path) {
  std::ostringstream item;
  item << "<DataItem Dimensions=\"" << num_vertices
       << " 3\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" << kH5Name << ":" << path
       << "</DataItem>";
  return item.str();
}

std::string xdmf_vertex_attribute(const char* name, global_index_t num_vertices,
                                  const std::string& path) {
  return detail::concat("        <Attribute Name=\"", name,
                        "\" AttributeType=\"Vector\" Center=\"Node\">\n          ",
                        xdmf_vertex_item(num_vertices, path), "\n        </Attribute>\n");
}

// One Uniform grid of the temporal collection: frame `frame`'s positions as
// its Geometry, its displacement and velocity as node Attributes. The first
// grid (`first`) holds the Topology, the others include that one, so that the
// connectivity is named once.
std::string xdmf_grid(int frame, double time, global_index_t num_vertices, global_index_t num_tets,
                      bool first) {
  const std::string group = std::string("/frames/") + frame_name(frame);
  std::ostringstream grid;
  grid << "      <Grid Name=\"frame_" << frame_name(frame) << "\" GridType=\"Uniform\">\n"
       << "        <Time Value=\"" << format_double(time) << "\"/>\n";
  if (first) {
    grid << "        <Topology TopologyType=\"Tetrahedron\" NumberOfElements=\"" << num_tets
         << "\">\n"
         << "          <DataItem Dimensions=\"" << num_tets
         << " 4\" NumberType=\"Int\" Precision=\"4\" Format=\"HDF\">" << kH5Name
         << ":/mesh/tets</DataItem>\n"
         << "        </Topology>\n";
  } else {
    grid << "        <xi:include xpointer=\"xpointer(/Xdmf/Domain/Grid/Grid[1]/Topology)\"/>\n";
  }
  grid << "        <Geometry GeometryType=\"XYZ\">\n"
       << "          " << xdmf_vertex_item(num_vertices, group + "/positions") << "\n"
       << "        </Geometry>\n"
       << xdmf_vertex_attribute("displacement", num_vertices, group + "/displacement")
       << xdmf_vertex_attribute("velocity", num_vertices, group + "/velocity") << "      </Grid>\n";
  return grid.str();
}

std::string xdmf_document(const std::string& grids) {
  return "<?xml version=\"1.0\" ?>\n"
         "<Xdmf Version=\"3.0\" xmlns:xi=\"http://www.w3.org/2001/XInclude\">\n"
         "  <Domain>\n"
         "    <Grid Name=\"frames\" GridType=\"Collection\" CollectionType=\"Temporal\">\n" +
         grids +
         "    </Grid>\n"
         "  </Domain>\n"
         "</Xdmf>\n";
}

}  // namespace

struct FrameWriter::Impl {
  Impl(MPI_Comm comm, const std::string& dir, const FrameWriterLayout& layout, int resume_after);
  // Resuming: drops frames after `last` from the file (a killed run may have
  // written past its last checkpoint) and rebuilds the XDMF list up to it.
  void resume(int last);
  void verify_layout(const FrameWriterLayout& layout,
                     std::span<const global_index_t> sorted_tet_ids) const;
  void create_output_directory() const;
  void write_mesh(const FrameWriterLayout& layout, std::span<const std::size_t> tet_order,
                  std::span<const global_index_t> sorted_tet_ids);
  void write_frame(int frame, double time, std::span<const double> owned_positions,
                   std::span<const double> owned_velocities);
  // Creates `name` in `group` and writes the owned rows, already in
  // sorted_vertex_ids order.
  void write_vertex_dataset(hid_t group, const char* name, std::span<const double> sorted_rows,
                            const std::string& where);

  MPI_Comm comm;  // the caller's; it outlives the writer
  int rank = 0;
  fs::path dir;
  global_index_t num_vertices;
  global_index_t num_tets;
  // Owned vertex k of the caller's order is row sorted_vertex_ids[k'] of the
  // file, where vertex_order[k'] == k.
  std::vector<std::size_t> vertex_order;
  std::vector<global_index_t> sorted_vertex_ids;
  // The owned rest positions in sorted_vertex_ids order, for the displacements.
  std::vector<double> sorted_rest_positions;
  std::string xdmf_grids;  // rank 0: one <Grid> per written frame
  // Released in reverse order of declaration: the transfer list, then the file.
  Hid file;
  Hid collective_transfer;
};

FrameWriter::Impl::Impl(MPI_Comm comm_, const std::string& dir_, const FrameWriterLayout& layout,
                        int resume_after)
    : comm(comm_),
      dir(dir_),
      num_vertices(layout.num_global_vertices),
      num_tets(layout.num_global_tets) {
  MPI_Comm_rank(comm, &rank);
  vertex_order = ascending_order(layout.owned_vertex_ids);
  sorted_vertex_ids = permute_rows(layout.owned_vertex_ids, vertex_order, 1);
  const auto tet_order = ascending_order(layout.tet_ids);
  const auto sorted_tet_ids = permute_rows(layout.tet_ids, tet_order, 1);
  verify_layout(layout, sorted_tet_ids);
  sorted_rest_positions = permute_rows(layout.owned_rest_positions, vertex_order, 3);

  create_output_directory();
  const std::string h5 = (dir / kH5Name).string();
  {
    Hid access = owned(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, "H5Pcreate", h5);
    check(H5Pset_fapl_mpio(access.get(), comm, MPI_INFO_NULL), "H5Pset_fapl_mpio", h5);
    // Default format bounds on purpose: the newest superblock marks a file as
    // open for writing, and a killed run would leave it unreadable without h5clear.
    file = resume_after >= 0
               ? owned(H5Fopen(h5.c_str(), H5F_ACC_RDWR, access.get()), H5Fclose, "H5Fopen", h5)
               : owned(H5Fcreate(h5.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, access.get()), H5Fclose,
                       "H5Fcreate", h5);
  }
  collective_transfer = owned(H5Pcreate(H5P_DATASET_XFER), H5Pclose, "H5Pcreate", h5);
  check(H5Pset_dxpl_mpio(collective_transfer.get(), H5FD_MPIO_COLLECTIVE), "H5Pset_dxpl_mpio", h5);
  if (resume_after >= 0) {
    resume(resume_after);
    return;
  }

  write_mesh(layout, tet_order, sorted_tet_ids);
  // Created empty; each frame adds its group here.
  Hid frames = owned(H5Gcreate2(file.get(), "/frames", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                     H5Gclose, "H5Gcreate2", h5 + ":/frames");
  check(H5Fflush(file.get(), H5F_SCOPE_GLOBAL), "H5Fflush", h5);
}

namespace {
herr_t collect_name(hid_t, const char* name, const H5L_info_t*, void* names) {
  static_cast<std::vector<std::string>*>(names)->emplace_back(name);
  return 0;
}
}  // namespace

void FrameWriter::Impl::resume(int last) {
  const std::string h5 = (dir / kH5Name).string();
  Hid frames =
      owned(H5Gopen2(file.get(), "/frames", H5P_DEFAULT), H5Gclose, "H5Gopen2", h5 + ":/frames");
  std::vector<std::string> names;  // zero-padded, so by name is by frame
  check(H5Literate(frames.get(), H5_INDEX_NAME, H5_ITER_INC, nullptr, collect_name, &names),
        "H5Literate", h5 + ":/frames");
  for (const std::string& name : names) {
    const std::string where = h5 + ":/frames/" + name;
    if (std::stoi(name) > last) {
      check(H5Ldelete(frames.get(), name.c_str(), H5P_DEFAULT), "H5Ldelete", where);
      continue;
    }
    if (rank != 0) continue;
    Hid attribute =
        owned(H5Aopen_by_name(frames.get(), name.c_str(), "time", H5P_DEFAULT, H5P_DEFAULT),
              H5Aclose, "H5Aopen_by_name", where + " attribute time");
    double time = 0;
    check(H5Aread(attribute.get(), H5T_NATIVE_DOUBLE, &time), "H5Aread", where);
    xdmf_grids += xdmf_grid(std::stoi(name), time, num_vertices, num_tets, xdmf_grids.empty());
  }
  check(H5Fflush(file.get(), H5F_SCOPE_GLOBAL), "H5Fflush", h5);
  int error = 0;
  if (rank == 0) error = write_file_atomically(dir / kXdmfName, xdmf_document(xdmf_grids));
  throw_on_every_rank_if_failed(comm, error,
                                detail::concat("cannot write ", (dir / kXdmfName).string()));
}

// Each rank checks its own part; the summed counts show that the parts cover
// the mesh (with no duplicates on a rank, this catches most mistakes).
void FrameWriter::Impl::verify_layout(const FrameWriterLayout& layout,
                                      std::span<const global_index_t> sorted_tet_ids) const {
  long long owned_counts[2] = {static_cast<long long>(sorted_vertex_ids.size()),
                               static_cast<long long>(sorted_tet_ids.size())};
  MPI_Allreduce(MPI_IN_PLACE, owned_counts, 2, MPI_LONG_LONG, MPI_SUM, comm);
  const bool layout_ok = owned_counts[0] == num_vertices && owned_counts[1] == num_tets &&
                         layout.owned_rest_positions.size() == 3 * layout.owned_vertex_ids.size() &&
                         layout.tet_vertices.size() == 4 * layout.tet_ids.size() &&
                         all_below(sorted_vertex_ids, num_vertices) &&
                         all_below(sorted_tet_ids, num_tets) &&
                         all_below(layout.tet_vertices, num_vertices) &&
                         !has_duplicates(sorted_vertex_ids) && !has_duplicates(sorted_tet_ids);
  verify_on_every_rank(comm, layout_ok,
                       detail::concat("FrameWriter for ", dir.string(),
                                      ": the layout must give every vertex and tet to exactly one "
                                      "rank, with ids in range and 3 positions or 4 vertex ids "
                                      "per row"));
}

// Rank 0 creates DIR and removes an index left by an earlier run, which would
// name frames that the new frames.h5 does not hold.
void FrameWriter::Impl::create_output_directory() const {
  int error = 0;
  if (rank == 0) {
    std::error_code created;
    fs::create_directories(dir, created);
    std::error_code removed;
    if (!created) fs::remove(dir / kXdmfName, removed);
    error = created ? created.value() : removed.value();
  }
  throw_on_every_rank_if_failed(
      comm, error, detail::concat("cannot prepare the output directory ", dir.string()));
}

void FrameWriter::Impl::write_mesh(const FrameWriterLayout& layout,
                                   std::span<const std::size_t> tet_order,
                                   std::span<const global_index_t> sorted_tet_ids) {
  const std::string h5 = (dir / kH5Name).string();
  Hid mesh = owned(H5Gcreate2(file.get(), "/mesh", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose,
                   "H5Gcreate2", h5 + ":/mesh");

  write_vertex_dataset(mesh.get(), "rest_positions", sorted_rest_positions,
                       h5 + ":/mesh/rest_positions");

  const std::string tets_where = h5 + ":/mesh/tets";
  Hid tets = create_dataset(mesh.get(), "tets", H5T_STD_I32LE, num_tets, 4, tets_where);
  const auto sorted_tet_vertices = permute_rows(layout.tet_vertices, tet_order, 4);
  write_rows(tets.get(), collective_transfer.get(), sorted_tet_ids, 4,
             std::span<const global_index_t>(sorted_tet_vertices), tets_where);
}

void FrameWriter::Impl::write_vertex_dataset(hid_t group, const char* name,
                                             std::span<const double> sorted_rows,
                                             const std::string& where) {
  Hid dataset = create_dataset(group, name, H5T_IEEE_F64LE, num_vertices, 3, where);
  write_rows(dataset.get(), collective_transfer.get(), sorted_vertex_ids, 3, sorted_rows, where);
}

void FrameWriter::Impl::write_frame(int frame, double time, std::span<const double> owned_positions,
                                    std::span<const double> owned_velocities) {
  const std::size_t owned_values = 3 * sorted_vertex_ids.size();
  verify_on_every_rank(
      comm,
      frame >= 0 && frame <= kLastFrame && owned_positions.size() == owned_values &&
          owned_velocities.size() == owned_values,
      detail::concat("FrameWriter::write_frame(", frame, "): the frame must be in [0, ", kLastFrame,
                     "] and come with 3 positions and 3 velocities per owned vertex"));
  const std::string h5 = (dir / kH5Name).string();
  const std::string group_path = "/frames/" + frame_name(frame);
  const std::string where = h5 + ":" + group_path;
  {
    Hid group =
        owned(H5Gcreate2(file.get(), group_path.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
              H5Gclose, "H5Gcreate2", where);

    const std::string time_where = where + " attribute time";
    Hid scalar = owned(H5Screate(H5S_SCALAR), H5Sclose, "H5Screate", time_where);
    Hid time_attribute = owned(
        H5Acreate2(group.get(), "time", H5T_IEEE_F64LE, scalar.get(), H5P_DEFAULT, H5P_DEFAULT),
        H5Aclose, "H5Acreate2", time_where);
    check(H5Awrite(time_attribute.get(), H5T_NATIVE_DOUBLE, &time), "H5Awrite", time_where);

    const auto sorted_positions = permute_rows(owned_positions, vertex_order, 3);
    write_vertex_dataset(group.get(), "positions", sorted_positions, where + "/positions");
    std::vector<double> sorted_displacements(sorted_positions.size());
    for (std::size_t k = 0; k < sorted_positions.size(); ++k)
      sorted_displacements[k] = sorted_positions[k] - sorted_rest_positions[k];
    write_vertex_dataset(group.get(), "displacement", sorted_displacements,
                         where + "/displacement");
    write_vertex_dataset(group.get(), "velocity", permute_rows(owned_velocities, vertex_order, 3),
                         where + "/velocity");
  }
  check(H5Fflush(file.get(), H5F_SCOPE_GLOBAL), "H5Fflush", h5);

  // The index names the frame only once its data is in the file.
  int error = 0;
  if (rank == 0) {
    xdmf_grids += xdmf_grid(frame, time, num_vertices, num_tets, xdmf_grids.empty());
    error = write_file_atomically(dir / kXdmfName, xdmf_document(xdmf_grids));
  }
  throw_on_every_rank_if_failed(comm, error,
                                detail::concat("cannot write ", (dir / kXdmfName).string()));
}

FrameWriter::FrameWriter(MPI_Comm comm, const std::string& dir, const FrameWriterLayout& layout,
                         int resume_after)
    : impl_(std::make_unique<Impl>(comm, dir, layout, resume_after)) {}

FrameWriter::~FrameWriter() = default;

void FrameWriter::write_frame(int frame, double time, std::span<const double> owned_positions,
                              std::span<const double> owned_velocities) {
  impl_->write_frame(frame, time, owned_positions, owned_velocities);
}

std::string FrameWriter::h5_path() const { return (impl_->dir / kH5Name).string(); }

std::string FrameWriter::xdmf_path() const { return (impl_->dir / kXdmfName).string(); }

}  // namespace descent

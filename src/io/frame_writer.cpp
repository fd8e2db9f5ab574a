// Frames written by every rank into one HDF5 file through MPI-IO, and the XDMF
// index that rank 0 rewrites beside it after each frame. The rows each rank
// owns are first routed to the rank whose block holds them (BlockRouting);
// each rank then writes its block of every dataset as one hyperslab, without
// collective buffering (io/hdf5_blocks.hpp, independent_transfer, says why).
#include "io/frame_writer.hpp"

#include <hdf5.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <optional>
#include <sstream>
#include <system_error>
#include <vector>

#include "comm/collective_error.hpp"
#include "common/block_range.hpp"
#include "common/error.hpp"
#include "io/block_routing.hpp"
#include "io/hdf5_blocks.hpp"
#include "io/hdf5_handle.hpp"
#include "io/hdf5_rows.hpp"
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

// A continued run writes on into DIR/frames.h5, which must be there and be
// HDF5 (every rank asks; the answers are alike on a shared file system).
void verify_resumable(const std::string& h5) {
  std::error_code ignored;
  if (!fs::is_regular_file(h5, ignored))
    throw InputError(h5 + ": missing: --restart continues the run whose output holds it");
  hdf5::quiet_errors();
  if (H5Fis_hdf5(h5.c_str()) <= 0)
    throw InputError(h5 + ": not an HDF5 file: --restart cannot continue its frames");
}

// A caller's mistake seen on any rank throws on every rank, so that no rank is
// left waiting in a collective call for one that gave up.
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

bool all_below(std::span<const global_index_t> ids, global_index_t end) {
  return std::all_of(ids.begin(), ids.end(),
                     [&](global_index_t id) { return id >= 0 && id < end; });
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
                      int tet_id_bytes, bool first) {
  const std::string group = std::string("/frames/") + frame_name(frame);
  std::ostringstream grid;
  grid << "      <Grid Name=\"frame_" << frame_name(frame) << "\" GridType=\"Uniform\">\n"
       << "        <Time Value=\"" << format_double(time) << "\"/>\n";
  if (first) {
    grid << "        <Topology TopologyType=\"Tetrahedron\" NumberOfElements=\"" << num_tets
         << "\">\n"
         << "          <DataItem Dimensions=\"" << num_tets
         << " 4\" NumberType=\"Int\" Precision=\"" << tet_id_bytes << "\" Format=\"HDF\">"
         << kH5Name << ":/mesh/tets</DataItem>\n"
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

int frame_tet_id_bytes(global_index_t num_vertices) {
  return num_vertices - 1 <= std::numeric_limits<std::int32_t>::max() ? 4 : 8;
}

struct FrameWriter::Impl {
  Impl(MPI_Comm comm, const std::string& dir, const FrameWriterLayout& layout, int resume_after);
  // Routes the layout's rows to their blocks: rest positions into
  // rest_block, tet rows into the returned tet block; throws LogicError on
  // every rank unless the layout covers every vertex and tet exactly once.
  std::vector<global_index_t> route_layout(const FrameWriterLayout& layout);
  // Resuming: drops frames after `last` from the file (a killed run may have
  // written past its last checkpoint) and rebuilds the XDMF list up to it.
  void resume(int last);
  void create_output_directory() const;
  void write_mesh(std::span<const global_index_t> tet_block, global_index_t first_tet);
  void write_frame(int frame, double time, std::span<const double> owned_positions,
                   std::span<const double> owned_velocities);
  // Creates `name` in `group` and writes this rank's block of rows.
  void write_vertex_block(hid_t group, const char* name, std::span<const double> block,
                          const std::string& where);

  MPI_Comm comm;  // the caller's; it outlives the writer
  int rank = 0;
  int size = 1;
  fs::path dir;
  global_index_t num_vertices;
  global_index_t num_tets;
  std::size_t num_owned;  // rows of the caller's frame arrays
  // Rest positions of this rank's unused vertices, sent with every frame
  // (zero velocity) so that their block rows are filled like any other.
  std::vector<double> unused_rest_positions;
  // Owned then unused vertices of this rank, to the vertex blocks.
  std::optional<BlockRouting> vertex_routing;
  // This rank's block of vertex rows, 3 doubles per row, in id order.
  std::vector<double> rest_block, positions_block, displacement_block, velocity_block;
  // Bytes per vertex id in /mesh/tets: 4 where every id fits (half the
  // bytes of the mesh's largest array to write at set-up), else 8.
  int tet_id_bytes = 8;
  std::string xdmf_grids;  // rank 0: one <Grid> per written frame
  // Released in reverse order of declaration: the transfer list, then the file.
  Hid file;
  Hid block_transfer;
};

FrameWriter::Impl::Impl(MPI_Comm comm_, const std::string& dir_, const FrameWriterLayout& layout,
                        int resume_after)
    : comm(comm_),
      dir(dir_),
      num_vertices(layout.num_global_vertices),
      num_tets(layout.num_global_tets),
      num_owned(layout.owned_vertex_ids.size()),
      unused_rest_positions(layout.unused_rest_positions.begin(),
                            layout.unused_rest_positions.end()) {
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const std::vector<global_index_t> tet_block = route_layout(layout);

  create_output_directory();
  const std::string h5 = (dir / kH5Name).string();
  if (resume_after >= 0) verify_resumable(h5);
  {
    Hid access = hdf5::mpio_access(comm, h5);
    // Default format bounds on purpose: the newest superblock marks a file as
    // open for writing, and a killed run would leave it unreadable without h5clear.
    file = resume_after >= 0
               ? owned(H5Fopen(h5.c_str(), H5F_ACC_RDWR, access.get()), H5Fclose, "H5Fopen", h5)
               : owned(H5Fcreate(h5.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, access.get()), H5Fclose,
                       "H5Fcreate", h5);
  }
  block_transfer = hdf5::independent_transfer(h5);
  if (resume_after >= 0) {
    resume(resume_after);
    return;
  }

  write_mesh(tet_block, BlockRange(num_tets, size).begin(rank));
  // Created empty; each frame adds its group here.
  Hid frames = owned(H5Gcreate2(file.get(), "/frames", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                     H5Gclose, "H5Gcreate2", h5 + ":/frames");
  check(H5Fflush(file.get(), H5F_SCOPE_GLOBAL), "H5Fflush", h5);
}

// Sizes and id ranges are checked first (a vertex id out of range has no
// block to go to); the routing then counts what reaches each block, which
// finds any row missing or given twice, on whichever ranks.
std::vector<global_index_t> FrameWriter::Impl::route_layout(const FrameWriterLayout& layout) {
  const std::string mistake =
      detail::concat("FrameWriter for ", dir.string(),
                     ": the layout must give every vertex and tet to exactly one rank, with ids in "
                     "range and 3 positions or 4 vertex ids per row");
  const bool shapes_ok =
      num_vertices >= 0 && num_tets >= 0 &&
      layout.owned_rest_positions.size() == 3 * layout.owned_vertex_ids.size() &&
      layout.unused_rest_positions.size() == 3 * layout.unused_vertex_ids.size() &&
      layout.tet_vertices.size() == 4 * layout.tet_ids.size() &&
      all_below(layout.owned_vertex_ids, num_vertices) &&
      all_below(layout.unused_vertex_ids, num_vertices) && all_below(layout.tet_ids, num_tets) &&
      all_below(layout.tet_vertices, num_vertices);
  verify_on_every_rank(comm, shapes_ok, mistake);

  std::vector<global_index_t> vertex_ids(layout.owned_vertex_ids.begin(),
                                         layout.owned_vertex_ids.end());
  vertex_ids.insert(vertex_ids.end(), layout.unused_vertex_ids.begin(),
                    layout.unused_vertex_ids.end());
  vertex_routing.emplace(comm, BlockRange(num_vertices, size), vertex_ids);
  BlockRouting tet_routing(comm, BlockRange(num_tets, size), layout.tet_ids);
  if (!vertex_routing->covers_each_row_once() || !tet_routing.covers_each_row_once())
    throw LogicError(mistake);  // both flags are the same on every rank

  std::vector<double> rest(layout.owned_rest_positions.begin(), layout.owned_rest_positions.end());
  rest.insert(rest.end(), unused_rest_positions.begin(), unused_rest_positions.end());
  const std::size_t block_values = 3 * static_cast<std::size_t>(vertex_routing->num_rows());
  rest_block.resize(block_values);
  vertex_routing->route<double>(rest, 3, rest_block);
  positions_block.resize(block_values);
  displacement_block.resize(block_values);
  velocity_block.resize(block_values);

  std::vector<global_index_t> tet_block(4 * static_cast<std::size_t>(tet_routing.num_rows()));
  tet_routing.route<global_index_t>(layout.tet_vertices, 4, tet_block);
  return tet_block;
}

namespace {
herr_t collect_name(hid_t, const char* name, const H5L_info_t*, void* names) {
  static_cast<std::vector<std::string>*>(names)->emplace_back(name);
  return 0;
}

// A frame group kept by a continued run: its number and time.
struct KeptFrame {
  std::string name;
  double time = 0;
};

// The time attribute of a frame group: one finite float.
double frame_time(hid_t frames, const std::string& name, const std::string& where) {
  if (H5Aexists_by_name(frames, name.c_str(), "time", H5P_DEFAULT) <= 0)
    throw InputError(where + ": no attribute time");
  Hid attribute = owned(H5Aopen_by_name(frames, name.c_str(), "time", H5P_DEFAULT, H5P_DEFAULT),
                        H5Aclose, "H5Aopen_by_name", where + " attribute time");
  Hid type = owned(H5Aget_type(attribute.get()), H5Tclose, "H5Aget_type", where);
  Hid space = owned(H5Aget_space(attribute.get()), H5Sclose, "H5Aget_space", where);
  double time = 0;
  if (H5Tget_class(type.get()) != H5T_FLOAT || H5Sget_simple_extent_npoints(space.get()) != 1)
    throw InputError(where + ": attribute time is not one float");
  check(H5Aread(attribute.get(), H5T_NATIVE_DOUBLE, &time), "H5Aread", where + " attribute time");
  if (!std::isfinite(time)) throw InputError(where + ": attribute time is not finite");
  return time;
}

// What a continued run finds in frames.h5, checked before it changes
// anything: this run's mesh, and under /frames only groups named by six
// digits; those up to frame `last` (kept) with a finite time and [V, 3]
// float datasets. Every rank reads the same metadata and throws alike.
// Returns the kept frames; `later` receives the names of the others.
std::vector<KeptFrame> verify_frames_file(hid_t file, const std::string& h5,
                                          global_index_t vertices, global_index_t tets, int last,
                                          std::vector<std::string>& later, int& tet_id_bytes) {
  const hdf5::RowsShape vertex_rows{3, H5T_FLOAT, "V", "3 values per vertex",
                                    "frames hold float64 values"};
  const hdf5::RowsShape tet_rows{4, H5T_INTEGER, "T", "4 vertex ids per tet",
                                 "vertex ids must be integers"};
  auto expect_rows = [&](const std::string& name, const hdf5::RowsShape& shape,
                         global_index_t rows) {
    hdf5::RowsDataset set = hdf5::open_rows_dataset(file, h5, name, shape);
    if (set.rows != rows)
      throw InputError(detail::concat(h5, ": ", name, " has ", set.rows,
                                      " rows, but this run's mesh has ", rows,
                                      shape.cols == 4 ? " tets" : " vertices",
                                      ": --restart continues the run that wrote this file"));
    return set;
  };
  expect_rows("/mesh/rest_positions", vertex_rows, vertices);
  {
    const hdf5::RowsDataset tet_set = expect_rows("/mesh/tets", tet_rows, tets);
    Hid type =
        owned(H5Dget_type(tet_set.dataset.get()), H5Tclose, "H5Dget_type", h5 + ":/mesh/tets");
    tet_id_bytes = static_cast<int>(H5Tget_size(type.get()));  // as an earlier build wrote them
  }
  if (!hdf5::object_exists(file, "/frames"))
    throw InputError(h5 + ": no group /frames: not the frames of a descent run");
  Hid frames = owned(H5Gopen2(file, "/frames", H5P_DEFAULT), H5Gclose, "H5Gopen2", h5 + ":/frames");
  std::vector<std::string> names;  // zero-padded, so by name is by frame
  check(H5Literate(frames.get(), H5_INDEX_NAME, H5_ITER_INC, nullptr, collect_name, &names),
        "H5Literate", h5 + ":/frames");
  std::vector<KeptFrame> kept;
  for (const std::string& name : names) {
    const std::string where = h5 + ":/frames/" + name;
    const bool six_digits = name.size() == 6 && std::all_of(name.begin(), name.end(), [](char c) {
                              return c >= '0' && c <= '9';
                            });
    if (!six_digits)
      throw InputError(where + ": not a frame (frames are named by six digits, e.g. 000010)");
    if (std::stoi(name) > last) {
      later.push_back(name);
      continue;
    }
    for (const char* dataset : {"positions", "displacement", "velocity"})
      expect_rows("/frames/" + name + "/" + dataset, vertex_rows, vertices);
    kept.push_back({name, frame_time(frames.get(), name, where)});
  }
  return kept;
}

}  // namespace

void FrameWriter::Impl::resume(int last) {
  const std::string h5 = (dir / kH5Name).string();
  std::vector<std::string> later;
  const std::vector<KeptFrame> kept =
      verify_frames_file(file.get(), h5, num_vertices, num_tets, last, later, tet_id_bytes);
  Hid frames =
      owned(H5Gopen2(file.get(), "/frames", H5P_DEFAULT), H5Gclose, "H5Gopen2", h5 + ":/frames");
  for (const std::string& name : later)
    check(H5Ldelete(frames.get(), name.c_str(), H5P_DEFAULT), "H5Ldelete", h5 + ":/frames/" + name);
  if (rank == 0)
    for (const KeptFrame& frame : kept)
      xdmf_grids += xdmf_grid(std::stoi(frame.name), frame.time, num_vertices, num_tets,
                              tet_id_bytes, xdmf_grids.empty());
  check(H5Fflush(file.get(), H5F_SCOPE_GLOBAL), "H5Fflush", h5);
  int error = 0;
  if (rank == 0) error = write_file_atomically(dir / kXdmfName, xdmf_document(xdmf_grids));
  throw_if_rank0_failed(comm, error, detail::concat("cannot write ", (dir / kXdmfName).string()));
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
  throw_if_rank0_failed(comm, error,
                        detail::concat("cannot prepare the output directory ", dir.string()));
}

void FrameWriter::Impl::write_mesh(std::span<const global_index_t> tet_block,
                                   global_index_t first_tet) {
  const std::string h5 = (dir / kH5Name).string();
  Hid mesh = owned(H5Gcreate2(file.get(), "/mesh", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose,
                   "H5Gcreate2", h5 + ":/mesh");
  write_vertex_block(mesh.get(), "rest_positions", rest_block, h5 + ":/mesh/rest_positions");
  const std::string tets_where = h5 + ":/mesh/tets";
  const global_index_t rows = static_cast<global_index_t>(tet_block.size() / 4);
  tet_id_bytes = frame_tet_id_bytes(num_vertices);
  if (tet_id_bytes == 8) {  // global vertex ids of a cluster-sized mesh pass 2^31
    Hid tets =
        hdf5::create_rows_dataset(mesh.get(), "tets", H5T_STD_I64LE, num_tets, 4, tets_where);
    hdf5::write_block(tets.get(), block_transfer.get(), H5T_NATIVE_INT64, first_tet, rows, 4,
                      tet_block.data(), tets_where);
    return;
  }
  // Narrowed here rather than by HDF5's conversion, which would write
  // through its conversion buffer.
  const std::vector<std::int32_t> narrow(tet_block.begin(), tet_block.end());
  Hid tets = hdf5::create_rows_dataset(mesh.get(), "tets", H5T_STD_I32LE, num_tets, 4, tets_where);
  hdf5::write_block(tets.get(), block_transfer.get(), H5T_NATIVE_INT32, first_tet, rows, 4,
                    narrow.data(), tets_where);
}

void FrameWriter::Impl::write_vertex_block(hid_t group, const char* name,
                                           std::span<const double> block,
                                           const std::string& where) {
  Hid dataset = hdf5::create_rows_dataset(group, name, H5T_IEEE_F64LE, num_vertices, 3, where);
  hdf5::write_block(dataset.get(), block_transfer.get(), H5T_NATIVE_DOUBLE,
                    vertex_routing->first_row(), vertex_routing->num_rows(), 3, block.data(),
                    where);
}

void FrameWriter::Impl::write_frame(int frame, double time, std::span<const double> owned_positions,
                                    std::span<const double> owned_velocities) {
  const std::size_t owned_values = 3 * num_owned;
  verify_on_every_rank(
      comm,
      frame >= 0 && frame <= kLastFrame && owned_positions.size() == owned_values &&
          owned_velocities.size() == owned_values,
      detail::concat("FrameWriter::write_frame(", frame, "): the frame must be in [0, ", kLastFrame,
                     "] and come with 3 positions and 3 velocities per owned vertex"));

  // One message per destination with both arrays: per row 3 positions then
  // 3 velocities. Unused vertices go at rest, with zero velocity.
  constexpr std::size_t kRowBytes = 6 * sizeof(double);
  BlockRouting& routing = *vertex_routing;
  std::vector<std::byte>& send = routing.send_buffer();
  send.resize(routing.num_sent() * kRowBytes);
  const double zero_velocity[3] = {0, 0, 0};
  for (std::size_t k = 0; k < routing.num_sent(); ++k) {
    std::byte* row = &send[routing.send_slot(k) * kRowBytes];
    const bool unused = k >= num_owned;
    const double* position =
        unused ? &unused_rest_positions[3 * (k - num_owned)] : &owned_positions[3 * k];
    std::memcpy(row, position, 3 * sizeof(double));
    std::memcpy(row + 3 * sizeof(double), unused ? zero_velocity : &owned_velocities[3 * k],
                3 * sizeof(double));
  }
  routing.exchange_rows(kRowBytes);
  const std::vector<std::byte>& received = routing.receive_buffer();
  for (std::size_t j = 0; j < routing.num_received(); ++j) {
    const std::size_t row = routing.block_row(j);
    std::memcpy(&positions_block[3 * row], &received[j * kRowBytes], 3 * sizeof(double));
    std::memcpy(&velocity_block[3 * row], &received[j * kRowBytes + 3 * sizeof(double)],
                3 * sizeof(double));
  }
  for (std::size_t k = 0; k < positions_block.size(); ++k)
    displacement_block[k] = positions_block[k] - rest_block[k];

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

    write_vertex_block(group.get(), "positions", positions_block, where + "/positions");
    write_vertex_block(group.get(), "displacement", displacement_block, where + "/displacement");
    write_vertex_block(group.get(), "velocity", velocity_block, where + "/velocity");
  }
  check(H5Fflush(file.get(), H5F_SCOPE_GLOBAL), "H5Fflush", h5);

  // The index names the frame only once its data is in the file.
  int error = 0;
  if (rank == 0) {
    xdmf_grids += xdmf_grid(frame, time, num_vertices, num_tets, tet_id_bytes, xdmf_grids.empty());
    error = write_file_atomically(dir / kXdmfName, xdmf_document(xdmf_grids));
  }
  throw_if_rank0_failed(comm, error, detail::concat("cannot write ", (dir / kXdmfName).string()));
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

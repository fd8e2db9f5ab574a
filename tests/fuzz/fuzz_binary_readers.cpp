// Fuzzing of the binary readers: HDF5 meshes (read_mesh_h5), partition files
// (read_partition_piece, distribute_piece) and checkpoints (read_checkpoint).
// Valid files are made here, then mutated with a fixed seed; every reader
// must end in a descent::Error on every rank or accept the file and keep
// what it promises, never crash, hang, leak or hit undefined behaviour.
//
//   fuzz_binary_readers ITERATIONS SEED MAX_SECONDS      (under mpiexec, any rank count)
//
// HDF5 files are mutated by rank 0 through the HDF5 API (values, shapes,
// types, missing objects, attributes, a dataset replaced by a group), then
// every rank reads them, as a run does. Checkpoints are mutated as bytes by
// each rank: any change to a file must be refused; and with the checksum
// forged to match, the payload parser must refuse or read consistent sizes.
#include <hdf5.h>
#include <mpi.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "app/partition_command.hpp"
#include "common/error.hpp"
#include "common/xxhash64.hpp"
#include "io/checkpoint.hpp"
#include "io/mesh_h5.hpp"
#include "io/scene.hpp"
#include "partition/partition_file.hpp"
#include "tests/fuzz/mutator.hpp"
#include "tests/mpi/file_bytes.hpp"

namespace descent {
namespace {

namespace fs = std::filesystem;
using fuzz::Rng;

int world_rank() {
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  return rank;
}

int world_size() {
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  return size;
}

[[noreturn]] void finding(const std::string& what) {
  std::fprintf(stderr, "fuzz finding on rank %d: %s\n", world_rank(), what.c_str());
  std::abort();
}

// ----- HDF5 mutations (rank 0, serial HDF5 on a closed file) -----

const char* const kDatasets[] = {"/mesh/positions",        "/mesh/tets",
                                 "/partition/tet_offsets", "/partition/tet_ids",
                                 "/partition/tets",        "/partition/surface_faces",
                                 "/partition/part_stats"};
const char* const kAttributes[] = {"num_parts", "cut_faces", "imbalance", "method"};

std::vector<hsize_t> dims_of(hid_t dataset) {
  const hid_t space = H5Dget_space(dataset);
  std::vector<hsize_t> dims(std::max(H5Sget_simple_extent_ndims(space), 0));
  H5Sget_simple_extent_dims(space, dims.data(), nullptr);
  H5Sclose(space);
  return dims;
}

// The values of a dataset as doubles (int64 values convert exactly here).
std::vector<double> values_of(hid_t dataset, const std::vector<hsize_t>& dims) {
  std::size_t count = 1;
  for (hsize_t d : dims) count *= d;
  std::vector<double> values(count);
  if (count > 0) H5Dread(dataset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data());
  return values;
}

// A dataset of `dims` and `type` at `name`, replacing what is there.
void replace_dataset(hid_t file, const std::string& name, hid_t type,
                     const std::vector<hsize_t>& dims, const std::vector<double>& values) {
  H5Ldelete(file, name.c_str(), H5P_DEFAULT);
  const hid_t space = dims.empty()
                          ? H5Screate(H5S_SCALAR)
                          : H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr);
  const hid_t set =
      H5Dcreate2(file, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  std::size_t count = 1;
  for (hsize_t d : dims) count *= d;
  std::vector<double> data(count, 0.0);
  std::copy_n(values.begin(), std::min(count, values.size()), data.begin());
  if (set >= 0 && count > 0 && H5Tget_class(type) != H5T_STRING)
    H5Dwrite(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data());
  if (set >= 0) H5Dclose(set);
  H5Sclose(space);
}

double special_value(Rng& rng, const std::vector<double>& values, double rows) {
  switch (rng.below(9)) {
    case 0:
      return -1;
    case 1:
      return 0;
    case 2:
      return rows;
    case 3:
      return rows + 1;
    case 4:
      return 4.0e18;
    case 5:
      return std::nan("");
    case 6:
      return INFINITY;
    case 7:
      return values.empty() ? 1 : values[rng.below(values.size())];
    default:
      return values.empty() ? 1 : values[rng.below(values.size())] + 1;
  }
}

void mutate_dataset(hid_t file, const std::string& name, Rng& rng) {
  const hid_t set = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
  if (set < 0) return;
  const hid_t file_type = H5Dget_type(set);
  const hid_t type = H5Tcopy(file_type);
  H5Tclose(file_type);
  std::vector<hsize_t> dims = dims_of(set);
  std::vector<double> values = values_of(set, dims);
  H5Dclose(set);
  const double rows = dims.empty() ? 0 : static_cast<double>(dims[0]);
  switch (rng.below(6)) {
    case 0:
    case 1:  // a few values
      for (std::size_t k = 0, n = 1 + rng.below(3); k < n && !values.empty(); ++k)
        values[rng.below(values.size())] = special_value(rng, values, rows);
      replace_dataset(file, name, type, dims, values);
      break;
    case 2: {  // another shape
      if (dims.empty() || rng.below(4) == 0) {
        dims = std::vector<hsize_t>(rng.below(4), 2);
      } else {
        hsize_t& d = dims[rng.below(dims.size())];
        d = rng.below(2) ? d + 1 + rng.below(3) : (d > 0 ? d - 1 - rng.below(d) : 0);
      }
      replace_dataset(file, name, type, dims, values);
      break;
    }
    case 3: {  // another type
      const hid_t types[] = {H5T_IEEE_F64LE, H5T_IEEE_F32LE, H5T_STD_I64LE, H5T_STD_U64LE,
                             H5T_STD_I8LE,   H5T_STD_U8BE,   H5T_STD_I32BE, H5T_C_S1};
      replace_dataset(file, name, types[rng.below(std::size(types))], dims, values);
      break;
    }
    case 4:  // missing
      H5Ldelete(file, name.c_str(), H5P_DEFAULT);
      break;
    default:  // a group in its place
      H5Ldelete(file, name.c_str(), H5P_DEFAULT);
      H5Gclose(H5Gcreate2(file, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
  }
  H5Tclose(type);
}

void mutate_attribute(hid_t file, Rng& rng) {
  const hid_t group = H5Gopen2(file, "/partition", H5P_DEFAULT);
  if (group < 0) return;
  const char* name = kAttributes[rng.below(std::size(kAttributes))];
  H5Adelete(group, name);
  const std::size_t kind = rng.below(5);
  if (kind < 4) {
    const hsize_t two = 2;
    const hid_t space = kind == 3 ? H5Screate_simple(1, &two, nullptr) : H5Screate(H5S_SCALAR);
    hid_t type = kind == 0   ? H5Tcopy(H5T_STD_I64LE)
                 : kind == 1 ? H5Tcopy(H5T_IEEE_F64LE)
                             : H5Tcopy(H5T_C_S1);
    if (kind == 2) H5Tset_size(type, 5);
    const hid_t attribute = H5Acreate2(group, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
    const double values[2] = {special_value(rng, {1.0, 2.0}, world_size()), 1.0};
    if (kind == 2)
      H5Awrite(attribute, type, rng.below(2) ? "metis" : "x\0yz");
    else
      H5Awrite(attribute, H5T_NATIVE_DOUBLE, values);
    H5Aclose(attribute);
    H5Tclose(type);
    H5Sclose(space);
  }  // else: left missing
  H5Gclose(group);
}

void mutate_h5(const std::string& path, Rng& rng) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  if (file < 0) finding("cannot open the copy to mutate");
  for (std::size_t k = 0, n = 1 + rng.below(3); k < n; ++k) {
    const std::size_t what = rng.below(12);
    if (what < 9)
      mutate_dataset(file, kDatasets[rng.below(std::size(kDatasets))], rng);
    else if (what < 11)
      mutate_attribute(file, rng);
    else
      H5Ldelete(file, rng.below(2) ? "/partition" : "/mesh", H5P_DEFAULT);
  }
  H5Fclose(file);
}

// ----- the readers, on every rank -----

// Runs `read` on every rank; returns whether every rank accepted. A rank's
// descent::Error is a refusal; anything else escapes and aborts.
template <class Read>
bool every_rank_accepts(Read&& read) {
  int accepted = 1;
  try {
    read();
  } catch (const Error&) {
    accepted = 0;
  }
  MPI_Allreduce(MPI_IN_PLACE, &accepted, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
  return accepted == 1;
}

void check_mesh_promises(const MeshSlice& slice) {
  for (const global_index_t v : slice.tets)
    if (v < 0 || v >= slice.num_global_vertices)
      finding("read_mesh_h5 accepted a vertex id out of range");
  for (const double x : slice.positions)
    if (!std::isfinite(x)) finding("read_mesh_h5 accepted a non-finite coordinate");
}

void check_piece_promises(const PartitionPiece& piece) {
  for (const global_index_t id : piece.tets.ids)
    if (id < 0 || id >= piece.num_global_tets)
      finding("a partition piece holds a tet id out of range");
  for (const global_index_t v : piece.tets.vertices)
    if (v < 0 || v >= piece.num_global_vertices)
      finding("a partition piece holds a vertex id out of range");
  global_index_t tets = piece.tets.num_tets();
  MPI_Allreduce(MPI_IN_PLACE, &tets, 1, MPI_INT64_T, MPI_SUM, MPI_COMM_WORLD);
  if (tets != piece.num_global_tets) finding("the parts do not hold every tet once");
}

struct Counts {
  long accepted = 0, refused = 0;
};

void read_h5_everywhere(const std::string& path, Counts& mesh, Counts& partition) {
  if (every_rank_accepts([&] { check_mesh_promises(read_mesh_h5(MPI_COMM_WORLD, path)); }))
    ++mesh.accepted;
  else
    ++mesh.refused;
  PartitionPiece piece;
  const bool read = every_rank_accepts([&] {
    piece = read_partition_piece(MPI_COMM_WORLD, path);
    check_piece_promises(piece);
  });
  // A piece that reads must also build a mesh, or refuse on every rank.
  const bool built = read && every_rank_accepts([&] {
                       distribute_piece(MPI_COMM_WORLD, std::move(piece), path, "rcm");
                     });
  ++(built ? partition.accepted : partition.refused);
}

// ----- checkpoints (each rank its own file) -----

using testing::read_bytes;
using testing::write_bytes;

Checkpoint sample_checkpoint() {
  Checkpoint c;
  c.rank = world_rank();
  c.num_ranks = world_size();
  c.frame = 7;
  c.num_global_vertices = 12;
  c.num_global_tets = 20;
  c.identity = "material.young = 100000\n";
  for (int k = 0; k < 12; ++k) {
    c.q.push_back(0.1 * k);
    c.v.push_back(-0.2 * k);
    c.v_prev.push_back(0.3 * k);
  }
  c.interpolants = {0.25, 0.5};
  return c;
}

std::vector<char> mutate_bytes(std::vector<char> bytes, const std::vector<char>& other, Rng& rng) {
  for (std::size_t k = 0, n = 1 + rng.below(3); k < n; ++k) {
    const std::size_t at = bytes.empty() ? 0 : rng.below(bytes.size());
    switch (rng.below(6)) {
      case 0:
        if (!bytes.empty()) bytes[at] = static_cast<char>(bytes[at] ^ (1 << rng.below(8)));
        break;
      case 1:
        if (!bytes.empty()) bytes[at] = static_cast<char>(rng.next());
        break;
      case 2:
        bytes.resize(at);
        break;
      case 3:
        bytes.insert(bytes.begin() + static_cast<std::ptrdiff_t>(at), 1 + rng.below(16),
                     static_cast<char>(rng.next()));
        break;
      case 4:  // eight bytes of a large or negative count
        for (std::size_t b = 0; b < 8 && at + b < bytes.size(); ++b)
          bytes[at + b] = static_cast<char>(b == 7 ? (rng.below(2) ? 0x7f : 0xff) : rng.next());
        break;
      default:  // a stretch of another rank's file
        if (!other.empty() && !bytes.empty()) {
          const std::size_t from = rng.below(other.size());
          for (std::size_t b = 0; b < 24 && at + b < bytes.size() && from + b < other.size(); ++b)
            bytes[at + b] = other[from + b];
        }
    }
  }
  return bytes;
}

// Makes the trailer the checksum of the rest, so the payload parser is reached.
void forge_checksum(std::vector<char>& bytes) {
  if (bytes.size() < 8) return;
  XxHash64 hash;
  hash.update(bytes.data(), bytes.size() - 8);
  const std::uint64_t digest = hash.digest();
  std::memcpy(bytes.data() + bytes.size() - 8, &digest, 8);
}

void fuzz_checkpoint(const std::string& dir, const std::vector<char>& good,
                     const std::vector<char>& other, Rng& rng, Counts& raw, Counts& forged) {
  const std::string path = dir + "/mutant-" + std::to_string(world_rank()) + ".bin";
  std::vector<char> bytes = mutate_bytes(good, other, rng);
  write_bytes(path, bytes);
  try {
    read_checkpoint(path, world_rank(), world_size());
    if (bytes != good) finding("read_checkpoint accepted a changed file");
    ++raw.accepted;
  } catch (const InputError&) {
    ++raw.refused;
  }
  forge_checksum(bytes);
  write_bytes(path, bytes);
  try {
    const Checkpoint c = read_checkpoint(path, world_rank(), world_size());
    if (c.v.size() != c.q.size() || c.v_prev.size() != c.q.size())
      finding("a forged checkpoint read with inconsistent sizes");
    ++forged.accepted;
  } catch (const InputError&) {
    ++forged.refused;
  }
}

int run(long iterations, std::uint64_t seed, double max_seconds) {
  const int rank = world_rank();
  // A directory every rank names alike: rank 0's process id.
  long id = static_cast<long>(getpid());
  MPI_Bcast(&id, 1, MPI_LONG, 0, MPI_COMM_WORLD);
  const std::string dir =
      (fs::temp_directory_path() / ("descent_fuzz_binary_" + std::to_string(id))).string();
  if (rank == 0) fs::create_directories(dir);
  MPI_Barrier(MPI_COMM_WORLD);

  // A valid partition file for this rank count; its /mesh is a valid mesh file.
  Scene scene;
  scene.mesh.generator = "box";
  scene.mesh.box.cells = {3, 2, 2};
  PartitionOptions options;
  options.parts = world_size();
  options.out_file = dir + "/pieces.h5";
  options.quiet = true;
  run_partition(MPI_COMM_WORLD, scene, options);
  const std::string mutant = dir + "/mutant.h5";
  Counts mesh, partition, raw, forged;
  read_h5_everywhere(options.out_file, mesh, partition);  // the valid file reads
  if (mesh.accepted != 1 || partition.accepted != 1) finding("the valid partition file is refused");

  const std::string checkpoint = dir + "/checkpoint/rank-" + std::to_string(rank) + ".bin";
  write_checkpoint(checkpoint, sample_checkpoint());
  const std::vector<char> good = read_bytes(checkpoint);
  Checkpoint other_rank = sample_checkpoint();
  other_rank.rank = (rank + 1) % world_size();
  other_rank.q[0] = 42;
  write_checkpoint(checkpoint + ".other", other_rank);
  const std::vector<char> other = read_bytes(checkpoint + ".other");

  Rng rng(seed + 7919 * static_cast<std::uint64_t>(rank));  // checkpoints: per rank
  Rng h5_rng(seed);                                         // HDF5 files: rank 0's
  const auto start = std::chrono::steady_clock::now();
  long done = 0;
  for (; done < iterations; ++done) {
    int stop = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() >
               max_seconds;
    MPI_Bcast(&stop, 1, MPI_INT, 0, MPI_COMM_WORLD);
    if (stop) break;
    // One HDF5 mutant per 20 checkpoint mutants: an HDF5 round (copy,
    // mutate, two collective reads) costs about 80 ms, a checkpoint one 0.1 ms.
    if (done % 20 == 0) {
      if (rank == 0) {
        fs::copy_file(options.out_file, mutant, fs::copy_options::overwrite_existing);
        mutate_h5(mutant, h5_rng);
      }
      MPI_Barrier(MPI_COMM_WORLD);
      read_h5_everywhere(mutant, mesh, partition);
    }
    fuzz_checkpoint(dir, good, other, rng, raw, forged);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  if (rank == 0) {
    std::printf("%ld iterations on %d rank(s), seed %llu\n", done, world_size(),
                static_cast<unsigned long long>(seed));
    std::printf("  mesh .h5:        %ld accepted, %ld refused\n", mesh.accepted, mesh.refused);
    std::printf("  partition file:  %ld accepted, %ld refused\n", partition.accepted,
                partition.refused);
    std::printf("  checkpoint:      %ld accepted, %ld refused (raw bytes, rank 0)\n", raw.accepted,
                raw.refused);
    std::printf("  checkpoint:      %ld accepted, %ld refused (checksum forged, rank 0)\n",
                forged.accepted, forged.refused);
    fs::remove_all(dir);
  }
  // Too few refusals or acceptances would mean the mutations miss the readers.
  if (done >= 100 && (mesh.refused == 0 || partition.refused == 0 || forged.refused == 0))
    finding("a reader refused no mutant: the mutations do not reach it");
  return 0;
}

}  // namespace
}  // namespace descent

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // the mutations fail often, by design
  const long iterations = argc > 1 ? std::atol(argv[1]) : 1000;
  const std::uint64_t seed = argc > 2 ? std::strtoull(argv[2], nullptr, 10) : 1;
  const double max_seconds = argc > 3 ? std::atof(argv[3]) : 60;
  const int code = descent::run(iterations, seed, max_seconds);
  MPI_Finalize();
  return code;
}

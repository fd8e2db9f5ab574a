// Per-frame statistics as CSV, written by rank 0 and flushed per row so that a
// run killed mid-way keeps every completed frame.
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <system_error>

#include "comm/collective_error.hpp"
#include "common/error.hpp"
#include "io/frame_writer.hpp"
#include "io/number_text.hpp"

namespace descent {
namespace {

namespace fs = std::filesystem;

constexpr const char* kStatsName = "stats.csv";
constexpr const char* kHeader =
    "frame,sim_time,iterations,rollbacks,alpha,energy,wall_ms,halo_ms,allreduce_ms,stalled,"
    "nonfinite_rollbacks,status,lambda_min,lambda_max,rho,spectrum_steps,error_estimate";

struct CloseFile {
  void operator()(std::FILE* file) const { std::fclose(file); }
};
using FilePtr = std::unique_ptr<std::FILE, CloseFile>;

std::string format_ms(double ms) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3f", ms);
  return text;
}

// Resuming: keeps the header and the rows of frames up to `last` (a killed
// run may have written past its checkpoint). Returns an errno value; EINVAL
// when the file's columns are not the run's.
int keep_rows_up_to(const fs::path& path, const std::string& header, int last) {
  std::ifstream in(path);
  if (!in) return ENOENT;
  std::string line, kept;
  if (!std::getline(in, line) || line + "\n" != header) return EINVAL;
  kept = header;
  while (std::getline(in, line)) {
    if (line.empty() || std::atoi(line.c_str()) > last) break;
    kept += line + "\n";
  }
  in.close();
  const fs::path temporary = path.string() + ".tmp";
  std::ofstream out(temporary, std::ios::trunc);
  out << kept;
  out.close();
  if (!out) return EIO;
  std::error_code renamed;
  fs::rename(temporary, path, renamed);
  return renamed.value();
}

}  // namespace

struct StatsWriter::Impl {
  fs::path path;
  std::size_t extra_columns = 0;
  FilePtr file;  // rank 0 only
};

// Collective over comm: rank 0 tells every rank whether it could open the file,
// so that all ranks throw together instead of the others waiting for rank 0.
StatsWriter::StatsWriter(MPI_Comm comm, const std::string& dir,
                         const std::vector<std::string>& extra_columns, int resume_after)
    : impl_(std::make_unique<Impl>()) {
  impl_->path = fs::path(dir) / kStatsName;
  impl_->extra_columns = extra_columns.size();
  std::string header = kHeader;
  for (const std::string& column : extra_columns) header += "," + column;
  header += "\n";
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  int error = 0;  // errno value on rank 0
  if (rank == 0) {
    std::error_code created;
    fs::create_directories(dir, created);
    if (created) {
      error = created.value();
    } else if (resume_after >= 0) {
      error = keep_rows_up_to(impl_->path, header, resume_after);
      if (error == 0) impl_->file.reset(std::fopen(impl_->path.c_str(), "a"));
      if (error == 0 && !impl_->file) error = errno != 0 ? errno : EIO;
    } else {
      impl_->file.reset(std::fopen(impl_->path.c_str(), "w"));
      if (!impl_->file || std::fputs(header.c_str(), impl_->file.get()) < 0 ||
          std::fflush(impl_->file.get()) != 0)
        error = errno != 0 ? errno : EIO;
    }
  }
  throw_if_rank0_failed(comm, error, "cannot create " + impl_->path.string());
}

StatsWriter::~StatsWriter() = default;

// Not collective: a failure here throws on rank 0 only.
void StatsWriter::write(const FrameStats& row) {
  if (!impl_->file) return;
  DESCENT_VERIFY(row.extra.size() == impl_->extra_columns, "stats row has ", row.extra.size(),
                 " extra values for ", impl_->extra_columns, " extra columns");
  std::string line = detail::concat(
      row.frame, ',', format_double(row.sim_time), ',', row.iterations, ',', row.rollbacks, ',',
      format_double(row.alpha), ',', format_double(row.energy), ',', format_ms(row.wall_ms), ',',
      format_ms(row.halo_ms), ',', format_ms(row.allreduce_ms), ',', row.stalled, ',',
      row.nonfinite_rollbacks, ',', row.status, ',', format_double(row.lambda_min), ',',
      format_double(row.lambda_max), ',', format_double(row.rho), ',', row.spectrum_steps, ',',
      format_double(row.error_estimate));
  for (double value : row.extra) {
    line += ',';
    line += format_double(value);
  }
  line += '\n';
  if (std::fputs(line.c_str(), impl_->file.get()) < 0 || std::fflush(impl_->file.get()) != 0)
    throw InputError(detail::concat("cannot write ", impl_->path.string(), ": ",
                                    std::generic_category().message(errno)));
}

std::string StatsWriter::path() const { return impl_->path.string(); }

}  // namespace descent

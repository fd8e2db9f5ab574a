// descent_extremes: runs cases of the extremes suite for the full sweep
// (jobs/extremes/sweep.py) and prints one JSON object per run on rank 0:
//   mpiexec -n 3 descent_extremes --case dt_1 --models all --precisions float,double
//           --reference-dir DIR
// The distance to the converged state needs a reference per case and model:
// solver.method = "newton" when this build has it (--reference auto or
// newton), else the same case with --reference-factor times the iterations
// (chebyshev), run in double and cached in DIR so every rank count and
// precision compares with the same one.
#include <mpi.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/error.hpp"
#include "run_case.hpp"

namespace {

using namespace descent;
using namespace descent::extremes;

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string item; std::getline(in, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

std::string number(double x) {
  if (!std::isfinite(x)) return std::isnan(x) ? "null" : (x > 0 ? "1e999" : "-1e999");
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", x);
  return text;
}

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (char ch : s) {
    if (ch == '"' || ch == '\\') out += '\\';
    out += ch;
  }
  return out + "\"";
}

// The cached reference of one case and model: the kind that made it and the
// final positions (rank 0 only). Made on the first request, on all ranks.
struct Reference {
  std::string kind;  // "newton" or "chebyshev xK"; empty when none is usable
  Result result;
};

Reference reference_for(MPI_Comm comm, const Case& c, const std::string& dir,
                        const std::string& wanted, int factor) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  const std::filesystem::path path =
      std::filesystem::path(dir) / (c.name + "." + c.scene.material.model + ".ref");
  Reference ref;
  int cached = rank == 0 && std::filesystem::exists(path) ? 1 : 0;
  MPI_Bcast(&cached, 1, MPI_INT, 0, comm);
  if (cached) {
    if (rank == 0) {
      std::ifstream in(path);
      std::getline(in, ref.kind);
      in >> ref.result.bbox_diagonal;
      for (double x; in >> x;) ref.result.positions.push_back(x);
    }
    return ref;
  }
  auto usable = [](const Result& r) { return r.finite && r.failed_frame == 0; };
  if (wanted != "chebyshev") {
    try {
      ref.result = run_case<double>(comm, c, 0, "newton");
      ref.kind = usable(ref.result) ? "newton" : "";
    } catch (const LogicError&) {
      // No newton stepper in this build: every rank throws alike.
      if (wanted == "newton") throw;
    }
  }
  if (ref.kind.empty()) {
    ref.result = run_case<double>(comm, c, factor * c.scene.solver.iterations);
    ref.kind = usable(ref.result) ? detail::concat("chebyshev x", factor) : "";
  }
  if (rank == 0) {
    std::filesystem::create_directories(dir);
    std::ofstream out(path);
    out << ref.kind << "\n";
    out.precision(17);
    out << ref.result.bbox_diagonal << "\n";
    for (double x : ref.result.positions) out << x << "\n";
  }
  return ref;
}

template <class Real>
void run_and_print(MPI_Comm comm, const Case& c, const Reference* ref) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const Result r = run_case<Real>(comm, c);
  if (rank != 0) return;
  double distance = std::numeric_limits<double>::quiet_NaN();
  std::string distance_kind = "none";
  if (c.recovers) {
    distance = r.worst_stretch;
    distance_kind = "max |sigma - 1|";
  } else if (ref && !ref->kind.empty() && r.finite) {
    distance = relative_distance(r, ref->result);
    distance_kind = ref->kind;
  }
  std::printf(
      "{\"case\": %s, \"group\": %s, \"what\": %s, \"model\": %s, \"precision\": %s, "
      "\"ranks\": %d, \"conversion\": %s, \"frames\": %d, \"steps\": %d, \"finite\": %s, "
      "\"state_finite\": %s, "
      "\"failed_frame\": %d, \"failure\": %s, \"iterations\": %ld, \"rollbacks\": %d, "
      "\"nonfinite_rollbacks\": %d, \"stalled_steps\": %d, \"final_alpha\": %s, "
      "\"energy_checked\": %s, \"energy_rises\": %d, \"worst_rise_ratio\": %s, "
      "\"min_det\": %s, \"min_sigma\": %s, \"max_inverted\": %ld, \"final_inverted\": %ld, "
      "\"distance\": %s, \"distance_kind\": %s, \"wall_s\": %s}\n",
      json_string(c.name).c_str(), json_string(c.group).c_str(), json_string(c.what).c_str(),
      json_string(c.scene.material.model).c_str(), sizeof(Real) == 4 ? "\"float\"" : "\"double\"",
      size, c.scene.material.conversion.enabled ? "true" : "false", c.frames, r.steps,
      r.finite ? "true" : "false", r.state_finite ? "true" : "false", r.failed_frame,
      json_string(r.failure).c_str(), r.iterations, r.rollbacks, r.nonfinite_rollbacks,
      r.stalled_steps, number(r.final_alpha).c_str(), r.energy_checked ? "true" : "false",
      r.energy_rises, number(r.worst_rise_ratio).c_str(), number(r.min_det).c_str(),
      number(r.min_sigma).c_str(), r.max_inverted, r.final_inverted, number(distance).c_str(),
      json_string(distance_kind).c_str(), number(r.wall_s).c_str());
  std::fflush(stdout);
}

int drive(int argc, char** argv) {
  CLI::App app{"descent_extremes: cases of the extremes suite, one JSON line per run"};
  std::string case_list = "all", model_list = "all", precision_list = "float,double";
  std::string reference_dir, reference = "auto";
  int factor = 16, frames = 0, iterations = 0;
  app.add_option("--case", case_list, "Case names, comma-separated, or all");
  app.add_option("--models", model_list, "Models, comma-separated, or all");
  app.add_option("--precisions", precision_list, "float, double or both");
  app.add_option("--reference-dir", reference_dir,
                 "Cache of converged references (none: no distance is reported)");
  app.add_option("--reference", reference, "auto, newton or chebyshev")
      ->check(CLI::IsMember({"auto", "newton", "chebyshev"}));
  app.add_option("--reference-factor", factor, "Iterations of a chebyshev reference, x the case's")
      ->check(CLI::PositiveNumber);
  app.add_option("--frames", frames, "Override the case's number of steps (exploration)");
  app.add_option("--iterations", iterations, "Override solver.iterations (exploration)");
  app.add_flag_callback("--list", [] {
    for (const std::string& n : case_names()) std::printf("%s\n", n.c_str());
    throw CLI::Success();
  });
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    int rank = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    return rank == 0 ? app.exit(e) : (e.get_exit_code() == 0 ? 0 : 1);
  }
  const std::vector<std::string> cases = case_list == "all" ? case_names() : split_list(case_list);
  const std::vector<std::string> models =
      model_list == "all" ? model_names() : split_list(model_list);
  for (const std::string& name : cases) {
    for (const std::string& model : models) {
      Case c = make_case(name, model);
      if (frames > 0) c.frames = frames;
      if (iterations > 0) c.scene.solver.iterations = iterations;
      Reference ref;
      const bool with_reference = !reference_dir.empty() && !c.recovers;
      if (with_reference) ref = reference_for(MPI_COMM_WORLD, c, reference_dir, reference, factor);
      for (const std::string& precision : split_list(precision_list)) {
        if (precision == "float")
          run_and_print<float>(MPI_COMM_WORLD, c, with_reference ? &ref : nullptr);
        else if (precision == "double")
          run_and_print<double>(MPI_COMM_WORLD, c, with_reference ? &ref : nullptr);
        else
          throw InputError(detail::concat("unknown precision '", precision, "'"));
      }
    }
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int code = 0;
  try {
    code = drive(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "descent_extremes: error: %s\n", e.what());
    code = 1;
  }
  MPI_Finalize();
  return code;
}

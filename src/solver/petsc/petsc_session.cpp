#include "solver/petsc/petsc_session.hpp"

#include "common/error.hpp"

#ifdef DESCENT_HAVE_PETSC
#include <petsclog.h>
#include <petscsys.h>
#endif

namespace descent {

#ifdef DESCENT_HAVE_PETSC

namespace {
bool started = false;
}

bool petsc_compiled() { return true; }

void start_petsc(const std::string& options, const std::string& what) {
  if (!started) {
    if (PetscInitializeNoArguments() != 0)
      throw Error("PetscInitialize failed (needed by " + what + ")");
    started = true;
  }
  if (options.empty()) return;
  if (PetscOptionsInsertString(nullptr, options.c_str()) != 0)
    throw InputError("solver.petsc_options: PETSc cannot read '" + options + "'");
  // -log_view is looked for at PetscInitialize; one given later starts the
  // log here, and finish_petsc() prints it.
  PetscBool log_view = PETSC_FALSE;
  PetscOptionsHasName(nullptr, nullptr, "-log_view", &log_view);
  if (log_view) PetscLogDefaultBegin();
}

void finish_petsc() {
  if (started) PetscFinalize();
  started = false;
}

long petsc_collectives() {
  return static_cast<long>(petsc_allreduce_ct + petsc_gather_ct + petsc_scatter_ct);
}

#else

bool petsc_compiled() { return false; }

void start_petsc(const std::string&, const std::string& what) {
  throw InputError(what +
                   " needs PETSc, and this build has none: install Debian's petsc-dev and "
                   "configure again (CMake finds it through pkg-config)");
}

void finish_petsc() {}

long petsc_collectives() { return 0; }

#endif

}  // namespace descent

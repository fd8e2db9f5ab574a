#pragma once
// The MPI datatype of a solver real (float or double).
#include <mpi.h>

namespace descent {

template <class Real>
MPI_Datatype mpi_type();
template <>
inline MPI_Datatype mpi_type<double>() {
  return MPI_DOUBLE;
}
template <>
inline MPI_Datatype mpi_type<float>() {
  return MPI_FLOAT;
}

}  // namespace descent

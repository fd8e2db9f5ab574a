#pragma once
// The datasets descent reads are tables of rows, [rows, cols] of integers or
// of float32 / float64 values. open_rows_dataset checks one before any value
// is read, so that a bad file ends in one InputError naming the file and the
// dataset, never in a failed or out-of-range read inside collective I/O.
#include <hdf5.h>

#include <string>

#include "common/mesh.hpp"
#include "io/hdf5_handle.hpp"

namespace descent::hdf5 {

// What a dataset must be, and the words its messages use.
struct RowsShape {
  int cols = 1;
  H5T_class_t type_class = H5T_INTEGER;  // integers of up to 64 bits, or H5T_FLOAT (32 or 64)
  const char* rows_symbol = "N";         // "expected [T, 4]"
  const char* columns_meaning = "";      // "(4 vertex ids per tet)"
  const char* values_meaning = "";       // "vertex ids must be integers"
};

struct RowsDataset {
  Hid dataset;
  global_index_t rows = 0;
};

// Opens dataset `name` (an absolute path) of `file` and checks that it exists
// and has the shape and type of `shape`; InputError "PATH: NAME ..." if not.
// Reads metadata only, which every rank sees alike, so every rank that calls
// it throws alike.
RowsDataset open_rows_dataset(hid_t file, const std::string& path, const std::string& name,
                              const RowsShape& shape);

// Whether `name` (an absolute path) names an object of `file`: every group on
// the way must exist too.
bool object_exists(hid_t file, const std::string& name);

}  // namespace descent::hdf5

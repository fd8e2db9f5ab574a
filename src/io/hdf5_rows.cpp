#include "io/hdf5_rows.hpp"

#include <algorithm>
#include <sstream>
#include <vector>

#include "common/error.hpp"

namespace descent::hdf5 {

bool object_exists(hid_t file, const std::string& name) {
  // H5Lexists fails (rather than answering no) when a group on the way is
  // missing, so each prefix is asked in turn.
  for (std::size_t slash = name.find('/', 1);; slash = name.find('/', slash + 1)) {
    const std::string prefix = name.substr(0, slash);
    if (H5Lexists(file, prefix.c_str(), H5P_DEFAULT) <= 0) return false;
    if (slash == std::string::npos) return true;
  }
}

RowsDataset open_rows_dataset(hid_t file, const std::string& path, const std::string& name,
                              const RowsShape& shape) {
  const std::string where = path + ":" + name;
  quiet_errors();
  if (!object_exists(file, name)) throw InputError(detail::concat(path, ": no dataset ", name));
  RowsDataset opened;
  const hid_t dataset = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
  if (dataset < 0)  // a group, a named type, or a link to nothing
    throw InputError(detail::concat(path, ": ", name, " is not a dataset"));
  opened.dataset = Hid(dataset, H5Dclose);
  Hid type = owned(H5Dget_type(opened.dataset.get()), H5Tclose, "H5Dget_type", where);
  const H5T_class_t found_class = H5Tget_class(type.get());
  const std::size_t bytes = H5Tget_size(type.get());
  if (shape.type_class == H5T_INTEGER && (found_class != H5T_INTEGER || bytes > 8))
    throw InputError(detail::concat(path, ": ", name, " does not hold integers",
                                    found_class == H5T_INTEGER ? " of at most 64 bits" : "", "; ",
                                    shape.values_meaning));
  if (shape.type_class == H5T_FLOAT && (found_class != H5T_FLOAT || (bytes != 4 && bytes != 8)))
    throw InputError(detail::concat(path, ": ", name, " does not hold float32 or float64 values; ",
                                    shape.values_meaning));

  Hid space = owned(H5Dget_space(opened.dataset.get()), H5Sclose, "H5Dget_space", where);
  const int rank =
      check(H5Sget_simple_extent_ndims(space.get()), "H5Sget_simple_extent_ndims", where);
  std::vector<hsize_t> dims(std::max(rank, 0));
  check(H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr), "H5Sget_simple_extent_dims",
        where);
  if (rank != 2 || dims[1] != static_cast<hsize_t>(shape.cols) ||
      dims[0] > static_cast<hsize_t>(global_index_t{1} << 48)) {
    std::ostringstream found;
    for (std::size_t d = 0; d < dims.size(); ++d) found << (d ? ", " : "") << dims[d];
    throw InputError(detail::concat(path, ": ", name, " has shape [", found.str(), "], expected [",
                                    shape.rows_symbol, ", ", shape.cols, "] (",
                                    shape.columns_meaning, ")"));
  }
  opened.rows = static_cast<global_index_t>(dims[0]);
  return opened;
}

}  // namespace descent::hdf5

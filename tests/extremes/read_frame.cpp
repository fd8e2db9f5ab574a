// read_frame FILE FRAME: prints how many coordinates frame FRAME of a
// frames.h5 (io/frame_writer.hpp: /frames/NNNNNN/positions, float64
// [num_vertices, 3]) holds and whether all are finite; exit 0 only when the
// frame is there, readable and finite. Serial HDF5 calls on a file the
// parallel writer closed: what any reader of our output would do.
#include <hdf5.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: read_frame FILE FRAME\n");
    return 2;
  }
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  char name[64];
  std::snprintf(name, sizeof name, "/frames/%06d/positions", std::atoi(argv[2]));
  const hid_t file = H5Fopen(argv[1], H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0) {
    std::printf("cannot open %s\n", argv[1]);
    return 1;
  }
  const hid_t set = H5Dopen2(file, name, H5P_DEFAULT);
  if (set < 0) {
    std::printf("%s: no %s\n", argv[1], name);
    H5Fclose(file);
    return 1;
  }
  const hid_t space = H5Dget_space(set);
  const hssize_t count = H5Sget_simple_extent_npoints(space);
  std::vector<double> values(count > 0 ? static_cast<std::size_t>(count) : 0);
  const herr_t read = H5Dread(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data());
  H5Sclose(space);
  H5Dclose(set);
  H5Fclose(file);
  std::size_t finite = 0;
  for (double x : values) finite += std::isfinite(x) ? 1 : 0;
  std::printf("%s: %s holds %zu coordinates, %zu finite\n", argv[1], name, values.size(), finite);
  return read >= 0 && count > 0 && finite == values.size() ? 0 : 1;
}

#pragma once
// The checkpoint `descent run --restart` continues from, chosen collectively.
//
// Each rank reads and verifies both of its generations (PATH and PATH.prev,
// io/checkpoint.hpp) before any rank goes on. The ranks then take the newest
// frame that has a verified checkpoint on every rank: a kill between two
// ranks' writes leaves some ranks one frame newer, and a damaged newer file
// leaves only the .prev set. A choice other than every rank's newer file is
// said on stderr with the reason (the first rank's damaged file, or a frame
// not every rank has). When no frame verifies on every rank, the restart is
// refused: exit 1 and one message naming the file and what failed.
#include <mpi.h>

#include <string>

#include "io/checkpoint.hpp"

namespace descent {

// Collective. Throws InputError on one rank and PeerFailure on the others
// (app/agree.hpp reports it once) when no frame verifies on every rank, or
// when the checkpoint belongs to another run (`identity`, app/run_identity.hpp).
Checkpoint restart_checkpoint(MPI_Comm comm, const std::string& dir, const std::string& identity);

}  // namespace descent

#pragma once
// The MPI executor of a sweep: `mpirun -n R hcpf sweep FILE --out DIR`
// (docs/sweeps.md). Rank 0 coordinates: it does what RunSweep does before
// its pool (folder lock, store, reuse of finished runs, waves), hands out run
// indices one at a time to the ranks that ask, and is the only writer of the
// results store. Ranks 1..R-1 expand the same sweep themselves (their sweep
// hash is checked against rank 0's), compute the runs they are given and send
// each run's record back. MPI stays inside mpi_sweep.cc: no MPI type crosses
// this header, and MPI is initialised only when an MPI launcher started the
// process with more than one rank.

#include <cstdlib>
#include <functional>
#include <optional>
#include <vector>

#include "hcpf/studies/sweep.h"

namespace hcpf::studies {

// Whether this build has the MPI executor (Open MPI found at configure time).
bool MpiExecutorBuilt();

// How many processes the MPI launcher that started this one started, read
// from its environment: OMPI_COMM_WORLD_SIZE (Open MPI's mpirun), PMI_SIZE
// (MPICH/Hydra, Intel MPI, `srun --mpi=pmi2`) or, with PMIX_RANK set
// (`srun --mpi=pmix`), SLURM_STEP_NUM_TASKS; the first of these that holds a
// positive integer. 1 when none does (not launched by an MPI launcher).
// `getenv` is std::getenv but for tests.
int LaunchedRankCount(const std::function<const char*(const char*)>& getenv = [](const char* name) {
  return static_cast<const char*>(std::getenv(name));
});

// Whether this process is the first (rank 0) of those its MPI launcher
// started, read from the same launchers' rank variables before MPI is
// initialised: OMPI_COMM_WORLD_RANK, PMI_RANK or PMIX_RANK, the first that
// is set; true when none is (not launched by an MPI launcher) or it is not
// a positive integer. For what is said once per sweep, not once per rank.
bool IsFirstLaunchedRank(const std::function<const char*(const char*)>& getenv =
                             [](const char* name) {
                               return static_cast<const char*>(std::getenv(name));
                             });

// Runs the sweep like RunSweep, across the ranks of an MPI job when the
// process was launched with more than one (LaunchedRankCount() > 1), else
// simply RunSweep (and MPI is never initialised). Every rank calls it with
// the same spec and runs. Returns the result on rank 0 (and without MPI),
// nullopt on the other ranks.
//
// Errors: a build without MPI launched with several ranks throws RunError
// (the ranks would otherwise each run the whole sweep into one folder), and
// so does a process that MPI_Init finds alone in its world although the
// launcher started several (another MPI's launcher). A
// rank whose expansion differs from rank 0's makes every rank throw RunError.
// When rank 0 cannot start the sweep (the folder is locked, holds another
// sweep's store: InputError), it throws that error and the other ranks return
// nullopt. Once runs are handed out, an error on any rank (a store write that
// fails, a rank that dies) ends the whole job (MPI_Abort; mpirun ends it when
// a rank dies); every run stored until then stays, and rerunning resumes.
std::optional<SweepResult> RunSweepMpi(const SweepSpec& spec, const std::vector<SweepRun>& runs,
                                       const SweepOptions& options);

}  // namespace hcpf::studies

#include <base/mpi_session.h>

#include <cstdlib>
#include <filesystem>
#include <system_error>

namespace flextrack::base
{
namespace
{
MPI_Comm fe_comm = MPI_COMM_WORLD;
}

bool started_by_mpirun()
{
  // Open MPI's mpirun, or a PMI/PMIx launcher (MPICH's hydra, Slurm's srun).
  return std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMI_SIZE") || std::getenv("PMIX_RANK");
}

MPI_Comm fe_communicator() { return fe_comm; }

void use_own_process_for_fe() { fe_comm = MPI_COMM_SELF; }

namespace
{
bool mpi_running()
{
  int started = 0, finished = 0;
  MPI_Initialized(&started);
  MPI_Finalized(&finished);
  return started && !finished;
}
} // namespace

unsigned int fe_processes()
{
  int size = 1;
  if (mpi_running()) MPI_Comm_size(fe_comm, &size);
  return static_cast<unsigned int>(size);
}

unsigned int fe_rank()
{
  int rank = 0;
  if (mpi_running()) MPI_Comm_rank(fe_comm, &rank);
  return static_cast<unsigned int>(rank);
}

std::string prepare_singleton_mpi()
{
  if (started_by_mpirun()) return "";
  setenv("OMPI_MCA_ess_singleton_isolated", "1", 0);
  if (std::getenv("OMPI_MCA_orte_tmpdir_base")) return ""; // the user chose one
  const char *tmp = std::getenv("TMPDIR");
  std::string folder = std::string(tmp && *tmp ? tmp : "/tmp") + "/flextrack-mpi-XXXXXX";
  if (!mkdtemp(folder.data())) return ""; // then Open MPI's default
  setenv("OMPI_MCA_orte_tmpdir_base", folder.c_str(), 1);
  return folder;
}

void remove_mpi_session_folder(const std::string &folder)
{
  if (folder.empty()) return;
  std::error_code ignore;
  std::filesystem::remove_all(folder, ignore);
}
} // namespace flextrack::base

// GoogleTest entry point: Trilinos (Epetra) needs MPI to be running. ctest runs every test case
// as a process of its own, two or more at once: each gets its own Open MPI session folder
// (base::prepare_singleton_mpi), or their singleton start-ups can collide.
#include <base/mpi_session.h>

#include <gtest/gtest.h>
#include <mpi.h>

int main(int argc, char **argv)
{
  const std::string mpi_folder = flextrack::base::prepare_singleton_mpi();
  MPI_Init(&argc, &argv);
  ::testing::InitGoogleTest(&argc, argv);
  const int status = RUN_ALL_TESTS();
  MPI_Finalize();
  flextrack::base::remove_mpi_session_folder(mpi_folder);
  return status;
}

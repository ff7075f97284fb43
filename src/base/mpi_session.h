// Open MPI's singleton start-up (a process started without mpirun), made safe for many
// processes starting at once: the FlexTrack executable and the unit tests use it.
#pragma once

#include <mpi.h>

#include <string>

namespace flextrack::base
{
/// Call before MPI_Init in a process that was not started by mpirun (no-op under mpirun): the
/// singleton starts without looking for a runtime daemon (much faster), and gets a session
/// folder of its own. Singleton processes otherwise share /tmp/ompi.HOST.UID, and one removing
/// it at MPI_Finalize while another creates its files there made MPI_Init fail ("A call to
/// mkdir was unable to create the desired directory", exit 1) when several started at once.
/// Returns that folder ("" if the user chose one, or none could be made), for
/// remove_mpi_session_folder() after MPI_Finalize.
std::string prepare_singleton_mpi();

/// Removes @p folder and its contents; nothing for "".
void remove_mpi_session_folder(const std::string &folder);

/// True in a process started by mpirun (Open MPI's environment), whether MPI runs yet or not.
bool started_by_mpirun();

/// The communicator the FE stage distributes a solid over and whose first process writes the
/// results: MPI_COMM_WORLD, except in `mpirun ... flextrack sweep`, where every process runs
/// cases of its own and sets MPI_COMM_SELF (use_own_process_for_fe()).
MPI_Comm fe_communicator();
void use_own_process_for_fe();
/// The number of processes of fe_communicator() and this process' rank in it: 1 and 0 in a
/// process that has not started MPI (a serial 'run' does not, to start faster).
unsigned int fe_processes();
unsigned int fe_rank();
} // namespace flextrack::base

# Runs `flextrack modes PRM` serially and under `mpirun -np 2`, and requires the frequencies of
# frequencies.csv to agree to 1e-8 relative (issue 3: the partitioned solid model is the same
# model). Both runs must also write their mode shapes.
file(REMOVE_RECURSE "${OUT}")
set(ENV{OMPI_ALLOW_RUN_AS_ROOT} 1)
set(ENV{OMPI_ALLOW_RUN_AS_ROOT_CONFIRM} 1)
# Two processes on two cores: one BLAS thread each (OpenBLAS would start one per core).
set(ENV{OPENBLAS_NUM_THREADS} 1)
execute_process(COMMAND ${EXE} modes ${PRM} -o ${OUT}/serial RESULT_VARIABLE rc1)
execute_process(COMMAND ${MPIRUN} -np 2 --oversubscribe ${EXE} modes ${PRM} -o ${OUT}/mpi RESULT_VARIABLE rc2)
if(NOT rc1 EQUAL 0 OR NOT rc2 EQUAL 0)
  message(FATAL_ERROR "serial run: ${rc1}, mpirun -np 2: ${rc2}")
endif()
file(STRINGS ${OUT}/serial/frequencies.csv serial)
file(STRINGS ${OUT}/mpi/frequencies.csv parallel)
list(LENGTH serial n)
if(n LESS 2)
  message(FATAL_ERROR "no frequencies")
endif()
math(EXPR last "${n} - 1")
foreach(i RANGE 1 ${last})
  list(GET serial ${i} a)
  list(GET parallel ${i} b)
  string(REGEX REPLACE "^[0-9]+," "" fa "${a}")
  string(REGEX REPLACE "^[0-9]+," "" fb "${b}")
  # CMake has no floating-point arithmetic: let python3 compare.
  execute_process(COMMAND /usr/bin/python3 -c
    "import sys; a, b = float(sys.argv[1]), float(sys.argv[2]); sys.exit(0 if abs(a - b) <= 1e-8 * abs(a) else 1)"
    ${fa} ${fb} RESULT_VARIABLE same)
  message(STATUS "mode ${i}: serial ${fa} Hz, 2 processes ${fb} Hz")
  if(NOT same EQUAL 0)
    message(FATAL_ERROR "mode ${i} differs by more than 1e-8: ${fa} vs ${fb}")
  endif()
endforeach()
foreach(f serial/mode_shapes.pvd mpi/mode_shapes.pvd mpi/mode_shapes_001.pvtu mpi/mode_shapes_001.1.vtu)
  if(NOT EXISTS ${OUT}/${f})
    message(FATAL_ERROR "missing ${OUT}/${f}")
  endif()
endforeach()

// Compiled vector operations for SUNDIALS' serial N_Vector.
//
// Debian 12's SUNDIALS 6.4.1 is built without optimisation: its serial vector operations
// (z = a x + b y, weighted norms, ...) keep every operand on the stack and take about 20
// instructions per entry. On the laser robot they were 13 % of all the instructions of a run
// (callgrind, 2026-12-03), more than the LU factorisations. install_compiled_ops() puts the
// same operations, compiled with the program's flags, into a serial vector's table of
// operations; IDA's working vectors are clones of the vectors it is given, and a clone copies
// the table, so installing them into y, y' and the id vector before IDAInit covers them all.
//
// The arithmetic is SUNDIALS' own, term by term and in its order, with its forms of a linear sum
// for coefficients of 1 and -1: the same results to the last bit, signs of zeros included
// (tests/unit/serial_vector_ops_test.cc compares every operation with the library's). The fused
// operations (linear combinations, ...) stay off, as in the library's serial vector: their
// fallbacks are loops over these operations.
#pragma once

#include <sundials/sundials_nvector.h>

namespace flextrack::multibody
{
/// Replaces the arithmetic operations of the serial vector @p v (N_VNew_Serial) by compiled
/// ones; its clones inherit them. Vectors of another kind are left unchanged.
void install_compiled_ops(N_Vector v);
} // namespace flextrack::multibody

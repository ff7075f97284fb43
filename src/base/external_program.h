// Running another program (gnuplot) without a shell.
// A command line built from input text ("cd '" + folder + "' && gnuplot ...") lets a folder name
// such as  q'; touch owned; echo '  run commands. Here the program gets an argument vector and a
// working folder, and nothing is ever interpreted by a shell.
#pragma once

#include <string>
#include <vector>

namespace flextrack::base
{
/// Runs arguments[0] (looked up in PATH) with the given arguments in @p folder, its standard
/// output and error discarded, and waits for it. Returns its exit status, or -1 when it could not
/// be started (not installed) or did not exit normally.
int run_program(const std::vector<std::string> &arguments, const std::string &folder);
} // namespace flextrack::base

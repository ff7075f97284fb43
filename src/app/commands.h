// The commands of the flextrack program. Each returns the process exit code.
#pragma once

#include <string>

namespace flextrack::app
{
struct Options
{
  std::string file;
  std::string output_directory; ///< from -o; empty = from the file, else output/<stem>
  unsigned int refinements = 3; ///< converge: number of refinements K
  std::string format;           ///< export: mbdyn or vtu
};

/// Modal analysis of one arm: frequencies.csv, summary.json, mode shapes (VTU/PVD).
int modes(const Options &options);
/// The same analysis on K successively halved meshes: convergence.csv, convergence.png.
int converge(const Options &options);
/// Reduce the flexible body of a "Model = body" scene: reduced_body.h5 (cached), frequencies.csv,
/// summary.json.
int reduce(const Options &options);
/// Export a reduced body file for another tool (--format mbdyn | vtu).
int export_body(const Options &options);
/// Print what a reduced body file holds (checks it thoroughly).
int inspect(const Options &options);
/// Every parameter with its default, allowed values, unit and documentation.
int print_parameters();
} // namespace flextrack::app

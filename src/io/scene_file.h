// A scene (parameter) file, read once and handed on as a parsed value.
//
// The two-pass pattern for named instances. A scene names its instances in lists (a body's
// "Body/Arms = boom, brace"; later the bodies, joints, forces and probes of a multibody scene)
// and describes each in a "subsection KIND NAME". deal.II's ParameterHandler must know every
// subsection before it parses strictly, so:
//   pass 1 (here, once per file): only the top-level "Model" entry and the lists of names are
//          declared, everything else is skipped; the result is kept in SceneFile::lists;
//   pass 2 (the scene reader of the model kind): declares every subsection, one per name, and
//          parses the same text strictly (an unknown entry is an error).
// A list is registered in one table (scene_file.cc) by the class that owns it, with its
// declaration function, so pass 1 and pass 2 declare it identically.
//
// Text formats: deal.II's .prm syntax, or JSON for a file whose name ends in .json. Limits
// (doc/user_guide.md): at most 16 MiB of text, "include" nested at most 8 deep (a file that
// includes itself is refused), JSON nested at most 64 deep.
#pragma once

#include <io/parameter_overrides.h>

#include <deal.II/base/parameter_handler.h>

#include <memory>
#include <string>
#include <vector>

namespace flextrack::io
{
struct SceneFile
{
  std::string name;      ///< as given (in messages)
  std::string directory; ///< relative file names in the scene are taken from here
  std::string text;      ///< the whole text, includes expanded
  bool json = false;
  std::string model;     ///< the "Model" entry: arm, solid or body
  /// Pass 1: "Model" and every list of names (see scene_file.cc), parsed leniently.
  std::shared_ptr<dealii::ParameterHandler> lists;
  /// Entries set on the command line (--set): those of scope "" are applied by parse() after the
  /// text; those of scope "Body NAME" belong to that body's body scene (overrides_of()).
  std::vector<ParameterOverride> overrides;

  /// Reads @p file (InputError naming it if it cannot be read or parsed), with @p overrides
  /// (applied in pass 1 too, so that they may change the lists of names).
  static SceneFile read(const std::string &file, const std::vector<ParameterOverride> &overrides = {});
  /// The same from text (tests); @p directory resolves relative file names.
  static SceneFile from_text(const std::string &text, const std::string &directory = ".", bool json = false,
                             const std::vector<ParameterOverride> &overrides = {});

  /// True if the text opens `subsection SUBSECTION` (a .prm file) or has the key "SUBSECTION"
  /// (JSON): a listed instance without its subsection would get every default silently.
  bool has_subsection(const std::string &subsection) const;

  /// A JSON scene with the keys @p subsections written as deal.II's ParameterHandler expects them
  /// (mangled: '_' as "_5f"). deal.II writes its JSON so, but a user writes "Body my_bob", which
  /// deal.II took for an undeclared subsection ("You can't ask for entry <Kind> you have not yet
  /// declared"). Only the keys named are touched; a .prm scene is returned unchanged.
  SceneFile with_mangled_json_keys(const std::vector<std::string> &subsections) const;

  /// Parses the text into @p prm, then sets the overrides of scope ""; deal.II's errors become
  /// InputError naming this file.
  void parse(dealii::ParameterHandler &prm, bool skip_undefined) const;
  /// The overrides for the body scene of body @p body_name, as overrides of that scene itself.
  std::vector<ParameterOverride> overrides_of(const std::string &body_name) const;
};

/// Declares the one top-level "Model" entry (every scene kind).
void declare_model_entry(dealii::ParameterHandler &prm);
} // namespace flextrack::io

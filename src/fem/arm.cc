#include <fem/arm.h>
#include <base/text.h>
#include <base/input_error.h>

#include <algorithm>
#include <sstream>

namespace flextrack::fem
{
using dealii::ParameterHandler;

SupportKind parse_support_kind(const std::string &text, const std::string &entry)
{
  std::string t = text;
  t.erase(0, t.find_first_not_of(" \t"));
  t.erase(t.find_last_not_of(" \t") + 1);
  if (t == "clamped") return SupportKind::clamped;
  if (t == "pinned") return SupportKind::pinned;
  if (t == "free") return SupportKind::free;
  throw InputError(entry, "unknown support '" + base::printable_excerpt(t) + "'; allowed: clamped, pinned, free");
}

void check_arm_cell_count(const Arm &arm, const double n_cells, const std::string &how)
{
  if (n_cells <= max_arm_cells) return;
  const double dofs = 6 * (arm.degree * n_cells + 1), bytes = 2048 * dofs;
  const char *units[] = {"B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
  double amount = bytes;
  int u = 0;
  for (; amount >= 1024 && u < 6; ++u) amount /= 1024;
  std::ostringstream m;
  m.precision(3);
  if (n_cells < 1e15)
    m << static_cast<long long>(n_cells);
  else
    m << n_cells;
  m << " cells of degree " << arm.degree << how << " would need about " << amount
    << " " << units[u] << " of memory (" << dofs << " degrees of freedom); allowed: at most "
    << static_cast<long>(max_arm_cells) << " cells";
  throw InputError(arm.section_name + "/Mesh/Number of elements", m.str());
}

void Arm::declare_parameters(ParameterHandler &prm, const std::string &section)
{
  prm.enter_subsection(section);
  prm.enter_subsection("Curve");
  geometry::declare_curve_parameters(prm);
  prm.leave_subsection();
  geometry::SectionFrame::declare_parameters(prm);
  CrossSection::declare_parameters(prm);
  Material::declare_parameters(prm);
  prm.enter_subsection("Supports");
  const auto kinds = dealii::Patterns::Selection("clamped|pinned|free");
  prm.declare_entry("Start", "clamped", kinds,
                    "Support at s = 0: 'clamped' (3 displacements and 3 rotations fixed), 'pinned' "
                    "(3 displacements fixed), 'free'.");
  prm.declare_entry("End", "free", kinds, "Support at the far end s = L (same choices).");
  prm.declare_entry("Intermediate", "", dealii::Patterns::Anything(),
                    "Further supports as 'arc length [m]: kind' separated by ';', e.g. '0.5: pinned; "
                    "1.2: clamped'. 0 <= s <= L; a mesh node is placed at each; at most 1000.");
  prm.leave_subsection();
  prm.enter_subsection("Mesh");
  prm.declare_entry("Number of elements", "16", dealii::Patterns::Integer(1),
                    "Number of beam elements along the arm on the coarsest mesh [-], 1 to 200000 (also after "
                    "the refinements of 'converge': about 2 KiB of memory per degree of freedom).");
  prm.declare_entry("Element degree", "2", dealii::Patterns::Integer(1, 3),
                    "Polynomial degree of the curved beam element [-]: 1, 2 or 3.");
  prm.leave_subsection();
  prm.leave_subsection();
}

Arm Arm::parse_parameters(ParameterHandler &prm, const std::string &directory, const std::string &section)
{
  Arm arm;
  arm.section_name = section;
  // An InputError ends the run, so subsections need not be left on the way out.
  prm.enter_subsection(section);
  {
      prm.enter_subsection("Curve");
      arm.curve = geometry::parse_curve(prm, {section + "/Curve", directory});
      prm.leave_subsection();
      arm.frame = std::make_shared<geometry::SectionFrame>(
        geometry::SectionFrame::parse_parameters(prm, arm.curve, {section, directory}));
      arm.material = Material::parse_parameters(prm, section);
      arm.section = CrossSection::parse_parameters(prm, section, arm.material.poisson_ratio);

      prm.enter_subsection("Supports");
      const double L = arm.curve->length();
      arm.supports.push_back({0.0, parse_support_kind(prm.get("Start"), section + "/Supports/Start")});
      arm.supports.push_back({L, parse_support_kind(prm.get("End"), section + "/Supports/End")});
      const std::string entry = section + "/Supports/Intermediate";
      const auto intermediate = base::named_items(prm.get("Intermediate"), entry, "arc length: kind");
      if (intermediate.size() > max_intermediate_supports)
        throw InputError(entry, std::to_string(intermediate.size()) + " supports; at most " +
                                  std::to_string(max_intermediate_supports) + " are allowed");
      for (const auto &[where, kind] : intermediate)
        {
          const double s = base::parse_number(where, entry, "an arc length [m]");
          if (s < 0 || s > L * (1 + 1e-12))
            {
              std::ostringstream m;
              m << "support at s = " << s << " m lies beyond the arm (its length is L = " << L
                << " m); allowed: 0 <= s <= L";
              throw InputError(entry, m.str());
            }
          arm.supports.push_back({std::min(s, L), parse_support_kind(kind, entry)});
        }
      prm.leave_subsection();

      prm.enter_subsection("Mesh");
      const long n_elements = prm.get_integer("Number of elements");
      arm.degree = prm.get_integer("Element degree");
      prm.leave_subsection();
      check_arm_cell_count(arm, n_elements, "");
      arm.n_elements = n_elements;
  }
  prm.leave_subsection();
  return arm;
}
} // namespace flextrack::fem

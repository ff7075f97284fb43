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
  throw InputError(entry, "unknown support '" + t + "'; allowed: clamped, pinned, free");
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
                    "1.2: clamped'. 0 <= s <= L; a mesh node is placed at each.");
  prm.leave_subsection();
  prm.enter_subsection("Mesh");
  prm.declare_entry("Number of elements", "16", dealii::Patterns::Integer(1),
                    "Number of beam elements along the arm on the coarsest mesh [-], >= 1.");
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
      for (const auto &[where, kind] : base::named_items(prm.get("Intermediate"), entry, "arc length: kind"))
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
      arm.n_elements = prm.get_integer("Number of elements");
      arm.degree = prm.get_integer("Element degree");
      prm.leave_subsection();
  }
  prm.leave_subsection();
  return arm;
}
} // namespace flextrack::fem

#include <reduction/modal_participation.h>

namespace flextrack::reduction
{
ModalParticipation modal_participation(const std::vector<dealii::Vector<double>> &shapes,
                                       const dealii::TrilinosWrappers::SparseMatrix &M,
                                       const std::vector<unsigned int> &component)
{
  ModalParticipation p;
  const std::size_t n = M.m();
  std::array<dealii::Vector<double>, 3> Mr;
  for (unsigned int d = 0; d < 3; ++d)
    {
      dealii::Vector<double> r(n);
      for (std::size_t i = 0; i < n; ++i) r[i] = component[i] == d ? 1.0 : 0.0;
      Mr[d].reinit(n);
      M.vmult(Mr[d], r);
      p.total_mass[d] = r * Mr[d];
    }
  for (const auto &phi : shapes)
    {
      std::array<double, 3> gamma{}, mass{};
      for (unsigned int d = 0; d < 3; ++d)
        {
          gamma[d] = phi * Mr[d];
          mass[d] = gamma[d] * gamma[d];
        }
      p.factors.push_back(gamma);
      p.effective_mass.push_back(mass);
    }
  return p;
}
} // namespace flextrack::reduction

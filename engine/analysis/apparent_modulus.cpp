#include "engine/analysis/apparent_modulus.h"

#include <cstddef>
#include <string>

namespace granulab {

namespace {
// The strain at which `stress` first reaches `level` (interpolated), or a negative value when it never does.
double first_crossing(const std::vector<double>& strain, const std::vector<double>& stress, double level) {
  for (std::size_t k = 0; k < stress.size() && k < strain.size(); ++k) {
    if (stress[k] < level) continue;
    if (k == 0) return strain[0];
    const double t = (level - stress[k - 1]) / (stress[k] - stress[k - 1]);
    return strain[k - 1] + t * (strain[k] - strain[k - 1]);
  }
  return -1;
}
}  // namespace

ApparentModulus apparent_modulus(const std::vector<double>& strain, const std::vector<double>& stress, double reference) {
  ApparentModulus m;
  m.reference = reference;
  if (!(reference > 0)) return m;
  m.from_strain = first_crossing(strain, stress, 0.1 * reference);
  m.to_strain = first_crossing(strain, stress, 0.4 * reference);
  m.found = m.from_strain >= 0 && m.to_strain > m.from_strain;
  if (m.found) m.value = 0.3 * reference / (m.to_strain - m.from_strain);
  return m;
}

void write_apparent_modulus(SummaryWriter& w, const ApparentModulus& m, double scale, const char* over_key,
                            double affine, const char* of) {
  w.begin_group("apparent_modulus");
  w.flag("found", m.found);
  w.text("definition", std::string("secant between 10 % and 40 % of the ") + of);
  if (m.found) {
    w.number("value", m.value, "Pa");
    w.number(over_key, scale > 0 ? m.value / scale : 0.0, "-");
    w.number("from_strain", m.from_strain, "-");
    w.number("to_strain", m.to_strain, "-");
  } else {
    w.text("reason", "the stress never rose from 10 % to 40 % of the " + std::string(of));
  }
  if (affine > 0) {
    w.number("affine_axial", affine, "Pa");
    if (m.found) w.number("affine_over_apparent", affine / m.value, "-");
    w.text("note",
           "affine_axial is the perfect crystal's tangent, every face closed and stuck, over strains of order eps0; "
           "the secant spans tens to hundreds of eps0, where faces inclined to the load open or slide and the bag "
           "holds the lateral stress, not the width: 1.1 to 8 times lower on perfect crystals (docs/model.md, "
           "\"Apparent modulus\")");
  }
  w.end_group();
}

}  // namespace granulab

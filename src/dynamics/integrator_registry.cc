// The integrators by name (integrator.h).
#include <utility>

#include "cga_rigid_sim/dynamics/integrator.h"
#include "cga_rigid_sim/dynamics/integrator_auto.h"
#include "cga_rigid_sim/dynamics/integrator_cga2.h"
#include "cga_rigid_sim/dynamics/integrator_cga4.h"
#include "cga_rigid_sim/dynamics/integrator_euler.h"
#include "cga_rigid_sim/dynamics/integrator_exact.h"
#include "cga_rigid_sim/dynamics/integrator_rk4.h"

namespace cga_rigid_sim {
namespace dynamics {
namespace {

template <class T>
std::unique_ptr<Integrator> make() {
  return std::make_unique<T>();
}

// In documentation order.
const std::vector<std::pair<std::string, std::unique_ptr<Integrator> (*)()>>& registry() {
  static const std::vector<std::pair<std::string, std::unique_ptr<Integrator> (*)()>> kRegistry = {
      {"auto", &make<AutoIntegrator>},   {"cga2", &make<Cga2Integrator>},
      {"cga4", &make<Cga4Integrator>},   {"exact", &make<ExactIntegrator>},
      {"euler", &make<EulerIntegrator>}, {"rk4", &make<Rk4Integrator>},
  };
  return kRegistry;
}

}  // namespace

const std::vector<std::string>& integratorNames() {
  static const std::vector<std::string> kNames = [] {
    std::vector<std::string> names;
    for (const auto& entry : registry()) names.push_back(entry.first);
    return names;
  }();
  return kNames;
}

Result<std::unique_ptr<Integrator>> makeIntegrator(const std::string& name) {
  for (const auto& entry : registry())
    if (entry.first == name) return entry.second();
  std::string valid;
  for (const auto& n : integratorNames()) valid += (valid.empty() ? "" : ", ") + n;
  return Error{"unknown integrator '" + name + "' (valid: " + valid + ")"};
}

}  // namespace dynamics
}  // namespace cga_rigid_sim

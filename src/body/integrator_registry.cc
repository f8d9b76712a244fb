// The integrators by name, once: the ~integrator names (integrator.h) with what each makes for a
// free body (makeIntegrator) and for an articulated tree (makeTreeIntegrator, tree_integrator.h).
#include <utility>

#include "cga_rigid_sim/body/integrator.h"
#include "cga_rigid_sim/body/integrator_auto.h"
#include "cga_rigid_sim/body/integrator_cga2.h"
#include "cga_rigid_sim/body/integrator_cga4.h"
#include "cga_rigid_sim/body/integrator_euler.h"
#include "cga_rigid_sim/body/integrator_exact.h"
#include "cga_rigid_sim/body/integrator_rk4.h"
#include "cga_rigid_sim/tree/tree_integrator.h"
#include "tree/tree_integrators.h"

namespace cga_rigid_sim {
namespace dynamics {
namespace {

template <class T>
std::unique_ptr<Integrator> make() {
  return std::make_unique<T>();
}
std::unique_ptr<TreeIntegrator> treeMidpoint() { return makeMidpointTreeIntegrator(false); }
std::unique_ptr<TreeIntegrator> treeMidpoint4() { return makeMidpointTreeIntegrator(true); }
std::unique_ptr<TreeIntegrator> treeRk4() { return makeExplicitTreeIntegrator(true); }
std::unique_ptr<TreeIntegrator> treeEuler() { return makeExplicitTreeIntegrator(false); }

struct Entry {
  const char* name;
  std::unique_ptr<Integrator> (*body)();
  std::unique_ptr<TreeIntegrator> (*tree)();  ///< null: the name has no form for trees
  const char* no_tree;                        ///< then why
};

// In documentation order.
constexpr Entry kRegistry[] = {
    {"auto", &make<AutoIntegrator>, &treeMidpoint, nullptr},
    {"cga2", &make<Cga2Integrator>, &treeMidpoint, nullptr},
    {"cga4", &make<Cga4Integrator>, &treeMidpoint4, nullptr},
    {"exact", &make<ExactIntegrator>, nullptr,
     "has no form for articulated trees (a tree has no closed-form flow)"},
    {"euler", &make<EulerIntegrator>, &treeEuler, nullptr},
    {"rk4", &make<Rk4Integrator>, &treeRk4, nullptr},
};

std::string listed(const std::vector<std::string>& names, const char* last_separator) {
  std::string out;
  for (std::size_t k = 0; k < names.size(); ++k)
    out += (k == 0 ? "" : k + 1 == names.size() ? last_separator : ", ") + names[k];
  return out;
}

}  // namespace

const std::vector<std::string>& integratorNames() {
  static const std::vector<std::string> kNames = [] {
    std::vector<std::string> names;
    for (const Entry& e : kRegistry) names.push_back(e.name);
    return names;
  }();
  return kNames;
}

Result<std::unique_ptr<Integrator>> makeIntegrator(const std::string& name) {
  for (const Entry& e : kRegistry)
    if (e.name == name) return e.body();
  return Error{"unknown integrator '" + name + "' (valid: " + listed(integratorNames(), ", ") +
               ")"};
}

const std::vector<std::string>& treeIntegratorNames() {
  static const std::vector<std::string> kNames = [] {
    std::vector<std::string> names;
    for (const Entry& e : kRegistry)
      if (e.tree) names.push_back(e.name);
    return names;
  }();
  return kNames;
}

Result<std::unique_ptr<TreeIntegrator>> makeTreeIntegrator(const std::string& name) {
  for (const Entry& e : kRegistry) {
    if (e.name != name) continue;
    if (e.tree) return e.tree();
    return Error("integrator", "",
                 "'" + name + "' " + e.no_tree + "; use auto (the default), " +
                     listed(std::vector<std::string>(treeIntegratorNames().begin() + 1,
                                                     treeIntegratorNames().end()),
                            " or "));
  }
  return Error(
      "integrator", "",
      "unknown integrator '" + name + "' for trees (" + listed(treeIntegratorNames(), ", ") + ")");
}

}  // namespace dynamics
}  // namespace cga_rigid_sim

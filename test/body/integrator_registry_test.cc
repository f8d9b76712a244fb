// Tests of the integrator registry (integrator.h): the names, in documentation order, and the
// error for an unknown name. Truth: the specification of the interface.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "cga_rigid_sim/body/integrator.h"

namespace cga_rigid_sim {
namespace dynamics {
namespace integrator_registry_test {

TEST(IntegratorRegistry, NamesInDocumentationOrder) {
  EXPECT_EQ(integratorNames(),
            (std::vector<std::string>{"auto", "cga2", "cga4", "exact", "euler", "rk4"}));
}

TEST(IntegratorRegistry, EachNameMakesThatIntegrator) {
  for (const std::string& name : integratorNames()) {
    auto it = makeIntegrator(name);
    ASSERT_TRUE(it.ok()) << it.error();
    EXPECT_EQ(it.value()->name(), name);
    // Two calls give two independent objects (an integrator belongs to one body).
    auto other = makeIntegrator(name);
    ASSERT_TRUE(other.ok());
    EXPECT_NE(it.value().get(), other.value().get());
  }
}

TEST(IntegratorRegistry, UnknownNameIsAnErrorListingTheValidOnes) {
  for (const std::string bad : {"verlet", "", "CGA2", "auto "}) {
    auto it = makeIntegrator(bad);
    ASSERT_FALSE(it.ok());
    EXPECT_EQ(it.error(),
              "unknown integrator '" + bad + "' (valid: auto, cga2, cga4, exact, euler, rk4)");
  }
}

}  // namespace integrator_registry_test
}  // namespace dynamics
}  // namespace cga_rigid_sim

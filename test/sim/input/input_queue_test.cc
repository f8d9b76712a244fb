// InputQueue: (step, arrival) order, popping, removal of a body's inputs.
#include "cga_rigid_sim/sim/input/input_queue.h"

#include <gtest/gtest.h>

namespace cga_rigid_sim {
namespace sim {
namespace input_queue_test {

QueuedInput input(std::uint64_t step, int body, QueuedInput::Kind kind = QueuedInput::Kind::kWrench,
                  double tag = 0) {
  QueuedInput q;
  q.kind = kind;
  q.step = step;
  q.body = body;
  q.F.f.x() = tag;
  return q;
}

// Truth: the ordering rule — by step, then by arrival — whatever order the inputs arrive in;
// popDue hands out only inputs due at or before the step asked for.
TEST(InputQueue, PopsInStepThenArrivalOrder) {
  InputQueue q;
  q.push(input(5, 0, QueuedInput::Kind::kWrench, 1));
  q.push(input(2, 0, QueuedInput::Kind::kWrench, 2));
  q.push(input(5, 1, QueuedInput::Kind::kImpulse, 3));
  q.push(input(2, 1, QueuedInput::Kind::kWrench, 4));
  q.push(input(9, 0, QueuedInput::Kind::kWrench, 5));
  EXPECT_EQ(q.size(), 5u);
  EXPECT_EQ(q.popDue(1), nullptr);
  std::vector<double> order;
  for (std::uint64_t k = 0; k < 10; ++k)
    while (const QueuedInput* in = q.popDue(k)) {
      EXPECT_EQ(in->step, k);
      order.push_back(in->F.f.x());
    }
  EXPECT_EQ(order, (std::vector<double>{2, 4, 1, 3, 5}));
  EXPECT_TRUE(q.empty());
}

// Truth: clearWrenches drops only wrenches; removeBody drops one body's inputs and renumbers
// the bodies after it; the relative order of what stays is kept.
TEST(InputQueue, ClearWrenchesAndRemoveBody) {
  InputQueue q;
  q.push(input(1, 0, QueuedInput::Kind::kWrench, 1));
  q.push(input(1, 1, QueuedInput::Kind::kImpulse, 2));
  q.push(input(1, 2, QueuedInput::Kind::kWrench, 3));
  q.push(input(1, 2, QueuedInput::Kind::kImpulse, 4));
  EXPECT_EQ(q.wrenchCount(2), 1u);
  q.removeBody(1);
  ASSERT_EQ(q.size(), 3u);
  EXPECT_EQ(q.wrenchCount(1), 1u);  // body 2 is now body 1
  q.clearWrenches();
  ASSERT_EQ(q.size(), 1u);
  const QueuedInput* in = q.popDue(1);
  ASSERT_NE(in, nullptr);
  EXPECT_EQ(in->F.f.x(), 4);
  EXPECT_EQ(in->body, 1);
  q.push(input(3, 0));
  q.clear();
  EXPECT_TRUE(q.empty());
}

}  // namespace input_queue_test
}  // namespace sim
}  // namespace cga_rigid_sim

// The paper's reported values (experiments/input/paper_values.hpp): each scene system with an
// optimal control example in the paper finds its section's table through the table's `system`.
#include <gtest/gtest.h>

#include "experiments/input/paper_values.hpp"
#include "lgvi/inertia.hpp"  // InvalidInput

namespace lgvi::experiments {
namespace {

TEST(PaperValues, EachOcpSystemFindsItsSectionsExample) {
  const PaperValues& paper = paper_values();
  const struct {
    const char* system;
    const char* key;
    const char* section;
  } expected[] = {{"dumbbell", "dumbbell_orbit_transfer", "3.1"},
                  {"pendulum", "pendulum_reorientation", "3.2"},
                  {"cart-pendulum", "cart_pendulum", "4.1"},
                  {"connected-bodies", "connected_bodies", "4.2"}};
  for (const auto& e : expected) {
    const PaperExample& example = paper.example(e.system);
    EXPECT_EQ(example.key, e.key) << e.system;
    EXPECT_EQ(example.section, e.section) << e.system;
    EXPECT_EQ(example.system, e.system);
    ASSERT_NE(paper.find(e.key), nullptr) << e.key;
    EXPECT_EQ(paper.find(e.key), &example) << e.key;
  }
  EXPECT_THROW(paper.example("free-body"), InvalidInput);
}

}  // namespace
}  // namespace lgvi::experiments

#include "model/core/event_manager.h"

#include <gtest/gtest.h>

#include <vector>

namespace orcs {
namespace {

TEST(EventManagerTest, RegisterIsIdempotentAndIdsAreInOrder) {
  EventManager events;
  EXPECT_EQ(events.size(), 0);
  EXPECT_EQ(events.Register("/Simulation/Step"), 0);
  EXPECT_EQ(events.Register("/Sim/SecondSphere/Collision"), 1);
  EXPECT_EQ(events.Register("/Simulation/Step"), 0);
  EXPECT_EQ(events.Register("/Sim/Box/Collision"), 2);
  EXPECT_EQ(events.size(), 3);
  EXPECT_EQ(events.name(0), "/Simulation/Step");
  EXPECT_EQ(events.name(1), "/Sim/SecondSphere/Collision");
  EXPECT_EQ(events.name(2), "/Sim/Box/Collision");
  EXPECT_EQ(events.Find("/Sim/Box/Collision"), 2);
  EXPECT_EQ(events.Find("/Sim/Missing"), -1);
}

TEST(EventManagerTest, TriggerRecordsOncePerStepInFirstTriggerOrder) {
  EventManager events;
  const int step = events.Register("/Simulation/Step");
  const int hit = events.Register("/Sim/Box/Collision");
  const int other = events.Register("/Sim/Other/Collision");
  EXPECT_TRUE(events.occurred().empty());
  events.Trigger(hit);
  events.Trigger(step);
  events.Trigger(hit);
  events.Trigger(hit);
  EXPECT_EQ(events.occurred(), (std::vector<int>{hit, step}));
  EXPECT_TRUE(events.occurred(hit));
  EXPECT_TRUE(events.occurred(step));
  EXPECT_FALSE(events.occurred(other));
}

TEST(EventManagerTest, BeginStepClears) {
  EventManager events;
  const int a = events.Register("/A");
  const int b = events.Register("/B");
  events.Trigger(a);
  events.Trigger(b);
  events.BeginStep();
  EXPECT_TRUE(events.occurred().empty());
  EXPECT_FALSE(events.occurred(a));
  EXPECT_FALSE(events.occurred(b));
  // The next step records afresh, including events seen in the previous one.
  events.Trigger(b);
  events.Trigger(a);
  events.Trigger(b);
  EXPECT_EQ(events.occurred(), (std::vector<int>{b, a}));
  EXPECT_TRUE(events.occurred(a));
}

TEST(EventManagerTest, ObserversAreCalledOnEveryTrigger) {
  EventManager events;
  const int a = events.Register("/A");
  const int b = events.Register("/B");
  std::vector<int> first_calls;
  std::vector<int> second_calls;
  events.AddObserver(a, [&first_calls](int id) { first_calls.push_back(id); });
  events.AddObserver(a, [&second_calls](int id) { second_calls.push_back(id); });
  events.AddObserver(b, [&second_calls](int id) { second_calls.push_back(id); });
  events.Trigger(a);
  events.Trigger(a);  // same step: still observed
  events.BeginStep();
  events.Trigger(a);
  events.Trigger(b);
  EXPECT_EQ(first_calls, (std::vector<int>{a, a, a}));
  EXPECT_EQ(second_calls, (std::vector<int>{a, a, a, b}));
}

TEST(EventManagerTest, ManagersAreIndependent) {
  EventManager first;
  EventManager second;
  first.Register("/X");
  EXPECT_EQ(second.Find("/X"), -1);
  EXPECT_EQ(second.Register("/Y"), 0);
  second.Trigger(0);
  first.Trigger(0);
  first.BeginStep();
  EXPECT_EQ(second.occurred(), std::vector<int>{0});
}

}  // namespace
}  // namespace orcs

#include "model/core/variable_repository.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "model/core/error.h"
#include "tests/support/input_error_of.h"

namespace orcs {
namespace {

using test_support::InputErrorOf;
using ::testing::HasSubstr;

TEST(VariableRepositoryTest, AddFindGet) {
  VariableRepository repository;
  Value& step = repository.Add("/Simulation/TimeStep", 0.01);
  Value& name = repository.Add("/Simulation/Name", "walk");
  EXPECT_EQ(repository.size(), 2);
  EXPECT_EQ(repository.Find("/Simulation/TimeStep"), &step);
  EXPECT_EQ(&repository.Get("/Simulation/Name"), &name);
  EXPECT_EQ(repository.Get("/Simulation/TimeStep").as_double(), 0.01);
  EXPECT_EQ(repository.Get("/Simulation/Name").as_string(), "walk");
  EXPECT_EQ(repository.Find("/Simulation/Missing"), nullptr);
  EXPECT_EQ(repository.Find("/Simulation/timestep"), nullptr);  // paths are case-sensitive
  EXPECT_EQ(repository.Find("/Simulation"), nullptr);           // no prefix matching

  const VariableRepository& constant = repository;
  EXPECT_EQ(constant.Find("/Simulation/TimeStep"), &step);
  EXPECT_EQ(&constant.Get("/Simulation/TimeStep"), &step);
}

TEST(VariableRepositoryTest, FirstRegistrationWins) {
  VariableRepository repository;
  Value& first = repository.Add("/A/Gain", 1.5);
  Value& second = repository.Add("/A/Gain", 99.0);
  EXPECT_EQ(&first, &second);
  EXPECT_EQ(repository.Get("/A/Gain").as_double(), 1.5);
  EXPECT_EQ(repository.size(), 1);
}

TEST(VariableRepositoryTest, GetOfUnknownPathThrowsNamingIt) {
  VariableRepository repository;
  repository.Add("/Known", 1);
  EXPECT_THAT(InputErrorOf([&] { repository.Get("/Sim/Nowhere"); }), HasSubstr("/Sim/Nowhere"));
  const VariableRepository& constant = repository;
  EXPECT_THAT(InputErrorOf([&] { constant.Get("/Sim/Nowhere"); }), HasSubstr("/Sim/Nowhere"));
  EXPECT_THAT(InputErrorOf([&] { repository.Set("/Sim/Nowhere", "1"); }), HasSubstr("/Sim/Nowhere"));
}

TEST(VariableRepositoryTest, ErrorsNameLongPathsInFull) {
  // Real paths exceed 40 characters; the name must not be shortened, or a typo at its end would be hidden.
  VariableRepository repository;
  const std::string typo = "/Simulation/ODE/ContactMaxCorrectingVelocityy";
  EXPECT_THAT(InputErrorOf([&] { repository.Get(typo); }), HasSubstr("'" + typo + "'"));
  const std::string long_regex = "/Simulation/ODE/(ContactMaxCorrectingVelocity|Missing";
  EXPECT_THAT(InputErrorOf([&] { repository.Match(long_regex); }), HasSubstr("'" + long_regex + "'"));
}

TEST(VariableRepositoryTest, ErrorsEscapeControlCharactersSoTheyStayOneLine) {
  // Paths and patterns arrive from orcs-view's requests and OSP datagrams: any bytes.
  VariableRepository repository;
  EXPECT_EQ(InputErrorOf([&] { repository.Get("/Sim/a\nb"); }), "unknown repository path '/Sim/a\\x0ab'");
  const std::string bad_pattern = InputErrorOf([&] { repository.Match("(\n"); });
  EXPECT_EQ(bad_pattern.find('\n'), std::string::npos) << bad_pattern;
  EXPECT_THAT(bad_pattern, HasSubstr("invalid regular expression '(\\n'"));
}

TEST(VariableRepositoryTest, SetParsesAndNotifies) {
  VariableRepository repository;
  Value& gain = repository.Add("/PID/Proportional", 1.0);
  Value& position = repository.Add("/Sim/Box/Position", Eigen::Vector3d::Zero().eval());
  std::vector<double> seen;
  gain.AddObserver([&seen](const Value& value) { seen.push_back(value.as_double()); });
  repository.Set("/PID/Proportional", " 2.5 ");
  repository.Set("/PID/Proportional", "2.5");  // unchanged: no notification
  repository.Set("/Sim/Box/Position", "(1,2,3)");
  EXPECT_EQ(gain.as_double(), 2.5);
  EXPECT_EQ(seen, std::vector<double>{2.5});
  EXPECT_EQ(position.as_vector3(), Eigen::Vector3d(1, 2, 3));
}

TEST(VariableRepositoryTest, SetWithBadTextThrowsNamingPathAndExpectedType) {
  VariableRepository repository;
  Value& gain = repository.Add("/PID/Proportional", 1.0);
  int calls = 0;
  gain.AddObserver([&calls](const Value&) { ++calls; });
  const std::string message = InputErrorOf([&] { repository.Set("/PID/Proportional", "fast"); });
  EXPECT_THAT(message, HasSubstr("/PID/Proportional"));
  EXPECT_THAT(message, HasSubstr("a number"));
  EXPECT_THAT(message, HasSubstr("'fast'"));
  EXPECT_EQ(gain.as_double(), 1.0);
  EXPECT_EQ(calls, 0);

  repository.Add("/Flag", true);
  EXPECT_THAT(InputErrorOf([&] { repository.Set("/Flag", "maybe"); }), HasSubstr("T or F"));
}

TEST(VariableRepositoryTest, MatchMatchesWholePathsInRegistrationOrder) {
  VariableRepository repository;
  const Value& zebra = repository.Add("/Sim/Zebra/Position", Eigen::Vector3d::Zero().eval());
  repository.Add("/Sim/Box/PositionX", 0.0);
  const Value& box = repository.Add("/Sim/Box/Position", Eigen::Vector3d::Zero().eval());
  repository.Add("/Other/Sim/Box/Position", Eigen::Vector3d::Zero().eval());
  repository.Add("/Sim/Box/Mass", 1.0);

  const std::vector<int> ids = repository.Match("/Sim/.*/Position");
  ASSERT_EQ(ids.size(), 2u);
  EXPECT_EQ(&repository.value(ids[0]), &zebra);  // registration order, not alphabetical
  EXPECT_EQ(&repository.value(ids[1]), &box);
  EXPECT_EQ(repository.path(ids[0]), "/Sim/Zebra/Position");
  EXPECT_EQ(repository.path(ids[1]), "/Sim/Box/Position");

  EXPECT_EQ(repository.Match("/Sim/Box").size(), 0u);  // a prefix does not match
  EXPECT_EQ(repository.Match("Position").size(), 0u);  // nor does a substring
  EXPECT_EQ(repository.Match(".*").size(), 5u);
  EXPECT_EQ(repository.Match(".*Position.*"), (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(repository.Match("/Sim/Box/(Mass|PositionX)"), (std::vector<int>{1, 4}));
}

TEST(VariableRepositoryTest, InvalidRegexThrowsInputError) {
  VariableRepository repository;
  repository.Add("/A", 1);
  EXPECT_THAT(InputErrorOf([&] { repository.Match("/Sim/(.*"); }), HasSubstr("/Sim/(.*"));
  EXPECT_THROW(repository.Match("[a-"), InputError);
  EXPECT_THROW(repository.Match("*"), InputError);
}

TEST(VariableRepositoryTest, IdsAreStableRegistrationIndices) {
  VariableRepository repository;
  Value& a = repository.Add("/A", 1);
  Value& b = repository.Add("/B", 2.0);
  EXPECT_EQ(repository.IdOf("/A"), 0);
  EXPECT_EQ(repository.IdOf("/B"), 1);
  EXPECT_EQ(repository.IdOf("/C"), -1);
  // More registrations (enough to reallocate any internal storage) change neither ids nor addresses.
  for (int i = 0; i < 1000; ++i) repository.Add("/Many/" + std::to_string(i), i);
  repository.Add("/A", 5);  // re-registration keeps the id
  EXPECT_EQ(repository.IdOf("/A"), 0);
  EXPECT_EQ(repository.IdOf("/B"), 1);
  EXPECT_EQ(repository.IdOf("/Many/999"), 1001);
  EXPECT_EQ(&repository.value(0), &a);
  EXPECT_EQ(&repository.value(1), &b);
  EXPECT_EQ(repository.Find("/A"), &a);
  EXPECT_EQ(repository.value(0).as_int(), 1);
  EXPECT_EQ(repository.path(1001), "/Many/999");
  EXPECT_EQ(repository.Get("/Many/500").as_int(), 500);
}

TEST(VariableRepositoryTest, RepositoriesAreIndependent) {
  VariableRepository first;
  VariableRepository second;
  first.Add("/X", 1.0);
  EXPECT_EQ(second.Find("/X"), nullptr);
  second.Add("/X", 2.0);
  first.Set("/X", "3");
  EXPECT_EQ(second.Get("/X").as_double(), 2.0);
}

}  // namespace
}  // namespace orcs

// "Did you mean" (base/near_names.h): the near names of a mistyped option, motor or value path.
#include "base/near_names.h"

#include <gtest/gtest.h>

namespace orcs {
namespace {

TEST(NearNamesTest, EditDistanceCountsSingleCharacterEdits) {
  EXPECT_EQ(EditDistance("jobs", "jobs"), 0u);
  EXPECT_EQ(EditDistance("job", "jobs"), 1u);
  EXPECT_EQ(EditDistance("jbos", "jobs"), 1u);  // a swap of neighbours is one edit
  EXPECT_EQ(EditDistance("", "abc"), 3u);
  EXPECT_EQ(EditDistance("kitten", "sitting"), 3u);
}

TEST(NearNamesTest, NearestFirstAndOnlyWhatIsNear) {
  const std::vector<std::string> motors = {"Right/HipRoll", "Right/HipPitch", "Right/HipYaw", "Right/Knee", "Waist"};
  EXPECT_EQ(NearNames("Right/Hip", motors), (std::vector<std::string>{"Right/HipYaw", "Right/HipRoll", "Right/HipPitch"}));
  EXPECT_EQ(NearNames("Right/Kne", motors), std::vector<std::string>{"Right/Knee"});
  EXPECT_EQ(NearNames("Wiast", motors), std::vector<std::string>{"Waist"});
  EXPECT_TRUE(NearNames("Head/Pan", motors).empty());
  EXPECT_TRUE(NearNames("Waist", motors).empty()) << "the name itself is no suggestion";
  EXPECT_EQ(NearNames("Right/Hip", motors, 1), std::vector<std::string>{"Right/HipYaw"});
}

TEST(NearNamesTest, DidYouMeanIsTheEndOfAMessage) {
  const std::vector<std::string> paths = {"/AngularMotor/PID/Proportional", "/AngularMotor/PID/Integral"};
  EXPECT_EQ(DidYouMean("/AngularMotor/PID/Proportionl", paths), " (did you mean '/AngularMotor/PID/Proportional'?)");
  EXPECT_EQ(DidYouMean("/Elsewhere", paths), "");
  EXPECT_EQ(DidYouMean("ab", {"abc", "abd"}), " (did you mean 'abc' or 'abd'?)");
}

}  // namespace
}  // namespace orcs

// --precision auto (app/precision_choice.hpp): what is asked wins; auto is
// double on the CPU, and float on a GPU only for targets at or above 1e-3
// or a fixed iteration budget.
#include <gtest/gtest.h>

#include "app/precision_choice.hpp"

namespace descent {
namespace {

TEST(PrecisionChoice, AskedPrecisionWins) {
  EXPECT_TRUE(choose_precision("float", false, 1e-6).use_float);
  EXPECT_FALSE(choose_precision("double", true, 1e-1).use_float);
}

TEST(PrecisionChoice, AutoIsDoubleOnTheCpu) {
  for (double accuracy : {0.0, 1e-1, 1e-3, 1e-6})
    EXPECT_FALSE(choose_precision("auto", false, accuracy).use_float) << accuracy;
}

TEST(PrecisionChoice, AutoOnAGpuIsFloatOnlyWellAboveFloatsFloor) {
  EXPECT_TRUE(choose_precision("auto", true, 0.0).use_float);
  EXPECT_TRUE(choose_precision("auto", true, 1e-2).use_float);
  EXPECT_TRUE(choose_precision("auto", true, kFloatAccuracyTarget).use_float);
  EXPECT_FALSE(choose_precision("auto", true, 0.5 * kFloatAccuracyTarget).use_float);
  EXPECT_FALSE(choose_precision("auto", true, 1e-5).use_float);
  EXPECT_NE(choose_precision("auto", true, 1e-5).why.find("solver.accuracy"), std::string::npos);
}

}  // namespace
}  // namespace descent

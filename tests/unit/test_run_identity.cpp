// What --restart checks: the identity of a run names the key that differs,
// and ignores what a restart may change.
#include <gtest/gtest.h>

#include "app/run_identity.hpp"

namespace descent {
namespace {

Scene scene_with(const std::vector<std::string>& overrides) {
  const char* text = R"(
gravity = [0.0, -9.81, 0.0]
[mesh]
generator = "box"
[[fixed]]
box_min = [-1.0, -1.0, -1.0]
box_max = [1.0, 0.1, 1.0]
)";
  return parse_scene(text, "<test scene>", overrides);
}

std::string identity_of(const std::vector<std::string>& overrides, std::uint64_t digest = 7,
                        const std::string& precision = "double", std::uint64_t partition = 3) {
  return run_identity(scene_with(overrides), {digest, partition}, precision);
}

TEST(RunIdentity, TheSameRunAgrees) {
  EXPECT_EQ(identity_difference(identity_of({}), identity_of({})), "");
}

TEST(RunIdentity, WhatARestartMayChangeIsNotPartOfIt) {
  EXPECT_EQ(identity_of({}),
            identity_of({"time.frames=600", "output.every=5", "output.checkpoint_every=3",
                         "output.dir=\"elsewhere\""}));
}

TEST(RunIdentity, NamesAChangedMaterialWithBothValues) {
  const std::string differs =
      identity_difference(identity_of({}), identity_of({"material.young=2.5e5"}));
  EXPECT_NE(differs.find("material.young is 250000 now but was 1e+05"), std::string::npos)
      << differs;
}

TEST(RunIdentity, NamesTheMeshWhenOnlyItsContentDiffers) {
  const std::string differs = identity_difference(identity_of({}, 7), identity_of({}, 8));
  EXPECT_EQ(differs.rfind("the mesh differs (mesh.digest", 0), 0u) << differs;
  EXPECT_NE(differs.find("is 8 now but was 7"), std::string::npos) << differs;
}

TEST(RunIdentity, NamesThePartitionWhenOnlyItDiffers) {
  const std::string differs =
      identity_difference(identity_of({}, 7, "double", 3), identity_of({}, 7, "double", 4));
  EXPECT_EQ(differs.rfind("the partition differs (partition.digest", 0), 0u) << differs;
  EXPECT_NE(differs.find("is 4 now but was 3"), std::string::npos) << differs;
  // partition.method is a scene key like any other.
  EXPECT_EQ(identity_difference(identity_of({}), identity_of({"partition.method=\"metis\""}))
                .rfind("partition.method is \"metis\" now but was \"auto\"", 0),
            0u);
}

TEST(RunIdentity, RefusesARunFromBeforePartitionDigests) {
  std::string before = identity_of({});
  before.erase(before.find("partition.digest"));  // the last lines: partition, precision
  before += "precision = \"double\"\n";
  EXPECT_EQ(identity_difference(before, identity_of({}))
                .rfind("the checkpoint's run predates partition digests", 0),
            0u);
}

TEST(RunIdentity, NamesThePrecision) {
  const std::string differs =
      identity_difference(identity_of({}, 7, "double"), identity_of({}, 7, "float"));
  EXPECT_EQ(differs.rfind("precision is \"float\" now", 0), 0u) << differs;
}

TEST(RunIdentity, NamesABoundaryConditionThatMovedOrCame) {
  EXPECT_EQ(identity_difference(identity_of({}), identity_of({"fixed.0.axes=\"y\""}))
                .rfind("fixed.0.axes is \"y\" now", 0),
            0u);
  // A checkpoint's run without an entry the scene has now.
  const std::string without = identity_of({});
  std::string with_load = without + "load.0.force = [0, 1, 0]\n";
  EXPECT_NE(identity_difference(without, with_load).find("load.0.force = [0, 1, 0] is new"),
            std::string::npos);
  EXPECT_NE(identity_difference(with_load, without).find("load.0.force = [0, 1, 0] of the"),
            std::string::npos);
}

}  // namespace
}  // namespace descent

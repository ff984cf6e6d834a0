// Args::parse: unknown options, missing values, repeats and --help, with the messages a
// user sees.
#include "cli/args.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace omniview::cli {
namespace {

const OptionSpec kSpec{.switches = {"grey"}, .single = {"rig", "out"}, .repeatable = {"view"}};

std::string usage_error(const std::vector<std::string>& argv) {
  try {
    Args::parse(argv, kSpec);
  } catch (const UsageError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(Args, ReadsValuesSwitchesAndRepeats) {
  const Args args = Args::parse({"--rig", "r.yaml", "--view=a.yaml", "--grey", "--view", "b.yaml", "pos"}, kSpec);
  EXPECT_FALSE(args.help_requested());
  EXPECT_EQ(args.get("rig"), "r.yaml");
  EXPECT_TRUE(args.has("grey"));
  EXPECT_EQ(args.all("view"), (std::vector<std::string>{"a.yaml", "b.yaml"}));
  EXPECT_EQ(args.positional(), (std::vector<std::string>{"pos"}));
}

TEST(Args, ValuesMayStartWithAMinus) {
  // Negative numbers are values, not options.
  const OptionSpec spec{.switches = {}, .single = {"rig-pose"}, .repeatable = {}};
  EXPECT_EQ(Args::parse({"--rig-pose", "-1 0 0 0 0 0"}, spec).get("rig-pose"), "-1 0 0 0 0 0");
  EXPECT_EQ(Args::parse({"--rig-pose", "-.5"}, spec).get("rig-pose"), "-.5");
}

TEST(Args, UnknownOptionsAreNamedEvenWithoutAValue) {
  EXPECT_EQ(usage_error({"--frobnicate"}), "unknown option --frobnicate (see --help)");
  EXPECT_EQ(usage_error({"--frobnicate", "x"}), "unknown option --frobnicate (see --help)");
  EXPECT_EQ(usage_error({"--frobnicate=x"}), "unknown option --frobnicate (see --help)");
  EXPECT_EQ(usage_error({"-x"}), "unknown option -x (see --help)");
}

TEST(Args, MissingValues) {
  EXPECT_EQ(usage_error({"--rig"}), "--rig needs a value");
  // The next option is not taken as the value.
  EXPECT_EQ(usage_error({"--rig", "--view", "v.yaml"}), "--rig needs a value");
  EXPECT_EQ(usage_error({"--grey=yes"}), "--grey takes no value");
}

TEST(Args, SingleValuedOptionsOnlyOnce) {
  EXPECT_EQ(usage_error({"--rig", "a.yaml", "--rig", "b.yaml"}),
            "--rig given twice ('a.yaml' and 'b.yaml'); give it once");
  EXPECT_NO_THROW(Args::parse({"--view", "a", "--view", "b", "--grey", "--grey"}, kSpec));
}

TEST(Args, HelpWinsWhereverItAppears) {
  for (const std::vector<std::string>& argv :
       std::vector<std::vector<std::string>>{{"--help"},
                                             {"-h"},
                                             {"--rig", "r.yaml", "--help"},
                                             {"--rig", "--help"},  // where a value is expected
                                             {"--frobnicate", "-h"},
                                             {"--rig", "a", "--rig", "b", "--help"}}) {
    EXPECT_TRUE(Args::parse(argv, kSpec).help_requested()) << testing::PrintToString(argv);
  }
}

TEST(Args, CountsInMessages) {
  EXPECT_EQ(count_of(1, "number", "numbers"), "1 number");
  EXPECT_EQ(count_of(0, "number", "numbers"), "0 numbers");
  EXPECT_EQ(count_of(7, "view", "views"), "7 views");
}

}  // namespace
}  // namespace omniview::cli

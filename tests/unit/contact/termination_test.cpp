// The status convention of stage results (contact/termination.hpp): names, success, brief().
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "jointhb/contact/termination.hpp"

using jointhb::Status;
using jointhb::Termination;

TEST(Termination, ToStringNamesEveryEnumerator) {
  EXPECT_EQ(jointhb::to_string(Termination::converged), "converged");
  EXPECT_EQ(jointhb::to_string(Termination::reached_end), "reached_end");
  EXPECT_EQ(jointhb::to_string(Termination::stopped_by_user), "stopped_by_user");
  EXPECT_EQ(jointhb::to_string(Termination::no_convergence), "no_convergence");
  EXPECT_EQ(jointhb::to_string(Termination::failed), "failed");
}

TEST(Termination, OnlyConvergedAndReachedEndSucceed) {
  EXPECT_TRUE(jointhb::succeeded(Termination::converged));
  EXPECT_TRUE(jointhb::succeeded(Termination::reached_end));
  EXPECT_FALSE(jointhb::succeeded(Termination::stopped_by_user));
  EXPECT_FALSE(jointhb::succeeded(Termination::no_convergence));
  EXPECT_FALSE(jointhb::succeeded(Termination::failed));
}

TEST(Termination, StatusDefaultsToFailedAndBriefJoinsNameAndMessage) {
  const Status none;
  EXPECT_EQ(none.termination, Termination::failed);
  EXPECT_FALSE(none.ok());
  EXPECT_EQ(none.brief(), "failed");  // no message: the name alone, no dangling colon

  const Status done{Termination::converged, "4 load steps, 9 Newton iterations"};
  EXPECT_TRUE(done.ok());
  EXPECT_EQ(done.brief(), "converged: 4 load steps, 9 Newton iterations");

  const Status stopped{Termination::stopped_by_user, "stopped by the accept callback at point 3"};
  EXPECT_FALSE(stopped.ok());
  EXPECT_EQ(stopped.brief(), "stopped_by_user: stopped by the accept callback at point 3");
}

TEST(Termination, WorstOfARunIsItsMostSevereNamedPart) {
  EXPECT_EQ(jointhb::worst({}).termination, Termination::converged);
  EXPECT_TRUE(jointhb::worst({}).message.empty());

  const std::vector<jointhb::NamedStatus> ok_run = {
      {"preload", {Termination::converged, "4 load steps"}},
      {"backbone mode 1", {Termination::reached_end, "reached the end"}}};
  const Status ok = jointhb::worst(ok_run);
  EXPECT_EQ(ok.termination, Termination::reached_end);
  EXPECT_TRUE(ok.ok());
  EXPECT_EQ(ok.message, "backbone mode 1: reached the end");

  // failed outranks no_convergence, which outranks stopped_by_user; the first of equals wins.
  const std::vector<jointhb::NamedStatus> bad_run = {
      {"curve level 0", {Termination::stopped_by_user, "stopped"}},
      {"curve level 1", {Termination::failed, "step below min_step"}},
      {"curve level 2", {Termination::no_convergence, "max_points"}},
      {"curve level 3", {Termination::failed, "start failed"}}};
  const Status bad = jointhb::worst(bad_run);
  EXPECT_EQ(bad.termination, Termination::failed);
  EXPECT_FALSE(bad.ok());
  EXPECT_EQ(bad.brief(), "failed: curve level 1: step below min_step");

  const std::vector<jointhb::NamedStatus> unnamed = {{"", {Termination::no_convergence, "x"}}};
  EXPECT_EQ(jointhb::worst(unnamed).message, "x");
}
